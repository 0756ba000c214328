//! Linear-solver equivalence and VTK output.

use activemuscle::fem::{
    AxisymmetricSolver, Bases, LinearSolver, Mesh, NeoHookean, SolverOptions, VtkOutput,
};

use crate::common;
use crate::scratch;
use common::NonSymmetric;
use scratch::scratch;

#[test]
fn gmres_with_symmetric_part_preconditioner_matches_the_sparse_lu() {
    let material = NonSymmetric {
        mu: 10.0,
        c: 1.5,
        approximate: false,
    };
    let targets = [0.8, 1.25];
    let mut stresses = Vec::new();
    for linear_solver in [LinearSolver::SymmetricPartGmres, LinearSolver::Lu] {
        let mesh = Mesh::structured(1.0, 3.0, 3, 9, 2.0).unwrap();
        let options = SolverOptions {
            linear_solver,
            ..SolverOptions::default()
        };
        let mut solver = AxisymmetricSolver::new(mesh, Bases::Clamped, &material, options).unwrap();
        let res = solver.sweep(&targets).unwrap().into_result().unwrap();
        let t = solver.timings();
        println!(
            "{linear_solver:?}: P = {:?}, solves {}, GMRES iterations {}, LU fallbacks {}",
            res.iter().map(|r| r.nominal_stress).collect::<Vec<_>>(),
            t.solves,
            t.krylov_iterations,
            t.lu_fallbacks
        );
        if linear_solver == LinearSolver::SymmetricPartGmres {
            // The tangent is non-symmetric, so GMRES needs more than one iteration per solve.
            assert!(t.krylov_iterations > t.solves);
        } else {
            assert_eq!(t.krylov_iterations, 0);
        }
        // One factorisation per Newton iteration unless an earlier one of its step served
        // (never for faer's LU, which solves directly), plus the fallbacks and refactorisations.
        assert_eq!(
            t.factorisations + t.earlier_factorisations,
            t.newton_iterations + t.lu_fallbacks + t.refactorisations,
            "{t:?}"
        );
        if linear_solver == LinearSolver::Lu {
            assert_eq!(t.earlier_factorisations, 0);
        }
        stresses.push(res.iter().map(|r| r.nominal_stress).collect::<Vec<_>>());
    }
    for other in &stresses[1..] {
        for (a, b) in stresses[0].iter().zip(other) {
            assert!((a - b).abs() < 1e-10 * b.abs(), "GMRES {a} vs {b}");
        }
    }
}

#[test]
fn vtu_output_holds_the_fields_with_the_homogeneous_values() {
    let mu = 4.0;
    let lambda = 1.3;
    let material = NeoHookean::new(mu).unwrap();
    let tmp = scratch("fem-vtu");
    let directory = tmp.join("vtk");
    let options = SolverOptions {
        vtk: Some(VtkOutput {
            directory: directory.clone(),
            stretches: vec![lambda],
        }),
        ..SolverOptions::default()
    };
    let mesh = Mesh::structured(1.0, 2.0, 2, 3, 1.0).unwrap();
    let mut solver = AxisymmetricSolver::new(mesh, Bases::Sliding, &material, options).unwrap();
    solver.sweep(&[1.1, lambda]).unwrap().into_result().unwrap();
    let path = directory.join("lambda_1.3000.vtu");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        !directory.join("lambda_1.1000.vtu").exists(),
        "only requested stretches are written"
    );
    assert!(text.contains(r#"NumberOfPoints="35" NumberOfCells="6""#));
    for name in [
        "\"u\"",
        "\"p\"",
        "\"J\"",
        "\"gamma\"",
        "\"fibre_stretch\"",
        "\"P_zz\"",
    ] {
        assert!(text.contains(&format!("Name={name}")), "missing {name}");
    }
    // Cell data: the uniaxial state, P_zz = μ(λ − λ⁻²), p = μ/λ, J = 1, fibre stretch λ, in
    // every cell.
    let block = |name: &str| common::vtu_data_array(&text, name);
    assert_eq!(block("P_zz").len(), 6);
    common::assert_uniaxial_neo_hookean_cells(&text, mu, lambda);
    assert!(block("J").iter().all(|v| (v - 1.0).abs() < 1e-10));
    assert!(block("fibre_stretch")
        .iter()
        .all(|v| (v - lambda).abs() < 1e-10));
}

#[test]
fn the_solver_returns_the_path_of_every_file_it_wrote() {
    let material = NeoHookean::new(4.0).unwrap();
    let tmp = scratch("fem-vtu-paths");
    let directory = tmp.join("vtk");
    let options = SolverOptions {
        vtk: Some(VtkOutput {
            directory: directory.clone(),
            stretches: vec![0.9, 1.3],
        }),
        ..SolverOptions::default()
    };
    let mesh = Mesh::structured(1.0, 2.0, 2, 3, 1.0).unwrap();
    let mut solver = AxisymmetricSolver::new(mesh, Bases::Sliding, &material, options).unwrap();
    let results = solver
        .sweep(&[0.9, 1.1, 1.3])
        .unwrap()
        .into_result()
        .unwrap();
    let files: Vec<Option<std::path::PathBuf>> =
        results.iter().map(|r| r.vtk_file.clone()).collect();
    assert_eq!(
        files,
        [
            Some(directory.join("lambda_0.9000.vtu")),
            None,
            Some(directory.join("lambda_1.3000.vtu")),
        ]
    );
    for file in files.iter().flatten() {
        assert!(file.is_file(), "{file:?}");
    }
    assert_eq!(std::fs::read_dir(&directory).unwrap().count(), 2);
}
