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
    #[error("{source_name}{}: {message}", if *line > 0 { format!(", line {line}") } else { String::new() })]
    Csv {
        /// File name or `"<reader>"`.
        source_name: String,
        /// 1-based line in the file (the header is line 1); 0: the file as a whole (it cannot
        /// be opened), and the message names no line.
        line: u64,
        /// What is wrong.
        message: String,
    },
    /// A number of the data is NaN or infinite.
    #[error("{location}: {column} = {} is not a finite number", crate::text::shortest(*.value))]
    NonFiniteData {
        /// "line n" (from a CSV file) or "point i" (data built in memory, 1-based).
        location: String,
        /// `lambda` or `P`.
        column: &'static str,
        /// The value.
        value: f64,
    },
    /// A stretch is zero or negative.
    #[error("{location}: lambda = {} must be > 0", crate::text::shortest(*.lambda))]
    NonPositiveStretch {
        /// Where.
        location: String,
        /// The offending stretch.
        lambda: f64,
    },
    /// The same stretch appears twice.
    #[error("{location}: lambda = {} repeats the previous point", crate::text::shortest(*.lambda))]
    DuplicateStretch {
        /// Where.
        location: String,
        /// The repeated stretch.
        lambda: f64,
    },
    /// Stretches must be strictly increasing.
    #[error("{location}: lambda = {} is below the previous lambda = {} (stretches must increase)", crate::text::shortest(*.lambda), crate::text::shortest(*.previous))]
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
        available: Vec<String>,
    },
    /// Nothing to fit.
    #[error("no free parameter selected")]
    NoFreeParameter,
    /// Data of another test than the fit takes (biaxial rows given to an active-curve fit).
    #[error("a {fit} fit takes {takes} data, not {given}")]
    WrongTest {
        /// The fit.
        fit: &'static str,
        /// The data it takes.
        takes: &'static str,
        /// The data it was given.
        given: &'static str,
    },
    /// A starting value outside its bounds, or bounds with lower ≥ upper.
    #[error("parameter {name}: start {} is not inside the bounds [{}, {}]", crate::text::shortest(*.start), crate::text::shortest(*.lower), crate::text::shortest(*.upper))]
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
    #[error("fit did not converge: {reason}; the Gauss-Newton step at the best point is {}; best point found: {} (residual norm {:.6e})", step_text(&best.names, step), list(&best.names, &best.values), best.residual_norm)]
    NotConverged {
        /// Why the search stopped short of a solution.
        reason: NotConverged,
        /// The Gauss–Newton step δ at the best point (not negligible, see [`super::solver`]);
        /// empty if the Jacobian cannot be computed there.
        step: Vec<f64>,
        /// The best point found, with its statistics.
        best: Box<FitReport>,
    },
    /// The scales σ of weighted residuals: one per residual, each finite and > 0.
    #[error("{}", scales_text(*.given, *.residuals, *.index, *.value))]
    BadScales {
        /// Scales given.
        given: usize,
        /// Residuals of the fit.
        residuals: usize,
        /// The first bad one (1-based; 0: the count is wrong).
        index: usize,
        /// Its value.
        value: f64,
    },
    /// A standard deviation of the data (`sigma` column) that is not > 0.
    #[error("{location}: sigma = {} must be finite and > 0 (a standard deviation)", crate::text::shortest(*.sigma))]
    NonPositiveSigma {
        /// Where.
        location: String,
        /// The value.
        sigma: f64,
    },
    /// A data file larger than a fit reads.
    #[error(
        "{source_name}: {what} (a fit reads at most {} bytes and {} points)",
        limits.0,
        limits.1
    )]
    DataTooLarge {
        /// File name or `"<reader>"`.
        source_name: String,
        /// What exceeded the limit.
        what: String,
        /// The limits: bytes and points a fit reads at most.
        limits: (u64, usize),
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

/// Why a least-squares search stopped short of a solution (see [`super::solver`]).
#[derive(Debug, Clone, PartialEq)]
pub enum NotConverged {
    /// The iteration cap was reached before the Gauss–Newton step became negligible.
    IterationCap {
        /// The cap (Levenberg–Marquardt iterations).
        iterations: u64,
    },
    /// No step from θ = `at` lowered the cost: `tries` ever more damped (shorter) steps were
    /// tried; `infeasible` of them left the bounds or could not be evaluated.
    NoDecrease {
        /// Where the search stopped.
        at: Vec<f64>,
        /// Steps tried.
        tries: u32,
        /// Of which outside the bounds or not computable (exp overflow, invalid parameters).
        infeasible: u32,
    },
    /// Every trial step from θ = `at` gave a non-finite cost or left the bounds, down to the
    /// shortest one tried, at θ = `last`.
    NonFiniteCost {
        /// Where the search stopped.
        at: Vec<f64>,
        /// The last (shortest) trial point.
        last: Vec<f64>,
        /// Steps tried.
        tries: u32,
    },
    /// The Jacobian at θ = `at` could not be computed or is not finite.
    Jacobian {
        /// Where.
        at: Vec<f64>,
        /// Why.
        reason: String,
    },
    /// The search stalled against a bound: no step within the bounds lowers the cost, and the
    /// Gauss–Newton step from the best point takes parameter `name` from `value` to `target`,
    /// past `bound` (the least-squares minimum lies beyond it).
    BeyondBound {
        /// Parameter name.
        name: String,
        /// Its value at the best point.
        value: f64,
        /// Where the Gauss–Newton step takes it.
        target: f64,
        /// The bound it crosses.
        bound: f64,
    },
    /// The search machinery itself failed (argmin reported an error).
    Solver {
        /// The message.
        message: String,
    },
}

impl std::fmt::Display for NotConverged {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NotConverged::IterationCap { iterations } => {
                write!(f, "iteration cap of {iterations} reached")
            }
            NotConverged::NoDecrease {
                at,
                tries,
                infeasible,
            } => write!(
                f,
                "no step from theta = {} lowers the cost ({tries} ever shorter steps tried, {infeasible} of them outside the bounds or not computable)",
                vector(at)
            ),
            NotConverged::NonFiniteCost { at, last, tries } => write!(
                f,
                "non-finite cost at every trial point from theta = {} ({tries} ever shorter steps, the last at theta = {}): the model overflows or leaves its bounds there",
                vector(at),
                vector(last)
            ),
            NotConverged::Jacobian { at, reason } => {
                write!(
                    f,
                    "the Jacobian at theta = {} cannot be computed: {reason}",
                    vector(at)
                )
            }
            NotConverged::BeyondBound {
                name,
                value,
                target,
                bound,
            } => write!(
                f,
                "the least-squares minimum lies beyond the bounds: the Gauss-Newton step takes {name} from {} to {}, past the bound {}",
                number(*value),
                number(*target),
                number(*bound)
            ),
            NotConverged::Solver { message } => write!(f, "the solver failed: {message}"),
        }
    }
}

/// Why scales σ of weighted residuals are refused.
fn scales_text(given: usize, residuals: usize, index: usize, value: f64) -> String {
    if index == 0 {
        format!("{given} scales σ for {residuals} residuals: weights need one per residual")
    } else {
        format!(
            "weights divide residual {index} by σ = {}, which must be finite and > 0 (relative weights divide by the datum itself: leave out a point where it is 0, or give the data a sigma column)",
            crate::text::shortest(value)
        )
    }
}

/// `a = 1, b = 2` from names and values.
fn list(names: &[String], values: &[f64]) -> String {
    names
        .iter()
        .zip(values)
        .map(|(n, v)| format!("{n} = {}", number(*v)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The Gauss–Newton step in words.
fn step_text(names: &[String], step: &[f64]) -> String {
    if step.is_empty() {
        "not computable".into()
    } else {
        format!("still {}", list(names, step))
    }
}

/// x in plain notation for 1e-4 ≤ |x| < 1e7 (and 0), else in scientific notation.
fn number(x: f64) -> String {
    if x == 0.0 || (1e-4..1e7).contains(&x.abs()) {
        x.to_string()
    } else {
        format!("{x:e}")
    }
}

/// `[a, b]` with [`number`].
fn vector(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|&x| number(x)).collect();
    format!("[{}]", items.join(", "))
}
