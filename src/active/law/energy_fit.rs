use super::{first_activation_root, implicit_derivatives, ActivationLaw, LawValue, PathPartials};
use crate::active::curve::ActiveCurve;
use crate::active::drive::Drive;
use crate::active::map::ActivationMap;
use crate::energy::{positive, StrainEnergy};
use crate::Result;
use num_dual::{first_derivative, second_derivative};

/// The energy-consistent activation law (Giantesio & Musesti 2017, "Strain-dependent internal
/// parameters in hyperelastic biological materials"): γ(λ) solves
///
/// Ŵ(λ, γ) = W_pas(λ) + (1 − d)·a·f_v ∫_{λ_min}^{λ} P_act(s) ds  ([`Drive::work`])
///
/// along the uniaxial fibre path, so that the *consistent* model Ψ(F) = Ŵ(F, γ(λ_f)) reproduces
/// P_pas + (1 − d)·a P_act exactly along the fibres (dΨ/dλ = P_pas + (1 − d)·a P_act there). With
/// force–velocity, f_v at the current rate is a factor of the work, as 4C's MAT_Muscle_Giantesio
/// writes its energy condition (the consistent stress then carries f_v′ ∫P_act too).
///
/// For λ ≲ 0.95, Ŵ(λ, γ) − W_pas(λ) first dips below zero as γ
/// grows (activation relieves the compression) and rises again; the law takes the first root
/// above γ = 0, which just above λ_min is γ ≈ 0.25, not 0: γ(λ) **jumps** at λ_min from 0 to the
/// root of Ŵ(λ_min, γ) = W_pas(λ_min). Along the uniaxial path Ψ stays continuous (both branches
/// have Ψ = W_pas there); off it, Ψ(F) = Ŵ(F, γ(λ_f)) is discontinuous across λ_f = λ_min, so a
/// body whose fibres cross λ_min is not described by a continuous energy there.
///
/// Cost: a quadrature of P_act (⌈(λ − λ_min)/0.1⌉ + 2 panels of 16 points) plus the bracketed Newton solve
/// (one dual number per step) and three hyper-hyper-duals for exact derivatives.
///
/// Below λ_min two choices are offered ([`BelowMinimum`]): γ = 0 (the chapter's "no activation
/// below λ_min", with the jump), or — the default — the continuation of the same root branch,
/// γ solving Ŵ(λ, γ) = W_pas(λ) (zero active work), which makes γ and Ψ continuous across λ_min
/// while the stress along the fibres stays P_pas there. We chose the continuous one because the
/// jump makes Ψ(F) discontinuous in any body whose fibres cross λ_min (a question of material
/// stability, not of root finding). For d = 1 the law is γ ≡ 0 either way; note that for any
/// d < 1 the branch has γ ≈ 0.25 near λ_min, so γ is discontinuous in d at d = 1.
#[derive(Debug, Clone)]
pub struct EnergyLaw<E> {
    energy: E,
    curve: ActiveCurve,
    below_minimum: BelowMinimum,
    map: ActivationMap,
}

/// What the energy-consistent law does at fibre stretches λ ≤ λ_min (in a scene:
/// `below_minimum = "zero-work" | "inactive"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BelowMinimum {
    /// γ = 0: no activation below λ_min; γ and Ψ jump at λ_min. A clamped cylinder whose fibres
    /// reach λ_min cannot be followed past that point (measured: it stops at λ ≈ 0.729).
    Inactive,
    /// γ continues on the zero-work root branch Ŵ(λ, γ) = W_pas(λ): continuous γ and Ψ; the
    /// stress along the fibres is P_pas below λ_min as with γ = 0. The default: with it the
    /// clamped cylinder sweep to λ = 0.70 completes.
    #[default]
    ZeroWork,
}

impl<E> EnergyLaw<E> {
    /// The active curve the law reproduces.
    pub fn curve(&self) -> &ActiveCurve {
        &self.curve
    }

    /// The energy the law is fitted for.
    pub fn energy(&self) -> &E {
        &self.energy
    }

    /// What the law does below λ_min.
    pub fn below_minimum_choice(&self) -> BelowMinimum {
        self.below_minimum
    }

    /// The activation map the law is solved with.
    pub fn map(&self) -> ActivationMap {
        self.map
    }

    /// The same law solved with the activation map `map`.
    pub fn with_map(self, map: impl Into<ActivationMap>) -> Self {
        Self {
            map: map.into(),
            ..self
        }
    }
}

impl<E: StrainEnergy> EnergyLaw<E> {
    /// The energy-consistent law for `energy` and the active curve `curve`, with the chapter's
    /// map.
    pub fn new(energy: E, curve: ActiveCurve) -> Self {
        Self {
            energy,
            curve,
            below_minimum: BelowMinimum::ZeroWork,
            map: ActivationMap::Chapter,
        }
    }

    /// The same law with the given behaviour below λ_min.
    pub fn below_minimum(self, below_minimum: BelowMinimum) -> Self {
        Self {
            below_minimum,
            ..self
        }
    }

    /// Residual in kPa (energy per volume): Ŵ(λ, γ) − W_pas(λ) − (1 − d)·a·f_v ∫ P_act.
    pub fn residual(&self, lambda: f64, gamma: f64, drive: impl Into<Drive>) -> f64 {
        self.map.fibre_path_energy(&self.energy, lambda, gamma)
            - self.map.fibre_path_energy(&self.energy, lambda, 0.0)
            - drive.into().work(&self.curve, lambda)
    }
}

impl<E: StrainEnergy> EnergyLaw<E> {
    /// The active work ([`Drive::work`]), and whether γ is 0 there: no activation at all
    /// (s = 0), or λ ≤ λ_min for [`BelowMinimum::Inactive`] (the jump is at λ_min itself, not
    /// where ∫P_act leaves 0 in f64, ≈ 6e-4 above it).
    fn work(&self, lambda: f64, drive: &Drive) -> Result<(f64, bool)> {
        drive.check()?;
        positive("fibre stretch", lambda)?;
        let work = drive.work(&self.curve, lambda);
        let inactive = drive.is_off()
            || (self.below_minimum == BelowMinimum::Inactive && lambda <= self.curve.lambda_min());
        Ok((work, inactive))
    }
}

impl<E: StrainEnergy> EnergyLaw<E> {
    /// The first root above 0 of Ŵ(λ, γ) − W_pas(λ) − work.
    fn root(&self, lambda: f64, damage: f64, work: f64) -> Result<f64> {
        let passive = self.map.fibre_path_energy(&self.energy, lambda, 0.0);
        first_activation_root(
            self.map.upper_bound(),
            || {
                format!(
                    "energy-consistent activation law at lambda = {}, d = {}",
                    crate::text::shortest(lambda),
                    crate::text::shortest(damage)
                )
            },
            |g| {
                let (w, w_g) = first_derivative(
                    |g| {
                        self.map
                            .fibre_path_energy(&self.energy, num_dual::Dual64::from(lambda), g)
                    },
                    g,
                );
                (w - passive - work, w_g)
            },
        )
    }
}

impl<E: StrainEnergy> ActivationLaw for EnergyLaw<E> {
    fn activation(&self, lambda: f64, drive: impl Into<Drive>) -> Result<f64> {
        let drive = drive.into();
        match self.work(lambda, &drive)? {
            (_, true) => Ok(0.0),
            (work, false) => self.root(lambda, drive.damage(), work),
        }
    }

    fn evaluate(&self, lambda: f64, drive: impl Into<Drive>) -> Result<LawValue> {
        let drive = drive.into();
        let (work, inactive) = self.work(lambda, &drive)?;
        if inactive {
            return Ok(LawValue::default());
        }
        let gamma = self.root(lambda, drive.damage(), work)?;
        // dwork/dλ (the target, times f_v and plus f_v′ ∫P_act with a rate) and d²work/dλ².
        let (_, t, t_l) = second_derivative(|l| drive.work(&self.curve, l), lambda);
        let at = PathPartials::at(&self.energy, self.map, lambda, gamma)?;
        let pas = PathPartials::at(&self.energy, self.map, lambda, 0.0)?;
        Ok(implicit_derivatives(
            gamma,
            at.w_l - pas.w_l - t,
            at.w_g,
            at.w_ll - pas.w_ll - t_l,
            at.w_lg,
            at.w_gg,
        ))
    }
}
