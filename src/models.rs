//! Models from choices: the scene's material and activation ([`Models`]) build the activation
//! law, the coupling and the muscle of a [`ModelChoice`] (law × coupling × damage); an
//! [`EnergySpec`] (a shipped energy by name, parameters by name) builds an [`Energy`] from the
//! registry [`crate::energy::SHIPPED`]. The scene and every study build their models here.

use crate::active::{
    ActivationMap, ActiveCurve, ActiveStrainMap, Approach, BelowMinimum, ConstantLaw, Coupling,
    CurveEntry, EnergyLaw, ExplicitLaw, ForceVelocity, FrozenTangent, ImplicitLaw, Law,
    LawRepresentation, TableSpec, CURVES,
};
use crate::app_error::SpecError;
use crate::energy::{Energy, GiantesioMusesti, Parametric, ShippedEnergy, SHIPPED};
use crate::text::shortest;
use crate::uniaxial::{Direction, UniaxialPoint};
use crate::volumetric::{Volumetric, VolumetricForm};
use crate::{Muscle, StrainEnergy};
use serde::de::{MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// An activation law by name (`law = "implicit"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LawKind {
    /// The chapter's exact fit, eq. (13) solved numerically ([`ImplicitLaw`]).
    #[default]
    Implicit,
    /// The chapter's closed form, eq. (14) ([`ExplicitLaw`]).
    Explicit,
    /// The energy-consistent fit ([`EnergyLaw`]).
    Energy,
}

impl LawKind {
    /// Name in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            LawKind::Implicit => "implicit",
            LawKind::Explicit => "explicit",
            LawKind::Energy => "energy",
        }
    }
}

/// A coupling by name (`coupling = "frozen"`); the frozen model's tangent is the scene's
/// `frozen_tangent`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CouplingKind {
    /// The chapter's model: γ held in the stress ([`Coupling::Frozen`]).
    #[default]
    Frozen,
    /// Truly hyperelastic: Ψ(F) = Ŵ(F, g(λ_f(F))) ([`Coupling::Consistent`]).
    Consistent,
}

impl CouplingKind {
    /// Name in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            CouplingKind::Frozen => "frozen",
            CouplingKind::Consistent => "consistent",
        }
    }
}

/// How the laws that solve an equation for γ (implicit, energy) are evaluated
/// (`representation = "tabulated"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RepresentationKind {
    /// Solved at every evaluation.
    #[default]
    Exact,
    /// From a table built once per damage and checked against the exact solve
    /// ([`crate::active::TabulatedLaw`]): |Δγ| ≤ 1e-12, fibre stress within 1e-9 kPa + 1e-13 |P|.
    Tabulated,
}

/// One activation model: law, coupling, damage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelChoice {
    /// Activation law.
    pub law: LawKind,
    /// Coupling.
    pub coupling: CouplingKind,
    /// Damage d ∈ [0, 1].
    pub damage: f64,
}

/// Every law × coupling × damage, in that order of nesting.
pub fn product(laws: &[LawKind], couplings: &[CouplingKind], damages: &[f64]) -> Vec<ModelChoice> {
    let mut models = Vec::with_capacity(laws.len() * couplings.len() * damages.len());
    for &law in laws {
        for &coupling in couplings {
            for &damage in damages {
                models.push(ModelChoice {
                    law,
                    coupling,
                    damage,
                });
            }
        }
    }
    models
}

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
    /// The activation approach (active strain, active stress, structural).
    pub approach: Approach,
    /// The active-strain map F_a(γ) of the active-strain approach.
    pub map: ActiveStrainMap,
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
            approach: Approach::ActiveStrain,
            map: ActiveStrainMap::Chapter,
            force_velocity: None,
            representation: LawRepresentation::Exact,
            volumetric: None,
        }
    }

    /// The activation map of the scene's approach: the active-strain map, or the structural map
    /// of the energy (refused, in words, for an energy without a structural invariant I = C:L);
    /// the chapter's for active stress, which has none (γ ≡ 0).
    pub fn activation_map(&self) -> Result<ActivationMap, String> {
        match self.approach {
            Approach::ActiveStrain => Ok(self.map.into()),
            Approach::ActiveStress => Ok(ActivationMap::Chapter),
            Approach::Structural => ActivationMap::structural(&self.energy).ok_or_else(|| {
                format!(
                    "the structural approach activates the structural invariant I = C:(L + ωM) \
                     of an energy that depends on C:M only through I = C:L (giantesio-musesti, \
                     ehret-bol-itskov, 4c-passive); material.energy is {}",
                    self.energy.name()
                )
            }),
        }
    }

    /// The models of a study: every law × coupling × damage, in that order of nesting
    /// ([`product`]); with active stress, which has neither law nor coupling, one per damage.
    pub fn choices(
        &self,
        laws: &[LawKind],
        couplings: &[CouplingKind],
        damages: &[f64],
    ) -> Vec<ModelChoice> {
        if self.approach.has_law() {
            product(laws, couplings, damages)
        } else {
            product(
                &laws[..laws.len().min(1)],
                &couplings[..couplings.len().min(1)],
                damages,
            )
        }
    }

    /// Whether `law` can be built on this material: the explicit law (eq. (14)) is derived
    /// for the chapter's energy only; the error is the rule, in words.
    pub fn supports(&self, law: LawKind) -> Result<(), String> {
        self.activation_map()?;
        match law {
            LawKind::Explicit if self.approach == Approach::Structural => Err(
                "the explicit law (eq. (14)) is fitted for active strain; activation.approach is structural"
                    .to_string(),
            ),
            _ if !self.approach.has_law() => Ok(()),
            LawKind::Explicit if self.map != ActiveStrainMap::Chapter => Err(format!(
                "the explicit law (eq. (14)) is fitted for the chapter's active-strain map; activation.map is {}",
                self.map.name()
            )),
            LawKind::Explicit
                if !matches!(self.curve, ActiveCurve::Chapter(_))
                    && self.explicit == ExplicitLaw::paper().coefficients() =>
            {
                Err(format!(
                    "the explicit law's a = {}, b = {} are the chapter's fit for its active curve \
                     (eq. (8)); activation.curve is {}: fit them for this curve (a study with \
                     fit = \"explicit-law\") and set activation.explicit = {{ a, b }}, or use the \
                     implicit law",
                    self.explicit.0,
                    self.explicit.1,
                    self.curve.name()
                ))
            }
            LawKind::Explicit => self.explicit_formula_holds(),
            LawKind::Implicit | LawKind::Energy => Ok(()),
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
        let law = self.law(LawKind::Explicit).map_err(|e| e.to_string())?;
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

    /// The activation map, or the error that refuses it as a model error.
    fn map_or_error(&self) -> crate::Result<ActivationMap> {
        self.activation_map()
            .map_err(|reason| crate::Error::Unsupported { reason })
    }

    /// The activation law `kind` on this material and curve.
    pub fn law(&self, kind: LawKind) -> crate::Result<Law<Energy>> {
        let map = self.map_or_error()?;
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
        if !self.approach.has_law() {
            return Muscle::active_stress(self.energy.clone(), self.curve, model.damage);
        }
        Muscle::new(
            self.energy.clone(),
            self.law(model.law)?
                .represented(self.representation, &[model.damage])?,
            model.damage,
            self.coupling(model.coupling),
        )?
        .with_map(self.map_or_error()?)
    }

    /// The active muscle of `model` at activation level a = `activation` ≥ 0: its law sees
    /// d_eff = d + (1 − d)(1 − a) ([`crate::active::Drive::effective_damage`]), and a tabulated
    /// law is tabulated at d_eff (not at d, whose table would leave every a < 1 to the exact
    /// law). a = 1 is [`Self::muscle`].
    pub fn muscle_at(&self, model: ModelChoice, activation: f64) -> crate::Result<Muscle<Energy>> {
        if !self.approach.has_law() {
            return self.muscle(model)?.with_activation(activation);
        }
        let effective = crate::active::Drive::new(model.damage, activation)?.effective_damage();
        if effective < 0.0 {
            // a > 1: no table holds a negative damage; the exact law answers.
            return Muscle::new(
                self.energy.clone(),
                self.law(model.law)?,
                model.damage,
                self.coupling(model.coupling),
            )?
            .with_activation(activation)?
            .with_map(self.map_or_error()?);
        }
        Muscle::new(
            self.energy.clone(),
            self.law(model.law)?
                .represented(self.representation, &[effective])?,
            model.damage,
            self.coupling(model.coupling),
        )?
        .with_activation(activation)?
        .with_map(self.map_or_error()?)
    }

    /// A muscle with constant activation γ (coupling irrelevant: g′ = 0).
    pub fn constant(&self, gamma: f64) -> crate::Result<Muscle<Energy>> {
        Muscle::new(
            self.energy.clone(),
            Law::Constant(ConstantLaw::new(gamma)?),
            0.0,
            Coupling::Consistent,
        )?
        .with_map(self.map_or_error()?)
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
    /// tabulated law); an approach other than the chapter's is named (`structural, implicit law,
    /// …`, `active stress, d = 0`), and so is the volume-preserving map.
    pub fn label(&self, m: &ModelChoice) -> String {
        if !self.approach.has_law() {
            return format!("{}, active stress, d = {}", self.energy.name(), m.damage);
        }
        let tabulated = matches!(self.representation, LawRepresentation::Tabulated(_))
            && m.law != LawKind::Explicit;
        let approach = match (self.approach, self.map) {
            (Approach::Structural, _) => "structural, ",
            (_, ActiveStrainMap::VolumePreserving) => "volume-preserving active strain, ",
            _ => "",
        };
        format!(
            "{}, {approach}{} law{}, {} coupling, d = {}",
            self.energy.name(),
            m.law.name(),
            if tabulated { " (tabulated)" } else { "" },
            m.coupling.name(),
            m.damage
        )
    }
}

/// A shipped energy by name with its parameters by name (`{ energy = "ehret-bol-itskov",
/// alpha = 10.0 }`); a parameter left out takes the chapter's value of that energy
/// ([`crate::energy::Parameter::default`]).
#[derive(Debug, Clone, PartialEq)]
pub struct EnergySpec {
    /// Name of a shipped energy (default: the first, the chapter's).
    pub energy: String,
    /// Parameters as given, in the order written.
    pub parameters: Vec<(String, f64)>,
}

impl Default for EnergySpec {
    fn default() -> Self {
        Self {
            energy: SHIPPED[0].name.to_string(),
            parameters: Vec::new(),
        }
    }
}

fn parameter_list(shipped: &ShippedEnergy) -> String {
    let v: Vec<String> = shipped
        .parameters
        .iter()
        .map(|p| format!("{} [{}]", p.name, p.unit))
        .collect();
    v.join(", ")
}

impl EnergySpec {
    /// The value of parameter `name` as given.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.parameters
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| *v)
    }

    /// The energy it describes, validated; errors name the key relative to the spec (`energy`,
    /// `mu`).
    pub fn build(&self) -> Result<Energy, SpecError> {
        let Some(shipped) = ShippedEnergy::find(&self.energy) else {
            let names: Vec<&str> = SHIPPED.iter().map(|e| e.name).collect();
            return Err(SpecError::new(
                "energy",
                format!("{:?}", self.energy),
                format!("unknown energy; the shipped ones are {}", names.join(", ")),
            ));
        };
        if let Some((name, value)) = self
            .parameters
            .iter()
            .find(|(n, _)| !shipped.parameters.iter().any(|p| p.name == n))
        {
            return Err(SpecError::new(
                name.as_str(),
                value,
                format!(
                    "unknown field: the {} energy has no parameter {name}; its parameters are {}",
                    shipped.name,
                    parameter_list(shipped)
                ),
            ));
        }
        let mut values = Vec::with_capacity(shipped.parameters.len());
        for p in shipped.parameters {
            match self.get(p.name).or(p.default) {
                Some(v) => values.push(v),
                None => {
                    return Err(SpecError::new(
                        p.name,
                        "(missing)",
                        format!(
                            "the {} energy has no chapter value: give {} [{}]",
                            shipped.name, p.name, p.unit
                        ),
                    ))
                }
            }
        }
        shipped.build(&values).map_err(|e| SpecError::model("", e))
    }

    /// The spec of a built energy: its name and every parameter it holds, given or default (what
    /// a printed scene shows, so that it is the energy that runs).
    pub fn written(e: &Energy) -> Self {
        Self {
            energy: e.name().to_string(),
            parameters: e
                .parameters()
                .iter()
                .zip(e.parameter_values())
                .map(|(p, v)| (p.name.to_string(), v))
                .collect(),
        }
    }
}

impl Serialize for EnergySpec {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(1 + self.parameters.len()))?;
        map.serialize_entry("energy", &self.energy)?;
        for (name, value) in &self.parameters {
            map.serialize_entry(name, value)?;
        }
        map.end()
    }
}

/// Reads `energy = "..."` and numeric parameters by name from a table, keeping each value's
/// position (a wrong type is reported where it is written); `fibre` is read too if `fibre`
/// is given a place.
fn visit_energy<'de, A: MapAccess<'de>>(
    mut map: A,
    mut fibre: Option<&mut Option<[f64; 3]>>,
) -> Result<EnergySpec, A::Error> {
    let mut spec = EnergySpec::default();
    while let Some(key) = map.next_key::<String>()? {
        match (key.as_str(), fibre.as_deref_mut()) {
            ("energy", _) => spec.energy = map.next_value()?,
            ("fibre", Some(slot)) => *slot = Some(map.next_value()?),
            _ => {
                /// A parameter's value: a number, or anything else (a misspelt key).
                #[derive(Deserialize)]
                #[serde(untagged)]
                enum Parameter {
                    Number(f64),
                    Other(serde::de::IgnoredAny),
                }
                match map.next_value::<Parameter>()? {
                    Parameter::Number(value) => spec.parameters.push((key, value)),
                    Parameter::Other(_) => {
                        let keys = if fibre.is_some() {
                            "energy = \"name\", fibre = [x, y, z] and the energy's parameters"
                        } else {
                            "energy = \"name\" and the energy's parameters"
                        };
                        return Err(serde::de::Error::custom(format!(
                            "{key} is not a number: the keys are {keys}, each a number (a misspelt key?)"
                        )));
                    }
                }
            }
        }
    }
    Ok(spec)
}

impl<'de> Deserialize<'de> for EnergySpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = EnergySpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a table { energy = \"name\", parameter = value, ... }")
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<EnergySpec, A::Error> {
                visit_energy(map, None)
            }
        }
        deserializer.deserialize_map(V)
    }
}

/// `[material]`: an energy with its parameters, and the fibre direction.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MaterialSpec {
    /// The energy.
    pub energy: EnergySpec,
    /// Fibre direction m in the reference configuration (normalised; default e₁).
    pub fibre: Option<[f64; 3]>,
}

impl Serialize for MaterialSpec {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let e = &self.energy;
        let mut map = serializer.serialize_map(Some(2 + e.parameters.len()))?;
        map.serialize_entry("energy", &e.energy)?;
        for (name, value) in &e.parameters {
            map.serialize_entry(name, value)?;
        }
        if let Some(f) = &self.fibre {
            map.serialize_entry("fibre", f)?;
        }
        map.end()
    }
}

impl<'de> Deserialize<'de> for MaterialSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = MaterialSpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a table { energy = \"name\", parameter = value, ..., fibre = [x, y, z] }",
                )
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<MaterialSpec, A::Error> {
                let mut fibre = None;
                let energy = visit_energy(map, Some(&mut fibre))?;
                Ok(MaterialSpec { energy, fibre })
            }
        }
        deserializer.deserialize_map(V)
    }
}

impl MaterialSpec {
    /// The energy and the unit fibre direction; errors name keys relative to `[material]`.
    pub fn build(&self) -> Result<(Energy, [f64; 3]), SpecError> {
        let energy = self.energy.build()?;
        let fibre = self.fibre.unwrap_or([1.0, 0.0, 0.0]);
        let norm = fibre.iter().map(|x| x * x).sum::<f64>().sqrt();
        if !(norm.is_finite() && norm > 1e-12) {
            let shown: Vec<String> = fibre.iter().map(|x| shortest(*x)).collect();
            return Err(SpecError::new(
                "fibre",
                format!("[{}]", shown.join(", ")),
                "the fibre direction must be a finite, non-zero vector",
            ));
        }
        Ok((energy, fibre.map(|x| x / norm)))
    }
}

/// `[activation]`: the approach, the active curve with its parameters (flat beside `curve`), the
/// explicit law's coefficients and the options every model shares ([`Models::from_spec`]), and
/// the studies' default law, coupling and damage values. `None` is the default.
///
/// The curve's parameters are read by name from the table (the scene reader takes the
/// parameters of every shipped curve out of it, see [`crate::scene`]); each must be one of the
/// chosen curve's.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActivationSpec {
    /// `active-strain` (default) | `active-stress` | `structural`.
    pub approach: Option<Approach>,
    /// A shipped active curve by name (default `chapter`).
    pub curve: Option<String>,
    /// The curve's parameters as given, in the order written (`lambda_min = 0.7`).
    #[serde(skip)]
    pub curve_parameters: Vec<(String, f64)>,
    /// Default law of the studies.
    pub law: Option<LawKind>,
    /// Default coupling of the studies.
    pub coupling: Option<CouplingKind>,
    /// Tangent of the frozen model.
    pub frozen_tangent: Option<FrozenTangent>,
    /// What the energy law does below λ_min.
    pub below_minimum: Option<BelowMinimum>,
    /// The active-strain map: "chapter" (default) | "volume-preserving".
    pub map: Option<ActiveStrainMap>,
    /// Default damage values d ∈ [0, 1].
    pub damage: Option<Vec<f64>>,
    /// Coefficients of the explicit law (eq. (14)).
    pub explicit: Option<ExplicitSpec>,
    /// How the implicit and energy laws are evaluated (default `exact`).
    pub representation: Option<RepresentationKind>,
    /// Stretch range `[λ_lo, λ_hi]` [-] of the tables (default `[0.5, 1.6]`; the exact solve
    /// outside); only with `representation = "tabulated"`.
    pub table_stretches: Option<[f64; 2]>,
    /// The force–velocity factor of activation-in-time studies (default none: f_v = 1).
    pub force_velocity: Option<ForceVelocity>,
}

impl Serialize for ActivationSpec {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(None)?;
        if let Some(v) = &self.approach {
            map.serialize_entry("approach", v)?;
        }
        if let Some(v) = &self.curve {
            map.serialize_entry("curve", v)?;
        }
        for (name, value) in &self.curve_parameters {
            map.serialize_entry(name, value)?;
        }
        macro_rules! entries {
            ($($key:ident),*) => {$(
                if let Some(v) = &self.$key {
                    map.serialize_entry(stringify!($key), v)?;
                }
            )*};
        }
        entries!(
            law,
            coupling,
            frozen_tangent,
            below_minimum,
            map,
            damage,
            explicit,
            representation,
            table_stretches,
            force_velocity
        );
        map.end()
    }
}

/// The names of every shipped curve's parameters: the keys of `[activation]` that the scene
/// reader hands to the curve.
pub fn curve_parameter_names() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    for c in CURVES {
        for p in c.parameters {
            if !names.contains(&p.name) {
                names.push(p.name);
            }
        }
    }
    names
}

impl ActivationSpec {
    /// The active curve it describes, validated; errors name the key as a scene writes it
    /// (`activation.curve`, `activation.k`).
    pub fn build_curve(&self) -> Result<ActiveCurve, SpecError> {
        let name = self.curve.as_deref().unwrap_or(CURVES[0].name);
        let Some(entry) = CurveEntry::find(name) else {
            let names: Vec<&str> = CURVES.iter().map(|c| c.name).collect();
            return Err(SpecError::new(
                "activation.curve",
                format!("{name:?}"),
                format!(
                    "unknown active curve; the shipped ones are {}",
                    names.join(", ")
                ),
            ));
        };
        let listed = || {
            let v: Vec<String> = entry
                .parameters
                .iter()
                .map(|p| format!("{} [{}]", p.name, p.unit))
                .collect();
            v.join(", ")
        };
        if let Some((key, value)) = self
            .curve_parameters
            .iter()
            .find(|(n, _)| !entry.parameters.iter().any(|p| p.name == n))
        {
            return Err(SpecError::new(
                format!("activation.{key}"),
                value,
                format!(
                    "the {} curve has no parameter {key}; its parameters are {}",
                    entry.name,
                    listed()
                ),
            ));
        }
        let mut values = Vec::with_capacity(entry.parameters.len());
        for p in entry.parameters {
            let given = self
                .curve_parameters
                .iter()
                .find(|(n, _)| n == p.name)
                .map(|(_, v)| *v);
            match given.or(p.default) {
                Some(v) => values.push(v),
                None => {
                    return Err(SpecError::new(
                        format!("activation.{}", p.name),
                        "(missing)",
                        format!("the {} curve needs {} [{}]", entry.name, p.name, p.unit),
                    ))
                }
            }
        }
        entry
            .build(&values)
            .map_err(|e| SpecError::model("activation", e))
    }

    /// The curve as a scene writes it: its name and every parameter.
    pub fn written_curve(curve: &ActiveCurve) -> (String, Vec<(String, f64)>) {
        (
            curve.name().to_string(),
            curve
                .parameters()
                .iter()
                .zip(curve.parameter_values())
                .map(|(p, v)| (p.name.to_string(), v))
                .collect(),
        )
    }
}

/// `explicit = { a = 1.0133, b = 0.2050 }`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExplicitSpec {
    /// a [-].
    pub a: Option<f64>,
    /// b [-].
    pub b: Option<f64>,
}

/// How incompressibility is imposed (`[incompressibility]`): `kind = "exact"` (default, the
/// chapter's J = 1 by a Lagrange multiplier), or a volumetric energy U(J) added to the material
/// ([`crate::volumetric`]): `"quadratic"` (κ/2)(J − 1)², `"logarithmic"` (κ/4)(J² − 1 − 2 ln J)
/// with `kappa` in kPa, or `"4c-giantesio"` μ/(4κ) J^(−2κ) (4C's `MAT_Muscle_Giantesio`) with
/// `kappa` a dimensionless exponent and `mu` in kPa (default: the energy's μ).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IncompressibilitySpec {
    /// `exact`, `quadratic`, `logarithmic` or `4c-giantesio`.
    pub kind: Option<String>,
    /// κ: bulk modulus \[kPa\] (quadratic, logarithmic) or exponent [-] (4c-giantesio).
    pub kappa: Option<f64>,
    /// μ \[kPa\] of the 4c-giantesio form.
    pub mu: Option<f64>,
}

impl IncompressibilitySpec {
    /// The volumetric energy (`None`: exact) for `energy`, its linear term chosen so that the
    /// passive reference is stress free ([`crate::uniaxial::reference_stress`]); errors name the
    /// keys relative to `[incompressibility]`.
    pub fn build(&self, energy: &Energy) -> Result<Option<Volumetric>, SpecError> {
        let kind = self.kind.as_deref().unwrap_or("exact");
        let kappa = || {
            self.kappa.ok_or_else(|| {
                SpecError::new(
                    "kappa",
                    "(missing)",
                    format!("kind = \"{kind}\" needs kappa (finite, > 0)"),
                )
            })
        };
        let form =
            match kind {
                "exact" => {
                    for (key, v) in [("kappa", self.kappa), ("mu", self.mu)] {
                        if let Some(v) = v {
                            return Err(SpecError::new(
                                key,
                                v,
                                "kind = \"exact\" (J = 1) takes no volumetric parameter",
                            ));
                        }
                    }
                    return Ok(None);
                }
                "quadratic" => VolumetricForm::Quadratic { kappa: kappa()? },
                "logarithmic" => VolumetricForm::Logarithmic { kappa: kappa()? },
                "4c-giantesio" => VolumetricForm::Giantesio4C {
                    kappa: kappa()?,
                    mu: match self.mu.or_else(|| EnergySpec::written(energy).get("mu")) {
                        Some(mu) => mu,
                        None => return Err(SpecError::new(
                            "mu",
                            "(missing)",
                            "the energy has no parameter mu: give the 4c-giantesio form's mu [kPa]",
                        )),
                    },
                },
                other => {
                    return Err(SpecError::new(
                        "kind",
                        format!("\"{other}\""),
                        "expected \"exact\", \"quadratic\", \"logarithmic\" or \"4c-giantesio\"",
                    ))
                }
            };
        if self.mu.is_some() && !matches!(form, VolumetricForm::Giantesio4C { .. }) {
            return Err(SpecError::new(
                "mu",
                self.mu.unwrap_or_default(),
                "only the 4c-giantesio form takes mu",
            ));
        }
        let s0 =
            crate::uniaxial::reference_stress(energy).map_err(|e| SpecError::model("kind", e))?;
        Volumetric::new(form, s0)
            .map(Some)
            .map_err(|e| SpecError::model("", e))
    }

    /// The spec as resolved: every value written out.
    pub fn written(volumetric: Option<&Volumetric>) -> Self {
        match volumetric.map(Volumetric::form) {
            None => Self {
                kind: Some("exact".into()),
                ..Self::default()
            },
            Some(form) => {
                let (kappa, mu) = match form {
                    VolumetricForm::Quadratic { kappa } | VolumetricForm::Logarithmic { kappa } => {
                        (kappa, None)
                    }
                    VolumetricForm::Giantesio4C { kappa, mu } => (kappa, Some(mu)),
                };
                Self {
                    kind: Some(form.name().into()),
                    kappa: Some(kappa),
                    mu,
                }
            }
        }
    }
}

impl Models {
    /// The models of a `[material]` and an `[activation]` as written: every value left out is the
    /// chapter's, every number is validated by the core constructor that owns it, and errors name
    /// the key as a scene writes it (`material.mu`, `activation.explicit.a`). The activation's
    /// law, coupling and damage values are the studies' defaults, not read here. The scene
    /// resolves its tables here, and so does the Python package's `Material`.
    pub fn from_spec(
        material: &MaterialSpec,
        activation: &ActivationSpec,
    ) -> Result<Self, SpecError> {
        let (energy, fibre) = material.build().map_err(|e| e.within("material"))?;
        let act = activation;
        let curve = act.build_curve()?;
        let (a, b) = ExplicitLaw::paper().coefficients();
        let ex = act.explicit.clone().unwrap_or_default();
        let explicit = (ex.a.unwrap_or(a), ex.b.unwrap_or(b));
        ExplicitLaw::new(explicit.0, explicit.1, GiantesioMusesti::paper(), curve)
            .map_err(|e| SpecError::model("activation.explicit", e))?;
        Ok(Self {
            energy,
            fibre,
            curve,
            explicit,
            frozen_tangent: act.frozen_tangent.unwrap_or_default(),
            below_minimum: act.below_minimum.unwrap_or_default(),
            approach: act.approach.unwrap_or_default(),
            map: act.map.unwrap_or_default(),
            force_velocity: match act.force_velocity {
                Some(fv) => Some(
                    fv.validated()
                        .map_err(|e| SpecError::model("activation", e))?,
                ),
                None => None,
            },
            representation: representation(act)?,
            volumetric: None,
        })
    }

    /// `representation` and `table_stretches` as a scene writes them.
    pub fn representation_spec(&self) -> (RepresentationKind, Option<[f64; 2]>) {
        match self.representation {
            LawRepresentation::Exact => (RepresentationKind::Exact, None),
            LawRepresentation::Tabulated(t) => (
                RepresentationKind::Tabulated,
                Some([t.lambda_lo, t.lambda_hi]),
            ),
        }
    }
}

/// The law representation of `[activation]`: tables on `table_stretches` (validated:
/// 0 < λ_lo < λ_hi, finite) with the default tolerances of [`TableSpec`].
fn representation(act: &ActivationSpec) -> Result<LawRepresentation, SpecError> {
    let shown = |[lo, hi]: [f64; 2]| format!("[{lo}, {hi}]");
    match (act.representation.unwrap_or_default(), act.table_stretches) {
        (RepresentationKind::Exact, None) => Ok(LawRepresentation::Exact),
        (RepresentationKind::Exact, Some(range)) => Err(SpecError::new(
            "activation.table_stretches",
            shown(range),
            "applies only with activation.representation = \"tabulated\"",
        )),
        (RepresentationKind::Tabulated, range) => {
            let mut spec = TableSpec::default();
            if let Some([lo, hi]) = range {
                spec.lambda_lo = lo;
                spec.lambda_hi = hi;
            }
            spec.validate().map_err(|_| {
                SpecError::new(
                    "activation.table_stretches",
                    shown([spec.lambda_lo, spec.lambda_hi]),
                    "the table's stretch range needs finite 0 < λ_lo < λ_hi",
                )
            })?;
            Ok(LawRepresentation::Tabulated(spec))
        }
    }
}
