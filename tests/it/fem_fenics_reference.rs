//! Another code on the same discretisation: legacy FEniCS (DOLFIN 2019) solving the clamped
//! neo-Hookean cylinder (R = 1 mm, L = 4 mm, μ = 5 kPa, λ = 1.17) with Taylor–Hood Q2/Q1 on the
//! same uniform quadrilaterals, 3 × 3 Gauss, exact incompressibility Π = ∫ [W(F) + p (J − 1)] 2πr
//! dr dz, its Jacobian derived by UFL, UMFPACK, and the reaction read from the discrete residual
//! (`python/bench/fenics_cylinder.py --element Q2Q1 NR NZ`, Debian's python3-dolfin). Its nominal
//! stresses, printed to 15 digits, are the references below: a different assembler, tangent
//! (symbolic instead of our dual numbers), linear solver and Newton loop; only the discrete
//! problem is shared. Measured: ours agrees to 2.4e-15 (8 × 32) and 2.2e-15 (16 × 64); the bound
//! 1e-10 is the Newton stopping tolerance of the FEniCS script. For scale, the mesh
//! change 8 × 32 → 16 × 64 moves P by 1.5e-4 and P2/P1 triangles on 16 × 64 by 2.4e-4.

use activemuscle::fem::{AxisymmetricSolver, Bases, Mesh, NeoHookean, SolverOptions};

#[test]
fn clamped_cylinder_matches_legacy_fenics_on_the_same_discretisation() {
    let material = NeoHookean::new(5.0).unwrap();
    // (nr, nz, FEniCS's free dofs, FEniCS's nominal stress P [kPa] at λ = 1.17)
    for (nr, nz, fenics_dofs, fenics_stress) in [
        (8, 32, 2376, 2.3866426884886),
        (16, 64, 9360, 2.38628123275558),
    ] {
        let mesh = Mesh::structured(1.0, 4.0, nr, nz, 1.0).unwrap();
        let mut solver =
            AxisymmetricSolver::new(mesh, Bases::Clamped, &material, SolverOptions::default())
                .unwrap();
        let result = solver.sweep(&[1.17]).unwrap().into_result().unwrap();
        let stress = result[0].nominal_stress;
        let relative = (stress - fenics_stress).abs() / fenics_stress;
        println!("{nr} × {nz}: ours P = {stress:.14} kPa, FEniCS {fenics_stress:.14}, relative {relative:.1e}");
        assert_eq!(solver.n_free_dofs(), fenics_dofs, "{nr} × {nz}: free dofs");
        assert!(
            relative < 1e-10,
            "{nr} × {nz}: P = {stress} vs FEniCS {fenics_stress}"
        );
    }
}
