//! The user's choice of how the Newton system K Δx = −R is solved ([`LinearSolver`]), a leaf:
//! the solver's options name it, [`super::tangent_solver`] carries it out and
//! [`super::memory`] prices its factors.

/// How the Newton system K Δx = −R is solved. Both give the exact Newton direction (to round-off).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinearSolver {
    /// GMRES on K preconditioned by LDLᵀ of (K + Kᵀ)/2 (fast; for a symmetric K one iteration),
    /// then by the LU on the LDLᵀ's pattern when GMRES does not converge, faer's LU as last
    /// resort; a tangent known to be non-symmetric, and on two or more threads any tangent of at
    /// least 4 000 unknowns, starts on the LU on the LDLᵀ's pattern (see
    /// [`super::tangent_solver`]).
    SymmetricPartGmres,
    /// faer's sparse LU with partial pivoting (COLAMD ordering) only.
    Lu,
}
