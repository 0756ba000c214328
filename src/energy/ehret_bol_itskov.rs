use super::{open_unit, positive, Invariants, StrainEnergy};
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
    /// μ [kPa] > 0, α [-] > 0, β [-] > 0, w0 [-] ∈ (0, 1).
    pub fn new(mu: f64, alpha: f64, beta: f64, w0: f64) -> Result<Self> {
        Ok(Self {
            mu: positive("mu", mu)?,
            alpha: positive("alpha", alpha)?,
            beta: positive("beta", beta)?,
            w0: open_unit("w0", w0)?,
        })
    }

    /// The parameters quoted in the chapter after eq. D:Webi.
    pub fn paper() -> Self {
        Self {
            mu: 0.1599,
            alpha: 19.69,
            beta: 1.190,
            w0: 0.7388,
        }
    }
}

impl StrainEnergy for EhretBolItskov {
    fn energy<T: Scalar>(&self, c: &Invariants<T>) -> T {
        let w0 = self.w0;
        let i_p = c.tr_c * (w0 / 3.0) + c.c_m * (1.0 - w0);
        let k_p = c.tr_c_inv * (w0 / 3.0) + c.c_inv_m * (1.0 - w0);
        ((i_p - 1.0) * self.alpha).exp_m1() * (self.mu / (4.0 * self.alpha))
            + ((k_p - 1.0) * self.beta).exp_m1() * (self.mu / (4.0 * self.beta))
    }

    fn name(&self) -> &str {
        "ehret-bol-itskov"
    }
}
