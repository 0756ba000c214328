//! The studies a scene can hold, one module each: its spec as written ([`StudySpec`], unknown
//! keys rejected per kind), its validated form ([`Study`]), how it runs and what it returns
//! ([`Outcome`], with a typed [`StudyResult`]). Studies build their models through
//! [`crate::models`] and know nothing of scene files or outputs.
//!
//! | kind | module | result |
//! |---|---|---|
//! | `uniaxial` | [`uniaxial`] | curves along or across the fibres |
//! | `cylinder` | [`cylinder`] | FE sweeps, each with its 0D curve |
//! | `fit` | [`fit`] | fitted parameters with statistics |
//! | `stability` | [`stability`] | softening and strong ellipticity along the fibres |
//! | `tradeoff` | [`tradeoff`] | speed versus accuracy of every option |
//! | `activation-in-time` | [`history`] | a 0D block driven in time by a(t) |
//!
//! Adding a kind: a module with its spec, `resolve`, study type and `run`, and one line in each
//! of [`StudyKind`], [`StudySpec`], [`Study`] and the matches below.

pub mod cylinder;
pub mod fit;
pub mod history;
pub mod spec;
pub mod stability;
pub mod tradeoff;
pub mod uniaxial;

use crate::app_error::{AppError, SpecError};
use crate::fem::Cancel;
use crate::models::Models;
use crate::uniaxial::Direction;
use serde::{Deserialize, Deserializer, Serialize};
use spec::Defaults;
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// Study kinds (`kind = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StudyKind {
    /// Homogeneous uniaxial tension (0D).
    Uniaxial,
    /// The axisymmetric FE cylinder.
    Cylinder,
    /// A least-squares fit of model parameters.
    Fit,
    /// Material stability along the uniaxial path along the fibres.
    Stability,
    /// Speed versus accuracy of every option that trades one for the other.
    Tradeoff,
    /// A homogeneous block driven in time by an activation level a(t).
    ActivationInTime,
}

impl StudyKind {
    /// Name in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            StudyKind::Uniaxial => "uniaxial",
            StudyKind::Cylinder => "cylinder",
            StudyKind::Fit => "fit",
            StudyKind::Stability => "stability",
            StudyKind::Tradeoff => "tradeoff",
            StudyKind::ActivationInTime => "activation-in-time",
        }
    }

    /// What to say about a key this kind of study does not take (`" (it takes a list: ...)"`),
    /// or nothing.
    pub fn hint(self, key: &str) -> String {
        let hints = match self {
            StudyKind::Uniaxial => uniaxial::HINTS,
            StudyKind::Cylinder => cylinder::HINTS,
            StudyKind::Fit => fit::HINTS,
            StudyKind::Stability => stability::HINTS,
            StudyKind::Tradeoff => tradeoff::HINTS,
            StudyKind::ActivationInTime => history::HINTS,
        };
        hints
            .iter()
            .find(|(k, _)| *k == key)
            .map_or(String::new(), |(_, h)| format!(" ({h})"))
    }
}

/// One `[[study]]` as written, by kind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum StudySpec {
    /// `kind = "uniaxial"`.
    Uniaxial(uniaxial::UniaxialSpec),
    /// `kind = "cylinder"`.
    Cylinder(cylinder::CylinderSpec),
    /// `kind = "fit"`.
    Fit(fit::FitSpec),
    /// `kind = "stability"`.
    Stability(stability::StabilitySpec),
    /// `kind = "tradeoff"`.
    Tradeoff(tradeoff::TradeoffSpec),
    /// `kind = "activation-in-time"`.
    ActivationInTime(history::HistorySpec),
}

impl StudySpec {
    /// The spec of a study of `kind` from a table without its `kind` key, so that errors keep
    /// their position in the file (serde's internally tagged enums lose it).
    pub fn of_kind<'de, D: Deserializer<'de>>(kind: StudyKind, table: D) -> Result<Self, D::Error> {
        Ok(match kind {
            StudyKind::Uniaxial => StudySpec::Uniaxial(Deserialize::deserialize(table)?),
            StudyKind::Cylinder => StudySpec::Cylinder(Deserialize::deserialize(table)?),
            StudyKind::Fit => StudySpec::Fit(Deserialize::deserialize(table)?),
            StudyKind::Stability => StudySpec::Stability(Deserialize::deserialize(table)?),
            StudyKind::Tradeoff => StudySpec::Tradeoff(Deserialize::deserialize(table)?),
            StudyKind::ActivationInTime => {
                StudySpec::ActivationInTime(Deserialize::deserialize(table)?)
            }
        })
    }

    /// Its kind.
    pub fn kind(&self) -> StudyKind {
        match self {
            StudySpec::Uniaxial(_) => StudyKind::Uniaxial,
            StudySpec::Cylinder(_) => StudyKind::Cylinder,
            StudySpec::Fit(_) => StudyKind::Fit,
            StudySpec::Stability(_) => StudyKind::Stability,
            StudySpec::Tradeoff(_) => StudyKind::Tradeoff,
            StudySpec::ActivationInTime(_) => StudyKind::ActivationInTime,
        }
    }

    /// Validates the spec against the scene's defaults; returns the study and the spec with
    /// every default written out. Keys in errors are relative to the study.
    pub fn resolve(&self, defaults: &Defaults) -> Result<(Study, StudySpec), SpecError> {
        Ok(match self {
            StudySpec::Uniaxial(s) => {
                let (study, r) = uniaxial::resolve(s, defaults)?;
                (Study::Uniaxial(study), StudySpec::Uniaxial(r))
            }
            StudySpec::Cylinder(s) => {
                let (study, r) = cylinder::resolve(s, defaults)?;
                (Study::Cylinder(study), StudySpec::Cylinder(r))
            }
            StudySpec::Fit(s) => {
                let (study, r) = fit::resolve(s, defaults)?;
                (Study::Fit(study), StudySpec::Fit(r))
            }
            StudySpec::Stability(s) => {
                let (study, r) = stability::resolve(s, defaults)?;
                (Study::Stability(study), StudySpec::Stability(r))
            }
            StudySpec::Tradeoff(s) => {
                let (study, r) = tradeoff::resolve(s)?;
                (Study::Tradeoff(study), StudySpec::Tradeoff(r))
            }
            StudySpec::ActivationInTime(s) => {
                let (study, r) = history::resolve(s, defaults)?;
                (
                    Study::ActivationInTime(study),
                    StudySpec::ActivationInTime(r),
                )
            }
        })
    }
}

/// A validated study, ready to run.
#[derive(Debug, Clone, PartialEq)]
pub enum Study {
    /// Homogeneous uniaxial tension.
    Uniaxial(uniaxial::UniaxialStudy),
    /// The FE cylinder.
    Cylinder(cylinder::CylinderStudy),
    /// A least-squares fit.
    Fit(fit::FitStudy),
    /// Material stability along the fibres.
    Stability(stability::StabilityStudy),
    /// Speed versus accuracy.
    Tradeoff(tradeoff::TradeoffStudy),
    /// A 0D block driven in time.
    ActivationInTime(history::HistoryStudy),
}

impl Study {
    /// The study's label.
    pub fn name(&self) -> &str {
        match self {
            Study::Uniaxial(s) => &s.name,
            Study::Cylinder(s) => &s.name,
            Study::Fit(s) => &s.name,
            Study::Stability(s) => &s.name,
            Study::Tradeoff(s) => &s.name,
            Study::ActivationInTime(s) => &s.name,
        }
    }

    /// Its kind.
    pub fn kind(&self) -> StudyKind {
        match self {
            Study::Uniaxial(_) => StudyKind::Uniaxial,
            Study::Cylinder(_) => StudyKind::Cylinder,
            Study::Fit(_) => StudyKind::Fit,
            Study::Stability(_) => StudyKind::Stability,
            Study::Tradeoff(_) => StudyKind::Tradeoff,
            Study::ActivationInTime(_) => StudyKind::ActivationInTime,
        }
    }

    /// What it will compute, in one line.
    pub fn describe(&self) -> String {
        match self {
            Study::Uniaxial(s) => s.describe(),
            Study::Cylinder(s) => s.describe(),
            Study::Fit(s) => s.describe(),
            Study::Stability(s) => s.describe(),
            Study::Tradeoff(s) => s.describe(),
            Study::ActivationInTime(s) => s.describe(),
        }
    }

    /// Runs the study on `models`; `fallback` completes a trade-off study.
    pub fn run(
        &self,
        models: &Models,
        fallback: &tradeoff::Fallback,
        ctx: &RunContext,
    ) -> Result<Outcome, AppError> {
        match self {
            Study::Uniaxial(s) => s.run(models, ctx),
            Study::Cylinder(s) => s.run(models, ctx),
            Study::Fit(s) => s.run(ctx),
            Study::Stability(s) => s.run(models, ctx),
            Study::Tradeoff(s) => s.run(models, fallback, ctx),
            Study::ActivationInTime(s) => s.run(models, ctx),
        }
    }
}

/// What a trade-off study takes from the other studies: the first cylinder study's cylinder and
/// mesh, the first uniaxial study along the fibres' stretches (or the defaults).
pub fn fallback(studies: &[Study]) -> tradeoff::Fallback {
    let mut f = tradeoff::Fallback::default();
    if let Some(c) = studies.iter().find_map(|s| match s {
        Study::Cylinder(c) => Some(c),
        _ => None,
    }) {
        f.geometry = tradeoff::Geometry {
            radius: c.radius,
            length: c.length,
            grading: c.grading,
        };
        f.cells = (c.nr, c.nz);
    }
    if let Some(u) = studies.iter().find_map(|s| match s {
        Study::Uniaxial(u) if u.direction == Direction::Along => Some(u),
        _ => None,
    }) {
        f.curve_stretches = u.stretches.clone();
    }
    f
}

/// Where a run reports its progress: log lines and one progress count per study. Every method
/// defaults to doing nothing ([`Silent`]).
pub trait Progress: Sync {
    /// One line about what is being computed.
    fn log(&self, _line: &str) {}
    /// A study `label` with `total` points starts.
    fn start(&self, _label: &str, _total: usize) {}
    /// `n` more points are done.
    fn advance(&self, _n: usize) {}
    /// One more point is done, said in `line` (e.g. a solved stretch of an FE sweep).
    fn point(&self, _line: &str) {
        self.advance(1);
    }
    /// The study is done.
    fn finish(&self) {}
}

/// Reports nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Progress for Silent {}

/// How studies run: where they report, where the FE solver writes VTK files, what stops them.
#[derive(Clone, Copy)]
pub struct RunContext<'a> {
    /// Progress reports.
    pub progress: &'a dyn Progress,
    /// Directory for VTK files (`None`: none are written).
    pub vtk_dir: Option<&'a Path>,
    /// Stops the FE sweeps, which return the stretches solved before (`None`: runs to the end).
    pub stop: Option<&'a Stop>,
}

/// A request to stop a run (an interruption, a time limit) and its reason: FE sweeps holding its
/// flag return what they solved, studies not started are not run. Clones share the request.
#[derive(Debug, Clone, Default)]
pub struct Stop {
    flag: Cancel,
    reason: Arc<Mutex<Option<String>>>,
}

impl Stop {
    /// A request not yet made.
    pub fn new() -> Self {
        Self::default()
    }

    /// Stops the run because of `reason` (the first reason given is kept).
    pub fn stop(&self, reason: &str) {
        if let Ok(mut r) = self.reason.lock() {
            r.get_or_insert_with(|| reason.to_string());
        }
        self.flag.cancel();
    }

    /// Why the run was stopped, once it was.
    pub fn reason(&self) -> Option<String> {
        if !self.flag.is_cancelled() {
            return None;
        }
        Some(
            self.reason
                .lock()
                .ok()
                .and_then(|r| r.clone())
                .unwrap_or_else(|| "stopped".into()),
        )
    }

    /// The flag the FE solver polls ([`crate::fem::SolverOptions::cancel`]).
    pub fn flag(&self) -> &Cancel {
        &self.flag
    }
}

/// Something a study could not compute, for a reason of the material or the solver: recorded and
/// reported, the study goes on.
#[derive(Debug, Clone, PartialEq)]
pub struct Failure {
    /// Which model (or `fit`, `stability`).
    pub model: String,
    /// What happened.
    pub message: String,
}

/// What a study computed.
#[derive(Debug, Clone, PartialEq)]
pub enum StudyResult {
    /// Uniaxial curves.
    Uniaxial(uniaxial::UniaxialResult),
    /// FE sweeps.
    Cylinder(cylinder::CylinderResult),
    /// Fits, converged or not.
    Fit(Vec<fit::FitOutcome>),
    /// Stability curves.
    Stability(Vec<stability::StabilityCurve>),
    /// Trade-off measurements.
    Tradeoff(tradeoff::TradeoffResults),
    /// Histories in time.
    ActivationInTime(history::HistoryResult),
    /// Nothing: the study stopped with an error before computing a result (the error is its
    /// failure, [`Outcome::nothing`]).
    Nothing,
}

/// One study's outcome: its result, its failures and its summary.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// The study's label.
    pub name: String,
    /// Its kind.
    pub kind: StudyKind,
    /// Models (curves, sweeps, fits, variants) computed.
    pub models: usize,
    /// Points computed (fits: converged).
    pub points: usize,
    /// Points requested.
    pub requested: usize,
    /// Wall time.
    pub elapsed: Duration,
    /// Facts about the study (mesh, dofs, verification), one line each.
    pub details: Vec<String>,
    /// What could not be computed, and why.
    pub failures: Vec<Failure>,
    /// The result.
    pub result: StudyResult,
}

impl Outcome {
    /// The outcome of `study`, which computed nothing: it stopped with an error, or was not run
    /// (the run was stopped). `message` says which, and is its one failure.
    pub fn nothing(study: &Study, message: String) -> Self {
        Outcome {
            name: study.name().to_string(),
            kind: study.kind(),
            models: 0,
            points: 0,
            requested: 0,
            elapsed: Duration::ZERO,
            details: vec!["nothing computed: see \"Where a model stopped\"".into()],
            failures: vec![Failure {
                model: "the whole study".into(),
                message,
            }],
            result: StudyResult::Nothing,
        }
    }

    /// Whether everything the study was asked for was computed: no failure, every requested
    /// point.
    pub fn complete(&self) -> bool {
        self.failures.is_empty() && self.points >= self.requested
    }
}

/// A file-name-safe lower-case form of `text` (runs of other characters become one `_`).
pub fn slug(text: &str) -> String {
    let mut s: String = text
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    while s.contains("__") {
        s = s.replace("__", "_");
    }
    s.trim_matches('_').to_string()
}
