//! The scene's `[material]` and `[incompressibility]` tables as written ([`MaterialSpec`],
//! [`IncompressibilitySpec`]) and how they build the [`Models`] with `[activation]`
//! ([`ActivationSpec`]): an [`EnergySpec`] (a shipped energy by name, parameters by name, or a
//! formula, [`super::formula`]) builds an [`Energy`] from the registry
//! [`crate::energy::SHIPPED`].

use super::activation::ActivationSpec;
use super::choice::RepresentationKind;
use super::factory::Models;
use super::formula::{read_parameters, FormulaSpec};
use crate::active::{ExplicitLaw, LawRepresentation};
use crate::app_error::SpecError;
use crate::energy::{Energy, GiantesioMusesti, Parametric, ShippedEnergy, FORMULA, SHIPPED};
use crate::text::shortest;
use crate::volumetric::{Volumetric, VolumetricForm};
use crate::StrainEnergy;
use serde::de::{MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// A shipped energy by name with its parameters by name (`{ energy = "ehret-bol-itskov",
/// alpha = 10.0 }`); a parameter left out takes the chapter's value of that energy
/// ([`crate::energy::Parameter::default`]). Or `energy = "formula"` with `W`, its declared
/// `parameters` and a `name` ([`FormulaSpec`]).
#[derive(Debug, Clone, PartialEq)]
pub struct EnergySpec {
    /// Name of a shipped energy (default: the first, the chapter's), or `formula`.
    pub energy: String,
    /// Parameters of a shipped energy as given, in the order written.
    pub parameters: Vec<(String, f64)>,
    /// W, its parameters and its name (`energy = "formula"` only).
    pub formula: FormulaSpec,
}

impl Default for EnergySpec {
    fn default() -> Self {
        Self {
            energy: SHIPPED[0].name.to_string(),
            parameters: Vec::new(),
            formula: FormulaSpec::default(),
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
        if self.energy == FORMULA {
            return self.build_formula();
        }
        let Some(shipped) = ShippedEnergy::find(&self.energy) else {
            let names: Vec<&str> = SHIPPED.iter().map(|e| e.name).collect();
            return Err(SpecError::new(
                "energy",
                format!("{:?}", self.energy),
                format!(
                    "unknown energy; the shipped ones are {}, or \"formula\" with W = \"...\"",
                    names.join(", ")
                ),
            ));
        };
        if self.formula.is_given() {
            let key = if self.formula.formula.is_some() {
                "W"
            } else if self.formula.name.is_some() {
                "name"
            } else {
                "parameters"
            };
            return Err(SpecError::new(
                key,
                "(given)",
                format!("{key} is a key of energy = \"formula\"; the {} energy takes its parameters by name ({})", shipped.name, parameter_list(shipped)),
            ));
        }
        if let Some((name, value)) = self
            .parameters
            .iter()
            .find(|(n, _)| !shipped.parameters.iter().any(|p| p.name == n.as_str()))
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
            match self.get(&p.name).or(p.default) {
                Some(v) => values.push(v),
                None => {
                    return Err(SpecError::new(
                        p.name.as_ref(),
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

    /// The formula energy of `energy = "formula"`: no parameter flat beside it.
    fn build_formula(&self) -> Result<Energy, SpecError> {
        if let Some((name, value)) = self.parameters.first() {
            return Err(SpecError::new(
                name.as_str(),
                value,
                format!("a formula energy declares its parameters in a table: parameters = {{ {name} = {{ value = {}, unit = \"kPa\", range = [0, inf] }} }}", crate::text::shortest(*value)),
            ));
        }
        self.formula.build().map(Energy::Formula)
    }

    /// The spec of a built energy: its name and every parameter it holds, given or default (what
    /// a printed scene shows, so that it is the energy that runs).
    pub fn written(e: &Energy) -> Self {
        if let Energy::Formula(f) = e {
            return Self {
                energy: FORMULA.to_string(),
                parameters: Vec::new(),
                formula: FormulaSpec::written(f),
            };
        }
        Self {
            energy: e.name().to_string(),
            parameters: e
                .parameters()
                .iter()
                .zip(e.parameter_values())
                .map(|(p, v)| (p.name.to_string(), v))
                .collect(),
            formula: FormulaSpec::default(),
        }
    }

    /// Writes the table's entries (`energy`, the parameters, a formula's `W`, `name`,
    /// `parameters`).
    fn serialize_entries<M: SerializeMap>(&self, map: &mut M) -> Result<(), M::Error> {
        map.serialize_entry("energy", &self.energy)?;
        for (name, value) in &self.parameters {
            map.serialize_entry(name, value)?;
        }
        self.formula.serialize_entries(map)
    }
}

impl Serialize for EnergySpec {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(None)?;
        self.serialize_entries(&mut map)?;
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
            ("W", _) => spec.formula.formula = Some(map.next_value()?),
            ("name", _) => spec.formula.name = Some(map.next_value()?),
            ("parameters", _) => spec.formula.parameters = read_parameters(&mut map)?,
            ("fibre", Some(slot)) => {
                *slot = Some(map.next_value::<crate::fixed_length::Exactly<f64, 3>>()?.0)
            }
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
                            "energy = \"name\", fibre = [x, y, z] and the energy's parameters (a formula: W, name, parameters)"
                        } else {
                            "energy = \"name\" and the energy's parameters (a formula: W, name, parameters)"
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
        let mut map = serializer.serialize_map(None)?;
        self.energy.serialize_entries(&mut map)?;
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
        // A direction: scaled by its largest component first, so that neither [1e-300, 0, 0]
        // underflows nor [1e300, 1e300, 0] overflows on the way to its norm.
        let largest = fibre.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let rule = if fibre.iter().any(|x| !x.is_finite()) {
            Some("the fibre direction must have finite components")
        } else if largest == 0.0 {
            Some("the fibre direction must be a non-zero vector")
        } else {
            None
        };
        if let Some(rule) = rule {
            let shown: Vec<String> = fibre.iter().map(|x| shortest(*x)).collect();
            return Err(SpecError::new(
                "fibre",
                format!("[{}]", shown.join(", ")),
                rule,
            ));
        }
        let scaled = fibre.map(|x| x / largest);
        let norm = scaled.iter().map(|x| x * x).sum::<f64>().sqrt();
        Ok((energy, scaled.map(|x| x / norm)))
    }
}

/// How incompressibility is imposed (`[incompressibility] kind = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IncompressibilityKind {
    /// J = 1 by a Lagrange multiplier (the chapter's).
    #[default]
    Exact,
    /// U = (κ/2)(J − 1)², κ \[kPa\].
    Quadratic,
    /// U = (κ/4)(J² − 1 − 2 ln J), κ \[kPa\].
    Logarithmic,
    /// U = μ/(4κ) J^(−2κ) (4C's `MAT_Muscle_Giantesio`), κ [-], μ \[kPa\].
    #[serde(rename = "4c-giantesio")]
    Giantesio4C,
}

impl IncompressibilityKind {
    /// Name in scene files: exact, quadratic, logarithmic, 4c-giantesio.
    pub fn name(self) -> &'static str {
        match self {
            IncompressibilityKind::Exact => "exact",
            IncompressibilityKind::Quadratic => "quadratic",
            IncompressibilityKind::Logarithmic => "logarithmic",
            IncompressibilityKind::Giantesio4C => "4c-giantesio",
        }
    }
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
    pub kind: Option<IncompressibilityKind>,
    /// κ: bulk modulus \[kPa\] (quadratic, logarithmic) or exponent [-] (4c-giantesio).
    pub kappa: Option<f64>,
    /// μ \[kPa\] of the 4c-giantesio form.
    pub mu: Option<f64>,
}

/// Refuses a volumetric energy whose bulk modulus K = U″(1) exceeds
/// [`crate::volumetric::MAX_STIFFNESS_RATIO`] times the passive energy's initial modulus E₀
/// along the fibres ([`crate::uniaxial::initial_modulus`]), at `kappa` (given as `kappa`).
fn stiff_enough(volumetric: &Volumetric, energy: &Energy, kappa: f64) -> Result<(), SpecError> {
    use crate::volumetric::MAX_STIFFNESS_RATIO;
    let e0 = crate::uniaxial::initial_modulus(energy).map_err(|e| SpecError::model("kind", e))?;
    let k = volumetric.bulk_modulus();
    if k.is_finite() && k <= MAX_STIFFNESS_RATIO * e0.abs() {
        return Ok(());
    }
    Err(SpecError::new(
        "kappa",
        kappa,
        format!(
            "the bulk modulus U''(1) = {} kPa is more than {} times the passive energy's initial \
             modulus along the fibres (E₀ = {} kPa): it may be at most {} kPa. Stiffer, J − 1 ≈ \
             σ/U''(1) drops below what f64 resolves and the solves fail (the homogeneous tests' \
             lateral equilibrium from about 1e16 E₀); no solid is stiffer than diamond (4.4e8 \
             kPa); for an incompressible body use kind = \"exact\"",
            shortest(k),
            format_args!("{MAX_STIFFNESS_RATIO:e}"),
            crate::text::significant(e0, 4),
            format_args!("{:.2e}", MAX_STIFFNESS_RATIO * e0.abs())
        ),
    ))
}

impl IncompressibilitySpec {
    /// The volumetric energy (`None`: exact) for `energy`, its linear term chosen so that the
    /// passive reference is stress free ([`crate::uniaxial::reference_stress`]); errors name the
    /// keys relative to `[incompressibility]`.
    pub fn build(&self, energy: &Energy) -> Result<Option<Volumetric>, SpecError> {
        let kind = self.kind.unwrap_or_default();
        let kappa = || {
            self.kappa.ok_or_else(|| {
                SpecError::new(
                    "kappa",
                    "(missing)",
                    format!("kind = \"{}\" needs kappa (finite, > 0)", kind.name()),
                )
            })
        };
        let form = match kind {
            IncompressibilityKind::Exact => {
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
            IncompressibilityKind::Quadratic => VolumetricForm::Quadratic { kappa: kappa()? },
            IncompressibilityKind::Logarithmic => VolumetricForm::Logarithmic { kappa: kappa()? },
            IncompressibilityKind::Giantesio4C => VolumetricForm::Giantesio4C {
                kappa: kappa()?,
                mu: self.mu_of(energy)?,
            },
        };
        if let (Some(mu), false) = (self.mu, kind == IncompressibilityKind::Giantesio4C) {
            return Err(SpecError::new(
                "mu",
                mu,
                "only the 4c-giantesio form takes mu",
            ));
        }
        let s0 =
            crate::uniaxial::reference_stress(energy).map_err(|e| SpecError::model("kind", e))?;
        let volumetric = Volumetric::new(form, s0).map_err(|e| SpecError::model("", e))?;
        stiff_enough(&volumetric, energy, self.kappa.unwrap_or_default())?;
        Ok(Some(volumetric))
    }

    /// μ of the 4c-giantesio form: as given, else the energy's.
    fn mu_of(&self, energy: &Energy) -> Result<f64, SpecError> {
        self.mu
            .or_else(|| EnergySpec::written(energy).get("mu"))
            .ok_or_else(|| {
                SpecError::new(
                    "mu",
                    "(missing)",
                    "the energy has no parameter mu: give the 4c-giantesio form's mu [kPa]",
                )
            })
    }

    /// The spec as resolved: every value written out.
    pub fn written(volumetric: Option<&Volumetric>) -> Self {
        let (kind, kappa, mu) = match volumetric.map(Volumetric::form) {
            None => (IncompressibilityKind::Exact, None, None),
            Some(VolumetricForm::Quadratic { kappa }) => {
                (IncompressibilityKind::Quadratic, Some(kappa), None)
            }
            Some(VolumetricForm::Logarithmic { kappa }) => {
                (IncompressibilityKind::Logarithmic, Some(kappa), None)
            }
            Some(VolumetricForm::Giantesio4C { kappa, mu }) => {
                (IncompressibilityKind::Giantesio4C, Some(kappa), Some(mu))
            }
        };
        Self {
            kind: Some(kind),
            kappa,
            mu,
        }
    }
}

impl Models {
    /// The models of a `[material]`, an `[activation]` and an `[incompressibility]` (`None`:
    /// exact) as written: every value left out is the chapter's, every number is validated by the
    /// core constructor that owns it, and errors name the key as a scene writes it
    /// (`material.mu`, `activation.explicit.a`, `incompressibility.kappa`). The activation's
    /// approach, law, coupling and damage values are the studies' defaults
    /// ([`ActivationSpec::defaults`]), not read here. The scene resolves its tables here, and so
    /// does the Python package's `Material`.
    pub fn from_spec(
        material: &MaterialSpec,
        activation: &ActivationSpec,
        incompressibility: Option<&IncompressibilitySpec>,
    ) -> Result<Self, SpecError> {
        let (energy, fibre) = material.build().map_err(|e| e.within("material"))?;
        let act = activation;
        let curve = act.build_curve()?;
        let (a, b) = ExplicitLaw::paper().coefficients();
        let ex = act.explicit.clone().unwrap_or_default();
        let explicit = (ex.a.unwrap_or(a), ex.b.unwrap_or(b));
        ExplicitLaw::new(explicit.0, explicit.1, GiantesioMusesti::paper(), curve)
            .map_err(|e| SpecError::model("activation.explicit", e))?;
        let volumetric = match incompressibility {
            Some(inc) => inc
                .build(&energy)
                .map_err(|e| e.within("incompressibility"))?,
            None => None,
        };
        Ok(Self {
            energy,
            fibre,
            curve,
            explicit,
            frozen_tangent: act.frozen_tangent.unwrap_or_default(),
            below_minimum: act.below_minimum.unwrap_or_default(),
            map: act.map.unwrap_or_default(),
            force_velocity: match act.force_velocity {
                Some(fv) => Some(
                    fv.validated()
                        .map_err(|e| SpecError::model("activation", e))?,
                ),
                None => None,
            },
            representation: act.representation()?,
            volumetric,
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
