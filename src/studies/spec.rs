//! What every study spec shares: stretch lists, the rules of common values (damages, lengths,
//! cell counts), and the scene-level defaults a study resolves against. Keys in errors are
//! relative to the study (`stretch.step`, `damage[1]`).

use super::rules::{each, non_empty, once, required, something};
use crate::active::Approach;
use crate::app_error::SpecError;
use crate::models::{product, CouplingKind, LawKind, ModelChoice, Models};
use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use std::fmt;
use std::path::Path;

/// What a study takes from the scene when it leaves a key out.
#[derive(Debug, Clone, Copy)]
pub struct Defaults<'a> {
    /// The material and activation.
    pub models: &'a Models,
    /// `activation.approach`.
    pub approach: Approach,
    /// `activation.law`.
    pub law: LawKind,
    /// `activation.coupling`.
    pub coupling: CouplingKind,
    /// `activation.damage`.
    pub damage: &'a [f64],
    /// The directory data files are named relative to (the scene file's).
    pub base: &'a Path,
}

impl Defaults<'_> {
    /// Every law `approach` has that the scene's material supports (a study's default when it
    /// asks for every law).
    pub fn supported_laws(&self, approach: Approach) -> Vec<LawKind> {
        approach
            .laws()
            .iter()
            .copied()
            .filter(|&l| self.models.supports(approach, l).is_ok())
            .collect()
    }
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
    required(
        optional_stretches(spec)?,
        "stretch",
        "every study needs its stretches",
    )
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
    each(
        key,
        v,
        |d| (0.0..=1.0).contains(d),
        "damage d must lie in [0, 1]",
    )?;
    once(
        key,
        v,
        |a, b| a == b,
        |j| {
            format!("{key}[{j}] is the same damage: each value is one model and one set of outputs, give it once")
        },
    )?;
    Ok(v.to_vec())
}

/// The model keys of a study as written: its approaches, laws, couplings and damages (each
/// `None` if left out), and how it names them: `laws`, `couplings` (lists) or `law`, `coupling`
/// (one each: `single`).
#[derive(Debug, Clone, Copy)]
pub struct ModelKeys<'a> {
    /// `approaches` (`None`: the scene's approach).
    pub approaches: Option<&'a [Approach]>,
    /// `laws` (or `law`).
    pub laws: Option<&'a [LawKind]>,
    /// `couplings` (or `coupling`).
    pub couplings: Option<&'a [CouplingKind]>,
    /// `damage`.
    pub damage: Option<&'a [f64]>,
    /// The study takes one law and one coupling (`law`, `coupling`), not lists.
    pub single: bool,
}

/// A study's models, resolved: approach × law × coupling × damage ([`product`]), and the keys
/// as the resolved scene writes them (laws and couplings only where an approach has a law).
#[derive(Debug, Clone, PartialEq)]
pub struct ModelSet {
    /// The approaches.
    pub approaches: Vec<Approach>,
    /// The laws (`None`: no approach of the study has one).
    pub laws: Option<Vec<LawKind>>,
    /// The couplings (`None`: no approach of the study has a law).
    pub couplings: Option<Vec<CouplingKind>>,
    /// The damages.
    pub damage: Vec<f64>,
    /// Every model, in the order of [`product`].
    pub choices: Vec<ModelChoice>,
}

impl<'a> ModelKeys<'a> {
    /// A study's `laws`, `couplings` and `damage` lists, of the scene's approach.
    pub fn lists(
        laws: &'a Option<Vec<LawKind>>,
        couplings: &'a Option<Vec<CouplingKind>>,
        damage: &'a Option<Vec<f64>>,
    ) -> Self {
        Self {
            approaches: None,
            laws: laws.as_deref(),
            couplings: couplings.as_deref(),
            damage: damage.as_deref(),
            single: false,
        }
    }

    /// A study's one `law`, one `coupling` and `damage` list, of the scene's approach.
    pub fn one(
        law: &'a Option<LawKind>,
        coupling: &'a Option<CouplingKind>,
        damage: &'a Option<Vec<f64>>,
    ) -> Self {
        Self {
            approaches: None,
            laws: law.as_ref().map(std::slice::from_ref),
            couplings: coupling.as_ref().map(std::slice::from_ref),
            damage: damage.as_deref(),
            single: true,
        }
    }

    /// The study's models against the scene's `defaults`, laws and couplings left out being the
    /// scene's `activation.law` and `activation.coupling` ([`ModelKeys::resolve`]).
    pub fn of_scene(&self, d: &Defaults) -> Result<ModelSet, SpecError> {
        self.resolve(d, &[d.law], &[d.coupling])
    }

    /// The key of a law (`laws[j]`, or `law`).
    fn key(&self, list: &str, one: &str, j: usize) -> String {
        if self.single {
            one.to_string()
        } else {
            format!("{list}[{j}]")
        }
    }

    /// The study's models against the scene's `defaults`: every approach must be possible on
    /// the material (`approaches[j]`), every law must apply to every approach that has a law
    /// (`laws[j]`, with the approach's reason), and laws or couplings given to a study none of
    /// whose approaches has a law are refused (`laws`), never cut. Left out, the laws are
    /// `default_laws`, the couplings `default_couplings`, the damages `activation.damage`.
    pub fn resolve(
        &self,
        d: &Defaults,
        default_laws: &[LawKind],
        default_couplings: &[CouplingKind],
    ) -> Result<ModelSet, SpecError> {
        let approaches = self
            .approaches
            .map_or_else(|| vec![d.approach], <[_]>::to_vec);
        let names: Vec<String> = approaches
            .iter()
            .map(|a| format!("{:?}", a.name()))
            .collect();
        once(
            "approaches",
            &names,
            |a, b| a == b,
            |i| {
                format!("approaches[{i}] is the same approach: each approach is one set of models and curves, give it once")
            },
        )?;
        for (j, &a) in approaches.iter().enumerate() {
            d.models.activation_map(a).map_err(|rule| {
                SpecError::new(
                    self.key("approaches", "approach", j),
                    format!("{:?}", a.name()),
                    rule,
                )
            })?;
        }
        let lawful: Vec<Approach> = approaches
            .iter()
            .copied()
            .filter(|a| !a.laws().is_empty())
            .collect();
        let damage = damages("damage", self.damage.unwrap_or(d.damage))?;
        if lawful.is_empty() {
            self.refuse_lawless(&approaches)?;
            let choices = product(&approaches, &[], &[], &damage);
            return Ok(ModelSet {
                approaches,
                laws: None,
                couplings: None,
                damage,
                choices,
            });
        }
        let laws = self
            .laws
            .map_or_else(|| default_laws.to_vec(), <[_]>::to_vec);
        for (j, &law) in laws.iter().enumerate() {
            for &a in &lawful {
                d.models.supports(a, law).map_err(|rule| match self.laws {
                    Some(_) => SpecError::new(
                        self.key("laws", "law", j),
                        format!("{:?}", law.name()),
                        rule,
                    ),
                    None => SpecError::new(
                        if self.single { "law" } else { "laws" },
                        format!("{:?} (left out: activation.law)", law.name()),
                        rule,
                    ),
                })?;
            }
        }
        let couplings = self
            .couplings
            .map_or_else(|| default_couplings.to_vec(), <[_]>::to_vec);
        couplings_for(&laws, &couplings)?;
        self.damages_in_domain(&laws, &damage)?;
        let choices = product(&approaches, &laws, &couplings, &damage);
        Ok(ModelSet {
            approaches,
            laws: Some(laws),
            couplings: Some(couplings),
            damage,
            choices,
        })
    }

    /// Refuses a damage outside the domain of one of `laws` ([`LawKind::domain`]: the explicit
    /// law's d ≤ 0.5, or 1): every point of such a model would leave it.
    fn damages_in_domain(&self, laws: &[LawKind], damage: &[f64]) -> Result<(), SpecError> {
        for law in laws {
            let Some(domain) = law.domain() else {
                continue;
            };
            if let Some(i) = damage.iter().position(|&d| !domain.holds_at_damage(d)) {
                let (key, value) = match self.damage {
                    Some(_) => (format!("damage[{i}]"), crate::text::shortest(damage[i])),
                    None => (
                        "damage".to_string(),
                        format!("{} (left out: activation.damage)", damage[i]),
                    ),
                };
                return Err(SpecError::new(
                    key,
                    value,
                    format!(
                        "the {} law holds for {} ({}): give it d ≤ {} (d = 1, no activation, is exact), or use the implicit or the energy law",
                        law.name(),
                        domain.describe(),
                        domain.why,
                        domain.effective_damage[1]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Refuses `laws` and `couplings` given to a study none of whose `approaches` has a law.
    fn refuse_lawless(&self, approaches: &[Approach]) -> Result<(), SpecError> {
        let names: Vec<String> = approaches
            .iter()
            .map(|a| format!("{:?}", a.name()))
            .collect();
        let why: Vec<&str> = approaches.iter().map(|a| a.no_law()).collect();
        let given = [
            (
                self.key("laws", "law", 0),
                self.laws
                    .map(|l| l.iter().map(|x| x.name()).collect::<Vec<_>>()),
            ),
            (
                self.key("couplings", "coupling", 0),
                self.couplings.map(|c| c.iter().map(|x| x.name()).collect()),
            ),
        ];
        for (key, value) in given {
            if let Some(v) = value {
                let key = key.trim_end_matches("[0]").to_string();
                return Err(SpecError::new(
                    key.clone(),
                    format!("{v:?}"),
                    format!(
                        "{key} does not apply to approach = {}: {}",
                        names.join(", "),
                        why.join("; ")
                    ),
                ));
            }
        }
        Ok(())
    }
}

impl ModelSet {
    /// The one law and one coupling of a study that takes one of each (`law`, `coupling`;
    /// `None`: its approach has no law).
    pub fn single(&self) -> (Option<LawKind>, Option<CouplingKind>) {
        fn first<T: Copy>(v: &Option<Vec<T>>) -> Option<T> {
            v.as_ref().and_then(|v| v.first().copied())
        }
        (first(&self.laws), first(&self.couplings))
    }
}

/// The models of a study that compares approaches (shear, biaxial): the passive material first
/// if `passive`, then every approach × law × coupling × damage of `keys` (approaches left out:
/// `default_approaches`; laws and couplings: the scene's). `kind` names the study when it asks
/// for nothing.
pub fn approach_models(
    keys: ModelKeys,
    passive: bool,
    d: &Defaults,
    default_approaches: &[Approach],
    kind: &str,
) -> Result<(Vec<ApproachModel>, ModelSet), SpecError> {
    let keys = ModelKeys {
        approaches: Some(keys.approaches.unwrap_or(default_approaches)),
        ..keys
    };
    let set = keys.of_scene(d)?;
    let mut models = Vec::with_capacity(set.choices.len() + 1);
    if passive {
        models.push(ApproachModel::passive(d));
    }
    models.extend(set.choices.iter().copied().map(ApproachModel::of));
    something(kind, !models.is_empty(), "passive = true or approaches")?;
    Ok((models, set))
}

/// Active laws need at least one coupling.
pub fn couplings_for(laws: &[LawKind], couplings: &[CouplingKind]) -> Result<(), SpecError> {
    if laws.is_empty() {
        return Ok(());
    }
    non_empty(
        "couplings",
        couplings,
        "active laws need at least one coupling",
    )
}

/// One model of a study that compares activation approaches (`None`: the passive material).
#[derive(Debug, Clone, PartialEq)]
pub struct ApproachModel {
    /// The approach (of the model; the scene's for the passive material, which has none).
    pub approach: Approach,
    /// The model (`None`: passive).
    pub model: Option<ModelChoice>,
}

impl ApproachModel {
    /// The passive material.
    pub fn passive(d: &Defaults) -> Self {
        Self {
            approach: d.approach,
            model: None,
        }
    }

    /// The approaches of `models`' active models, each once, in order.
    pub fn approaches(models: &[ApproachModel]) -> Vec<Approach> {
        let mut v: Vec<Approach> = Vec::new();
        for a in models.iter().filter_map(|m| m.model).map(|m| m.approach) {
            if !v.contains(&a) {
                v.push(a);
            }
        }
        v
    }

    /// A model of `choice`.
    pub fn of(choice: ModelChoice) -> Self {
        Self {
            approach: choice.approach,
            model: Some(choice),
        }
    }

    /// Its (approach, law, coupling) table cells: the passive material has law `passive` and
    /// no approach; an approach without a law has no law or coupling.
    pub fn cells(&self) -> [Option<String>; 3] {
        match self.model {
            None => [None, Some("passive".into()), None],
            Some(c) => [
                Some(c.approach.name().into()),
                c.law_name().map(String::from),
                c.coupling_name().map(String::from),
            ],
        }
    }

    /// The model in words without the energy, for legends and tables: `passive`,
    /// `active-stress, d = 0`, `active-strain, implicit law, frozen coupling, d = 0`.
    pub fn words(&self) -> String {
        let Some(m) = self.model else {
            return "passive".into();
        };
        match m.activation_law() {
            Some((l, k)) => format!(
                "{}, {} law, {} coupling, d = {}",
                m.approach.name(),
                l.name(),
                k.name(),
                m.damage
            ),
            None => format!("{}, d = {}", m.approach.name(), m.damage),
        }
    }

    /// Its muscle: the passive material's, or the model's; an error names `study` and the model.
    pub fn muscle(
        &self,
        models: &Models,
        study: &str,
    ) -> Result<crate::Muscle<crate::energy::Energy>, crate::app_error::AppError> {
        match self.model {
            None => Ok(models.passive()),
            Some(c) => models.muscle(c).map_err(|e| {
                crate::app_error::AppError::from(e).within(format!("{study}: {}", models.label(&c)))
            }),
        }
    }

    /// The model in words: `…, passive`, `…, active stress, d = 0`, `…, implicit law, frozen
    /// coupling, d = 0` ([`Models::label`]).
    pub fn label(&self, models: &Models) -> String {
        match self.model {
            None => format!("{}, passive", crate::StrainEnergy::name(&models.energy)),
            Some(c) => models.label(&c),
        }
    }
}
