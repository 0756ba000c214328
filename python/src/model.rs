//! Keyword choices → a core [`Muscle`], through the scene's own models
//! ([`activemuscle::models`]): the keywords are the keys of a scene's `[material]` and
//! `[activation]` tables, gathered into a [`MaterialSpec`] and an [`ActivationSpec`] and resolved
//! by [`Models::from_spec`], the function that resolves a scene's. Names, defaults (the
//! chapter's values), rules and messages are therefore the scene's; an error names the keyword
//! (`mu = -1: ...`) where a scene names `material.mu`. Beyond a scene's laws, `law` takes
//! `"passive"` and `"constant"` (with `gamma`): a uniaxial study's passive and constant-γ curves.

use activemuscle::active::{ConstantLaw, Law};
use activemuscle::app_error::SpecError;
use activemuscle::energy::Energy;
use activemuscle::models::{
    ActivationSpec, CouplingKind, LawKind, MaterialSpec, ModelChoice, Models,
};
use activemuscle::Muscle;
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
