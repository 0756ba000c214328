//! Named, validated model parameters, shared by the energies ([`crate::energy`]) and the active
//! curves ([`crate::active::curve`]): what a scene writes, a fit frees and a report prints, and
//! the scalar bound that lets a model's formula take its parameters as `f64` or as dual numbers.

use crate::{Error, Result, Scalar};

/// A scalar `T` that combines with model parameters of type `P` (`T op P -> T`): `P = f64` for
/// fixed parameters (the fast path every response takes, no zero derivatives carried) or
/// `P = T` for parameters carried as dual numbers (derivatives in the parameters, for fitting).
/// Lets each model write its formula once for both.
pub trait ScalarWith<P>:
    Scalar
    + std::ops::Add<P, Output = Self>
    + std::ops::Sub<P, Output = Self>
    + std::ops::Mul<P, Output = Self>
    + std::ops::Div<P, Output = Self>
{
}

impl<P, T> ScalarWith<P> for T where
    T: Scalar
        + std::ops::Add<P, Output = T>
        + std::ops::Sub<P, Output = T>
        + std::ops::Mul<P, Output = T>
        + std::ops::Div<P, Output = T>
{
}

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            rule: "must be finite and > 0",
        })
    }
}

/// Checks that `value` lies in the open interval (0, 1).
pub(crate) fn open_unit(name: &'static str, value: f64) -> Result<f64> {
    if value > 0.0 && value < 1.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name,
            value,
            rule: "must lie in (0, 1)",
        })
    }
}

/// A name, symbol or unit of a [`Parameter`]: borrowed for the shipped models (their tables are
/// constants), owned for a parameter declared at run time (a formula energy's, read from a scene).
pub type Text = std::borrow::Cow<'static, str>;

/// A named parameter of an energy: what a scene writes, a fit frees, a report prints.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    /// Name in scene files, fits and outputs (`mu`).
    pub name: Text,
    /// Symbol in the docs (`μ`).
    pub symbol: Text,
    /// Unit (`kPa`, or `-` for a dimensionless parameter).
    pub unit: Text,
    /// The chapter's value, used when a scene leaves the parameter out; `None`: it must be given.
    pub default: Option<f64>,
    /// Admissible range: the open interval (lower, upper) (infinite ends allowed; the
    /// constructor may admit a finite end, see each model).
    pub range: (f64, f64),
    /// The default bounds [lower, upper] of a fit: the range, or narrower.
    pub bounds: (f64, f64),
}

impl Parameter {
    /// A parameter with admissible range `range`, which is also the default bounds of a fit.
    pub const fn ranged(
        name: &'static str,
        symbol: &'static str,
        unit: &'static str,
        default: Option<f64>,
        range: (f64, f64),
    ) -> Self {
        Self {
            name: Text::Borrowed(name),
            symbol: Text::Borrowed(symbol),
            unit: Text::Borrowed(unit),
            default,
            range,
            bounds: range,
        }
    }

    /// A parameter declared at run time (a formula energy's): `name` [`unit`] with value
    /// `value`, admissible in the open interval `range`, which is also its fit bounds; its
    /// symbol is its name.
    pub fn declared(
        name: impl Into<String>,
        unit: impl Into<String>,
        value: f64,
        range: (f64, f64),
    ) -> Self {
        let name: String = name.into();
        Self {
            symbol: Text::Owned(name.clone()),
            name: Text::Owned(name),
            unit: Text::Owned(unit.into()),
            default: Some(value),
            range,
            bounds: range,
        }
    }

    /// The same parameter with the default bounds of a fit `bounds` (within the range).
    pub fn with_bounds(self, bounds: (f64, f64)) -> Self {
        Self { bounds, ..self }
    }

    /// The same parameter with symbol `symbol` (in reports and figures).
    pub fn with_symbol(self, symbol: impl Into<String>) -> Self {
        Self {
            symbol: Text::Owned(symbol.into()),
            ..self
        }
    }

    /// A parameter that must be > 0.
    pub const fn positive(
        name: &'static str,
        symbol: &'static str,
        unit: &'static str,
        default: Option<f64>,
    ) -> Self {
        Self::ranged(name, symbol, unit, default, (0.0, f64::INFINITY))
    }

    /// A dimensionless parameter in (0, 1).
    pub const fn fraction(name: &'static str, symbol: &'static str, default: Option<f64>) -> Self {
        Self::ranged(name, symbol, "-", default, (0.0, 1.0))
    }
}
