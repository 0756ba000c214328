//! The scene's `[material]`, `[activation]` and `[incompressibility]` tables as written
//! ([`MaterialSpec`], [`ActivationSpec`], [`IncompressibilitySpec`]) and how they build the
//! [`Models`]: an [`EnergySpec`] (a shipped energy by name, parameters by name, or a formula,
//! [`super::formula`]) builds an [`Energy`] from the registry [`crate::energy::SHIPPED`].

use super::choice::{CouplingKind, LawKind, RepresentationKind};
use super::factory::Models;
use super::formula::{read_parameters, FormulaSpec};
use crate::active::ActiveStrainMap;
use crate::active::{
    ActiveCurve, Approach, BelowMinimum, CurveEntry, ExplicitLaw, ForceVelocity, FrozenTangent,
    LawRepresentation, TableSpec, CURVES,
};
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
            if !names.contains(&p.name.as_ref()) {
                names.push(p.name.as_ref());
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
            .find(|(n, _)| !entry.parameters.iter().any(|p| p.name == n.as_str()))
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
                .find(|(n, _)| *n == p.name)
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
