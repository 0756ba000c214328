//! The local relaxation of an overshooting predictor ([`activemuscle::fem::relaxation`]): on a
//! converged state with one interior node pushed away, the patch around it is brought back to
//! the converged state (the patch's equilibrium with its boundary held there), and no dof
//! outside the patch moves.

use activemuscle::fem::assembly::Assembler;
use activemuscle::fem::continuation::{Continuation, Observer, StepRecord, Stepping};
use activemuscle::fem::dofs::DofMap;
use activemuscle::fem::ldlt::SymmetricPartLdlt;
use activemuscle::fem::problem::MixedProblem;
use activemuscle::fem::relaxation::{relax, OVERSHOOT};
use activemuscle::fem::tangent_solver::TangentSolver;
use activemuscle::fem::{Bases, FemResult, Mesh, NeoHookean, NonlinearSystem};

/// The converged state at the one target load.
#[derive(Default)]
struct Keep(Vec<f64>);

impl<S> Observer<S> for Keep {
    fn reached(&mut self, _: &mut S, _: f64, x: &[f64], _: Vec<StepRecord>) -> FemResult<()> {
        self.0 = x.to_vec();
        Ok(())
    }
}

#[test]
fn a_pushed_node_is_relaxed_back_to_equilibrium_and_nothing_outside_its_patch_moves() {
    let material = NeoHookean { mu: 5.0 };
    let mesh = Mesh::structured(1.0, 4.0, 8, 32, 1.0).unwrap();
    let dofs = DofMap::new(&mesh, Bases::Clamped);
    let asm = Assembler::new(&mesh, &dofs).unwrap();
    let ldlt = SymmetricPartLdlt::for_mesh(&asm.pattern, &mesh, &dofs, asm.system_index()).unwrap();
    let linear = TangentSolver::new(asm.pattern.n, Some(ldlt), true, 1);
    let mut problem = MixedProblem::new(mesh, dofs, asm, linear, &material, 1e-6);
    let stepping = Stepping {
        tolerance: 1e-12,
        ..Stepping::default()
    };
    let mut driver = Continuation::new(problem.unknowns(), stepping, None);
    let mut converged = Keep::default();
    let failures = driver.sweep(&mut problem, &[1.2], &mut converged).unwrap();
    assert!(failures.is_empty());
    let solution = converged.0;
    problem.evaluate(&solution, true).unwrap();
    let scale = problem.scale();
    // Push a vertex node inside the mesh (the third corner of cell 100): its free dofs move by
    // 0.05 (a fifth of a cell), which raises the stresses of the cells around it.
    let pushed_node = problem.mesh.elements().nth(100).unwrap()[2] as usize;
    let mut x = solution.clone();
    let moved: Vec<usize> = problem.dofs.node_u[pushed_node]
        .iter()
        .map(|&d| d as usize)
        .filter(|&d| d < problem.dofs.n_free)
        .collect();
    assert_eq!(moved.len(), 2, "an interior node with u_r and u_z free");
    for &d in &moved {
        x[d] += 0.05;
    }
    problem.evaluate(&x, true).unwrap();
    let over: Vec<f64> = problem.asm.cell_scales().to_vec();
    // Relax against a converged scale chosen so that only the cells around the node are over.
    let threshold = 0.5 * (over.iter().cloned().fold(0.0, f64::max) + scale);
    let seeds = over.iter().filter(|&&s| s > threshold).count();
    assert!((1..=4).contains(&seeds), "{seeds} cells over");
    let before = x.clone();
    assert!(relax(
        &problem.asm,
        &problem.dofs,
        &material,
        &mut x,
        threshold / OVERSHOOT
    ));
    let mut untouched = 0;
    for (i, (a, b)) in x.iter().zip(&before).enumerate() {
        if a == b {
            untouched += 1;
        } else {
            assert!(i < problem.dofs.n_free, "prescribed dof {i} moved");
        }
    }
    assert!(
        untouched > x.len() / 2,
        "{untouched} of {} dofs untouched",
        x.len()
    );
    let error = x
        .iter()
        .zip(&solution)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!(
        "{seeds} cells over, {untouched} dofs untouched, back to the solution within {error:.1e}"
    );
    assert!(error < 1e-8, "{error}");
}
