//! The studies a scene can hold, one module each: its spec as written (unknown keys rejected per
//! kind), its validated form, how it runs and what it returns ([`Outcome`], with a typed
//! [`StudyResult`]). Studies build their models through [`crate::models`] and know nothing of
//! scene files or outputs.
//!
//! | kind | module | result |
//! |---|---|---|
//! | `uniaxial` | [`uniaxial`] | curves along or across the fibres |
//! | `cylinder` | [`cylinder`] | FE sweeps, each with its 0D curve |
//! | `fit` | [`fit`] | fitted parameters with statistics |
//! | `stability` | [`stability`] | softening and strong ellipticity along the fibres |
//! | `tradeoff` | [`tradeoff`] | speed versus accuracy of every option |
//! | `activation-in-time` | [`history`] | a 0D block driven in time by a(t) |
//! | `shear` | [`shear`] | simple shear per approach and fibre angle |
//! | `biaxial` | [`biaxial`] | planar biaxial stretch per approach |
//! | `tangent` | [`tangent`] | Taylor tests of every model's tangent at chosen states |
//!
//! Adding a kind: a module with its spec, study and result types, `impl KindSpec` for the spec
//! and `impl KindStudy` for the study, `impl outputs::KindOutput` for the result (in the
//! module's `output.rs`: its tables, figures and report section), and one line in
//! `study_kinds!` below, which generates [`StudyKind`], [`StudySpec`], [`Study`],
//! [`StudyResult`] and their dispatch.
//!
//! A kind's tables: [`outputs::KindOutput::tables`] returns, per study, a
//! [`table::Table`] built with its column builders (`text`, `number` with its unit, `integer`,
//! `boolean`; each with its description) and the CSV file it goes to. From that one declaration
//! the run writes the file (the tables of every study of the file appended), describes every
//! column in `datapackage.json`, and Python returns the same columns as numpy arrays
//! (`Study.table`); nothing else names the columns. `src/studies/shear.rs` (`ShearResult::table`)
//! with `src/studies/shear/output.rs` is the model to follow.

pub mod biaxial;
pub mod curves;
pub mod cylinder;
pub mod domain;
pub mod fit;
pub mod history;
pub mod outputs;
pub mod rules;
pub mod shear;
pub mod size;
pub mod spec;
pub mod stability;
pub mod table;
pub mod tangent;
pub mod tradeoff;
pub mod uniaxial;

use crate::active::Approach;
use crate::app_error::{AppError, SpecError};
use crate::fem::Cancel;
use crate::models::Models;
use serde::{Deserialize, Deserializer, Serialize};
use spec::Defaults;
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// A study kind's spec as written: it validates itself against the scene's defaults, returning
/// the validated study and the spec with every default written out.
pub trait KindSpec: Sized {
    /// The validated study.
    type Study;
    /// Keys in errors are relative to the study.
    fn resolve(&self, defaults: &Defaults) -> Result<(Self::Study, Self), SpecError>;
    /// Once every study of the scene is resolved (`studies`, among them this one, `study`): the
    /// study and its resolved spec completed from the others, where it takes what it leaves out
    /// from them (`None`: nothing to complete, the default).
    fn completed(
        &self,
        _study: &Self::Study,
        _resolved: &Self,
        _studies: &[Study],
        _defaults: &Defaults,
    ) -> Result<Option<(Self::Study, Self)>, SpecError> {
        Ok(None)
    }
}

/// A validated study of some kind.
pub trait KindStudy {
    /// Whether it runs alone, after the others (it measures run times).
    const ALONE: bool = false;
    /// Whether it is driven in time: the stretch rate, hence force–velocity, applies.
    const IN_TIME: bool = false;
    /// Why a scene holds at most one study of its kind, if it does (`None`: any number).
    const ONE_PER_SCENE: Option<&'static str> = None;
    /// Whether it solves the axisymmetric FE cylinder, whose fibres run along its axis.
    const AXIAL_FIBRES: bool = false;
    /// Its label.
    fn name(&self) -> &str;
    /// What it will compute, in one line.
    fn describe(&self) -> String;
    /// The activation approaches it uses besides the scene's (empty: the scene's only).
    fn approaches(&self) -> Vec<Approach> {
        Vec::new()
    }
    /// Runs it on `models`.
    fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError>;
}

/// The study kinds: `study_kinds! { Variant("name", module::Spec, module::Study, Result, "doc"), ... }`
/// generates the four enums and every dispatch over them.
macro_rules! study_kinds {
    ($($(#[$doc:meta])* $variant:ident($name:literal, $spec:ty, $study:ty, $result:ty, $hints:expr)),* $(,)?) => {
        /// Study kinds (`kind = "..."`).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
        #[serde(rename_all = "kebab-case")]
        pub enum StudyKind {
            $($(#[$doc])* $variant,)*
        }

        impl StudyKind {
            /// Every kind, in the order of the registry.
            pub const ALL: &'static [StudyKind] = &[$(StudyKind::$variant,)*];

            /// Name in scene files and outputs.
            pub fn name(self) -> &'static str {
                match self {
                    $(StudyKind::$variant => $name,)*
                }
            }

            /// Whether its studies are driven in time ([`KindStudy::IN_TIME`]).
            pub fn in_time(self) -> bool {
                match self {
                    $(StudyKind::$variant => <$study as KindStudy>::IN_TIME,)*
                }
            }

            /// Why a scene holds at most one study of this kind, if it does
            /// ([`KindStudy::ONE_PER_SCENE`]).
            pub fn one_per_scene(self) -> Option<&'static str> {
                match self {
                    $(StudyKind::$variant => <$study as KindStudy>::ONE_PER_SCENE,)*
                }
            }

            /// Whether its studies solve the axisymmetric FE cylinder, whose fibres run along
            /// its axis ([`KindStudy::AXIAL_FIBRES`]).
            pub fn axial_fibres(self) -> bool {
                match self {
                    $(StudyKind::$variant => <$study as KindStudy>::AXIAL_FIBRES,)*
                }
            }

            /// Whether its studies run alone, after the others ([`KindStudy::ALONE`]).
            pub fn runs_alone(self) -> bool {
                match self {
                    $(StudyKind::$variant => <$study as KindStudy>::ALONE,)*
                }
            }

            /// Every kind's name, quoted, joined with `|` (for messages).
            pub fn names() -> String {
                let names: Vec<String> = Self::ALL
                    .iter()
                    .map(|k| format!("\"{}\"", k.name()))
                    .collect();
                names.join(" | ")
            }

            /// What to say about a key this kind of study does not take (`" (it takes a list:
            /// ...)"`), or nothing.
            pub fn hint(self, key: &str) -> String {
                let hints: &[(&str, &str)] = match self {
                    $(StudyKind::$variant => $hints,)*
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
            $($(#[$doc])* $variant($spec),)*
        }

        impl StudySpec {
            /// The spec of a study of `kind` from a table without its `kind` key, so that errors
            /// keep their position in the file (serde's internally tagged enums lose it).
            pub fn of_kind<'de, D: Deserializer<'de>>(kind: StudyKind, table: D) -> Result<Self, D::Error> {
                Ok(match kind {
                    $(StudyKind::$variant => StudySpec::$variant(Deserialize::deserialize(table)?),)*
                })
            }

            /// Its kind.
            pub fn kind(&self) -> StudyKind {
                match self {
                    $(StudySpec::$variant(_) => StudyKind::$variant,)*
                }
            }

            /// Validates the spec against the scene's defaults; returns the study and the spec
            /// with every default written out. Keys in errors are relative to the study.
            pub fn resolve(&self, defaults: &Defaults) -> Result<(Study, StudySpec), SpecError> {
                Ok(match self {
                    $(StudySpec::$variant(s) => {
                        let (study, r) = KindSpec::resolve(s, defaults)?;
                        (Study::$variant(study), StudySpec::$variant(r))
                    })*
                })
            }

            /// The study at `own` of the resolved `studies` and its `resolved` spec, completed
            /// from the others ([`KindSpec::completed`]; `None`: nothing to complete).
            pub fn completed(
                &self,
                resolved: &StudySpec,
                own: usize,
                studies: &[Study],
                defaults: &Defaults,
            ) -> Result<Option<(Study, StudySpec)>, SpecError> {
                Ok(match (self, &studies[own], resolved) {
                    $((StudySpec::$variant(s), Study::$variant(study), StudySpec::$variant(r)) => {
                        KindSpec::completed(s, study, r, studies, defaults)?
                            .map(|(a, b)| (Study::$variant(a), StudySpec::$variant(b)))
                    })*
                    _ => None,
                })
            }
        }

        /// A validated study, ready to run.
        #[derive(Debug, Clone, PartialEq)]
        pub enum Study {
            $($(#[$doc])* $variant($study),)*
        }

        impl Study {
            /// The study's label.
            pub fn name(&self) -> &str {
                match self {
                    $(Study::$variant(s) => KindStudy::name(s),)*
                }
            }

            /// Its kind.
            pub fn kind(&self) -> StudyKind {
                match self {
                    $(Study::$variant(_) => StudyKind::$variant,)*
                }
            }

            /// What it will compute, in one line.
            pub fn describe(&self) -> String {
                match self {
                    $(Study::$variant(s) => KindStudy::describe(s),)*
                }
            }

            /// Whether it is driven in time ([`KindStudy::IN_TIME`]).
            pub fn in_time(&self) -> bool {
                self.kind().in_time()
            }

            /// The approaches it uses besides the scene's ([`KindStudy::approaches`]).
            pub fn approaches(&self) -> Vec<Approach> {
                match self {
                    $(Study::$variant(s) => KindStudy::approaches(s),)*
                }
            }

            /// Runs the study on `models`.
            pub fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
                match self {
                    $(Study::$variant(s) => KindStudy::run(s, models, ctx),)*
                }
            }
        }

        /// What a study computed.
        #[derive(Debug, Clone, PartialEq)]
        pub enum StudyResult {
            $($(#[$doc])* $variant($result),)*
            /// Nothing: the study stopped with an error before computing a result (the error is
            /// its failure, [`Outcome::nothing`]).
            Nothing,
        }

        $(
            impl outputs::OfResult for $result {
                fn of(result: &StudyResult) -> Option<&Self> {
                    match result {
                        StudyResult::$variant(r) => Some(r),
                        _ => None,
                    }
                }
            }
        )*

        impl StudyResult {
            /// Every kind's figures ([`outputs::KindOutput::figures`]), kind by kind in the
            /// order of the registry, each given its studies of `outcomes` in scene order.
            pub fn figures(outcomes: &[Outcome], cx: &outputs::Context) -> Vec<crate::plot::Figure> {
                let mut figures = Vec::new();
                $(figures.extend(outputs::figures_of::<$result>(outcomes, cx));)*
                figures
            }

            /// Every kind's report section ([`outputs::KindOutput::report`]), in the order of
            /// [`Self::figures`], appended to `h`.
            pub fn report(outcomes: &[Outcome], cx: &outputs::Context, h: &mut String) -> Result<(), AppError> {
                $(outputs::report_of::<$result>(outcomes, cx, h)?;)*
                Ok(())
            }

            /// The study's tables ([`outputs::KindOutput::tables`]), none if it computed
            /// nothing.
            pub fn tables(&self, study: &str) -> Vec<outputs::OwnTable> {
                match self {
                    $(StudyResult::$variant(r) => outputs::KindOutput::tables(r, study),)*
                    StudyResult::Nothing => Vec::new(),
                }
            }

            /// What it computed with ([`outputs::KindOutput::used`]).
            pub fn used(&self) -> outputs::Used {
                match self {
                    $(StudyResult::$variant(r) => outputs::KindOutput::used(r),)*
                    StudyResult::Nothing => outputs::Used::default(),
                }
            }

            /// The VTK files it wrote ([`outputs::KindOutput::vtk_files`]).
            pub fn vtk_files(&self) -> Vec<&Path> {
                match self {
                    $(StudyResult::$variant(r) => outputs::KindOutput::vtk_files(r),)*
                    StudyResult::Nothing => Vec::new(),
                }
            }

            /// Its lines for the command line ([`outputs::KindOutput::console`]).
            pub fn console(&self, study: &str) -> Vec<String> {
                match self {
                    $(StudyResult::$variant(r) => outputs::KindOutput::console(r, study),)*
                    StudyResult::Nothing => Vec::new(),
                }
            }

            /// What it found ([`outputs::KindOutput::findings`]).
            pub fn findings(&self) -> Vec<String> {
                match self {
                    $(StudyResult::$variant(r) => outputs::KindOutput::findings(r),)*
                    StudyResult::Nothing => Vec::new(),
                }
            }
        }
    };
}

// A new study kind: its module (spec, study, result; `impl KindSpec`, `impl KindStudy`) and one
// line here.
study_kinds! {
    /// Homogeneous uniaxial tension (0D).
    Uniaxial("uniaxial", uniaxial::UniaxialSpec, uniaxial::UniaxialStudy, uniaxial::UniaxialResult, uniaxial::HINTS),
    /// The axisymmetric FE cylinder.
    Cylinder("cylinder", cylinder::CylinderSpec, cylinder::CylinderStudy, cylinder::CylinderResult, cylinder::HINTS),
    /// A least-squares fit of model parameters.
    Fit("fit", fit::FitSpec, fit::FitStudy, Vec<fit::FitOutcome>, fit::HINTS),
    /// Material stability along the uniaxial path along the fibres.
    Stability("stability", stability::StabilitySpec, stability::StabilityStudy, Vec<stability::StabilityCurve>, stability::HINTS),
    /// Speed versus accuracy of every option that trades one for the other.
    Tradeoff("tradeoff", tradeoff::TradeoffSpec, tradeoff::TradeoffStudy, tradeoff::TradeoffResults, tradeoff::HINTS),
    /// A homogeneous block driven in time by an activation level a(t).
    ActivationInTime("activation-in-time", history::HistorySpec, history::HistoryStudy, history::HistoryResult, history::HINTS),
    /// Homogeneous simple shear, per activation approach and fibre angle.
    Shear("shear", shear::ShearSpec, shear::ShearStudy, shear::ShearResult, shear::HINTS),
    /// Homogeneous planar biaxial stretch.
    Biaxial("biaxial", biaxial::BiaxialSpec, biaxial::BiaxialStudy, biaxial::BiaxialResult, biaxial::HINTS),
    /// Tangent accuracy: Taylor remainders of every model at chosen states.
    Tangent("tangent", tangent::TangentSpec, tangent::TangentStudy, tangent::TangentResult, tangent::HINTS),
}

/// `impl KindSpec` and `impl KindStudy` for a kind whose module has `resolve(spec, defaults)` and
/// whose study has `name`, `describe()` and `run(models, ctx)`; a block after them holds the
/// study's other `KindStudy` items (`IN_TIME`, `approaches`).
macro_rules! plain_kind {
    ($spec:ty, $study:ty, $resolve:path $(, { $($items:tt)* })?) => {
        impl KindSpec for $spec {
            type Study = $study;
            fn resolve(&self, d: &Defaults) -> Result<($study, Self), SpecError> {
                $resolve(self, d)
            }
        }
        impl KindStudy for $study {
            $($($items)*)?
            fn name(&self) -> &str {
                &self.name
            }
            fn describe(&self) -> String {
                <$study>::describe(self)
            }
            fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
                <$study>::run(self, models, ctx)
            }
        }
    };
}

plain_kind!(
    uniaxial::UniaxialSpec,
    uniaxial::UniaxialStudy,
    uniaxial::resolve
);
plain_kind!(
    cylinder::CylinderSpec,
    cylinder::CylinderStudy,
    cylinder::resolve,
    {
        const AXIAL_FIBRES: bool = true;
    }
);
plain_kind!(
    stability::StabilitySpec,
    stability::StabilityStudy,
    stability::resolve
);
plain_kind!(
    history::HistorySpec,
    history::HistoryStudy,
    history::resolve,
    {
        const IN_TIME: bool = true;
    }
);
plain_kind!(shear::ShearSpec, shear::ShearStudy, shear::resolve, {
    fn approaches(&self) -> Vec<Approach> {
        spec::ApproachModel::approaches(&self.models)
    }
});
plain_kind!(
    biaxial::BiaxialSpec,
    biaxial::BiaxialStudy,
    biaxial::resolve,
    {
        fn approaches(&self) -> Vec<Approach> {
            spec::ApproachModel::approaches(&self.models)
        }
    }
);
plain_kind!(
    tangent::TangentSpec,
    tangent::TangentStudy,
    tangent::resolve
);

impl KindSpec for fit::FitSpec {
    type Study = fit::FitStudy;
    fn resolve(&self, d: &Defaults) -> Result<(fit::FitStudy, Self), SpecError> {
        fit::resolve(self, d)
    }
}

impl KindStudy for fit::FitStudy {
    fn name(&self) -> &str {
        &self.name
    }
    fn describe(&self) -> String {
        fit::FitStudy::describe(self)
    }
    fn run(&self, _: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
        fit::FitStudy::run(self, ctx)
    }
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
    /// The models computed outside the domain their law holds on, one line each (the points
    /// are computed and written all the same: [`domain`]).
    pub left_domain: Vec<domain::LeftDomain>,
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
            left_domain: Vec::new(),
            result: StudyResult::Nothing,
        }
    }

    /// Whether everything the study was asked for was computed: no failure, every requested
    /// point.
    pub fn complete(&self) -> bool {
        self.failures.is_empty() && self.points >= self.requested
    }
}

/// A file-name-safe lower-case form of `text`: its letters and digits (any script:
/// [`char::is_alphanumeric`], so `"Мышца"` is `мышца` and `"筋肉"` stays `筋肉`), lower-cased;
/// every run of other characters (spaces, punctuation, path separators, control characters)
/// becomes one `_`, none at either end. ASCII names give what they always gave (`"cyl A"` →
/// `cyl_a`); a slug never holds a path separator, a control character or a leading dot.
pub fn slug(text: &str) -> String {
    let mut s = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_alphanumeric() {
            s.extend(c.to_lowercase());
        } else if !s.is_empty() && !s.ends_with('_') {
            s.push('_');
        }
    }
    let trimmed = s.trim_end_matches('_').len();
    s.truncate(trimmed);
    s
}

/// The longest [`slug`] of a study's name, in bytes (UTF-8), so that every file name derived
/// from it stays within the 255 bytes a file name may have: `points_<slug>.csv`,
/// `vtk/<slug>_d<damage>/` (damage written short: at most 24 bytes more), `fig_<kind>_<slug>.svg`
/// and, where two studies' figures share a stem, `fig_history_<slug₁>_<slug₂>_<n>.png`
/// (2 × 100 + 20 bytes).
pub const MAX_SLUG_BYTES: usize = 100;
