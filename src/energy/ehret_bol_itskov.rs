use super::{open_unit, positive, Invariants, Parameter, ScalarWith, Shipped, StrainEnergy};
use crate::Result;
use crate::Scalar;

/// The Ehret–Böl–Itskov passive energy (eq. D:Webi):
///
/// W(C) = μ/4 { [e^{α(I_p − 1)} − 1]/α + [e^{β(K_p − 1)} − 1]/β },
/// with I_p, K_p as in [`super::GiantesioMusesti`].
///
/// Defaults: μ = 0.1599 kPa, α = 19.69, β = 1.190, w0 = 0.7388.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EhretBolItskov {
    mu: f64,
    alpha: f64,
    beta: f64,
    w0: f64,
}

impl EhretBolItskov {
    /// μ \[kPa\] > 0, α [-] > 0, β [-] > 0, w0 [-] ∈ (0, 1).
    pub fn new(mu: f64, alpha: f64, beta: f64, w0: f64) -> Result<Self> {
        Ok(Self {
            mu: positive("mu", mu)?,
            alpha: positive("alpha", alpha)?,
            beta: positive("beta", beta)?,
            w0: open_unit("w0", w0)?,
        })
    }

    /// The parameters quoted in the chapter after eq. D:Webi.
    pub const PAPER: Self = Self {
        mu: 0.1599,
        alpha: 19.69,
        beta: 1.190,
        w0: 0.7388,
    };

    /// The parameters quoted in the chapter after eq. D:Webi.
    pub fn paper() -> Self {
        Self::PAPER
    }

    /// Shear-like modulus μ \[kPa\].
    pub fn mu(&self) -> f64 {
        self.mu
    }
    /// Exponential stiffening of the I_p term α [-].
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
    /// Exponential stiffening of the K_p term β [-].
    pub fn beta(&self) -> f64 {
        self.beta
    }
    /// Isotropic weight w0 [-].
    pub fn w0(&self) -> f64 {
        self.w0
    }

    /// The formula of eq. D:Webi, written once: W \[kPa\] from μ \[kPa\], α, β, w0 [-] and the
    /// invariants. The parameters are `f64` ([`StrainEnergy::energy`]) or dual numbers
    /// (derivatives in the parameters, for fitting); nothing is checked here.
    pub fn energy_with<P: Scalar, T: ScalarWith<P>>(
        mu: P,
        alpha: P,
        beta: P,
        w0: P,
        c: &Invariants<T>,
    ) -> T {
        let (isotropic, fibre) = (w0 / 3.0, -w0 + 1.0);
        let i_p = c.tr_c * isotropic + c.c_m * fibre;
        let k_p = c.tr_c_inv * isotropic + c.c_inv_m * fibre;
        super::exp_m1((i_p - 1.0) * alpha) * (mu / (alpha * 4.0))
            + super::exp_m1((k_p - 1.0) * beta) * (mu / (beta * 4.0))
    }
}

impl StrainEnergy for EhretBolItskov {
    fn energy<T: Scalar>(&self, c: &Invariants<T>) -> T {
        Self::energy_with(self.mu, self.alpha, self.beta, self.w0, c)
    }

    fn name(&self) -> &str {
        Self::NAME
    }

    fn uses_det_c(&self) -> bool {
        false
    }

    /// f = 1 − w0: W depends on C:M only through I_p = (w0/3) tr C + (1 − w0) C:M.
    fn structural_fibre_weight(&self) -> Option<f64> {
        Some(1.0 - self.w0)
    }
}

impl Shipped for EhretBolItskov {
    const NAME: &'static str = "ehret-bol-itskov";
    const W: Option<&'static str> = Some("Ip = w0/3*tr_c + (1 - w0)*c_m; Kp = w0/3*tr_c_inv + (1 - w0)*c_inv_m; mu/4*(expm1(alpha*(Ip - 1))/alpha + expm1(beta*(Kp - 1))/beta)");
    const FORMULA: &'static str = "the Ehret–Böl–Itskov energy: the K_p − 1 term becomes [e^{β(K_p−1)} − 1]/β";
    const CHAPTER: &'static str = "eq. (4)";
    const PARAMETERS: &'static [Parameter] = &[
        Parameter::positive("mu", "μ", "kPa", Some(Self::PAPER.mu)),
        Parameter::positive("alpha", "α", "-", Some(Self::PAPER.alpha)),
        Parameter::positive("beta", "β", "-", Some(Self::PAPER.beta)),
        Parameter::fraction("w0", "w0", Some(Self::PAPER.w0)),
    ];
    fn values(&self) -> Vec<f64> {
        vec![self.mu, self.alpha, self.beta, self.w0]
    }
    fn from_values(v: &[f64]) -> Result<Self> {
        Self::new(v[0], v[1], v[2], v[3])
    }
    fn energy_of<T: Scalar>(p: &[T], invariants: &Invariants<T>) -> T {
        Self::energy_with(p[0], p[1], p[2], p[3], invariants)
    }
}
