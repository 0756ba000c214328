//! Sliding bases: the exact solution is homogeneous uniaxial stretch, which Q2/Q1 represents
//! exactly, so the FE solution must equal the closed form to solver tolerance.

use activemuscle::fem::element::jacobian;
use activemuscle::fem::{AxisymmetricSolver, Bases, Mesh, NeoHookean, SolverOptions};

const MU: f64 = 2.5; // kPa
const R: f64 = 1.5; // mm
const L: f64 = 4.0; // mm

/// Closed form for the incompressible neo-Hookean bar: P = μ (λ − λ⁻²).
fn closed_form(lambda: f64) -> f64 {
    MU * (lambda - lambda.powi(-2))
}

#[test]
fn sliding_bases_reproduce_the_homogeneous_neo_hookean_curve() {
    let material = NeoHookean::new(MU).unwrap();
    // A graded, non-uniform mesh: the homogeneous solution must not care.
    let mesh = Mesh::structured(R, L, 3, 5, 2.0).unwrap();
    let mut solver =
        AxisymmetricSolver::new(mesh, Bases::Sliding, &material, SolverOptions::default()).unwrap();
    let targets: Vec<f64> = (7..=16)
        .filter(|&k| k != 10)
        .map(|k| k as f64 / 10.0)
        .collect();
    let mut with_one = targets.clone();
    with_one.push(1.0);
    let results = solver.sweep(&with_one).unwrap().into_result().unwrap();
    assert_eq!(results.len(), 10);
    let mesh = solver.mesh().clone();
    let dofs = solver.dofs().clone();
    for res in &results {
        let lambda = res.stretch;
        let exact = closed_form(lambda);
        if lambda == 1.0 {
            assert!(
                res.nominal_stress.abs() < 1e-10 * MU,
                "stress at λ = 1: {}",
                res.nominal_stress
            );
        } else {
            let rel = (res.nominal_stress - exact).abs() / exact.abs();
            println!(
                "λ = {lambda:.2}: P_FE = {:.12e}, P_exact = {exact:.12e}, rel = {rel:.2e}",
                res.nominal_stress
            );
            assert!(rel < 1e-9, "λ = {lambda}: relative error {rel:e}");
        }
        // Homogeneous displacement at every node: u_r = (λ^{-1/2} − 1) r, u_z = (λ − 1) z.
        let mut worst = 0.0f64;
        for (node, x) in mesh.nodes.iter().enumerate() {
            let d = dofs.node_u[node];
            let ur = res.state.x[d[0] as usize];
            let uz = res.state.x[d[1] as usize];
            worst = worst
                .max((ur - (lambda.powf(-0.5) - 1.0) * x[0]).abs())
                .max((uz - (lambda - 1.0) * x[1]).abs());
        }
        assert!(
            worst < 1e-10 * L,
            "λ = {lambda}: nodal displacement error {worst:e}"
        );
        // det F = 1 at every quadrature point.
        let qps = solver.quadrature_points(&res.state);
        let vol = qps
            .iter()
            .map(|q| (jacobian(&q.f) - 1.0).abs())
            .fold(0.0, f64::max);
        assert!(vol < 1e-10, "λ = {lambda}: max |J − 1| = {vol:e}");
        assert!(res.max_volume_error < 1e-10);
        // Pressure is the uniaxial p = μ/λ everywhere.
        let pmax = qps
            .iter()
            .map(|q| (q.pressure - MU / lambda).abs())
            .fold(0.0, f64::max);
        assert!(pmax < 1e-9 * MU, "λ = {lambda}: pressure error {pmax:e}");
        // Neo-Hookean is passive: γ = 0 and the fibre stretch at the centre is λ.
        assert_eq!(res.gamma_centre, 0.0);
        assert!((res.fibre_stretch_centre - lambda).abs() < 1e-10);
    }
}

#[test]
fn zero_stress_and_unit_jacobian_at_the_reference_state() {
    let material = NeoHookean::new(MU).unwrap();
    let mesh = Mesh::structured(R, L, 2, 3, 1.0).unwrap();
    let mut solver =
        AxisymmetricSolver::new(mesh, Bases::Clamped, &material, SolverOptions::default()).unwrap();
    let res = solver.sweep(&[1.0]).unwrap().into_result().unwrap();
    assert_eq!(res.len(), 1);
    assert!(res[0].nominal_stress.abs() < 1e-12 * MU);
    assert!(res[0].max_volume_error < 1e-14);
    let qps = solver.quadrature_points(&res[0].state);
    assert!(qps.iter().all(|q| (q.pressure - MU).abs() < 1e-10 * MU));
}
