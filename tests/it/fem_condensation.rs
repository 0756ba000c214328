//! Static condensation of the Q2/Q1 centre nodes changes the linear system, not the Newton step:
//! the direction and the load rate computed on the condensed system equal the solutions of the
//! full free–free system, whose matrix is built here independently, by central differences of
//! the residual.

use activemuscle::fem::assembly::Assembler;
use activemuscle::fem::dofs::DofMap;
use activemuscle::fem::ldlt::SymmetricPartLdlt;
use activemuscle::fem::problem::MixedProblem;
use activemuscle::fem::tangent_solver::TangentSolver;
use activemuscle::fem::{Bases, Mesh, NonlinearSystem};
use nalgebra::{DMatrix, DVector};

use crate::common;
use common::NonSymmetric;

/// The residual on the free dofs at `x`.
fn residual(problem: &mut MixedProblem<'_, NonSymmetric>, x: &[f64]) -> DVector<f64> {
    problem.evaluate(x, false).unwrap();
    DVector::from_column_slice(&problem.asm.residual[..problem.free()])
}

/// The material of both tests: non-symmetric tangent.
const MATERIAL: NonSymmetric = NonSymmetric {
    mu: 10.0,
    c: 1.5,
    approximate: false,
};

/// The problem on a clamped 2 × 3 Q2/Q1 mesh (centre nodes condensed); `symmetric`: whether
/// the tangent solver may start on the LDLᵀ (otherwise the pattern LU, as the frozen sweeps).
fn small_problem(symmetric: bool) -> MixedProblem<'static, NonSymmetric> {
    let mesh = Mesh::structured(1.0, 2.0, 2, 3, 1.0).unwrap();
    let dofs = DofMap::new(&mesh, Bases::Clamped);
    let asm = Assembler::new(&mesh, &dofs).unwrap();
    let ldlt = SymmetricPartLdlt::for_mesh(&asm.pattern, &mesh, &dofs, asm.system_index()).unwrap();
    let linear = TangentSolver::new(asm.pattern.n, Some(ldlt), symmetric, 1);
    MixedProblem::new(mesh, dofs, asm, linear, &MATERIAL, 1e-6)
}

/// A state off equilibrium: λ with a smooth perturbation of every free dof.
fn off_equilibrium(problem: &MixedProblem<'_, NonSymmetric>, lambda: f64) -> Vec<f64> {
    let mut x: Vec<f64> = (0..problem.unknowns())
        .map(|i| 0.01 * ((i as f64) * 0.7).sin())
        .collect();
    problem.apply_load(&mut x, lambda);
    x
}

#[test]
fn the_condensed_newton_step_and_load_rate_solve_the_full_system() {
    let mut problem = small_problem(true);
    let cells = problem.mesh.n_elements();
    assert!(problem.asm.is_condensed());
    assert_eq!(problem.asm.pattern.n, problem.dofs.n_free - 2 * cells);
    let (n, nf) = (problem.unknowns(), problem.free());
    let lambda = 1.1;
    let x = off_equilibrium(&problem, lambda);
    // The full free–free tangent and ∂R_f/∂λ by central differences.
    let h = 1e-6;
    let k = tangent_by_differences(&mut problem, &x);
    let (mut plus, mut minus) = (x.clone(), x.clone());
    problem.apply_load(&mut plus, lambda + h);
    problem.apply_load(&mut minus, lambda - h);
    let dr_dlambda = (residual(&mut problem, &plus) - residual(&mut problem, &minus)) / (2.0 * h);
    let lu = k.lu();
    // Newton direction: K dx = −R.
    let r = residual(&mut problem, &x);
    let expected = lu.solve(&(-&r)).unwrap();
    problem.evaluate(&x, true).unwrap();
    let mut dx = vec![0.0; nf];
    problem.newton_direction(&mut dx, true).unwrap();
    let error = (DVector::from_column_slice(&dx) - &expected).amax() / expected.amax();
    println!("Newton direction: relative difference {error:.2e}");
    assert!(error < 1e-7, "{error}");
    // Load rate: K v_f = −∂R_f/∂λ.
    let expected = lu.solve(&(-dr_dlambda)).unwrap();
    let mut rate = vec![0.0; n];
    problem.load_rate(&mut rate).unwrap();
    let error = (DVector::from_column_slice(&rate[..nf]) - &expected).amax() / expected.amax();
    println!("load rate: relative difference {error:.2e}");
    assert!(error < 1e-7, "{error}");
}

/// The free–free tangent at `x` by central differences of the residual.
fn tangent_by_differences(problem: &mut MixedProblem<'_, NonSymmetric>, x: &[f64]) -> DMatrix<f64> {
    let (h, nf) = (1e-6, problem.free());
    let mut k = DMatrix::<f64>::zeros(nf, nf);
    for j in 0..nf {
        let (mut plus, mut minus) = (x.to_vec(), x.to_vec());
        plus[j] += h;
        minus[j] -= h;
        let column = (residual(problem, &plus) - residual(problem, &minus)) / (2.0 * h);
        k.set_column(j, &column);
    }
    k
}

/// A Newton direction solved without refactorising (the pattern LU of an earlier iterate's
/// tangent preconditions GMRES on the current one) is the current tangent's: it equals the
/// solution of the tangent built by differences at the new state, and the direction after a
/// fresh factorisation, and no factorisation was made for it.
#[test]
fn a_newton_direction_on_an_earlier_factorisation_solves_the_current_tangent() {
    // Non-symmetric: the pattern LU from the start, as in the frozen sweeps.
    let mut problem = small_problem(false);
    let nf = problem.free();
    let mut x = off_equilibrium(&problem, 1.1);
    problem.evaluate(&x, true).unwrap();
    let mut dx = vec![0.0; nf];
    problem.newton_direction(&mut dx, true).unwrap();
    // A later iterate, a hundredth of the step away (as near convergence): its tangent
    // differs from the factorised one.
    for (xi, d) in x.iter_mut().zip(&dx) {
        *xi += 0.01 * d;
    }
    let expected = tangent_by_differences(&mut problem, &x)
        .lu()
        .solve(&(-residual(&mut problem, &x)))
        .unwrap();
    problem.evaluate(&x, true).unwrap();
    let factorisations = problem.timings.factorisations;
    let krylov = problem.timings.krylov_iterations;
    problem.newton_direction(&mut dx, false).unwrap();
    assert_eq!(problem.timings.factorisations, factorisations);
    let iterations = problem.timings.krylov_iterations - krylov;
    let reused = DVector::from_column_slice(&dx);
    let error = (&reused - &expected).amax() / expected.amax();
    println!("on the earlier factorisation: {iterations} Krylov iterations, relative difference to the differences' solve {error:.2e}");
    assert!(error < 1e-7, "{error}");
    // More than the one iteration of a fresh factorisation: the earlier one is not this tangent's.
    assert!(iterations > 1, "{iterations}");
    problem.newton_direction(&mut dx, true).unwrap();
    let fresh = DVector::from_column_slice(&dx);
    let error = (&reused - &fresh).amax() / fresh.amax();
    println!("against a fresh factorisation: relative difference {error:.2e}");
    assert!(error < 1e-10, "{error}");
}
