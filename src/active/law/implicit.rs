use super::{
    check_damage, fibre_stress_and_slope, first_activation_root, implicit_derivatives,
    ActivationLaw, LawValue, PathPartials,
};
use crate::active::curve::ActiveCurve;
use crate::active::strain::ActiveStrainMap;
use crate::energy::{positive, StrainEnergy};
use crate::Result;
use num_dual::second_derivative;

/// The chapter's activation law (eq. D:eqgammaesplicita): γ(λ) solves
///
/// P_tot(λ, γ) = P_pas(λ) + (1 − d) P_act(λ),  P_tot = ∂Ŵ/∂λ along F = diag(λ, λ^-½, λ^-½),
///
/// for any energy and either active-strain map (for the chapter's energy and map this is exactly
/// the printed equation). γ = 0 for
/// λ ≤ λ_min and wherever (1 − d) P_act = 0.
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
    map: ActiveStrainMap,
}

impl<E: StrainEnergy> ImplicitLaw<E> {
    /// The law fitted for `energy` to the active curve `curve`, with the chapter's map.
    pub fn new(energy: E, curve: ActiveCurve) -> Self {
        Self {
            energy,
            curve,
            map: ActiveStrainMap::Chapter,
        }
    }

    /// The same law solved with the active-strain map `map`.
    pub fn with_map(self, map: ActiveStrainMap) -> Self {
        Self { map, ..self }
    }

    /// The active-strain map the law is solved with.
    pub fn map(&self) -> ActiveStrainMap {
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

    /// Residual of eq. D:eqgammaesplicita in kPa: P_tot(λ, γ) − P_pas(λ) − (1 − d) P_act(λ).
    pub fn residual(&self, lambda: f64, gamma: f64, damage: f64) -> f64 {
        let (p_tot, _) = fibre_stress_and_slope(&self.energy, self.map, lambda, gamma);
        let (p_pas, _) = fibre_stress_and_slope(&self.energy, self.map, lambda, 0.0);
        p_tot - p_pas - (1.0 - damage) * self.curve.value(lambda)
    }
}

impl<E: StrainEnergy> ActivationLaw for ImplicitLaw<E> {
    fn activation(&self, lambda: f64, damage: f64) -> Result<f64> {
        check_damage(damage)?;
        positive("fibre stretch", lambda)?;
        let t = self.curve.value(lambda) * (1.0 - damage);
        if t <= 0.0 {
            return Ok(0.0);
        }
        let (p_pas, _) = fibre_stress_and_slope(&self.energy, self.map, lambda, 0.0);
        first_activation_root(
            || format!("implicit activation law at lambda = {lambda}, d = {damage}"),
            |g| {
                let (p, dp) = fibre_stress_and_slope(&self.energy, self.map, lambda, g);
                (p - p_pas - t, dp)
            },
        )
    }

    fn evaluate(&self, lambda: f64, damage: f64) -> Result<LawValue> {
        let gamma = self.activation(lambda, damage)?;
        let scale = 1.0 - damage;
        let (t, t_l, t_ll) = second_derivative(|l| self.curve.value(l) * scale, lambda);
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
