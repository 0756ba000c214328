//! The model factory: the scene's material and activation ([`Models`]) build the activation
//! map, law, coupling and muscle of a [`ModelChoice`] (approach × law × coupling × damage), each
//! approach as the registry [`crate::active::approach`] declares it.

use super::choice::{CouplingKind, LawKind, ModelChoice};
use crate::active::{
    ActivationMap, ActiveCurve, Approach, BelowMinimum, ConstantLaw, Coupling, EnergyLaw,
    ExplicitLaw, ForceVelocity, FrozenTangent, ImplicitLaw, Law, LawRepresentation,
};
use crate::energy::{Energy, GiantesioMusesti};
use crate::uniaxial::{Direction, UniaxialPoint};
use crate::volumetric::Volumetric;
use crate::{Muscle, StrainEnergy};

/// Stretches (from, to, intervals) on which the explicit law must hold for a scene to use it.
const EXPLICIT_PROBE: (f64, f64, usize) = (0.5, 2.0, 150);

/// The material and the activation every model of a scene shares.
#[derive(Debug, Clone, PartialEq)]
pub struct Models {
    /// The passive energy.
    pub energy: Energy,
    /// Fibre direction (unit). The tests are defined relative to it, so any direction gives the
    /// same curves; the cylinder's axis is aligned with it.
    pub fibre: [f64; 3],
    /// Active curve.
    pub curve: ActiveCurve,
    /// Explicit-law coefficients (a, b).
    pub explicit: (f64, f64),
    /// Tangent used by the frozen model.
    pub frozen_tangent: FrozenTangent,
    /// What the energy law does below λ_min.
    pub below_minimum: BelowMinimum,
    /// The map `[activation] map` names, for the approaches that take one (active strain:
    /// [`ActivationMap::Chapter`] or [`ActivationMap::VolumePreserving`]).
    pub map: ActivationMap,
    /// The force–velocity factor of activation-in-time studies (`None`: f_v = 1; quasi-static
    /// studies have λ̇ = 0, so f_v = 1 there whatever this is).
    pub force_velocity: Option<ForceVelocity>,
    /// How the implicit and energy laws of [`Models::muscle`] are evaluated.
    pub representation: LawRepresentation,
    /// Near incompressibility: Ŵ + U(J) without constraint; `None`: exact, J = 1 (the
    /// chapter's). Studies along and across the fibres and cylinders follow it.
    pub volumetric: Option<Volumetric>,
}

impl Models {
    /// The chapter's: its energy, active curve and explicit law, fibres along e₁, exact frozen
    /// tangent, the zero-work energy law below λ_min.
    pub fn paper() -> Self {
        Self {
            energy: Energy::GiantesioMusesti(GiantesioMusesti::paper()),
            fibre: [1.0, 0.0, 0.0],
            curve: ActiveCurve::paper(),
            explicit: ExplicitLaw::paper().coefficients(),
            frozen_tangent: FrozenTangent::default(),
            below_minimum: BelowMinimum::default(),
            map: ActivationMap::Chapter,
            force_velocity: None,
            representation: LawRepresentation::Exact,
            volumetric: None,
        }
    }

    /// The activation map of `approach` on this material ([`Approach::map`]), or why the
    /// material cannot be activated that way (the structural approach needs an energy with a
    /// structural invariant I = C:L).
    pub fn activation_map(&self, approach: Approach) -> Result<ActivationMap, String> {
        approach.map(&self.energy, self.map)
    }

    /// Whether `law` can be built for `approach` on this material: the approach must list it
    /// ([`Approach::laws`]), and the explicit law (eq. (14)) is a fit of the chapter's map, energy
    /// and curve; the error is the rule, in words.
    pub fn supports(&self, approach: Approach, law: LawKind) -> Result<(), String> {
        self.activation_map(approach)?;
        if !approach.laws().contains(&law) {
            return Err(format!(
                "the {} law does not apply to approach = \"{}\": {}",
                law.name(),
                approach.name(),
                approach.no_law()
            ));
        }
        match law {
            LawKind::Explicit => self.explicit_applies(approach),
            LawKind::Implicit | LawKind::Energy => Ok(()),
        }
    }

    /// Whether the explicit law with this scene's (a, b) holds for `approach` (which lists it):
    /// on the chapter's active-strain map, with (a, b) fitted for the active curve, where its
    /// formula holds ([`Self::explicit_formula_holds`]).
    fn explicit_applies(&self, approach: Approach) -> Result<(), String> {
        self.explicit_fit_for(approach)?;
        if !matches!(self.curve, ActiveCurve::Chapter(_))
            && self.explicit == ExplicitLaw::paper().coefficients()
        {
            return Err(format!(
                "the explicit law's a = {}, b = {} are the chapter's fit for its active curve \
                 (eq. (8)); activation.curve is {}: fit them for this curve (a study with \
                 fit = \"explicit-law\") and set activation.explicit = {{ a, b }}, or use the \
                 implicit law",
                self.explicit.0,
                self.explicit.1,
                self.curve.name()
            ));
        }
        self.explicit_formula_holds()
    }

    /// Whether an explicit-law fit (eq. (14)) applies to `approach`: the approach lists the
    /// explicit law and its map is the chapter's (the fit is of the chapter's active-strain γ).
    pub fn explicit_fit_for(&self, approach: Approach) -> Result<(), String> {
        if !approach.laws().contains(&LawKind::Explicit) {
            return Err(format!(
                "the explicit law does not apply to approach = \"{}\": {}",
                approach.name(),
                approach.no_law()
            ));
        }
        match self.activation_map(approach)? {
            ActivationMap::Chapter => Ok(()),
            map => Err(format!(
                "the explicit law (eq. (14)) is fitted for the chapter's active-strain map; activation.map is {}",
                map.name()
            )),
        }
    }

    /// Whether the explicit law's formula applies to this material, on whatever map: it is
    /// derived for the chapter's energy, and must hold there ([`Self::explicit_law_holds`]).
    /// A trade-off measures the explicit law on another map (its error then includes the map's),
    /// never on another energy.
    pub fn explicit_formula_holds(&self) -> Result<(), String> {
        match &self.energy {
            Energy::GiantesioMusesti(_) => self.explicit_law_holds(),
            other => Err(format!(
                "the explicit law (eq. (14)) is derived for the giantesio-musesti energy; material.energy is {}",
                other.name()
            )),
        }
    }

    /// Whether the explicit law's closed form stays in its domain (logarithms and square roots of
    /// positive numbers) at every λ of `EXPLICIT_PROBE` for d = 0 and d = 1: its (a, b) are the
    /// chapter's fit for the chapter's energy and active curve, and with other parameters the
    /// formula can leave its domain at ordinary stretches (μ = 0.5 kPa, α = 12: at λ = 0.63).
    fn explicit_law_holds(&self) -> Result<(), String> {
        use crate::active::ActivationLaw;
        let law = self
            .law(LawKind::Explicit, ActivationMap::Chapter)
            .map_err(|e| e.to_string())?;
        let (from, to, n) = EXPLICIT_PROBE;
        for k in 0..=n {
            let lambda = from + (to - from) * k as f64 / n as f64;
            for d in [0.0, 1.0] {
                if let Err(e) = law.evaluate(lambda, d) {
                    return Err(format!(
                        concat!(
                            "the explicit law (eq. (14)) with a = {}, b = {} fails on this material at ",
                            "λ = {:.3}, d = {} ({}); a and b are a fit for one energy and active curve ",
                            "(the chapter's: a = 1.0133, b = 0.2050): fit them for this material (a study ",
                            "with fit = \"explicit-law\") and set activation.explicit = {{ a, b }}, or use ",
                            "the implicit law"
                        ),
                        self.explicit.0,
                        self.explicit.1,
                        lambda,
                        d,
                        e
                    ));
                }
            }
        }
        Ok(())
    }

    /// Whether the explicit law's (a, b) are a fit for this material: the chapter's (a, b) on
    /// the chapter's energy and active curve, or (a, b) the scene gives (its own fit, e.g. by a
    /// study with fit = "explicit-law"). The chapter's fit on another material can be far off
    /// (90 % in P on the chapter's energy with μ = 0.5 kPa, α = 12, w0 = 0.7).
    pub fn explicit_fit_applies(&self) -> Result<(), String> {
        let paper = Self::paper();
        if self.explicit != paper.explicit
            || (self.energy == paper.energy && self.curve == paper.curve)
        {
            Ok(())
        } else {
            Err(format!(
                "the explicit law's a = {}, b = {} are the chapter's fit, for the chapter's energy \
                 and active curve, which this scene changes; fit them for this material (a study \
                 with fit = \"explicit-law\") and set activation.explicit = {{ a, b }} to use it",
                self.explicit.0, self.explicit.1
            ))
        }
    }

    /// The chapter's energy with this material's parameters, or the chapter's own if the material
    /// is another energy: what the explicit law is built on.
    pub fn explicit_energy(&self) -> GiantesioMusesti {
        match &self.energy {
            Energy::GiantesioMusesti(gm) => *gm,
            _ => GiantesioMusesti::paper(),
        }
    }

    /// The activation map of `approach`, or the error that refuses it as a model error.
    fn map_or_error(&self, approach: Approach) -> crate::Result<ActivationMap> {
        self.activation_map(approach)
            .map_err(|reason| crate::Error::Unsupported { reason })
    }

    /// The activation law `kind` on this material and curve, solved (implicit, energy) with the
    /// activation map `map`.
    pub fn law(&self, kind: LawKind, map: ActivationMap) -> crate::Result<Law<Energy>> {
        Ok(match kind {
            LawKind::Implicit => {
                Law::Implicit(ImplicitLaw::new(self.energy.clone(), self.curve).with_map(map))
            }
            LawKind::Energy => Law::Energy(
                EnergyLaw::new(self.energy.clone(), self.curve)
                    .below_minimum(self.below_minimum)
                    .with_map(map),
            ),
            LawKind::Explicit => Law::Explicit(ExplicitLaw::new(
                self.explicit.0,
                self.explicit.1,
                self.explicit_energy(),
                self.curve,
            )?),
        })
    }

    /// The coupling `kind`, with this material's frozen tangent.
    pub fn coupling(&self, kind: CouplingKind) -> Coupling {
        match kind {
            CouplingKind::Consistent => Coupling::Consistent,
            CouplingKind::Frozen => Coupling::Frozen(self.frozen_tangent),
        }
    }

    /// The active muscle of `model`, its law in this material's [`Models::representation`] (a
    /// table is built for `model.damage`: 0.04–0.1 s for the chapter's laws).
    pub fn muscle(&self, model: ModelChoice) -> crate::Result<Muscle<Energy>> {
        self.built(model, model.damage, None)
    }

    /// The active muscle of `model` at activation level a = `activation` ≥ 0: its law sees
    /// d_eff = d + (1 − d)(1 − a) ([`crate::active::Drive::effective_damage`]), and a tabulated
    /// law is tabulated at d_eff (not at d, whose table would leave every a < 1 to the exact
    /// law). a = 1 is [`Self::muscle`].
    pub fn muscle_at(&self, model: ModelChoice, activation: f64) -> crate::Result<Muscle<Energy>> {
        let effective = crate::active::Drive::new(model.damage, activation)?.effective_damage();
        self.built(model, effective, Some(activation))
    }

    /// The muscle of `model` with its law tabulated at damage `table` (a negative one, of
    /// a > 1: the exact law, no table holds it) and at activation level `activation`: the
    /// approach's map, its law (none: γ ≡ 0) and the energy of the fibre stretch it adds.
    fn built(
        &self,
        model: ModelChoice,
        table: f64,
        activation: Option<f64>,
    ) -> crate::Result<Muscle<Energy>> {
        let map = self.map_or_error(model.approach)?;
        let (law, coupling) = match model.activation_law() {
            None => (Law::Passive, Coupling::Consistent),
            Some((law, coupling)) => {
                let law = self.law(law, map)?;
                let law = if table < 0.0 {
                    law
                } else {
                    law.represented(self.representation, &[table])?
                };
                (law, self.coupling(coupling))
            }
        };
        let muscle = Muscle::new(self.energy.clone(), law, model.damage, coupling)?
            .with_fibre_energy(model.approach, self.curve);
        let muscle = match activation {
            Some(a) => muscle.with_activation(a)?,
            None => muscle,
        };
        muscle.with_map(map)
    }

    /// A muscle of `approach` with constant activation γ (coupling irrelevant: g′ = 0).
    pub fn constant(&self, approach: Approach, gamma: f64) -> crate::Result<Muscle<Energy>> {
        Muscle::new(
            self.energy.clone(),
            Law::Constant(ConstantLaw::new(gamma)?),
            0.0,
            Coupling::Consistent,
        )?
        .with_map(self.map_or_error(approach)?)
    }
    /// The uniaxial test of `muscle` at stretch `lambda` in `direction`, exactly incompressible
    /// ([`Direction::point`]) or, with [`Self::volumetric`], nearly incompressible
    /// ([`crate::uniaxial::nearly_incompressible`]).
    pub fn uniaxial(
        &self,
        muscle: &Muscle<Energy>,
        direction: Direction,
        lambda: f64,
    ) -> crate::Result<UniaxialPoint> {
        crate::uniaxial::point(muscle, self.volumetric.as_ref(), direction, lambda)
    }

    /// Free contraction of `muscle` along the fibres (zero axial load), exactly or, with
    /// [`Self::volumetric`], nearly incompressible ([`crate::uniaxial::zero_load_point`]).
    pub fn free_contraction(&self, muscle: &Muscle<Energy>) -> crate::Result<UniaxialPoint> {
        crate::uniaxial::zero_load_point(muscle, self.volumetric.as_ref())
    }

    /// The passive material.
    pub fn passive(&self) -> Muscle<Energy> {
        Muscle::passive(self.energy.clone())
    }

    /// `giantesio-musesti, explicit law, frozen coupling, d = 0` (`implicit law (tabulated)` for a
    /// tabulated law); an approach other than the chapter's active strain is named as the
    /// registry words it ([`Approach::words`]: `structural, implicit law, …`,
    /// `active stress, d = 0`, `volume-preserving active strain, …`).
    pub fn label(&self, m: &ModelChoice) -> String {
        let approach = m.approach.words(self.map);
        let Some((law, coupling)) = m.activation_law() else {
            return format!("{}, {approach}d = {}", self.energy.name(), m.damage);
        };
        let tabulated =
            matches!(self.representation, LawRepresentation::Tabulated(_)) && law.solves();
        format!(
            "{}, {approach}{} law{}, {} coupling, d = {}",
            self.energy.name(),
            law.name(),
            if tabulated { " (tabulated)" } else { "" },
            coupling.name(),
            m.damage
        )
    }
}
