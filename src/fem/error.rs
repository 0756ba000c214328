//! Errors of the finite-element solver: what failed, at which stretch, and why.

use crate::text::significant;
use thiserror::Error;

/// Why one Newton solve (one load step) was rejected. A rejected step is cut, never a crash;
/// when cutting cannot help any more, the last cause is reported in [`FemError::TargetNotReached`].
#[derive(Debug, Clone, Error, PartialEq)]
pub enum StepFailure {
    /// The material refused a trial state (non-finite response, det F ≤ 0, γ out of range, …).
    #[error("material error at a trial state: {0}")]
    Material(crate::Error),
    /// Newton did not meet both convergence criteria within the allowed iterations.
    #[error(
        "no convergence in {iterations} Newton iterations: scaled residual {residual:.3e} and \
         scaled increment {increment:.3e}, both must reach the tolerance"
    )]
    MaxIterations {
        /// Iterations performed.
        iterations: usize,
        /// Last scaled residual norm.
        residual: f64,
        /// Last scaled increment norm.
        increment: f64,
    },
    /// The backtracking line search found no step length that decreases the residual.
    #[error(
        "line search failed: no decrease of the scaled residual {residual:.3e} along the Newton \
         direction (a residual at its round-off floor, or a poor direction)"
    )]
    LineSearch {
        /// Scaled residual at the start of the search.
        residual: f64,
    },
    /// The LU factorisation of the tangent failed or produced non-finite numbers.
    #[error("singular tangent: {detail}")]
    SingularTangent {
        /// What the linear solver reported.
        detail: String,
    },
    /// The sweep was cancelled ([`super::SolverOptions::cancel`]) during this step.
    #[error("cancelled")]
    Cancelled,
}

/// Every fallible operation of the FE solver returns this error.
#[derive(Debug, Error)]
pub enum FemError {
    /// An input (mesh size, geometry, stretch, option) is outside its admissible range.
    #[error("invalid input {name} = {value}: {rule}")]
    InvalidInput {
        /// Name of the input as in the API.
        name: &'static str,
        /// The offending value, printed.
        value: String,
        /// The rule it breaks.
        rule: &'static str,
    },
    /// A constitutive-core error outside the Newton loop (e.g. while writing output fields).
    #[error(transparent)]
    Material(#[from] crate::Error),
    /// The sparse linear solver failed outside a Newton step (symbolic analysis, allocation).
    #[error("linear solver: {0}")]
    LinearSolver(String),
    /// A target stretch could not be reached even with the smallest allowed load step.
    #[error(
        "target stretch {} not reached: largest converged stretch {}; \
         last attempted stretch {} with step {step:.3e} failed: {cause}",
        significant(*target, 10), significant(*reached, 10), significant(*attempted, 10)
    )]
    TargetNotReached {
        /// The requested stretch.
        target: f64,
        /// The largest (in the direction of loading) stretch at which Newton converged.
        reached: f64,
        /// The stretch of the last rejected trial step.
        attempted: f64,
        /// The load-step size |Δλ| of that trial; half of it is below the minimum step.
        step: f64,
        /// Why that last trial was rejected.
        cause: StepFailure,
    },
    /// A direction of the sweep used up its load steps ([`super::Stepping::max_steps`]).
    #[error(
        "target stretch {} not reached: largest converged stretch {} after \
         {steps} load steps (the limit, SolverOptions::stepping.max_steps)",
        significant(*target, 10), significant(*reached, 10)
    )]
    StepLimit {
        /// The requested stretch.
        target: f64,
        /// The last stretch solved.
        reached: f64,
        /// Load steps taken in this direction.
        steps: usize,
    },
    /// The sweep was cancelled ([`super::SolverOptions::cancel`]); the stretches solved before
    /// are kept in [`super::Sweep::results`].
    #[error("sweep cancelled on the way to stretch {}", crate::text::shortest(*.target))]
    Cancelled {
        /// The target being solved for when the sweep stopped.
        target: f64,
    },
    /// The estimated memory of the solve exceeds the limit; nothing large was allocated.
    #[error(
        "the solve on {mesh} ({dofs:.0} dofs) needs an estimated {} of memory, above the limit of {} \
         (SolverOptions::memory_limit; by default half the available memory): use a coarser mesh",
        bytes(*estimate),
        bytes(*limit as f64)
    )]
    MemoryLimit {
        /// The mesh, in words.
        mesh: String,
        /// Its free dofs (estimate).
        dofs: f64,
        /// The memory estimate \[bytes\].
        estimate: f64,
        /// The limit \[bytes\].
        limit: u64,
    },
    /// The reference state λ = 1 (the pressure balancing the stress at F = I) was not found.
    #[error("reference state λ = 1 not found: {cause}")]
    ReferenceState {
        /// Why Newton failed there.
        cause: StepFailure,
    },
    /// Writing output files failed.
    #[error("I/O error writing {path}: {source}")]
    Io {
        /// The file being written.
        path: String,
        /// The underlying error.
        source: std::io::Error,
    },
}

/// A byte count in MiB or GiB.
fn bytes(b: f64) -> String {
    const MIB: f64 = 1024.0 * 1024.0;
    if b >= 1024.0 * MIB {
        format!("{:.1} GiB", b / (1024.0 * MIB))
    } else {
        format!("{:.1} MiB", b / MIB)
    }
}

/// Result alias of the FE solver.
pub type FemResult<T> = std::result::Result<T, FemError>;
