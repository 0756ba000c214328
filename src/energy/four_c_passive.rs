use super::{EhretBolItskov, Invariants, Parameter, ScalarWith, Shipped, StrainEnergy};
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
/// with L = (w0/3) I + (1 − w0) M. It is the Ehret–Böl–Itskov energy (eq. D:Webi) with K_p
/// replaced by J = det C · K_p: the two agree where det C = 1 and differ only in a compressible or
/// nearly incompressible body. Written so: EBI's formula evaluated at the invariants with tr C⁻¹
/// and C⁻¹:M scaled by det C (K_p is linear in them). 4C writes it without the two −1 (a constant:
/// the stress is the same) and calls μ `GAMMA`, w0 `OMEGA0`. 4C adds a volumetric term
/// S_vol = −(μ/2) det(C)^(−κ) C⁻¹ (parameter `KAPPA`), which this energy does not include (it
/// belongs to the volumetric penalty, not to W).
///
/// Parameters and defaults as [`EhretBolItskov`]: μ = 0.1599 kPa, α = 19.69, β = 1.190,
/// w0 = 0.7388 (the values quoted in the chapter after eq. D:Webi).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FourCPassive(EhretBolItskov);

impl FourCPassive {
    /// μ \[kPa\] > 0, α [-] > 0, β [-] > 0, w0 [-] ∈ (0, 1).
    pub fn new(mu: f64, alpha: f64, beta: f64, w0: f64) -> Result<Self> {
        EhretBolItskov::new(mu, alpha, beta, w0).map(Self)
    }

    /// The Ehret–Böl–Itskov parameters quoted in the chapter after eq. D:Webi.
    pub fn paper() -> Self {
        Self(EhretBolItskov::PAPER)
    }

    /// The same parameters as an [`EhretBolItskov`] energy: μ \[kPa\] (4C: `GAMMA`), α, β,
    /// w0 (4C: `OMEGA0`).
    pub fn parameters(&self) -> &EhretBolItskov {
        &self.0
    }

    /// The formula: W \[kPa\] from μ \[kPa\], α, β, w0 [-] and the invariants.
    pub fn energy_with<P: Scalar, T: ScalarWith<P>>(
        mu: P,
        alpha: P,
        beta: P,
        w0: P,
        c: &Invariants<T>,
    ) -> T {
        let scaled = Invariants {
            tr_c_inv: c.tr_c_inv * c.det_c,
            c_inv_m: c.c_inv_m * c.det_c,
            ..*c
        };
        EhretBolItskov::energy_with(mu, alpha, beta, w0, &scaled)
    }
}

impl StrainEnergy for FourCPassive {
    fn energy<T: Scalar>(&self, c: &Invariants<T>) -> T {
        let e = &self.0;
        Self::energy_with(e.mu(), e.alpha(), e.beta(), e.w0(), c)
    }

    fn name(&self) -> &str {
        Self::NAME
    }

    /// f = 1 − w0: W depends on C:M only through I_p = (w0/3) tr C + (1 − w0) C:M.
    fn structural_fibre_weight(&self) -> Option<f64> {
        Some(1.0 - self.0.w0())
    }
}

impl Shipped for FourCPassive {
    const NAME: &'static str = "4c-passive";
    const W: Option<&'static str> = Some("I = w0/3*tr_c + (1 - w0)*c_m; Jc = det_c*(w0/3*tr_c_inv + (1 - w0)*c_inv_m); mu/4*(expm1(alpha*(I - 1))/alpha + expm1(beta*(Jc - 1))/beta)");
    const FORMULA: &'static str = "4C's passive muscle energy (Weickenmeier et al. 2014), W = μ/4 {[e^{α(I−1)} − 1]/α + [e^{β(J−1)} − 1]/β}, I = (w0/3) tr C + (1−w0) C:M, J = det C [(w0/3) tr C⁻¹ + (1−w0) C⁻¹:M]: the Ehret–Böl–Itskov energy with K_p scaled by det C (the same where det C = 1)";
    const CHAPTER: &'static str = "as eq. (4) where det C = 1; not in the chapter";
    const PARAMETERS: &'static [Parameter] = EhretBolItskov::PARAMETERS;
    fn values(&self) -> Vec<f64> {
        self.0.values()
    }
    fn from_values(v: &[f64]) -> Result<Self> {
        EhretBolItskov::from_values(v).map(Self)
    }
    fn energy_of<T: Scalar>(p: &[T], invariants: &Invariants<T>) -> T {
        Self::energy_with(p[0], p[1], p[2], p[3], invariants)
    }
}
