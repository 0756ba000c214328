//! Activation-in-time studies (`kind = "activation-in-time"`): a homogeneous (0D) block along
//! the fibres driven in time by an activation level a(t) ([`crate::active::time`]): at each time
//! step the law reproduces the target (1 − d)·a(t)·f_v(λ̇)·P_act and the state is solved, either
//! under a prescribed stretch λ(t) (the stress history) or under free contraction (zero axial
//! load: the stretch history). One history per damage value, in parallel.
//!
//! With `[activation] force_velocity` the factor f_v of the fibre stretch rate λ̇ enters
//! ([`crate::active::ForceVelocity`]): λ̇ = (λ − λ_prev)/(t − t_prev) by backward Euler from the
//! previous step's state, inside the step's solve with its exact derivative 1/Δt (λ̇ = 0 at the
//! first step: the history starts at rest), so the result depends on the time steps.
//!
//! Exactly incompressible (the chapter's model, [`crate::uniaxial`]) or, with the scene's
//! `[incompressibility]`, nearly incompressible: then the two lateral stretches are solved from
//! zero lateral traction at every step ([`crate::uniaxial::nearly_incompressible`]) and the volume
//! ratio J = λ λ₂ λ₃ is reported.

mod output;

use super::domain::{lines, Tally, Words};
use super::rules::required;
use super::spec::{Defaults, ModelKeys, StretchSpec};
use super::{Failure, Outcome, RunContext, StudyKind, StudyResult};
use crate::active::time::{ActivationInTime, Interpolation, MotorUnit, MotorUnits, Schedule};
use crate::active::{OutsideDomain, StretchRate};
use crate::app_error::{AppError, SpecError};
use crate::energy::Energy;
use crate::fixed_length::Exactly;
use crate::models::{CouplingKind, LawKind, ModelChoice, Models};
use crate::text::shortest;
use crate::uniaxial::{Direction, UniaxialPoint};
use crate::volumetric::Volumetric;
use crate::Muscle;
use rayon::prelude::*;
use serde::de::{self, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use std::fmt;

/// One motor-unit type as written (`{ fraction = 0.5, twitch_force = 0.37, contraction_time =
/// 0.08, interstimulus = 0.02 }`); every key is required.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotorUnitSpec {
    /// Fraction ρ [-].
    pub fraction: f64,
    /// Twitch force F [-].
    pub twitch_force: f64,
    /// Twitch contraction time T \[s\].
    pub contraction_time: f64,
    /// Interstimulus interval I \[s\].
    pub interstimulus: f64,
}

/// The word `free`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FreeWord {
    /// Free contraction.
    Free,
}

/// The loading: `stretch = 1.1` (constant), `stretch = [[0, 1.0], [1, 1.2]]` ((t \[s\], λ)
/// points, linear between them) or `stretch = "free"` (zero axial load).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum LoadingSpec {
    /// A constant stretch λ.
    Constant(f64),
    /// (t, λ) points.
    Schedule(Vec<[f64; 2]>),
    /// Free contraction.
    Free(FreeWord),
}

// Hand-written so that errors inside keep their position in the file.
impl<'de> Deserialize<'de> for LoadingSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = LoadingSpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a stretch, a list of [t, stretch] points or \"free\"")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<LoadingSpec, E> {
                Ok(LoadingSpec::Constant(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<LoadingSpec, E> {
                Ok(LoadingSpec::Constant(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<LoadingSpec, E> {
                Ok(LoadingSpec::Constant(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<LoadingSpec, E> {
                match v {
                    "free" => Ok(LoadingSpec::Free(FreeWord::Free)),
                    other => Err(E::invalid_value(
                        de::Unexpected::Str(other),
                        &"\"free\" (or a number, or [[t, stretch], ...])",
                    )),
                }
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<LoadingSpec, A::Error> {
                let mut v = Vec::new();
                while let Some(p) = seq.next_element::<Exactly<f64, 2>>()? {
                    v.push(p.0);
                }
                Ok(LoadingSpec::Schedule(v))
            }
        }
        deserializer.deserialize_any(V)
    }
}

/// `[[study]] kind = "activation-in-time"` as written; `None` is a key left to its default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HistorySpec {
    /// Label (default `activation in time`).
    pub name: Option<String>,
    /// Time steps t \[s\] (required): `[0, 0.1, 0.2]` or `{ from, to, step }`.
    pub time: Option<StretchSpec>,
    /// The activation schedule a_s: [t \[s\], value ∈ [0, 1]] points (default `[[0, 1]]`).
    #[serde(default, deserialize_with = "crate::fixed_length::exact")]
    pub schedule: Option<Vec<[f64; 2]>>,
    /// `constant` (default) or `linear` between schedule points.
    pub interpolation: Option<Interpolation>,
    /// Motor-unit types: a(t) is their twitch superposition driven by the schedule (default
    /// none: a(t) = a_s(t)).
    pub motor_units: Option<Vec<MotorUnitSpec>>,
    /// The loading (default 1: isometric at the rest length).
    pub stretch: Option<LoadingSpec>,
    /// Activation law (default `activation.law`).
    pub law: Option<LawKind>,
    /// Coupling (default `activation.coupling`).
    pub coupling: Option<CouplingKind>,
    /// Damage values, one history each (default `activation.damage`).
    pub damage: Option<Vec<f64>>,
}

/// Keys an activation-in-time study does not take, and what to write instead.
pub const HINTS: &[(&str, &str)] = &[
    (
        "laws",
        "an activation-in-time study takes one law: law = \"...\"",
    ),
    (
        "couplings",
        "an activation-in-time study takes one coupling: coupling = \"...\"",
    ),
    (
        "activation",
        "the activation in time is schedule = [[t, a], ...] (and motor_units)",
    ),
];

/// The loading of a validated study.
#[derive(Debug, Clone, PartialEq)]
pub enum Loading {
    /// λ(t), linear between (t, λ) points (one point: constant).
    Prescribed(Schedule),
    /// Zero axial load.
    Free,
}

impl Loading {
    /// `prescribed` or `free`.
    pub fn name(&self) -> &'static str {
        match self {
            Loading::Prescribed(_) => "prescribed",
            Loading::Free => "free",
        }
    }
}

/// A validated activation-in-time study.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryStudy {
    /// Label.
    pub name: String,
    /// Time steps \[s\], ascending.
    pub times: Vec<f64>,
    /// a(t).
    pub activation: ActivationInTime,
    /// The loading.
    pub loading: Loading,
    /// The scene's approach.
    pub approach: crate::active::Approach,
    /// The models, one per damage value (the scene's approach, the study's law and coupling):
    /// one history each.
    pub models: Vec<ModelChoice>,
}

/// Twitch terms one run may sum at most (steps × stimuli): ≈ 1 s of arithmetic.
pub const MAX_TWITCH_TERMS: f64 = 2e8;

fn points(v: &[[f64; 2]]) -> Vec<(f64, f64)> {
    v.iter().map(|p| (p[0], p[1])).collect()
}

/// Validates `spec`; returns the study and the spec with every default written out.
pub fn resolve(spec: &HistorySpec, d: &Defaults) -> Result<(HistoryStudy, HistorySpec), SpecError> {
    let time = required(
        spec.time.as_ref(),
        "time",
        "give the time steps in s: time = { from = 0, to = 1, step = 0.01 } or a list",
    )?;
    let times = time.resolve_times("time")?;
    let written = spec.schedule.clone().unwrap_or_else(|| vec![[0.0, 1.0]]);
    let interpolation = spec.interpolation.unwrap_or_default();
    let schedule = Schedule::new(points(&written), interpolation)
        .map_err(|e| SpecError::new(format!("schedule[{}]", e.index), e.value, e.rule))?;
    starts_in_time(
        &schedule,
        &times,
        "schedule[0]",
        "[0, 0] for a muscle at rest",
    )?;
    let activation = ActivationInTime::new(schedule, motor_units(spec.motor_units.as_deref())?);
    let levels = bounded_activation(&activation, &times)?;
    let loading_spec = spec.stretch.clone().unwrap_or(LoadingSpec::Constant(1.0));
    let loading = loading(&loading_spec, &times)?;
    let set = ModelKeys::one(&spec.law, &spec.coupling, &spec.damage).of_scene(d)?;
    levels_in_domain(&set.choices, &activation, &times, &levels)?;
    let name = spec
        .name
        .clone()
        .unwrap_or_else(|| "activation in time".into());
    let resolved = HistorySpec {
        name: Some(name.clone()),
        time: Some(time.clone()),
        schedule: Some(written),
        interpolation: Some(interpolation),
        motor_units: spec.motor_units.clone(),
        stretch: Some(loading_spec),
        law: set.single().0,
        coupling: set.single().1,
        damage: Some(set.damage.clone()),
    };
    Ok((
        HistoryStudy {
            name,
            times,
            activation,
            loading,
            approach: d.approach,
            models: set.choices,
        },
        resolved,
    ))
}

/// The motor units of `motor_units = [...]` (`None`: none), validated; errors name
/// `motor_units[j]`.
fn motor_units(units: Option<&[MotorUnitSpec]>) -> Result<Option<MotorUnits>, SpecError> {
    let Some(units) = units else {
        return Ok(None);
    };
    let mut built = Vec::with_capacity(units.len());
    for (j, u) in units.iter().enumerate() {
        built.push(
            MotorUnit::new(
                u.fraction,
                u.twitch_force,
                u.contraction_time,
                u.interstimulus,
            )
            .map_err(|e| SpecError::model(&format!("motor_units[{j}]"), e))?,
        );
    }
    MotorUnits::new(built).map(Some).map_err(|e| match e {
        crate::Error::InvalidParameter { value, rule, .. } => SpecError::new(
            "motor_units",
            value,
            format!("{rule} (fractions sum to {value})"),
        ),
        other => SpecError::model("motor_units", other),
    })
}

/// The key that sets a(t): `motor_units` when there are, else `schedule`.
fn activation_key(activation: &ActivationInTime) -> &'static str {
    if activation.motor_units().is_some() {
        "motor_units"
    } else {
        "schedule"
    }
}

/// The level a(t) at each of `times`; refuses an activation whose twitch sum over `times` would
/// exceed [`MAX_TWITCH_TERMS`], or whose level is not finite and ≥ 0 at one of them.
fn bounded_activation(activation: &ActivationInTime, times: &[f64]) -> Result<Vec<f64>, SpecError> {
    let last = times.last().copied().unwrap_or(0.0);
    let terms = activation.stimuli_before(last) * times.len() as f64;
    if terms > MAX_TWITCH_TERMS {
        return Err(SpecError::new(
            "motor_units",
            format!("{terms:.3e} twitch terms"),
            format!("the twitch sum over all time steps would take more than {MAX_TWITCH_TERMS:e} terms (steps × stimuli): use fewer time steps or longer interstimulus intervals"),
        ));
    }
    let mut levels = Vec::with_capacity(times.len());
    for &t in times {
        let a = activation.level(t);
        if !(a.is_finite() && a >= 0.0) {
            return Err(SpecError::new(
                activation_key(activation),
                format!("a({} s) = {}", shortest(t), shortest(a)),
                "the activation level must be finite and >= 0",
            ));
        }
        levels.push(a);
    }
    Ok(levels)
}

/// Refuses an activation that takes a model whose law has a domain ([`LawKind::domain`]: the
/// explicit law's) outside it at some time step: d_eff = d + (1 − d)(1 − a(t)) ∉ [0, 0.5] and ≠ 1,
/// as a ramp from rest or a level below 0.5 does (`levels`: a(t) at each of `times`).
fn levels_in_domain(
    models: &[ModelChoice],
    activation: &ActivationInTime,
    times: &[f64],
    levels: &[f64],
) -> Result<(), SpecError> {
    for m in models {
        let Some(domain) = m.activation_law().and_then(|(law, _)| law.domain()) else {
            continue;
        };
        // As the drive writes it (crate::active::Drive::effective_damage).
        let d_eff = |a: f64| m.damage + (1.0 - m.damage) * (1.0 - a);
        let Some(i) = levels
            .iter()
            .position(|&a| !domain.holds_at_damage(d_eff(a)))
        else {
            continue;
        };
        return Err(SpecError::new(
            activation_key(activation),
            format!("a({} s) = {}", shortest(times[i]), shortest(levels[i])),
            format!(
                "with d = {} the {} law would see d_eff = d + (1 − d)(1 − a) = {} there, and it holds for {} ({}): keep (1 − d)·a in [{}, 1] or at 0 at every time step, or use the implicit or the energy law",
                m.damage,
                m.law.name(),
                crate::text::significant(d_eff(levels[i]), 6),
                domain.describe(),
                domain.why,
                1.0 - domain.effective_damage[1],
            ),
        ));
    }
    Ok(())
}

/// The loading of `stretch` over `times`: free, a constant stretch or a stretch schedule.
fn loading(spec: &LoadingSpec, times: &[f64]) -> Result<Loading, SpecError> {
    Ok(match spec {
        LoadingSpec::Free(_) => Loading::Free,
        LoadingSpec::Constant(l) => {
            Loading::Prescribed(stretch_schedule(vec![(0.0, *l)], "stretch")?)
        }
        LoadingSpec::Schedule(p) => {
            let schedule = stretch_schedule(points(p), "stretch")?;
            starts_in_time(
                &schedule,
                times,
                "stretch[0]",
                "[0, 1] for the resting length",
            )?;
            Loading::Prescribed(schedule)
        }
    })
}

/// Refuses a schedule whose first point comes after the study's first time `times[0]`: before
/// its first point a schedule holds that point's value, so `[[5, 1]]` would mean fully active
/// from t = 0 without saying so. `start` is the point to suggest.
fn starts_in_time(
    schedule: &Schedule,
    times: &[f64],
    key: &str,
    start: &str,
) -> Result<(), SpecError> {
    let (first, _) = schedule.points()[0];
    match times.first() {
        Some(&t0) if first > t0 => Err(SpecError::new(
            key,
            format!("[{}, …]", shortest(first)),
            format!(
                "the schedule starts at t = {} s, after the study's first time {} s, and would \
                 hold its first value before it: begin it at or before {} s (e.g. {start})",
                shortest(first),
                shortest(t0),
                shortest(t0)
            ),
        )),
        _ => Ok(()),
    }
}

/// A stretch schedule: positive stretches, linear between points.
fn stretch_schedule(p: Vec<(f64, f64)>, key: &str) -> Result<Schedule, SpecError> {
    let single = p.len() == 1;
    Schedule::checked(
        p,
        Interpolation::Linear,
        |v| v.is_finite() && v > 0.0,
        "stretches must be finite and > 0",
    )
    .map_err(|e| {
        let key = if single {
            key.to_string()
        } else {
            format!("{key}[{}]", e.index)
        };
        SpecError::new(key, e.value, e.rule)
    })
}

/// One time step of a history.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HistoryPoint {
    /// Time t \[s\].
    pub t: f64,
    /// The schedule a_s(t) [-].
    pub schedule: f64,
    /// The activation level a(t) [-].
    pub level: f64,
    /// Stretch along the fibres λ [-] (prescribed, or solved under free contraction).
    pub lambda: f64,
    /// γ [-].
    pub gamma: f64,
    /// Nominal stress along the fibres \[kPa\] (0 to rounding under free contraction).
    pub stress: f64,
    /// Cauchy stress along the fibres σ₁₁ = P₁₁ λ / J \[kPa\].
    pub cauchy: f64,
    /// Volume ratio J = λ λ₂ λ₃ [-] (1 when exactly incompressible).
    pub volume: f64,
    /// Passive stress P_pas(λ) \[kPa\].
    pub passive: f64,
    /// Target active stress (1 − d)·a·f_v·P_act(λ) \[kPa\].
    pub active_target: f64,
    /// The fibre stretch rate λ̇ of the step \[1/s\] (backward Euler; 0 at the first step), in
    /// a scene with force–velocity.
    pub rate: Option<f64>,
    /// The force–velocity factor f_v(λ̇) [-] of the step, in a scene with force–velocity.
    pub velocity_factor: Option<f64>,
    /// Where the law at the step is outside its domain, if it is (the explicit law's:
    /// [`crate::active::Domain`]).
    pub outside: Option<OutsideDomain>,
}

/// The steps of a history that shorten the fibres faster than the force–velocity curve's
/// fastest rate |λ̇_min| ([`crate::active::ForceVelocity::within_range`]): there f_v is
/// extrapolated, and clamped at 0 where the formula turns negative.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct FastShortening {
    /// How many steps.
    steps: usize,
    /// The first: its time \[s\], its rate λ̇ \[1/s\], λ̇_min \[1/s\] and f_v there [-].
    first: Option<(f64, f64, f64, f64)>,
}

impl FastShortening {
    /// Counts the step ending at time `t` with fibre stretch `lambda` if its rate is beyond the
    /// curve's range.
    fn check(&mut self, rate: &StretchRate, lambda: f64, t: f64) {
        let r = rate.rate(lambda);
        if !rate.law.within_range(r) {
            self.steps += 1;
            self.first
                .get_or_insert((t, r, rate.law.min_rate, rate.law.factor(r)));
        }
    }

    /// The flag in words, if any step was beyond the range (of `total` steps).
    fn message(&self, total: usize) -> Option<String> {
        let (t, r, min, fv) = self.first?;
        Some(format!(
            "force-velocity beyond its range at {} of {total} steps: from t = {} s the fibre \
             shortens at {} 1/s, faster than min_rate = {} 1/s, where Böl & Reese's curve ends; \
             there f_v is extrapolated and clamped at 0 where it would turn negative (f_v = {} at \
             the first such step), so the active stress never pushes; smaller time steps or a \
             faster min_rate keep the history inside the curve",
            self.steps,
            shortest(t),
            crate::text::significant(r, 4),
            shortest(min),
            crate::text::significant(fv, 4)
        ))
    }
}

/// The history of one model.
#[derive(Debug, Clone, PartialEq)]
pub struct History {
    /// The model.
    pub model: ModelChoice,
    /// The steps computed, in time order.
    pub points: Vec<HistoryPoint>,
}

/// How an activation-in-time study's line names its points.
const WORDS: Words = Words {
    points: "time steps",
    x: "t",
    unit: " s",
    target: "P_pas + (1 − d)·a·f_v·P_act",
    file: output::FILE,
};

impl History {
    /// Where the steps of this history left its law's domain, with the distance of the stress
    /// from the target P_pas + (1 − d)·a·f_v·P_act (`None`: a law that holds everywhere).
    fn tally(&self) -> Option<Tally> {
        let mut tally = Tally::of(&self.model)?;
        for p in &self.points {
            let distance = p.stress - (p.passive + p.active_target);
            tally.add(p.t, p.outside, Some(distance));
        }
        Some(tally)
    }
}

/// What an activation-in-time study computed.
#[derive(Debug, Clone, PartialEq)]
pub struct HistoryResult {
    /// `prescribed` or `free`.
    pub loading: &'static str,
    /// The energy's name.
    pub energy: String,
    /// The activation approach.
    pub approach: crate::active::Approach,
    /// The volumetric energy of a nearly incompressible block (`None`: exactly incompressible).
    pub volumetric: Option<Volumetric>,
    /// One history per damage value.
    pub histories: Vec<History>,
}

/// The homogeneous state of `muscle` under `loading` at time `t`: the uniaxial point along the
/// fibres, exactly or (with the scene's volumetric energy) nearly incompressible
/// ([`Models::uniaxial`]); under free contraction the stretch with zero axial load
/// ([`Models::free_contraction`]).
pub fn state(
    models: &Models,
    muscle: &Muscle<Energy>,
    loading: &Loading,
    t: f64,
) -> crate::Result<UniaxialPoint> {
    match loading {
        Loading::Prescribed(s) => models.uniaxial(muscle, Direction::Along, s.value(t)),
        Loading::Free => models.free_contraction(muscle),
    }
}

impl HistoryStudy {
    /// One line for `check`.
    pub fn describe(&self) -> String {
        format!(
            "{}: {} time steps in [{}, {}] s, {} loading, a(t) = {}, {} {}",
            self.name,
            self.times.len(),
            self.times.first().copied().unwrap_or(f64::NAN),
            self.times.last().copied().unwrap_or(f64::NAN),
            self.loading.name(),
            if self.activation.motor_units().is_some() {
                "twitch superposition"
            } else {
                "schedule"
            },
            self.models.len(),
            if self.models.len() == 1 {
                "history"
            } else {
                "histories"
            }
        )
    }

    /// Runs one history per damage value (in parallel); a step that cannot be computed ends its
    /// history with a failure; a stop request ends every history at the step it reaches.
    pub fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
        ctx.progress.log(&self.describe());
        let choices = &self.models;
        ctx.progress
            .start(&self.name, choices.len() * self.times.len());
        let computed: Vec<Result<(History, Vec<Failure>), AppError>> = choices
            .par_iter()
            .map(|m| self.history(models, *m, ctx))
            .collect();
        ctx.progress.finish();
        let mut histories = Vec::with_capacity(computed.len());
        let (mut failures, mut tallies) = (Vec::new(), Vec::new());
        for h in computed {
            let (history, failed) = h.map_err(|e| e.within(&self.name))?;
            tallies.extend(history.tally().map(|t| (models.label(&history.model), t)));
            histories.push(history);
            failures.extend(failed);
        }
        let points = histories.iter().map(|h| h.points.len()).sum();
        Ok(Outcome {
            name: self.name.clone(),
            kind: StudyKind::ActivationInTime,
            models: histories.len(),
            points,
            requested: choices.len() * self.times.len(),
            elapsed: Default::default(),
            details: vec![self.describe()],
            failures,
            left_domain: lines(tallies, &WORDS),
            result: StudyResult::ActivationInTime(HistoryResult {
                loading: self.loading.name(),
                energy: crate::StrainEnergy::name(&models.energy).to_string(),
                approach: self.approach,
                volumetric: models.volumetric,
                histories,
            }),
        })
    }

    /// The history of model `m`, with its failures: the one that ended it early, if any, and
    /// the steps beyond the force–velocity curve's range.
    fn history(
        &self,
        models: &Models,
        m: ModelChoice,
        ctx: &RunContext,
    ) -> Result<(History, Vec<Failure>), AppError> {
        let mut muscle = models.muscle(m)?;
        let passive = models.passive();
        let label = models.label(&m);
        let mut history = History {
            model: m,
            points: Vec::with_capacity(self.times.len()),
        };
        let every = (self.times.len() / 20).max(1);
        // The fibre stretch and time of the previous step, for the force–velocity rate.
        let mut previous: Option<(f64, f64)> = None;
        let mut fast = FastShortening::default();
        let mut stopped = None;
        for (i, &t) in self.times.iter().enumerate() {
            if let Some(reason) = ctx.stop.and_then(|s| s.reason()) {
                stopped = Some(format!(
                    "{reason}: stopped before t = {} s; the steps solved before are kept",
                    shortest(t)
                ));
                break;
            }
            let level = self.activation.level(t);
            let rate = match (models.force_velocity, previous) {
                (Some(law), Some((t0, lambda0))) => Some(StretchRate {
                    law,
                    previous: lambda0,
                    dt: t - t0,
                }),
                _ => None,
            };
            let step = self.step(models, (&mut muscle, &passive), t, level, rate);
            let (point, fibre_stretch) = match step {
                Ok(step) => step,
                Err(e) => {
                    stopped = Some(format!(
                        "at t = {} s (a = {}): {e}; the history stops there",
                        shortest(t),
                        shortest(level)
                    ));
                    break;
                }
            };
            if let Some(rate) = rate {
                fast.check(&rate, fibre_stretch, t);
            }
            history.points.push(point);
            previous = Some((t, fibre_stretch));
            if i % every == 0 || i + 1 == self.times.len() {
                ctx.progress.point(&format!(
                    "{}: {label}: t = {t} s ({}/{}), a = {level:.4}, lambda = {:.5}, P = {:.4} kPa",
                    self.name,
                    i + 1,
                    self.times.len(),
                    point.lambda,
                    point.stress
                ));
            } else {
                ctx.progress.advance(1);
            }
        }
        let failures = fast
            .message(self.times.len())
            .into_iter()
            .chain(stopped)
            .map(|message| Failure {
                model: label.clone(),
                message,
            })
            .collect();
        Ok((history, failures))
    }

    /// One step of a history: the state of the muscle (and its passive counterpart) at time `t`
    /// with activation level `level` (and the stretch rate of the step, with force–velocity),
    /// and its fibre stretch.
    fn step(
        &self,
        models: &Models,
        (muscle, passive): (&mut Muscle<Energy>, &Muscle<Energy>),
        t: f64,
        level: f64,
        rate: Option<StretchRate>,
    ) -> crate::Result<(HistoryPoint, f64)> {
        muscle.set_activation(level)?;
        muscle.set_rate(rate)?;
        let p = state(models, muscle, &self.loading, t)?;
        let passive = models.uniaxial(passive, Direction::Along, p.lambda)?.stress;
        let point = HistoryPoint {
            t,
            schedule: self.activation.schedule().value(t),
            level,
            lambda: p.lambda,
            gamma: p.gamma,
            stress: p.stress,
            cauchy: p.cauchy,
            volume: p.lambda * p.lateral[0] * p.lateral[1],
            passive,
            active_target: muscle.drive().target(&models.curve, p.lambda),
            rate: models.force_velocity.map(|_| {
                let rate = muscle.drive().rate();
                rate.map_or(0.0, |r| r.rate(p.fibre_stretch))
            }),
            velocity_factor: models
                .force_velocity
                .map(|_| muscle.drive().velocity_factor(p.fibre_stretch)),
            outside: muscle.outside_domain(p.fibre_stretch),
        };
        Ok((point, p.fibre_stretch))
    }
}
