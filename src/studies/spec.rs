//! What every study spec shares: stretch lists, the rules of common values (damages, lengths,
//! cell counts), and the scene-level defaults a study resolves against. Keys in errors are
//! relative to the study (`stretch.step`, `damage[1]`).

use crate::app_error::SpecError;
use crate::models::{CouplingKind, LawKind, ModelChoice, Models};
use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use std::fmt;
use std::path::Path;

/// What a study takes from the scene when it leaves a key out.
#[derive(Debug, Clone, Copy)]
pub struct Defaults<'a> {
    /// The material and activation.
    pub models: &'a Models,
    /// `activation.law`.
    pub law: LawKind,
    /// `activation.coupling`.
    pub coupling: CouplingKind,
    /// `activation.damage`.
    pub damage: &'a [f64],
    /// The directory data files are named relative to (the scene file's).
    pub base: &'a Path,
}

/// Stretches: `[0.8, 1.0, 1.2]` or `{ from = 0.7, to = 1.6, step = 0.05, extra = [1.17] }`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum StretchSpec {
    /// Explicit list.
    List(Vec<f64>),
    /// Evenly spaced, plus extra points.
    Range {
        /// First stretch.
        from: f64,
        /// Last stretch (must be reached by whole steps).
        to: f64,
        /// Step > 0.
        step: f64,
        /// Extra stretches merged in.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        extra: Vec<f64>,
    },
}

// Hand-written so that errors inside keep their position in the file (an untagged derive
// buffers the value and loses it).
impl<'de> Deserialize<'de> for StretchSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = StretchSpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a list of stretches or a table { from, to, step, extra }")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut v = Vec::new();
                while let Some(x) = seq.next_element::<f64>()? {
                    v.push(x);
                }
                Ok(StretchSpec::List(v))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                const FIELDS: &[&str] = &["from", "to", "step", "extra"];
                let (mut from, mut to, mut step, mut extra) = (None, None, None, Vec::new());
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "from" => from = Some(map.next_value::<f64>()?),
                        "to" => to = Some(map.next_value::<f64>()?),
                        "step" => step = Some(map.next_value::<f64>()?),
                        "extra" => extra = map.next_value::<Vec<f64>>()?,
                        other => return Err(de::Error::unknown_field(other, FIELDS)),
                    }
                }
                Ok(StretchSpec::Range {
                    from: from.ok_or_else(|| de::Error::missing_field("from"))?,
                    to: to.ok_or_else(|| de::Error::missing_field("to"))?,
                    step: step.ok_or_else(|| de::Error::missing_field("step"))?,
                    extra,
                })
            }
        }
        deserializer.deserialize_any(V)
    }
}

/// `[a, b, c]`.
pub fn fmt_list(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|&x| crate::text::shortest(x)).collect();
    format!("[{}]", items.join(", "))
}

impl StretchSpec {
    /// The stretches: finite, > 0, ascending without duplicates, at most [`MAX_GRID_POINTS`]; errors name
    /// `key` (`stretch`, `stretch.step`).
    pub fn resolve(&self, key: &str) -> Result<Vec<f64>, SpecError> {
        self.grid(key, Grid::Stretch)
    }

    /// The same list read as times t \[s\]: finite, ≥ 0, ascending without duplicates.
    pub fn resolve_times(&self, key: &str) -> Result<Vec<f64>, SpecError> {
        self.grid(key, Grid::Time)
    }

    /// The same list read as amounts of shear k [-]: finite, any sign, ascending without
    /// duplicates.
    pub fn resolve_amounts(&self, key: &str) -> Result<Vec<f64>, SpecError> {
        self.grid(key, Grid::Amount)
    }

    fn grid(&self, key: &str, grid: Grid) -> Result<Vec<f64>, SpecError> {
        const MAX: usize = MAX_GRID_POINTS;
        let mut v = match self {
            StretchSpec::List(v) => v.clone(),
            StretchSpec::Range {
                from,
                to,
                step,
                extra,
            } => {
                if !(step.is_finite() && *step > 0.0) {
                    return Err(SpecError::new(
                        format!("{key}.step"),
                        step,
                        "must be finite and > 0",
                    ));
                }
                if !(from.is_finite() && to.is_finite() && to >= from) {
                    return Err(SpecError::new(
                        format!("{key}.to"),
                        to,
                        format!("must be finite and ≥ from = {from}"),
                    ));
                }
                let n = ((to - from) / step).round();
                if ((from + n * step) - to).abs() > 1e-9 * step.max(1.0) {
                    return Err(SpecError::new(
                        format!("{key}.step"),
                        step,
                        format!("from = {from} must reach to = {to} in whole steps"),
                    ));
                }
                if n >= MAX as f64 {
                    return Err(SpecError::new(
                        format!("{key}.step"),
                        step,
                        format!("gives more than {MAX} values ({GRID_CAP_REASON})"),
                    ));
                }
                // Rounded to 10 decimals so that 0.65 + 0.01 i prints as the decimal it means.
                let mut v: Vec<f64> = (0..=n as usize)
                    .map(|i| ((from + i as f64 * step) * 1e10).round() / 1e10)
                    .collect();
                v.extend_from_slice(extra);
                v
            }
        };
        if v.len() > MAX {
            return Err(SpecError::new(
                key,
                format!("[… {} values]", v.len()),
                format!("at most {MAX} values ({GRID_CAP_REASON})"),
            ));
        }
        let (what, rule) = match grid {
            Grid::Time => ("time", "every time must be finite and ≥ 0"),
            Grid::Stretch => ("stretch", "every stretch must be finite and > 0"),
            Grid::Amount => ("amount of shear", "every amount of shear must be finite"),
        };
        non_empty(
            key,
            &v,
            &format!("the {what} list is empty: give at least one {what}"),
        )?;
        let admissible = |x: f64| {
            x.is_finite()
                && match grid {
                    Grid::Stretch => x > 0.0,
                    Grid::Time => x >= 0.0,
                    Grid::Amount => true,
                }
        };
        if let Some(bad) = v.iter().find(|x| !admissible(**x)) {
            return Err(SpecError::new(key, bad, rule));
        }
        v.sort_by(f64::total_cmp);
        v.dedup();
        Ok(v)
    }
}

/// The most stretches, times or amounts of shear one list may give.
pub const MAX_GRID_POINTS: usize = 10_000;
const GRID_CAP_REASON: &str =
    "each is a solve and a CSV row; a curve of more points is no smoother on a figure";

/// The most damages a study may list.
pub const MAX_DAMAGES: usize = 16;

/// What a [`StretchSpec`] lists.
#[derive(Clone, Copy)]
enum Grid {
    Stretch,
    Time,
    Amount,
}

/// The stretches of an optional `stretch` key; errors name `stretch`.
pub fn optional_stretches(spec: &Option<StretchSpec>) -> Result<Option<Vec<f64>>, SpecError> {
    spec.as_ref().map(|s| s.resolve("stretch")).transpose()
}

/// The stretches of a required `stretch` key.
pub fn required_stretches(spec: &Option<StretchSpec>) -> Result<Vec<f64>, SpecError> {
    optional_stretches(spec)?
        .ok_or_else(|| SpecError::new("stretch", "(missing)", "every study needs its stretches"))
}

/// Damage values: at least one, each in [0, 1].
pub fn damages(key: &str, v: &[f64]) -> Result<Vec<f64>, SpecError> {
    non_empty(
        key,
        v,
        "the damage list is empty: give at least one d ∈ [0, 1]",
    )?;
    if v.len() > MAX_DAMAGES {
        return Err(SpecError::new(
            key,
            format!("[… {} values]", v.len()),
            format!(
                "at most {MAX_DAMAGES} damages: each is a model solved at every stretch and a \
                 curve in every figure, and more curves than that cannot be told apart"
            ),
        ));
    }
    for (i, d) in v.iter().enumerate() {
        if !(0.0..=1.0).contains(d) {
            return Err(SpecError::new(
                format!("{key}[{i}]"),
                d,
                "damage d must lie in [0, 1]",
            ));
        }
        if let Some(j) = v[..i].iter().position(|e| e == d) {
            return Err(SpecError::new(
                format!("{key}[{i}]"),
                d,
                format!("{key}[{j}] is the same damage: each value is one model and one set of outputs, give it once"),
            ));
        }
    }
    Ok(v.to_vec())
}

/// A list that must not be empty; `rule` says what to give.
pub fn non_empty<T>(key: &str, v: &[T], rule: &str) -> Result<(), SpecError> {
    if v.is_empty() {
        Err(SpecError::new(key, "[]", rule))
    } else {
        Ok(())
    }
}

/// A length or tolerance: finite and > 0.
pub fn positive(key: &str, v: f64) -> Result<f64, SpecError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(SpecError::new(key, v, "must be finite and > 0"))
    }
}

/// A number of cells along one direction: an integer in [1, 10000].
pub fn cell_count(key: &str, v: i64) -> Result<usize, SpecError> {
    if (1..=10_000).contains(&v) {
        Ok(v as usize)
    } else {
        Err(SpecError::new(
            key,
            v,
            "the number of cells must be an integer in [1, 10000]",
        ))
    }
}

/// The middle/base cell-height ratio of a cylinder mesh: finite and ≥ 1.
pub fn grading(key: &str, v: f64) -> Result<f64, SpecError> {
    if v.is_finite() && v >= 1.0 {
        Ok(v)
    } else {
        Err(SpecError::new(
            key,
            v,
            "must be finite and ≥ 1 (1 = uniform)",
        ))
    }
}

/// Laws that must all be buildable on the material (`laws[j]` in errors).
pub fn supported_laws(key: &str, laws: &[LawKind], models: &Models) -> Result<(), SpecError> {
    for (j, l) in laws.iter().enumerate() {
        models
            .supports(*l)
            .map_err(|rule| SpecError::new(format!("{key}[{j}]"), "\"explicit\"", rule))?;
    }
    Ok(())
}

/// Active laws need at least one coupling.
pub fn couplings_for(laws: &[LawKind], couplings: &[CouplingKind]) -> Result<(), SpecError> {
    if !laws.is_empty() && couplings.is_empty() {
        Err(SpecError::new(
            "couplings",
            "[]",
            "active laws need at least one coupling",
        ))
    } else {
        Ok(())
    }
}

/// One model of a study that compares activation approaches: the scene's models with the
/// approach set, and the model choice (law × coupling × damage; for active stress the law and
/// coupling are unused). `None`: the passive material.
#[derive(Debug, Clone, PartialEq)]
pub struct ApproachModel {
    /// The approach.
    pub approach: crate::active::Approach,
    /// The model (`None`: passive).
    pub model: Option<ModelChoice>,
}

impl ApproachModel {
    /// Its (approach, law, coupling) table cells: the passive material has law `passive` and
    /// no approach; active stress has no law or coupling.
    pub fn cells(&self) -> [Option<String>; 3] {
        match (self.model, self.approach.has_law()) {
            (None, _) => [None, Some("passive".into()), None],
            (Some(_), false) => [Some(self.approach.name().into()), None, None],
            (Some(c), true) => [
                Some(self.approach.name().into()),
                Some(c.law.name().into()),
                Some(c.coupling.name().into()),
            ],
        }
    }

    /// The model in words without the energy, for legends and tables: `passive`,
    /// `active-stress, d = 0`, `active-strain, implicit law, frozen coupling, d = 0`.
    pub fn words(&self) -> String {
        match (self.cells(), self.model) {
            ([None, ..], _) | (_, None) => "passive".into(),
            ([Some(a), Some(l), Some(k)], Some(m)) => {
                format!("{a}, {l} law, {k} coupling, d = {}", m.damage)
            }
            ([Some(a), ..], Some(m)) => format!("{a}, d = {}", m.damage),
        }
    }

    /// The model in words: `…, passive`, `…, active stress, d = 0`, `…, implicit law, frozen
    /// coupling, d = 0`.
    pub fn label(&self, models: &Models) -> String {
        match self.model {
            None => format!("{}, passive", crate::StrainEnergy::name(&models.energy)),
            Some(c) => Models {
                approach: self.approach,
                ..models.clone()
            }
            .label(&c),
        }
    }
}

/// Every approach × law × coupling × damage a study asks for, each approach checked against
/// the material (`approaches[j]`, `laws[j]` name the offending entry).
pub fn approach_models(
    models: &Models,
    approaches: &[crate::active::Approach],
    laws: &[LawKind],
    couplings: &[CouplingKind],
    damages: &[f64],
) -> Result<Vec<ApproachModel>, SpecError> {
    let mut out = Vec::new();
    for (j, &approach) in approaches.iter().enumerate() {
        let m = Models {
            approach,
            ..models.clone()
        };
        m.activation_map().map_err(|rule| {
            SpecError::new(
                format!("approaches[{j}]"),
                format!("{:?}", approach.name()),
                rule,
            )
        })?;
        if approach.has_law() {
            supported_laws("laws", laws, &m)?;
        }
        out.extend(
            m.choices(laws, couplings, damages)
                .into_iter()
                .map(|c| ApproachModel {
                    approach,
                    model: Some(c),
                }),
        );
    }
    Ok(out)
}
