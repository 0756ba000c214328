//! The formula part of an energy table (`energy = "formula"`): `W`, the declared `parameters`
//! and an optional `name`, as written, and how they build a [`FormulaEnergy`].
//!
//! ```toml
//! [material]
//! energy = "formula"
//! name = "yeoh-fibres"                      # in outputs and labels (default "formula")
//! W = "c10*(I1 - 3) + k1/(2*k2)*expm1(k2*(I4 - 1)^2)"
//! [material.parameters]
//! c10 = { value = 0.1, unit = "kPa", range = [0, inf] }
//! k1 = { value = 0.5, unit = "kPa", range = [0, inf], bounds = [0, 50] }
//! k2 = 8.0                                  # value only: unit "-", range (-inf, inf)
//! ```
//!
//! A parameter's `range = [lower, upper]` is the open interval lower < value < upper it is
//! admissible in (what a division by it is checked against), `bounds` the default bounds of a
//! fit (the range if left out), `symbol` its symbol in reports (its name if left out).

use crate::app_error::SpecError;
use crate::energy::{FormulaEnergy, Parameter, FORMULA};
use crate::text::shortest;
use serde::de::{self, MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// One declared parameter as written: a number (its value), or a table.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeclaredSpec {
    /// Its value (required).
    pub value: Option<f64>,
    /// Unit (default `-`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    /// Symbol in reports (default: the name).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub symbol: Option<String>,
    /// Open admissible interval [lower, upper] (default [-inf, inf]).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "crate::fixed_length::exact"
    )]
    pub range: Option<[f64; 2]>,
    /// Default fit bounds (default: the range).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "crate::fixed_length::exact"
    )]
    pub bounds: Option<[f64; 2]>,
}

/// `W`, the parameters and the name of a formula energy, as written.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FormulaSpec {
    /// The formula (`W = "..."`).
    pub formula: Option<String>,
    /// Declared parameters, by name (`parameters = { mu = { value = 1, unit = "kPa" } }`).
    pub parameters: Vec<(String, DeclaredSpec)>,
    /// Name in outputs.
    pub name: Option<String>,
}

impl FormulaSpec {
    /// Whether any of `W`, `parameters`, `name` is given.
    pub fn is_given(&self) -> bool {
        self.formula.is_some() || !self.parameters.is_empty() || self.name.is_some()
    }

    /// The formula energy it describes; errors name keys relative to the energy's table (`W`,
    /// `parameters.mu.range`).
    pub fn build(&self) -> Result<FormulaEnergy, SpecError> {
        let Some(formula) = &self.formula else {
            return Err(SpecError::new(
                "W",
                "(missing)",
                "energy = \"formula\" needs W = \"...\", the strain energy [kPa] as a formula of the invariants (see docs/user-energy.md)",
            ));
        };
        let mut parameters = Vec::with_capacity(self.parameters.len());
        for (name, d) in &self.parameters {
            let Some(value) = d.value else {
                return Err(SpecError::new(
                    format!("parameters.{name}.value"),
                    "(missing)",
                    "a formula parameter needs its value",
                ));
            };
            let [lo, hi] = d.range.unwrap_or([f64::NEG_INFINITY, f64::INFINITY]);
            let mut p = Parameter::declared(
                name.as_str(),
                d.unit.as_deref().unwrap_or("-"),
                value,
                (lo, hi),
            );
            if let Some([a, b]) = d.bounds {
                p = p.with_bounds((a, b));
            }
            if let Some(s) = &d.symbol {
                p = p.with_symbol(s.as_str());
            }
            parameters.push(p);
        }
        let error = |e: crate::energy::FormulaError| SpecError::new(e.key, e.value, e.rule);
        let energy = FormulaEnergy::new(formula, parameters).map_err(error)?;
        match &self.name {
            Some(name) => energy.named(name).map_err(error),
            None => Ok(energy),
        }
    }

    /// The spec of a built formula energy: its formula, name and parameters at their current
    /// values (what a printed scene shows).
    pub fn written(e: &FormulaEnergy) -> Self {
        use crate::energy::{Parametric, StrainEnergy};
        let parameters = e
            .parameters()
            .iter()
            .zip(e.parameter_values())
            .map(|(p, v)| {
                let range = [p.range.0, p.range.1];
                let bounds = [p.bounds.0, p.bounds.1];
                (
                    p.name.to_string(),
                    DeclaredSpec {
                        value: Some(v),
                        unit: Some(p.unit.to_string()),
                        symbol: (p.symbol != p.name).then(|| p.symbol.to_string()),
                        range: Some(range),
                        bounds: (bounds != range).then_some(bounds),
                    },
                )
            })
            .collect();
        Self {
            formula: Some(e.formula().to_string()),
            parameters,
            name: (e.name() != FORMULA).then(|| e.name().to_string()),
        }
    }

    /// Writes `W`, `name` and `parameters` into a table being serialised.
    pub fn serialize_entries<M: SerializeMap>(&self, map: &mut M) -> Result<(), M::Error> {
        if let Some(name) = &self.name {
            map.serialize_entry("name", name)?;
        }
        if let Some(w) = &self.formula {
            map.serialize_entry("W", w)?;
        }
        if !self.parameters.is_empty() {
            map.serialize_entry("parameters", &Declared(&self.parameters))?;
        }
        Ok(())
    }

    /// The parameters in words, for reports: `c10 = 0.1 kPa ∈ (0, inf), k2 = 8 ∈ (-inf, inf)`.
    pub fn parameters_text(e: &FormulaEnergy) -> String {
        use crate::energy::Parametric;
        let v: Vec<String> = e
            .parameters()
            .iter()
            .zip(e.parameter_values())
            .map(|(p, v)| {
                let unit = if p.unit == "-" {
                    String::new()
                } else {
                    format!(" {}", p.unit)
                };
                format!(
                    "{} = {}{unit} ∈ ({}, {})",
                    p.symbol,
                    shortest(v),
                    p.range.0,
                    p.range.1
                )
            })
            .collect();
        v.join(", ")
    }
}

/// The declared parameters as a table of tables.
struct Declared<'a>(&'a [(String, DeclaredSpec)]);

impl Serialize for Declared<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (name, d) in self.0 {
            map.serialize_entry(name, d)?;
        }
        map.end()
    }
}

/// Reads `parameters = { name = value | { value, unit, symbol, range, bounds }, ... }`.
pub fn read_parameters<'de, A: MapAccess<'de>>(
    map: &mut A,
) -> Result<Vec<(String, DeclaredSpec)>, A::Error> {
    map.next_value::<DeclaredTable>().map(|t| t.0)
}

struct DeclaredTable(Vec<(String, DeclaredSpec)>);

impl<'de> Deserialize<'de> for DeclaredTable {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = DeclaredTable;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a table of parameters { name = { value = ..., unit = \"kPa\", range = [lower, upper] }, ... }")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<DeclaredTable, A::Error> {
                let mut out = Vec::new();
                while let Some(name) = map.next_key::<String>()? {
                    out.push((name, map.next_value::<OneDeclared>()?.0));
                }
                Ok(DeclaredTable(out))
            }
        }
        deserializer.deserialize_map(V)
    }
}

/// A number (the value) or a table.
struct OneDeclared(DeclaredSpec);

impl<'de> Deserialize<'de> for OneDeclared {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = OneDeclared;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number (the value) or { value = ..., unit = \"...\", symbol = \"...\", range = [lower, upper], bounds = [lower, upper] }")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<OneDeclared, E> {
                Ok(OneDeclared(DeclaredSpec {
                    value: Some(v),
                    ..DeclaredSpec::default()
                }))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<OneDeclared, E> {
                self.visit_f64(v as f64)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<OneDeclared, E> {
                self.visit_f64(v as f64)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<OneDeclared, A::Error> {
                DeclaredSpec::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(OneDeclared)
            }
        }
        deserializer.deserialize_any(V)
    }
}
