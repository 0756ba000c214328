//! Running a scene: the studies at the same time (a kind that measures run times alone, after),
//! each building only the models it needs (homogeneous curves and FE sweeps in parallel too),
//! progress reported through [`crate::studies::Progress`].

use super::Scene;
use crate::studies::outputs::OfResult;
use crate::studies::{Failure, Outcome, Progress, RunContext, Silent, Stop, Study};
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::io::Write;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// How to run.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Print what is being computed, one line each.
    pub verbose: bool,
    /// Show progress bars (only with `verbose`; meaningful on a terminal).
    pub progress: bool,
    /// Where the solver writes VTK files (e.g. a staging directory; `None`: no VTK).
    pub vtk_dir: Option<PathBuf>,
    /// Stops the run (e.g. on SIGINT or at a time limit): the FE sweep running returns the
    /// stretches it solved, the studies not started are recorded as not run.
    pub stop: Option<Stop>,
}

/// Everything a run computed: one outcome per study, in the scene's order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Results {
    /// The studies' outcomes.
    pub studies: Vec<Outcome>,
}

impl Results {
    /// Whether every study computed everything it was asked for ([`Outcome::complete`]).
    pub fn complete(&self) -> bool {
        self.studies.iter().all(Outcome::complete)
    }

    /// Whether several studies ran at the same time (a study of a kind that runs alone runs
    /// after them, [`crate::studies::StudyKind::runs_alone`]), so their wall times overlap.
    pub fn ran_together(&self) -> bool {
        self.studies.iter().filter(|s| !s.kind.runs_alone()).count() > 1
    }

    /// Every failure, with the name of its study.
    pub fn failures(&self) -> impl Iterator<Item = (&str, &Failure)> {
        self.studies
            .iter()
            .flat_map(|s| s.failures.iter().map(move |f| (s.name.as_str(), f)))
    }

    /// The results of kind `R` (a [`crate::studies::StudyResult`]'s payload, e.g.
    /// `CylinderResult`), with their studies' names, in scene order.
    pub fn of<'a, R: OfResult + 'a>(&'a self) -> impl Iterator<Item = (&'a str, &'a R)> + 'a {
        self.studies
            .iter()
            .filter_map(|s| R::of(&s.result).map(|r| (s.name.as_str(), r)))
    }
}

/// Progress: log lines, and a bar per study if asked (on a terminal); without bars, one plain
/// line per point that says it ([`Progress::point`]), stamped with the time since the start.
/// Each study reports through its own handle ([`Printing::study`]), so studies that run at the
/// same time each keep a bar.
pub struct Printing {
    bars: MultiProgress,
    verbose: bool,
    progress: bool,
    started: Instant,
}

impl Printing {
    /// Lines if `verbose`; bars too if `progress`.
    pub fn new(verbose: bool, progress: bool) -> Self {
        Self {
            bars: MultiProgress::with_draw_target(if verbose && progress {
                ProgressDrawTarget::stdout()
            } else {
                ProgressDrawTarget::hidden()
            }),
            verbose,
            progress,
            started: Instant::now(),
        }
    }

    /// The progress handle of one study (its bar, when it starts one).
    pub fn study(&self) -> StudyProgress<'_> {
        StudyProgress {
            printing: self,
            bar: Mutex::new(None),
        }
    }
}

/// One study's progress: lines through the run's [`Printing`], and the study's own bar.
pub struct StudyProgress<'a> {
    printing: &'a Printing,
    bar: Mutex<Option<ProgressBar>>,
}

impl StudyProgress<'_> {
    fn current(&self) -> Option<ProgressBar> {
        self.bar.lock().ok().and_then(|b| b.clone())
    }
}

impl Progress for StudyProgress<'_> {
    fn log(&self, line: &str) {
        if !self.printing.verbose {
            return;
        }
        // Prints above the bars without tearing them.
        if !self.printing.progress || self.printing.bars.println(line).is_err() {
            let _ = writeln!(std::io::stdout(), "{line}");
        }
    }

    fn start(&self, label: &str, total: usize) {
        if !(self.printing.verbose && self.printing.progress) {
            return;
        }
        let style =
            ProgressStyle::with_template("{spinner} {msg:40!} [{bar:30}] {pos}/{len} ({elapsed})")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> ");
        let pb = self.printing.bars.add(ProgressBar::new(total as u64));
        pb.set_style(style);
        pb.set_message(label.to_string());
        pb.enable_steady_tick(Duration::from_millis(120));
        if let Ok(mut slot) = self.bar.lock() {
            *slot = Some(pb);
        }
    }

    fn advance(&self, n: usize) {
        if let Some(pb) = self.current() {
            pb.inc(n as u64);
        }
    }

    fn point(&self, line: &str) {
        if !self.printing.verbose {
            return;
        }
        if self.printing.progress {
            self.advance(1);
        } else {
            // A closed pipe (`| head`) does not stop the run.
            let _ = writeln!(
                std::io::stdout(),
                "[{:8.1} s] {line}",
                self.printing.started.elapsed().as_secs_f64()
            );
        }
    }

    fn finish(&self) {
        if let Some(pb) = self.bar.lock().ok().and_then(|mut b| b.take()) {
            pb.finish_and_clear();
        }
    }
}

/// Runs every study of `scene`. The studies run at the same time, sharing the cores (each
/// one's own loops, over models or damages and over the FE cells, are parallel too), except
/// those of a kind that runs alone ([`crate::studies::StudyKind::runs_alone`]: it measures run
/// times), after the others. The results keep the scene's order. A study that stops with an error is recorded as its outcome's failure
/// ([`Outcome::nothing`]) and the others go on; once the run is stopped
/// ([`RunOptions::stop`]) the studies not started are recorded as not run.
pub(super) fn run(scene: &Scene, options: &RunOptions) -> Results {
    let printing = Printing::new(options.verbose, options.progress);
    let run_one = |study: &Study| -> Outcome {
        if let Some(reason) = options.stop.as_ref().and_then(Stop::reason) {
            return Outcome::nothing(study, format!("not run: {reason}"));
        }
        let bar = printing.study();
        let progress: &dyn Progress = if options.verbose { &bar } else { &Silent };
        let ctx = RunContext {
            progress,
            vtk_dir: options.vtk_dir.as_deref(),
            stop: options.stop.as_ref(),
        };
        let t0 = Instant::now();
        let mut outcome = study.run(&scene.models, &ctx).unwrap_or_else(|e| {
            progress.finish();
            Outcome::nothing(study, e.to_string())
        });
        outcome.elapsed = t0.elapsed();
        progress.log(&format!(
            "{}: {} points in {:.2} s",
            outcome.name,
            outcome.points,
            outcome.elapsed.as_secs_f64()
        ));
        outcome
    };
    let alone = |s: &Study| s.kind().runs_alone();
    let mut outcomes: Vec<Option<Outcome>> = scene
        .studies
        .par_iter()
        .map(|s| (!alone(s)).then(|| run_one(s)))
        .collect();
    for (outcome, study) in outcomes.iter_mut().zip(&scene.studies) {
        if outcome.is_none() {
            *outcome = Some(run_one(study));
        }
    }
    Results {
        studies: outcomes.into_iter().flatten().collect(),
    }
}
