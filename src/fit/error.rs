//! Errors of the fitting module: unusable data, impossible requests, fits that do not converge.

use super::FitReport;
use thiserror::Error;

/// Everything a fit can refuse or fail with.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum FitError {
    /// An error of the constitutive library (e.g. an invalid fitted parameter set).
    #[error(transparent)]
    Model(#[from] crate::Error),
    /// The CSV file could not be read or parsed (I/O, missing header, text where a number belongs).
    #[error("{source_name}, line {line}: {message}")]
    Csv {
        /// File name or `"<reader>"`.
        source_name: String,
        /// 1-based line in the file (the header is line 1).
        line: u64,
        /// What is wrong.
        message: String,
    },
    /// A number of the data is NaN or infinite.
    #[error("{location}: {column} = {value} is not a finite number")]
    NonFiniteData {
        /// "line n" (from a CSV file) or "point i" (data built in memory, 1-based).
        location: String,
        /// `lambda` or `P`.
        column: &'static str,
        /// The value.
        value: f64,
    },
    /// A stretch is zero or negative.
    #[error("{location}: lambda = {lambda} must be > 0")]
    NonPositiveStretch {
        /// Where.
        location: String,
        /// The offending stretch.
        lambda: f64,
    },
    /// The same stretch appears twice.
    #[error("{location}: lambda = {lambda} repeats the previous point")]
    DuplicateStretch {
        /// Where.
        location: String,
        /// The repeated stretch.
        lambda: f64,
    },
    /// Stretches must be strictly increasing.
    #[error("{location}: lambda = {lambda} is below the previous lambda = {previous} (stretches must increase)")]
    DecreasingStretch {
        /// Where.
        location: String,
        /// The offending stretch.
        lambda: f64,
        /// The stretch before it.
        previous: f64,
    },
    /// The columns have different lengths (data built in memory).
    #[error("{stretches} stretches but {stresses} stresses")]
    LengthMismatch {
        /// Number of λ.
        stretches: usize,
        /// Number of P.
        stresses: usize,
    },
    /// Not enough points: standard errors need more points than free parameters.
    #[error("{points} data points for {parameters} free parameters: need at least {} points", parameters + 1)]
    TooFewPoints {
        /// Points given.
        points: usize,
        /// Free parameters.
        parameters: usize,
    },
    /// A parameter name that the model does not have, or a parameter freed twice.
    #[error("unknown or repeated parameter {name:?}; the model has {available:?}")]
    UnknownParameter {
        /// The name asked for.
        name: String,
        /// The model's parameter names.
        available: Vec<&'static str>,
    },
    /// Nothing to fit.
    #[error("no free parameter selected")]
    NoFreeParameter,
    /// A starting value outside its bounds, or bounds with lower ≥ upper.
    #[error("parameter {name}: start {start} is not inside the bounds [{lower}, {upper}]")]
    StartOutOfBounds {
        /// Parameter name.
        name: String,
        /// Starting value.
        start: f64,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },
    /// The model cannot be evaluated at the starting point (e.g. exp overflow).
    #[error("the model cannot be evaluated at the starting point {start:?}: {reason}")]
    BadStart {
        /// The starting values of the free parameters.
        start: Vec<f64>,
        /// Why.
        reason: String,
    },
    /// JᵀJ is singular at the solution: the data cannot tell the free parameters apart.
    #[error("the free parameters {names:?} are not identifiable from these data (JᵀJ is singular at {values:?})")]
    Unidentifiable {
        /// Names of the free parameters.
        names: Vec<String>,
        /// Where.
        values: Vec<f64>,
    },
    /// The fit did not converge. `best` holds the best point found (its `converged` is false):
    /// it is not a solution.
    #[error("fit did not converge ({reason}); best point found: {:?} = {:?}, residual norm {}", best.names, best.values, best.residual_norm)]
    NotConverged {
        /// Why (solver termination, size of the remaining Gauss–Newton step).
        reason: String,
        /// The best point found, with its statistics.
        best: Box<FitReport>,
    },
    /// Writing a plot failed.
    #[error("plot {path}: {message}")]
    Plot {
        /// File being written.
        path: String,
        /// What went wrong.
        message: String,
    },
}
