//! Errors of the library: what failed, with which value, and why.

use thiserror::Error;

/// Every fallible operation of the library returns this error.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum Error {
    /// A model parameter is outside its admissible range.
    #[error("parameter {name} = {} is invalid: {rule}", crate::text::shortest(*.value))]
    InvalidParameter {
        /// Parameter name as written in the docs (e.g. `mu`, `w0`).
        name: &'static str,
        /// The offending value.
        value: f64,
        /// The rule it breaks (e.g. "must be > 0").
        rule: &'static str,
    },
    /// The deformation gradient does not describe an admissible deformation.
    #[error("deformation gradient has det F = {} (must be > 0); F = {f:?}", crate::text::shortest(*.det))]
    NonPositiveJacobian {
        /// det F.
        det: f64,
        /// The offending F, row by row.
        f: [[f64; 3]; 3],
    },
    /// The activation variable left its range: γ ∉ [0, 1) (active strain) or ω < 0
    /// (structural).
    #[error("activation gamma = {} is outside its range ([0, 1) for active strain, [0, inf) for the structural omega)", crate::text::shortest(*.gamma))]
    ActivationOutOfRange {
        /// The offending γ (or ω).
        gamma: f64,
    },
    /// A number that must be finite was not.
    #[error("non-finite {quantity} ({value}) {context}")]
    NonFinite {
        /// What was computed (e.g. "strain energy").
        quantity: &'static str,
        /// The value (inf or NaN).
        value: f64,
        /// Where it came from, with the state that produced it.
        context: String,
    },
    /// A scalar equation had no root where one was required.
    #[error("no solution of {equation}: {reason}")]
    NoSolution {
        /// Which equation (e.g. "implicit activation law at lambda = 0.8").
        equation: String,
        /// Why not.
        reason: String,
    },
    /// A muscle was given an activation map other than the one its activation law is solved
    /// with.
    #[error("the {law} law is solved with the {law_map} activation map; the muscle asks for the {map} map")]
    MapMismatch {
        /// The law's name.
        law: &'static str,
        /// The map the law is solved with.
        law_map: &'static str,
        /// The map asked for.
        map: &'static str,
    },
    /// A formula energy that cannot be used with these parameter values (one outside its range,
    /// or the formula fails its checks at F = I with them).
    #[error("formula energy: {0}")]
    Formula(crate::energy::FormulaError),
    /// A combination of model choices that is not defined, and why.
    #[error("{reason}")]
    Unsupported {
        /// Why (which choice, and what would work).
        reason: String,
    },
}

/// Result alias of the library.
pub type Result<T> = std::result::Result<T, Error>;

/// Returns `value` if finite, otherwise a [`Error::NonFinite`] naming `quantity` and `context`.
pub fn finite(value: f64, quantity: &'static str, context: impl FnOnce() -> String) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::NonFinite {
            quantity,
            value,
            context: context(),
        })
    }
}
