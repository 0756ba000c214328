use super::{open_unit, positive, Invariants, Parameter, ScalarWith, Shipped, StrainEnergy};
use crate::Result;
use crate::Scalar;

/// The passive energy of 4C's `MAT_Muscle_Giantesio` and `MAT_Muscle_Weickenmeier`
/// (Weickenmeier et al. 2014):
///
/// W(C) = μ/4 { [e^{α(I − 1)} − 1]/α + [e^{β(J − 1)} − 1]/β },
///
/// I = tr(C L) = (w0/3) tr C + (1 − w0) C:M,
/// J = cof C : L = det C · tr(C⁻¹ L) = det C [(w0/3) tr C⁻¹ + (1 − w0) C⁻¹:M],
///
/// with L = (w0/3) I + (1 − w0) M. 4C writes it without the two −1 (a constant: the stress is the
/// same) and calls μ `GAMMA`, w0 `OMEGA0`. Where det C = 1 it is the Ehret–Böl–Itskov energy
/// (eq. D:Webi, J = K_p); it differs from it only in a compressible or nearly incompressible
/// body. 4C adds a volumetric term S_vol = −(μ/2) det(C)^(−κ) C⁻¹ (parameter `KAPPA`), which
/// this energy does not include (it belongs to the volumetric penalty, not to W).
///
/// Defaults: the Ehret–Böl–Itskov values quoted in the chapter, μ = 0.1599 kPa, α = 19.69,
/// β = 1.190, w0 = 0.7388.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FourCPassive {
    mu: f64,
    alpha: f64,
    beta: f64,
    w0: f64,
}

impl FourCPassive {
    /// μ \[kPa\] > 0, α [-] > 0, β [-] > 0, w0 [-] ∈ (0, 1).
    pub fn new(mu: f64, alpha: f64, beta: f64, w0: f64) -> Result<Self> {
        Ok(Self {
            mu: positive("mu", mu)?,
            alpha: positive("alpha", alpha)?,
            beta: positive("beta", beta)?,
            w0: open_unit("w0", w0)?,
        })
    }

    /// The Ehret–Böl–Itskov parameters quoted in the chapter after eq. D:Webi.
    pub const PAPER: Self = Self {
        mu: 0.1599,
        alpha: 19.69,
        beta: 1.190,
        w0: 0.7388,
    };

    /// The Ehret–Böl–Itskov parameters quoted in the chapter after eq. D:Webi.
    pub fn paper() -> Self {
        Self::PAPER
    }

    /// Shear-like modulus μ \[kPa\] (4C: `GAMMA`).
    pub fn mu(&self) -> f64 {
        self.mu
    }
    /// Exponential stiffening of the I term α [-].
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
    /// Exponential stiffening of the J term β [-].
    pub fn beta(&self) -> f64 {
        self.beta
    }
    /// Isotropic weight w0 [-] (4C: `OMEGA0`).
    pub fn w0(&self) -> f64 {
        self.w0
    }

    /// The formula, written once: W \[kPa\] from μ \[kPa\], α, β, w0 [-] and the invariants.
    pub fn energy_with<P: Scalar, T: ScalarWith<P>>(
        mu: P,
        alpha: P,
        beta: P,
        w0: P,
        c: &Invariants<T>,
    ) -> T {
        let (isotropic, fibre) = (w0 / 3.0, -w0 + 1.0);
        let i = c.tr_c * isotropic + c.c_m * fibre;
        let j = c.det_c * (c.tr_c_inv * isotropic + c.c_inv_m * fibre);
        ((i - 1.0) * alpha).exp_m1() * (mu / (alpha * 4.0))
            + ((j - 1.0) * beta).exp_m1() * (mu / (beta * 4.0))
    }
}

impl StrainEnergy for FourCPassive {
    fn energy<T: Scalar>(&self, c: &Invariants<T>) -> T {
        Self::energy_with(self.mu, self.alpha, self.beta, self.w0, c)
    }

    fn name(&self) -> &str {
        Self::NAME
    }
}

impl Shipped for FourCPassive {
    const NAME: &'static str = "4c-passive";
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
