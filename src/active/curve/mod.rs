//! Active force–stretch curves P_act(λ) \[kPa\]: the active nominal stress of a tetanised muscle
//! along its fibres, which every activation law reproduces (scaled, see
//! [`crate::active::drive`]).
//!
//! | curve (`curve = "..."`) | P_act(λ) for λ > λ_min (0 at and below) | ∫_{λ_min}^{λ} P_act |
//! |---|---|---|
//! | `chapter` ([`ChapterCurve`], the default) | P_opt exp[−k (λ² − λ_opt²)²/(λ − λ_min)] (eq. (8)) | Gauss–Legendre quadrature |
//! | `ehret-bol-itskov` ([`EhretBolItskovCurve`]) | P_opt (λ − λ_min)/(λ_opt − λ_min) exp[(2λ_min − λ − λ_opt)(λ − λ_opt)/(2(λ_min − λ_opt)²)] | P_opt (λ_min − λ_opt)(exp[…] − e^{1/2}) |
//!
//! A curve is one generic function of λ ([`ShippedCurve::value`]): dual numbers give its
//! derivatives. It also carries the lower end of its support λ_min (it vanishes at and below
//! it), its parameter table (names, units, defaults, the default bounds of a fit) and, where one
//! exists, its integral in closed form; otherwise the integral is [`quadrature`]. A new curve is
//! its file in this directory (`impl ShippedCurve`) and one line in `shipped_curves!` below: the
//! laws, the fits, scene files, `check`, the report and Python take it from [`CURVES`].

use crate::parameter::{Parameter, ScalarWith};
use crate::{Error, Result, Scalar};

/// A shipped active curve: its name, parameter table and formula.
pub trait ShippedCurve: Copy + PartialEq + std::fmt::Debug + Sized {
    /// Name in scene files and outputs (`chapter`).
    const NAME: &'static str;
    /// The formula for λ > λ_min, as the report prints it.
    const FORMULA: &'static str;
    /// Where it comes from (`the chapter's eq. (8)`).
    const SOURCE: &'static str;
    /// The parameters, in the order of [`values`](Self::values).
    const PARAMETERS: &'static [Parameter];
    /// The parameter values.
    fn values(&self) -> Vec<f64>;
    /// The curve with these parameter values, validated.
    fn from_values(values: &[f64]) -> Result<Self>;
    /// λ_min [-]: the lower end of the support; P_act = 0 for λ ≤ λ_min.
    fn lambda_min(&self) -> f64;
    /// A stretch past which the curve decreases for good (its peak): the quadrature stops
    /// there once a panel adds exactly 0.
    fn peak(&self) -> f64;
    /// P_act(λ) \[kPa\], 0 at and below λ_min (the test is on the real part, so f64 and dual
    /// numbers take the same branch).
    fn value<T: Scalar>(&self, lambda: T) -> T;
    /// P_act(λ) with the parameters given as scalars, in the order of
    /// [`PARAMETERS`](Self::PARAMETERS) (dual numbers differentiate in them, for fitting).
    fn value_of<P: Scalar, T: ScalarWith<P>>(parameters: &[P], lambda: T) -> T;
    /// ∫_{λ_min}^{λ} P_act \[kPa\] in closed form, where one exists (`None`: [`quadrature`]).
    fn closed_integral(&self, _lambda: f64) -> Option<f64> {
        None
    }
}

/// Checks that every value is finite and > 0 (each value named by its parameter).
pub(crate) fn check_positive(parameters: &'static [Parameter], values: &[f64]) -> Result<()> {
    for (p, &v) in parameters.iter().zip(values) {
        crate::parameter::positive(p.name.as_ref(), v)?;
    }
    Ok(())
}

/// Checks λ_opt > λ_min.
pub(crate) fn check_order(lambda_min: f64, lambda_opt: f64) -> Result<()> {
    if lambda_opt > lambda_min {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name: "lambda_opt",
            value: lambda_opt,
            rule: "must be > lambda_min",
        })
    }
}

/// 16-point Gauss–Legendre nodes (positive half) and weights on [−1, 1].
const GAUSS_16: [(f64, f64); 8] = [
    (0.095_012_509_837_637_44, 0.189_450_610_455_068_5),
    (0.281_603_550_779_258_9, 0.182_603_415_044_923_6),
    (0.458_016_777_657_227_4, 0.169_156_519_395_002_5),
    (0.617_876_244_402_643_7, 0.149_595_988_816_576_7),
    (0.755_404_408_355_003, 0.124_628_971_255_533_9),
    (0.865_631_202_387_831_7, 0.095_158_511_682_492_78),
    (0.944_575_023_073_232_6, 0.062_253_523_938_647_89),
    (0.989_400_934_991_649_9, 0.027_152_459_411_754_09),
];

/// ∫_{λ_min}^{λ} f(s) ds (0 for λ ≤ λ_min) by composite 16-point Gauss–Legendre on equal panels
/// of width ≤ 0.1, the first of which (where the chapter's integrand is flat to all orders,
/// e^{−c/(s − λ_min)}) is split into its quarters [0, ¼], [¼, ½] and [½, 1]. For the chapter's
/// curve, measured against 1 200 panels: ≤ 6e-16 kPa below λ = 0.75 (equal panels of 0.05
/// without the split: 4e-15, which the energy law turned into a γ error of ≈ 1e-14 near
/// λ = 0.67), rounding (≈ 1e-16 relative) above. Past `peak` a curve decreases for good, so
/// once a panel there adds exactly 0 (the integrand underflowed) so do all later ones and the
/// sum stops: at most min(λ, λ₀)/0.1 + 3 panels whatever λ (λ₀ ≈ 12.6 for the chapter's curve).
pub fn quadrature(f: impl Fn(f64) -> f64, lambda_min: f64, peak: f64, lambda: f64) -> f64 {
    if lambda <= lambda_min {
        return 0.0;
    }
    let width = lambda - lambda_min;
    let panels = (width / 0.1).ceil().max(1.0) as usize;
    let h = width / panels as f64;
    let panel = |a: f64, b: f64| {
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        let sum: f64 = GAUSS_16
            .iter()
            .map(|&(x, w)| w * (f(mid - half * x) + f(mid + half * x)))
            .sum();
        sum * half
    };
    let first = [0.0, 0.25, 0.5, 1.0].map(|t| lambda_min + t * h);
    let mut sum: f64 = first.windows(2).map(|w| panel(w[0], w[1])).sum();
    for p in 1..panels {
        let (a, b) = (lambda_min + p as f64 * h, lambda_min + (p + 1) as f64 * h);
        let added = panel(a, b);
        if added == 0.0 && a > peak {
            break;
        }
        sum += added;
    }
    sum
}

/// One entry of [`CURVES`]: a shipped curve's name, parameters and constructor.
#[derive(Debug, Clone, Copy)]
pub struct CurveEntry {
    /// Name in scene files (`curve = "..."`).
    pub name: &'static str,
    /// Its parameters.
    pub parameters: &'static [Parameter],
    /// Its formula (for λ > λ_min).
    pub formula: &'static str,
    build: fn(&[f64]) -> Result<ActiveCurve>,
}

impl CurveEntry {
    /// The shipped curve called `name`.
    pub fn find(name: &str) -> Option<&'static CurveEntry> {
        CURVES.iter().find(|c| c.name == name)
    }

    /// The curve with parameter `values`, one per parameter, in order; validated.
    pub fn build(&self, values: &[f64]) -> Result<ActiveCurve> {
        if values.len() != self.parameters.len() {
            return Err(Error::InvalidParameter {
                name: "parameters",
                value: values.len() as f64,
                rule: "give one value per parameter of the curve",
            });
        }
        (self.build)(values)
    }

    /// The curve with its default parameters, if every parameter has one.
    pub fn default_curve(&self) -> Option<ActiveCurve> {
        let values: Option<Vec<f64>> = self.parameters.iter().map(|p| p.default).collect();
        self.build(&values?).ok()
    }
}

/// The shipped curves: `shipped_curves! { file::Type, ... }` declares each curve's module
/// (`src/active/curve/file.rs`), re-exports its type and generates [`ActiveCurve`] (one variant
/// per type, named as the type), its methods and [`CURVES`].
macro_rules! shipped_curves {
    ($($(#[$doc:meta])* $file:ident::$curve:ident => $variant:ident),* $(,)?) => {
        $(mod $file;
        pub use $file::$curve;)*

        /// Any of the shipped active curves, chosen at run time (e.g. from a scene file).
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub enum ActiveCurve {
            $($(#[$doc])* $variant($curve),)*
        }

        impl ActiveCurve {
            /// Name in scene files and outputs.
            pub fn name(&self) -> &'static str {
                match self {
                    $(ActiveCurve::$variant(_) => $curve::NAME,)*
                }
            }
            /// The formula for λ > λ_min.
            pub fn formula(&self) -> &'static str {
                match self {
                    $(ActiveCurve::$variant(_) => $curve::FORMULA,)*
                }
            }
            /// Where the formula comes from.
            pub fn source(&self) -> &'static str {
                match self {
                    $(ActiveCurve::$variant(_) => $curve::SOURCE,)*
                }
            }
            /// The parameters, in order.
            pub fn parameters(&self) -> &'static [Parameter] {
                match self {
                    $(ActiveCurve::$variant(_) => $curve::PARAMETERS,)*
                }
            }
            /// Current parameter values, in the order of [`parameters`](Self::parameters).
            pub fn parameter_values(&self) -> Vec<f64> {
                match self {
                    $(ActiveCurve::$variant(c) => c.values(),)*
                }
            }
            /// The same curve with new parameter values, validated.
            pub fn rebuilt(&self, values: &[f64]) -> Result<Self> {
                Ok(match self {
                    $(ActiveCurve::$variant(_) => ActiveCurve::$variant($curve::from_values(values)?),)*
                })
            }
            /// λ_min [-]: the lower end of the support; P_act = 0 for λ ≤ λ_min.
            pub fn lambda_min(&self) -> f64 {
                match self {
                    $(ActiveCurve::$variant(c) => c.lambda_min(),)*
                }
            }
            /// The stretch of the curve's peak [-].
            pub fn peak(&self) -> f64 {
                match self {
                    $(ActiveCurve::$variant(c) => c.peak(),)*
                }
            }
            /// P_act(λ) \[kPa\], generic so that dual numbers give its derivatives (all 0 at
            /// and below λ_min).
            pub fn value<T: Scalar>(&self, lambda: T) -> T {
                match self {
                    $(ActiveCurve::$variant(c) => c.value(lambda),)*
                }
            }
            /// P_act(λ) with this curve's formula and the parameters given as scalars (in the
            /// order of [`parameters`](Self::parameters); dual numbers differentiate in them).
            pub fn value_with<P: Scalar, T: ScalarWith<P>>(&self, parameters: &[P], lambda: T) -> T {
                match self {
                    $(ActiveCurve::$variant(_) => $curve::value_of(parameters, lambda),)*
                }
            }
            /// ∫_{λ_min}^{λ} P_act(s) ds \[kPa\] (0 for λ ≤ λ_min): the closed form where the
            /// curve has one, else [`quadrature`].
            pub fn integral(&self, lambda: f64) -> f64 {
                if lambda <= self.lambda_min() {
                    return 0.0;
                }
                let closed = match self {
                    $(ActiveCurve::$variant(c) => c.closed_integral(lambda),)*
                };
                closed.unwrap_or_else(|| self.quadrature(lambda))
            }
            /// ∫_{λ_min}^{λ} P_act by [`quadrature`], whether or not a closed form exists.
            pub fn quadrature(&self, lambda: f64) -> f64 {
                quadrature(|s| self.value(s), self.lambda_min(), self.peak(), lambda)
            }
            /// Whether the integral has a closed form.
            pub fn has_closed_integral(&self) -> bool {
                match self {
                    $(ActiveCurve::$variant(c) => c.closed_integral(c.peak()).is_some(),)*
                }
            }
        }

        /// The shipped curves, in the order of [`ActiveCurve`]'s variants (the first is the
        /// chapter's, the default of scene files).
        pub const CURVES: &[CurveEntry] = &[$(CurveEntry {
            name: $curve::NAME,
            parameters: $curve::PARAMETERS,
            formula: $curve::FORMULA,
            build: |v| Ok(ActiveCurve::$variant($curve::from_values(v)?)),
        },)*];
    };
}

// A new shipped curve: its file in this directory (`impl ShippedCurve`) and one line here.
shipped_curves! {
    /// The chapter's eq. (8).
    chapter::ChapterCurve => Chapter,
    /// Ehret, Böl & Itskov (2011), as 4C.
    ehret_bol_itskov::EhretBolItskovCurve => EhretBolItskov,
}

impl ActiveCurve {
    /// The chapter's curve, Table D:paratt: λ_min = 0.6243, λ_opt = 1.1704, k = 0.4342,
    /// P_opt = 73.52 kPa.
    pub fn paper() -> Self {
        ActiveCurve::Chapter(ChapterCurve::PAPER)
    }

    /// The chapter's curve (eq. (8)) with λ_min [-] > 0, λ_opt [-] > λ_min, k [-] > 0,
    /// P_opt \[kPa\] > 0.
    pub fn chapter(lambda_min: f64, lambda_opt: f64, k: f64, p_opt: f64) -> Result<Self> {
        ChapterCurve::new(lambda_min, lambda_opt, k, p_opt).map(ActiveCurve::Chapter)
    }

    /// Ehret, Böl & Itskov's curve with λ_min [-] > 0, λ_opt [-] > λ_min, P_opt \[kPa\] > 0.
    pub fn ehret_bol_itskov(lambda_min: f64, lambda_opt: f64, p_opt: f64) -> Result<Self> {
        EhretBolItskovCurve::new(lambda_min, lambda_opt, p_opt).map(ActiveCurve::EhretBolItskov)
    }

    /// The value of the parameter called `name`, if the curve has one.
    pub fn parameter(&self, name: &str) -> Option<f64> {
        self.parameters()
            .iter()
            .zip(self.parameter_values())
            .find(|(p, _)| p.name == name)
            .map(|(_, v)| v)
    }
}
