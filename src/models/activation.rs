//! The scene's `[activation]` table ([`ActivationSpec`]): each key declared once in
//! `activation_keys!` below — its type, what it is, the approaches it applies to (from what each
//! approach declares, [`crate::active::approach`]) and what the resolved scene writes for it.
//! The parser, the resolved scene (`check` prints it), the refusal of a key that applies to no
//! approach of the scene and Python's keywords ([`ActivationSpec::set`]) all follow from it.

use super::choice::{Approach, CouplingKind, LawKind, RepresentationKind};
use super::factory::Models;
use crate::active::{
    ActivationMap, ActiveCurve, BelowMinimum, CurveEntry, ForceVelocity, FrozenTangent,
    LawRepresentation, TableSpec, CURVES,
};
use crate::app_error::SpecError;
use serde::ser::SerializeMap;
use serde::{Deserialize, Serialize, Serializer};

/// What the studies take from `[activation]` when they leave a key out: the approach, law,
/// coupling and damage values of their models.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelDefaults {
    /// `activation.approach`.
    pub approach: Approach,
    /// `activation.law`.
    pub law: LawKind,
    /// `activation.coupling`.
    pub coupling: CouplingKind,
    /// `activation.damage` (validated by the scene).
    pub damage: Vec<f64>,
}

/// The refusal of `key = value`, which applies to none of `approaches`, for `reasons`.
fn refusal<T: Serialize>(
    key: &str,
    value: &T,
    approaches: &[Approach],
    reasons: &[String],
) -> SpecError {
    let names: Vec<String> = approaches
        .iter()
        .map(|a| format!("{:?}", a.name()))
        .collect();
    let shown = toml::Value::try_from(value).map_or_else(|_| String::new(), |v| v.to_string());
    let mut reasons = reasons.to_vec();
    reasons.dedup();
    SpecError::new(
        format!("activation.{key}"),
        shown,
        format!(
            "{key} does not apply to approach = {}: {}",
            names.join(", "),
            reasons.join("; ")
        ),
    )
}

/// `Ok` if `holds`, else why a key does not apply to an approach.
fn applies_if(holds: bool, why: impl Fn() -> String) -> Result<(), String> {
    if holds {
        Ok(())
    } else {
        Err(why())
    }
}

/// The `[activation]` keys: `key: Type, applies |approach| …, written |models, defaults| …;`
/// generates [`ActivationSpec`] (one `Option` field per key, plus the curve's name and
/// parameters), its serialisation in this order (the curve's parameters after `curve`), the
/// list of its keys, [`ActivationSpec::set`], [`ActivationSpec::refuse_inapplicable`] and
/// [`ActivationSpec::written`].
macro_rules! activation_keys {
    ($($(#[$doc:meta])* $key:ident: $ty:ty,
        applies |$a:ident| $applies:expr,
        written |$m:ident, $d:ident| $written:expr;)*) => {
        /// `[activation]`: the approach, the active curve with its parameters (flat beside
        /// `curve`), the options every model shares ([`Models::from_spec`]) and the studies'
        /// default approach, law, coupling and damage values. `None` is the default.
        ///
        /// The curve's parameters are read by name from the table (the scene reader takes the
        /// parameters of every shipped curve out of it, see [`crate::scene`]); each must be one of
        /// the chosen curve's.
        #[derive(Debug, Clone, Default, PartialEq, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct ActivationSpec {
            /// The curve's parameters as given, in the order written (`lambda_min = 0.7`).
            #[serde(skip)]
            pub curve_parameters: Vec<(String, f64)>,
            $($(#[$doc])* pub $key: Option<$ty>,)*
        }

        impl ActivationSpec {
            /// Every key (the curve's parameters aside), in the order a scene is written.
            pub const KEYS: &'static [&'static str] = &[$(stringify!($key),)*];

            /// Sets `key` from a value (as a TOML value: a string, a number, a list, a table);
            /// errors name the key (Python's keywords come here).
            pub fn set(&mut self, key: &str, value: toml::Value) -> Result<(), SpecError> {
                let shown = value.to_string();
                let wrong = |e: toml::de::Error| SpecError::new(key, shown.clone(), e.message().to_string());
                match key {
                    $(stringify!($key) => self.$key = Some(value.try_into().map_err(wrong)?),)*
                    _ => return Err(SpecError::new(key, shown.clone(), format!(
                        "not a key of [activation]; its keys are {}", Self::KEYS.join(", ")))),
                }
                Ok(())
            }

            /// The first key given that applies to none of `approaches` (the scene's and its
            /// studies'), with why, named as a scene writes it (`activation.law`).
            pub fn refuse_inapplicable(&self, approaches: &[Approach]) -> Result<(), SpecError> {
                $(if let Some(v) = &self.$key {
                    let applies = |$a: Approach| -> Result<(), String> { $applies };
                    let reasons: Vec<String> = approaches.iter().filter_map(|&a| applies(a).err()).collect();
                    if !reasons.is_empty() && reasons.len() == approaches.len() {
                        return Err(refusal(stringify!($key), v, approaches, &reasons));
                    }
                })*
                Ok(())
            }

            /// The table as the resolved scene writes it: every value of `models` and
            /// `defaults` for a key that applies to one of `approaches` (the others are left out:
            /// nothing reads them).
            pub fn written(models: &Models, defaults: &ModelDefaults, approaches: &[Approach]) -> Self {
                let mut spec = Self {
                    curve_parameters: written_curve(&models.curve).1,
                    ..Self::default()
                };
                $({
                    let applies = |$a: Approach| -> Result<(), String> { $applies };
                    let ($m, $d) = (models, defaults);
                    if approaches.iter().any(|&a| applies(a).is_ok()) {
                        spec.$key = $written;
                    }
                })*
                spec
            }
        }

        impl Serialize for ActivationSpec {
            fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                let mut map = serializer.serialize_map(None)?;
                $(if let Some(v) = &self.$key {
                    map.serialize_entry(stringify!($key), v)?;
                }
                if stringify!($key) == "curve" {
                    for (name, value) in &self.curve_parameters {
                        map.serialize_entry(name, value)?;
                    }
                })*
                map.end()
            }
        }
    };
}

activation_keys! {
    /// `active-strain` (default) | `active-stress` | `structural` (the registry
    /// [`crate::active::approach`]): the studies' default approach.
    approach: Approach,
        applies |_a| Ok(()),
        written |_m, d| Some(d.approach);
    /// A shipped active curve by name (default `chapter`), its parameters beside it.
    curve: String,
        applies |_a| Ok(()),
        written |m, _d| Some(m.curve.name().to_string());
    /// Default law of the studies.
    law: LawKind,
        applies |a| applies_if(!a.laws().is_empty(), || a.no_law().to_string()),
        written |_m, d| Some(d.law);
    /// Default coupling of the studies.
    coupling: CouplingKind,
        applies |a| applies_if(!a.couplings().is_empty(), || a.no_law().to_string()),
        written |_m, d| Some(d.coupling);
    /// Tangent of the frozen coupling.
    frozen_tangent: FrozenTangent,
        applies |a| applies_if(a.couplings().contains(&CouplingKind::Frozen), || a.no_law().to_string()),
        written |m, _d| Some(m.frozen_tangent);
    /// What the energy law does below λ_min.
    below_minimum: BelowMinimum,
        applies |a| applies_if(a.laws().contains(&LawKind::Energy), || format!("it is the energy law's; {}", a.no_law())),
        written |m, _d| Some(m.below_minimum);
    /// The active-strain map: "chapter" (default) | "volume-preserving".
    map: ActivationMap,
        applies |a| applies_if(!a.maps().is_empty(), || a.no_map().to_string()),
        written |m, _d| Some(m.map);
    /// Default damage values d ∈ [0, 1].
    damage: Vec<f64>,
        applies |_a| Ok(()),
        written |_m, d| Some(d.damage.clone());
    /// Coefficients of the explicit law (eq. (14)).
    explicit: ExplicitSpec,
        applies |a| applies_if(a.laws().contains(&LawKind::Explicit), || format!("they are the explicit law's; {}", a.no_law())),
        written |m, _d| Some(ExplicitSpec { a: Some(m.explicit.0), b: Some(m.explicit.1) });
    /// How the implicit and energy laws are evaluated (default `exact`).
    representation: RepresentationKind,
        applies |a| applies_if(a.laws().iter().any(|l| l.solves()), || a.no_law().to_string()),
        written |m, _d| Some(m.representation_spec().0);
    /// Stretch range `[λ_lo, λ_hi]` [-] of the tables (default `[0.5, 1.6]`; the exact solve
    /// outside); only with `representation = "tabulated"`.
    #[serde(default, deserialize_with = "crate::fixed_length::exact")]
    table_stretches: [f64; 2],
        applies |a| applies_if(a.laws().iter().any(|l| l.solves()), || a.no_law().to_string()),
        written |m, _d| m.representation_spec().1;
    /// The force–velocity factor of activation-in-time studies (default none: f_v = 1).
    force_velocity: ForceVelocity,
        applies |_a| Ok(()),
        written |m, _d| m.force_velocity;
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

impl ActivationSpec {
    /// The studies' defaults it gives (`damage` as written; the scene validates it).
    pub fn defaults(&self) -> ModelDefaults {
        ModelDefaults {
            approach: self.approach.unwrap_or_default(),
            law: self.law.unwrap_or_default(),
            coupling: self.coupling.unwrap_or_default(),
            damage: self.damage.clone().unwrap_or_else(|| vec![0.0]),
        }
    }

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

    /// The law representation: tables on `table_stretches` (validated: 0 < λ_lo < λ_hi,
    /// finite) with the default tolerances of [`TableSpec`].
    pub fn representation(&self) -> Result<LawRepresentation, SpecError> {
        let shown = |[lo, hi]: [f64; 2]| format!("[{lo}, {hi}]");
        match (
            self.representation.unwrap_or_default(),
            self.table_stretches,
        ) {
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
