//! Keyword choices → a core [`Muscle`], through the scene's own models
//! ([`activemuscle::models`]): the keywords are the keys of a scene's `[material]` and
//! `[activation]` tables, gathered into a [`MaterialSpec`] and an [`ActivationSpec`] and resolved
//! by [`Models::from_spec`], the function that resolves a scene's. Names, defaults (the
//! chapter's values), rules and messages are therefore the scene's; an error names the keyword
//! (`mu = -1: ...`) where a scene names `material.mu`. Beyond a scene's laws, `law` takes
//! `"passive"` and `"constant"` (with `gamma`): a uniaxial study's passive and constant-γ curves.

use activemuscle::active::{ConstantLaw, CurveEntry, ForceVelocity, Law, CURVES};
use activemuscle::app_error::SpecError;
use activemuscle::energy::{Energy, ShippedEnergy, SHIPPED};
use activemuscle::models::{
    ActivationSpec, CouplingKind, DeclaredSpec, ExplicitSpec, LawKind, MaterialSpec, ModelChoice,
    Models,
};
use activemuscle::Muscle;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::de::value::{Error as ValueError, StrDeserializer};
use serde::de::{DeserializeOwned, IntoDeserializer};
use std::collections::HashMap;

/// What `law = "..."` names.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LawChoice {
    /// γ ≡ 0.
    Passive,
    /// γ held at the given value.
    Constant,
    /// One of a scene's activation laws.
    Active(LawKind),
}

/// The value `value` of the scene's enumeration `T` (its serde names: `"frozen"`,
/// `"zero-work"`, ...), or the scene's message naming `key`.
pub fn named<T: DeserializeOwned>(key: &str, value: &str) -> Result<T, SpecError> {
    let de: StrDeserializer<'_, ValueError> = value.into_deserializer();
    T::deserialize(de).map_err(|e| SpecError::new(key, format!("{value:?}"), e.to_string()))
}

impl LawChoice {
    /// `law`: `"passive"`, `"constant"` or a scene's law; `None` is the scene's default law.
    pub fn parse(law: Option<&str>) -> Result<Self, SpecError> {
        Ok(match law {
            Some("passive") => LawChoice::Passive,
            Some("constant") => LawChoice::Constant,
            Some(name) => LawChoice::Active(named("law", name).map_err(|e| SpecError {
                rule: format!("{} (or \"passive\", or \"constant\" with gamma)", e.rule),
                ..e
            })?),
            None => LawChoice::Active(LawKind::default()),
        })
    }
}

/// Keys of the scene's tables as this module names them: without `material.` or `activation.`.
fn as_keyword(e: SpecError) -> SpecError {
    let key = ["material.", "activation."]
        .iter()
        .find_map(|p| e.key.strip_prefix(p))
        .map_or(e.key.clone(), str::to_string);
    SpecError { key, ..e }
}

/// The muscle of `material` and `activation` (the activation's `coupling`, `None` the scene's
/// default) with activation law `law` (`gamma` for the constant law only) and damage `damage`.
pub fn muscle(
    material: &MaterialSpec,
    activation: &ActivationSpec,
    law: LawChoice,
    gamma: Option<f64>,
    damage: f64,
) -> Result<Muscle<Energy>, SpecError> {
    let models = Models::from_spec(material, activation).map_err(as_keyword)?;
    let coupling: CouplingKind = activation.coupling.unwrap_or_default();
    if let (Some(g), false) = (gamma, law == LawChoice::Constant) {
        return Err(SpecError::new(
            "gamma",
            g,
            "applies to law = \"constant\" only",
        ));
    }
    let model = |e: activemuscle::Error| SpecError::model("", e);
    // A law without a map of its own (passive, constant) takes the scene's active-strain map.
    let fixed = |law: Law<Energy>| {
        Muscle::new(
            models.energy.clone(),
            law,
            damage,
            models.coupling(coupling),
        )
        .and_then(|m| m.with_map(models.map))
        .map_err(model)
    };
    match law {
        LawChoice::Passive => fixed(Law::Passive),
        LawChoice::Constant => {
            let gamma = gamma.ok_or_else(|| {
                SpecError::new(
                    "gamma",
                    "(missing)",
                    "law = \"constant\" needs gamma in [0, 1)",
                )
            })?;
            fixed(Law::Constant(
                ConstantLaw::new(gamma).map_err(|e| SpecError::model("gamma", e))?,
            ))
        }
        LawChoice::Active(law) => {
            models
                .supports(law)
                .map_err(|rule| SpecError::new("law", format!("{:?}", law.name()), rule))?;
            models
                .muscle(ModelChoice {
                    law,
                    coupling,
                    damage,
                })
                .map_err(model)
        }
    }
}

/// The keywords of `Material(...)`, gathered into a scene's tables: every parameter name comes
/// from the registries ([`activemuscle::energy::SHIPPED`], [`activemuscle::active::CURVES`]).
#[derive(Debug, Default)]
pub struct Choices {
    material: MaterialSpec,
    activation: ActivationSpec,
    law: Option<String>,
    gamma: Option<f64>,
    damage: f64,
    /// Numeric keywords that are neither options nor known yet to be the energy's or the
    /// curve's: sorted out once the energy and the curve are known.
    parameters: Vec<(String, f64)>,
}

/// The keywords that are options (not parameters), as the error for an unknown one lists them.
const OPTIONS: &[&str] = &[
    "energy",
    "W",
    "parameters",
    "name",
    "approach",
    "curve",
    "law",
    "gamma",
    "coupling",
    "frozen_tangent",
    "damage",
    "explicit",
    "below_minimum",
    "map",
    "representation",
    "table_stretches",
    "force_velocity",
];

fn keyword_error(key: &str, rule: impl Into<String>) -> PyErr {
    PyValueError::new_err(SpecError::new(key, "(given)", rule.into()).to_string())
}

impl Choices {
    /// Takes one keyword.
    pub fn take(&mut self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let text = || -> PyResult<String> { value.extract() };
        let err = |e: SpecError| PyValueError::new_err(e.to_string());
        let act = &mut self.activation;
        match key {
            "energy" => self.material.energy.energy = text()?,
            "W" => self.material.energy.formula.formula = Some(text()?),
            "name" => self.material.energy.formula.name = Some(text()?),
            "parameters" => self.material.energy.formula.parameters = declared(value)?,
            "curve" => act.curve = Some(text()?),
            "law" => self.law = Some(text()?),
            "gamma" => self.gamma = Some(value.extract()?),
            "damage" => self.damage = value.extract()?,
            "approach" => act.approach = Some(named("approach", &text()?).map_err(err)?),
            "coupling" => act.coupling = Some(named("coupling", &text()?).map_err(err)?),
            "frozen_tangent" => {
                act.frozen_tangent = Some(named("frozen_tangent", &text()?).map_err(err)?)
            }
            "below_minimum" => {
                act.below_minimum = Some(named("below_minimum", &text()?).map_err(err)?)
            }
            "map" => act.map = Some(named("map", &text()?).map_err(err)?),
            "representation" => {
                act.representation = Some(named("representation", &text()?).map_err(err)?)
            }
            "table_stretches" => act.table_stretches = Some(value.extract()?),
            "explicit" => {
                let m: HashMap<String, f64> = value.extract()?;
                if let Some(k) = m.keys().find(|k| *k != "a" && *k != "b") {
                    return Err(err(SpecError::new(
                        format!("explicit.{k}"),
                        m[k],
                        "unknown key: eq. (14) has coefficients a and b",
                    )));
                }
                act.explicit = Some(ExplicitSpec {
                    a: m.get("a").copied(),
                    b: m.get("b").copied(),
                });
            }
            "force_velocity" => {
                let m: HashMap<String, f64> = value.extract()?;
                let keys = ["min_rate", "ke", "kc", "de", "dc"];
                if let Some(k) = m.keys().find(|k| !keys.contains(&k.as_str())) {
                    return Err(keyword_error(
                        &format!("force_velocity.{k}"),
                        format!("unknown key: the keys are {}", keys.join(", ")),
                    ));
                }
                let get = |k: &str| {
                    m.get(k).copied().ok_or_else(|| {
                        keyword_error(
                            &format!("force_velocity.{k}"),
                            "missing: give all of min_rate [1/s], ke, kc, de, dc",
                        )
                    })
                };
                act.force_velocity = Some(ForceVelocity {
                    min_rate: get("min_rate")?,
                    ke: get("ke")?,
                    kc: get("kc")?,
                    de: get("de")?,
                    dc: get("dc")?,
                });
            }
            _ => self.parameter(key, value)?,
        }
        Ok(())
    }

    /// A numeric keyword that is no option: a parameter of an energy or a curve, sorted out in
    /// [`Self::muscle`]; any other name is refused with the list of keywords.
    fn parameter(&mut self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let known = SHIPPED
            .iter()
            .flat_map(|e| e.parameters.iter())
            .chain(CURVES.iter().flat_map(|c| c.parameters.iter()))
            .any(|p| p.name == key);
        if !known {
            let mut names: Vec<&str> = SHIPPED
                .iter()
                .flat_map(|e| e.parameters.iter().map(|p| p.name.as_ref()))
                .chain(
                    CURVES
                        .iter()
                        .flat_map(|c| c.parameters.iter().map(|p| p.name.as_ref())),
                )
                .collect();
            names.sort_unstable();
            names.dedup();
            return Err(keyword_error(
                key,
                format!(
                    "unknown keyword: the keywords are {} and the energies' and curves' parameters ({})",
                    OPTIONS.join(", "),
                    names.join(", ")
                ),
            ));
        }
        self.parameters.push((key.to_string(), value.extract()?));
        Ok(())
    }

    /// The muscle the keywords describe: each parameter goes to the chosen energy if it has
    /// one of that name, else to the chosen curve, else to whichever registry knows the name
    /// (whose message then says that the chosen one has no such parameter).
    pub fn muscle(mut self) -> Result<Muscle<Energy>, SpecError> {
        let energy = ShippedEnergy::find(&self.material.energy.energy);
        let curve = CurveEntry::find(self.activation.curve.as_deref().unwrap_or(CURVES[0].name));
        let has = |params: Option<&[activemuscle::energy::Parameter]>, n: &str| {
            params.is_some_and(|ps| ps.iter().any(|p| p.name == n))
        };
        let in_any_energy = |n: &str| SHIPPED.iter().any(|e| has(Some(e.parameters), n));
        for (name, value) in std::mem::take(&mut self.parameters) {
            let to_energy = has(energy.map(|e| e.parameters), &name)
                || (!has(curve.map(|c| c.parameters), &name) && in_any_energy(&name));
            if to_energy {
                self.material.energy.parameters.push((name, value));
            } else {
                self.activation.curve_parameters.push((name, value));
            }
        }
        muscle(
            &self.material,
            &self.activation,
            LawChoice::parse(self.law.as_deref())?,
            self.gamma,
            self.damage,
        )
    }
}

/// `parameters = {"mu": 0.2, "k1": {"value": 1.0, "unit": "kPa", "range": [0, inf], "bounds":
/// [0, 50], "symbol": "k₁"}}`: a formula energy's declared parameters (a number is the value).
fn declared(value: &Bound<'_, PyAny>) -> PyResult<Vec<(String, DeclaredSpec)>> {
    let table = value.cast::<PyDict>().map_err(|_| {
        keyword_error(
            "parameters",
            "a dict {name: value or {value, unit, symbol, range, bounds}}",
        )
    })?;
    let mut out = Vec::with_capacity(table.len());
    for (name, entry) in table.iter() {
        let name: String = name.extract()?;
        if let Ok(v) = entry.extract::<f64>() {
            let spec = DeclaredSpec {
                value: Some(v),
                ..DeclaredSpec::default()
            };
            out.push((name, spec));
            continue;
        }
        let fields = entry.cast::<PyDict>().map_err(|_| {
            keyword_error(
                &format!("parameters.{name}"),
                "a number (the value) or a dict {value, unit, symbol, range, bounds}",
            )
        })?;
        let mut spec = DeclaredSpec::default();
        for (field, v) in fields.iter() {
            let field: String = field.extract()?;
            let pair = |v: &Bound<'_, PyAny>| -> PyResult<[f64; 2]> {
                let p: Vec<f64> = v.extract()?;
                <[f64; 2]>::try_from(p).map_err(|_| {
                    keyword_error(
                        &format!("parameters.{name}.{field}"),
                        "[lower, upper]: two numbers (±inf allowed)",
                    )
                })
            };
            match field.as_str() {
                "value" => spec.value = Some(v.extract()?),
                "unit" => spec.unit = Some(v.extract()?),
                "symbol" => spec.symbol = Some(v.extract()?),
                "range" => spec.range = Some(pair(&v)?),
                "bounds" => spec.bounds = Some(pair(&v)?),
                _ => {
                    return Err(keyword_error(
                        &format!("parameters.{name}.{field}"),
                        "unknown key: a parameter has value, unit, symbol, range, bounds",
                    ))
                }
            }
        }
        out.push((name, spec));
    }
    Ok(out)
}
