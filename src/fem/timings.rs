//! The time the solver spends per phase (assembly, factorisation, solve) and the counts behind
//! it, accumulated over a sweep: what [`super::problem`] and [`super::tangent_solver`] record and
//! [`super::solver::AxisymmetricSolver::timings`] reports.

use std::time::Duration;

/// Accumulated wall-clock time of the solver phases.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Timings {
    /// Full assemblies (residual + tangent).
    pub assembly: Duration,
    /// Number of full assemblies.
    pub assemblies: usize,
    /// Residual-only assemblies (line search).
    pub residual_assembly: Duration,
    /// Number of residual-only assemblies.
    pub residual_assemblies: usize,
    /// Newton iterations (each: one full assembly, one solve, and one factorisation unless an
    /// earlier one serves).
    pub newton_iterations: usize,
    /// Numeric factorisations (LDLᵀ or LU).
    pub factorisation: Duration,
    /// Number of factorisations.
    pub factorisations: usize,
    /// Linear solves (GMRES and triangular solves, factorisations excluded).
    pub solve: Duration,
    /// Number of solves.
    pub solves: usize,
    /// GMRES iterations in all solves.
    pub krylov_iterations: usize,
    /// Solves that fell back to the sparse LU.
    pub lu_fallbacks: usize,
    /// Solves for a later tangent (the rate at a converged state, a Newton iteration near
    /// convergence) on which GMRES with the held factorisation, of an earlier tangent, did not
    /// converge: that tangent was factorised.
    pub refactorisations: usize,
    /// Newton iterations solved without a factorisation of their own: GMRES on the tangent,
    /// preconditioned by the factorisation of an earlier iterate of the load step.
    pub earlier_factorisations: usize,
    /// Factorisations by the LU on the LDLᵀ's pattern (non-symmetric tangents).
    pub pattern_lu_factorisations: usize,
}

impl Timings {
    /// Wall-clock seconds per Newton iteration: all assemblies, factorisations and solves
    /// divided by the Newton iterations.
    pub fn per_newton_iteration(&self) -> f64 {
        let total = self.assembly + self.residual_assembly + self.factorisation + self.solve;
        total.as_secs_f64() / self.newton_iterations.max(1) as f64
    }
}
