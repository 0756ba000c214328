use super::{
    fibre_stiffness, fibre_stress_and_slope, first_activation_root, implicit_derivatives,
    ActivationLaw, LawValue, PathPartials,
};
use crate::active::curve::ActiveCurve;
use crate::active::drive::Drive;
use crate::active::map::ActivationMap;
use crate::energy::{positive, StrainEnergy};
use crate::Result;
use num_dual::{first_derivative, second_derivative};

/// The chapter's activation law (eq. D:eqgammaesplicita): γ(λ) solves
///
/// P_tot(λ, γ) = P_pas(λ) + T(λ),  P_tot = ∂Ŵ/∂λ along F = diag(λ, λ^-½, λ^-½),
///
/// with the target T = (1 − d)·a·f_v·P_act ([`Drive::target`]), for any energy and any
/// activation map (for the chapter's energy and map at a = 1 this is exactly the printed
/// equation; for the structural map the variable is ω, and for 4C's energy the root is 4C's
/// closed form through the Lambert W function). γ = 0 for λ ≤ λ_min and wherever T = 0.
///
/// Valid for λ > λ_min up to the stretch where P_tot overflows at the root (≈ 1.9 for the
/// chapter's parameters). Ill-conditioned just above λ_min: P_tot is nearly flat in γ there, so
/// γ climbs from ≈ 0 at λ = 0.65 to ≈ 0.30 at λ = 0.70. Cost: a bracket by steps of 0.05 in γ
/// plus ≈ 5 safeguarded Newton steps (one hyper-dual each), then three hyper-hyper-duals for the
/// exact derivatives (implicit-function theorem).
#[derive(Debug, Clone)]
pub struct ImplicitLaw<E> {
    energy: E,
    curve: ActiveCurve,
    map: ActivationMap,
}

impl<E: StrainEnergy> ImplicitLaw<E> {
    /// The law fitted for `energy` to the active curve `curve`, with the chapter's map.
    pub fn new(energy: E, curve: ActiveCurve) -> Self {
        Self {
            energy,
            curve,
            map: ActivationMap::Chapter,
        }
    }

    /// The same law solved with the activation map `map`.
    pub fn with_map(self, map: impl Into<ActivationMap>) -> Self {
        Self {
            map: map.into(),
            ..self
        }
    }

    /// The activation map the law is solved with.
    pub fn map(&self) -> ActivationMap {
        self.map
    }

    /// The active curve the law reproduces.
    pub fn curve(&self) -> &ActiveCurve {
        &self.curve
    }

    /// The energy the law is fitted for.
    pub fn energy(&self) -> &E {
        &self.energy
    }

    /// Residual of eq. D:eqgammaesplicita in kPa: P_tot(λ, γ) − P_pas(λ) − T(λ).
    pub fn residual(&self, lambda: f64, gamma: f64, drive: impl Into<Drive>) -> f64 {
        let (p_tot, _) = fibre_stress_and_slope(&self.energy, self.map, lambda, gamma);
        let (p_pas, _) = fibre_stress_and_slope(&self.energy, self.map, lambda, 0.0);
        p_tot - p_pas - drive.into().target(&self.curve, lambda)
    }
}

impl<E: StrainEnergy> ActivationLaw for ImplicitLaw<E> {
    fn activation(&self, lambda: f64, drive: impl Into<Drive>) -> Result<f64> {
        let drive = drive.into();
        drive.check()?;
        positive("fibre stretch", lambda)?;
        let t = drive.target(&self.curve, lambda);
        if t <= 0.0 {
            return Ok(0.0);
        }
        let (p_pas, _) = fibre_stress_and_slope(&self.energy, self.map, lambda, 0.0);
        let damage = drive.damage();
        first_activation_root(
            self.map.upper_bound(),
            || {
                format!(
                    "implicit activation law at lambda = {}, d = {}",
                    crate::text::shortest(lambda),
                    crate::text::shortest(damage)
                )
            },
            |g| {
                let (p, dp) = fibre_stress_and_slope(&self.energy, self.map, lambda, g);
                (p - p_pas - t, dp)
            },
        )
    }

    /// γ′ = −F_λ/F_γ for F(λ, γ) = P_tot(λ, γ) − P_pas(λ) − T(λ): F_λ = ∂P_tot/∂λ(λ, γ) −
    /// ∂P_tot/∂λ(λ, 0) − T′(λ), F_γ = ∂P_tot/∂γ, by hyper-duals (second order: a third of the cost
    /// of [`evaluate`](Self::evaluate)'s third-order partials).
    fn gamma_and_slope(&self, lambda: f64, drive: impl Into<Drive>) -> Result<(f64, f64)> {
        let drive = drive.into();
        let gamma = self.activation(lambda, drive)?;
        let (t, t_l) = first_derivative(|l| drive.target(&self.curve, l), lambda);
        if t <= 0.0 {
            return Ok((0.0, 0.0));
        }
        let (_, f_g) = fibre_stress_and_slope(&self.energy, self.map, lambda, gamma);
        let f_l = fibre_stiffness(&self.energy, self.map, lambda, gamma)?
            - fibre_stiffness(&self.energy, self.map, lambda, 0.0)?
            - t_l;
        let slope = -f_l / f_g;
        if !slope.is_finite() {
            return Err(crate::Error::NonFinite {
                quantity: "implicit activation slope",
                value: slope,
                context: format!(
                    "at lambda = {}, gamma = {}: dP_tot/dgamma = {}",
                    crate::text::shortest(lambda),
                    crate::text::shortest(gamma),
                    crate::text::shortest(f_g)
                ),
            });
        }
        Ok((gamma, slope))
    }

    fn evaluate(&self, lambda: f64, drive: impl Into<Drive>) -> Result<LawValue> {
        let drive = drive.into();
        let gamma = self.activation(lambda, drive)?;
        let (t, t_l, t_ll) = second_derivative(|l| drive.target(&self.curve, l), lambda);
        if t <= 0.0 {
            return Ok(LawValue::default());
        }
        let at = PathPartials::at(&self.energy, self.map, lambda, gamma)?;
        let passive = PathPartials::at(&self.energy, self.map, lambda, 0.0)?;
        Ok(implicit_derivatives(
            gamma,
            at.w_ll - passive.w_ll - t_l,
            at.w_lg,
            at.w_lll - passive.w_lll - t_ll,
            at.w_llg,
            at.w_lgg,
        ))
    }
}
