//! Keyword choices → a core [`Muscle`], through the scene's own models
//! ([`activemuscle::models`]): the keywords are the keys of a scene's `[material]` and
//! `[activation]` tables, gathered into a [`MaterialSpec`] and an [`ActivationSpec`] (its keys
//! and their types are the scene's own table, [`ActivationSpec::KEYS`] and
//! [`ActivationSpec::set`]) and resolved by [`Models::from_spec`], the function that resolves a
//! scene's. Names, defaults (the chapter's values), rules and messages are therefore the scene's;
//! an error names the keyword (`mu = -1: ...`) where a scene names `material.mu`, and a keyword
//! that does not apply to the approach is refused as a scene refuses it. Beyond a scene's laws,
//! `law` takes `"passive"` and `"constant"` (with `gamma`): a uniaxial study's passive and
//! constant-γ curves; `damage` is one value.

use activemuscle::active::{ConstantLaw, CurveEntry, Law, CURVES};
use activemuscle::app_error::SpecError;
use activemuscle::energy::{Energy, ShippedEnergy, SHIPPED};
use activemuscle::models::{
    ActivationSpec, DeclaredSpec, LawKind, MaterialSpec, ModelChoice, Models,
};
use activemuscle::Muscle;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde::de::value::{Error as ValueError, StrDeserializer};
use serde::de::{DeserializeOwned, IntoDeserializer};

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
    /// `law`: `"passive"`, `"constant"` or a scene's law.
    pub fn parse(law: &str) -> Result<Self, SpecError> {
        Ok(match law {
            "passive" => LawChoice::Passive,
            "constant" => LawChoice::Constant,
            name => LawChoice::Active(named("law", name).map_err(|e| SpecError {
                rule: format!("{} (or \"passive\", or \"constant\" with gamma)", e.rule),
                ..e
            })?),
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

/// The muscle of `material` and `activation` (its approach and coupling, `None` the scene's
/// defaults) with activation law `law` (`gamma` for the constant law only) and damage `damage`.
pub fn muscle(
    material: &MaterialSpec,
    activation: &ActivationSpec,
    law: Option<LawChoice>,
    gamma: Option<f64>,
    damage: f64,
) -> Result<Muscle<Energy>, SpecError> {
    let models = Models::from_spec(material, activation, None).map_err(as_keyword)?;
    let defaults = activation.defaults();
    let approach = defaults.approach;
    activation
        .refuse_inapplicable(&[approach])
        .map_err(as_keyword)?;
    let map = models
        .activation_map(approach)
        .map_err(|rule| SpecError::new("approach", format!("{:?}", approach.name()), rule))?;
    if let (Some(g), false) = (gamma, law == Some(LawChoice::Constant)) {
        return Err(SpecError::new(
            "gamma",
            g,
            "applies to law = \"constant\" only",
        ));
    }
    let model = |e: activemuscle::Error| SpecError::model("", e);
    // A law without a map of its own (passive, constant) takes the approach's map.
    let fixed = |law: Law<Energy>| {
        Muscle::new(
            models.energy.clone(),
            law,
            damage,
            models.coupling(defaults.coupling),
        )
        .and_then(|m| m.with_map(map))
        .map_err(model)
    };
    match law {
        Some(LawChoice::Passive) => fixed(Law::Passive),
        Some(LawChoice::Constant) => fixed(constant(approach, gamma)?),
        Some(LawChoice::Active(law)) => {
            models
                .supports(approach, law)
                .map_err(|rule| SpecError::new("law", format!("{:?}", law.name()), rule))?;
            models
                .muscle(ModelChoice {
                    approach,
                    law,
                    coupling: defaults.coupling,
                    damage,
                })
                .map_err(model)
        }
        // Left out: the scene's default law (an approach without a law reads none).
        None => models
            .muscle(ModelChoice {
                approach,
                law: defaults.law,
                coupling: defaults.coupling,
                damage,
            })
            .map_err(model),
    }
}

/// The constant law γ = `gamma` of `approach` (which must have an activation variable).
fn constant(
    approach: activemuscle::active::Approach,
    gamma: Option<f64>,
) -> Result<Law<Energy>, SpecError> {
    if approach.variable().is_none() {
        return Err(SpecError::new(
            "law",
            "\"constant\"",
            format!(
                "a constant activation holds the approach's activation variable; approach = {:?} has none: {}",
                approach.name(),
                approach.no_law()
            ),
        ));
    }
    let gamma = gamma.ok_or_else(|| {
        SpecError::new(
            "gamma",
            "(missing)",
            "law = \"constant\" needs gamma in [0, 1)",
        )
    })?;
    Ok(Law::Constant(
        ConstantLaw::new(gamma).map_err(|e| SpecError::model("gamma", e))?,
    ))
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

/// The keywords Python reads itself (the others are the `[activation]` keys,
/// [`ActivationSpec::KEYS`], and the energies' and curves' parameters); `W`, `name` and
/// `parameters` are a formula energy's.
const OWN: &[&str] = &[
    "energy",
    "W",
    "name",
    "parameters",
    "law",
    "gamma",
    "damage",
];

fn keyword_error(key: &str, rule: impl Into<String>) -> PyErr {
    PyValueError::new_err(SpecError::new(key, "(given)", rule.into()).to_string())
}

/// A Python value as the TOML value a scene would hold (a bool, a number, a string, a list, a
/// dict of string keys), for [`ActivationSpec::set`].
fn toml_value(value: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    Ok(if value.is_instance_of::<PyBool>() {
        toml::Value::Boolean(value.extract()?)
    } else if value.is_instance_of::<PyInt>() {
        toml::Value::Integer(value.extract()?)
    } else if value.is_instance_of::<PyFloat>() {
        toml::Value::Float(value.extract()?)
    } else if value.is_instance_of::<PyString>() {
        toml::Value::String(value.extract()?)
    } else if let Ok(d) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            table.insert(k.extract()?, toml_value(&v)?);
        }
        toml::Value::Table(table)
    } else if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items: PyResult<Vec<toml::Value>> =
            value.try_iter()?.map(|v| toml_value(&v?)).collect();
        toml::Value::Array(items?)
    } else {
        // numpy scalars and other numbers.
        toml::Value::Float(value.extract()?)
    })
}

impl Choices {
    /// Takes one keyword.
    pub fn take(&mut self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let err = |e: SpecError| PyValueError::new_err(e.to_string());
        match key {
            "energy" => self.material.energy.energy = value.extract()?,
            "W" => self.material.energy.formula.formula = Some(value.extract()?),
            "name" => self.material.energy.formula.name = Some(value.extract()?),
            "parameters" => self.material.energy.formula.parameters = declared(value)?,
            "law" => self.law = Some(value.extract()?),
            "gamma" => self.gamma = Some(value.extract()?),
            "damage" => self.damage = value.extract()?,
            _ if ActivationSpec::KEYS.contains(&key) => {
                self.activation.set(key, toml_value(value)?).map_err(err)?
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
            let mut options: Vec<&str> = OWN.to_vec();
            options.extend(ActivationSpec::KEYS.iter().filter(|k| !OWN.contains(k)));
            return Err(keyword_error(
                key,
                format!(
                    "unknown keyword: the keywords are {} and the energies' and curves' parameters ({})",
                    options.join(", "),
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
            self.law.as_deref().map(LawChoice::parse).transpose()?,
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
