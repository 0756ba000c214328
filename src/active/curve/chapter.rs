use super::ShippedCurve;
use crate::parameter::{Parameter, ScalarWith};
use crate::{Error, Result, Scalar};

/// The chapter's active curve (eq. D:pact, eq. (8)): the active nominal stress of a tetanised
/// muscle along its fibres,
///
/// P_act(λ) = P_opt exp[−k (λ² − λ_opt²)² / (λ − λ_min)] for λ > λ_min, 0 otherwise.
///
/// Flat to all orders at λ_min (e^{−c/(λ − λ_min)}). Its integral has no closed form: the
/// registry's Gauss–Legendre quadrature ([`super::quadrature`]). Defaults: Table D:paratt.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChapterCurve {
    lambda_min: f64,
    lambda_opt: f64,
    k: f64,
    p_opt: f64,
}

/// Above this exponent e^{−x} < 1e-304: the curve and all its derivatives are 0 in f64, and
/// returning an exact 0 avoids 0·∞ in the derivatives just above λ_min.
const UNDERFLOW_EXPONENT: f64 = 700.0;

impl ChapterCurve {
    /// Table D:paratt: λ_min = 0.6243, λ_opt = 1.1704, k = 0.4342, P_opt = 73.52 kPa.
    #[allow(clippy::approx_constant)] // k = 0.4342 is the chapter's fitted value, not log10(e)
    pub const PAPER: Self = Self {
        lambda_min: 0.6243,
        lambda_opt: 1.1704,
        k: 0.4342,
        p_opt: 73.52,
    };

    /// λ_min [-] > 0, λ_opt [-] > λ_min, k [-] > 0, P_opt \[kPa\] > 0.
    pub fn new(lambda_min: f64, lambda_opt: f64, k: f64, p_opt: f64) -> Result<Self> {
        super::check_positive(Self::PARAMETERS, &[lambda_min, lambda_opt, k, p_opt])?;
        super::check_order(lambda_min, lambda_opt)?;
        Ok(Self {
            lambda_min,
            lambda_opt,
            k,
            p_opt,
        })
    }

    /// λ_opt [-]: stretch of the peak.
    pub fn lambda_opt(&self) -> f64 {
        self.lambda_opt
    }
    /// Shape parameter k [-].
    pub fn k(&self) -> f64 {
        self.k
    }
    /// Peak stress P_opt \[kPa\].
    pub fn p_opt(&self) -> f64 {
        self.p_opt
    }

    /// The formula of eq. D:pact, written once: P_act(λ) \[kPa\] from λ_min, λ_opt, k [-] and
    /// P_opt \[kPa\], which are `f64` or dual numbers (derivatives in the parameters, for
    /// fitting); nothing is checked here.
    pub fn value_with<P: Scalar, T: ScalarWith<P>>(
        lambda_min: P,
        lambda_opt: P,
        k: P,
        p_opt: P,
        lambda: T,
    ) -> T {
        if lambda.re() <= lambda_min.re() {
            return T::zero();
        }
        let q = lambda * lambda - lambda_opt * lambda_opt;
        let x = q * q * k / (lambda - lambda_min);
        if x.re() > UNDERFLOW_EXPONENT {
            return T::zero();
        }
        (-x).exp() * p_opt
    }
}

impl ShippedCurve for ChapterCurve {
    const NAME: &'static str = "chapter";
    const FORMULA: &'static str = "P_opt exp[−k (λ² − λ_opt²)²/(λ − λ_min)]";
    const SOURCE: &'static str = "the chapter's eq. (8)";
    const PARAMETERS: &'static [Parameter] = &[
        Parameter::ranged("lambda_min", "λ_min", "-", Some(Self::PAPER.lambda_min), (0.0, 1.0)),
        Parameter::ranged("lambda_opt", "λ_opt", "-", Some(Self::PAPER.lambda_opt), (0.5, 2.0)),
        Parameter::positive("k", "k", "-", Some(Self::PAPER.k)),
        Parameter::positive("p_opt", "P_opt", "kPa", Some(Self::PAPER.p_opt)),
    ];

    fn values(&self) -> Vec<f64> {
        vec![self.lambda_min, self.lambda_opt, self.k, self.p_opt]
    }
    fn from_values(v: &[f64]) -> Result<Self> {
        match *v {
            [lambda_min, lambda_opt, k, p_opt] => Self::new(lambda_min, lambda_opt, k, p_opt),
            _ => Err(Error::InvalidParameter {
                name: "parameters",
                value: v.len() as f64,
                rule: "the chapter's curve has four: lambda_min, lambda_opt, k, p_opt",
            }),
        }
    }
    fn lambda_min(&self) -> f64 {
        self.lambda_min
    }
    fn peak(&self) -> f64 {
        self.lambda_opt
    }
    fn value<T: Scalar>(&self, lambda: T) -> T {
        Self::value_with(self.lambda_min, self.lambda_opt, self.k, self.p_opt, lambda)
    }
    fn value_of<P: Scalar, T: ScalarWith<P>>(p: &[P], lambda: T) -> T {
        Self::value_with(p[0], p[1], p[2], p[3], lambda)
    }
}
