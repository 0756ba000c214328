//! Running a scene: builds only the models its studies need, computes the homogeneous curves in
//! parallel (rayon) and the cylinder sweeps with the FE solver, and collects tidy rows.

use super::fit::{run_fit, FitOutcome};
use super::resolve::{coupling_name, law_name, CylinderStudy, ModelChoice, UniaxialStudy};
use super::schema::{BasesKind, DirectionKind, ElementKind};
use super::stability::{run_stability, StabilityCurve};
use super::{Scene, Study};
use crate::energy::{Energy, StrainEnergy};
use crate::fem::{AxisymmetricSolver, Bases, FemError, Mesh, SolverOptions, VtkOutput};
use crate::stability::diagnose_axisymmetric;
use crate::tradeoff::{run as run_tradeoff, TradeoffOptions, TradeoffResults};
use crate::uniaxial::{across_fibres, along_fibres, UniaxialPoint};
use crate::Muscle;
use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// One point of one curve: a row of `curves.csv`. `None` is an empty cell.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Index of the study in the scene (not a CSV column).
    pub study: usize,
    /// `uniaxial` | `cylinder`.
    pub model: &'static str,
    /// `along` | `across` (uniaxial).
    pub direction: Option<&'static str>,
    /// `sliding` | `clamped` (cylinder).
    pub bases: Option<&'static str>,
    /// Energy name.
    pub energy: String,
    /// `passive` | `constant` | `implicit` | `explicit` | `energy`.
    pub law: &'static str,
    /// `frozen` | `consistent` (active laws only).
    pub coupling: Option<&'static str>,
    /// Damage (active laws only).
    pub d: Option<f64>,
    /// Stretch λ.
    pub lambda: f64,
    /// γ (uniaxial) or γ at the centre of the cylinder.
    pub gamma: Option<f64>,
    /// Nominal stress along the stretch \[kPa\].
    pub p: f64,
    /// Passive stress of the material at λ \[kPa\] (active uniaxial rows along the fibres).
    pub p_pas: Option<f64>,
    /// Target active stress (1 − d) P_act(λ) \[kPa\] (same rows).
    pub p_act: Option<f64>,
    /// Newton iterations to reach this stretch from the previous one (cylinder).
    pub newton_iterations: Option<usize>,
}

/// Something a study could not finish, for a reason of the material or the solver. Recorded
/// and reported; the run still succeeds.
#[derive(Debug, Clone, PartialEq)]
pub struct Note {
    /// Study label.
    pub study: String,
    /// Which model.
    pub model: String,
    /// What happened.
    pub message: String,
}

/// Per-study summary.
#[derive(Debug, Clone, PartialEq)]
pub struct StudySummary {
    /// Label.
    pub name: String,
    /// `uniaxial` or `cylinder`.
    pub kind: &'static str,
    /// Models (curves or FE sweeps) built.
    pub models: usize,
    /// Rows produced.
    pub points: usize,
    /// Points requested.
    pub requested: usize,
    /// Wall time.
    pub elapsed: Duration,
    /// Extra facts (mesh, dofs, verification), one line each.
    pub details: Vec<String>,
}

/// A cylinder sweep next to the homogeneous (0D) curve of the same model at the same stretches.
#[derive(Debug, Clone, PartialEq)]
pub struct FeComparison {
    /// Study index.
    pub study: usize,
    /// Bases.
    pub bases: &'static str,
    /// Damage.
    pub d: f64,
    /// Model label.
    pub label: String,
    /// (λ, P_FE, P_0D).
    pub points: Vec<(f64, f64, f64)>,
}

/// Everything a run computed.
#[derive(Debug, Clone, Default)]
pub struct Results {
    /// Tidy rows, in study order.
    pub rows: Vec<Row>,
    /// Stops and failures recorded along the way.
    pub notes: Vec<Note>,
    /// One summary per study.
    pub studies: Vec<StudySummary>,
    /// FE vs 0D.
    pub fe_vs_0d: Vec<FeComparison>,
    /// VTK files written (relative to the VTK staging directory).
    pub vtk_files: Vec<PathBuf>,
    /// Fits, converged or not (see [`FitOutcome::converged`]).
    pub fits: Vec<FitOutcome>,
    /// Stability curves.
    pub stability: Vec<StabilityCurve>,
    /// The trade-off study's measurements (a scene holds at most one).
    pub tradeoff: Option<TradeoffResults>,
}

/// How to run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Show progress bars and log lines.
    pub verbose: bool,
    /// Show progress bars (only meaningful if `verbose`; off when stdout is not a terminal).
    pub progress: bool,
    /// Where the solver writes VTK files (a staging directory; `None`: no VTK).
    pub vtk_dir: Option<PathBuf>,
}

/// A run error: a study could not be set up or the solver failed for a non-material reason.
#[derive(Debug)]
pub struct RunError(pub String);

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for RunError {}

struct Reporter {
    bars: MultiProgress,
    verbose: bool,
    progress: bool,
}

impl Reporter {
    fn log(&self, msg: &str) {
        if !self.verbose {
            return;
        }
        if self.progress {
            // Prints above the bars without tearing them.
            if self.bars.println(msg).is_err() {
                println!("{msg}");
            }
        } else {
            println!("{msg}");
        }
    }

    fn bar(&self, len: usize, label: &str) -> ProgressBar {
        if !(self.verbose && self.progress) {
            return ProgressBar::hidden();
        }
        let style =
            ProgressStyle::with_template("{spinner} {msg:40!} [{bar:30}] {pos}/{len} ({elapsed})")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> ");
        let pb = self.bars.add(ProgressBar::new(len as u64));
        pb.set_style(style);
        pb.set_message(label.to_string());
        pb.enable_steady_tick(Duration::from_millis(120));
        pb
    }
}

fn model_label(scene: &Scene, m: &ModelChoice) -> String {
    format!(
        "{}, {} law, {} coupling, d = {}",
        scene.material.name(),
        law_name(m.law),
        coupling_name(m.coupling),
        m.damage
    )
}

fn direction_name(d: DirectionKind) -> &'static str {
    match d {
        DirectionKind::Along => "along",
        DirectionKind::Across => "across",
    }
}

fn bases_name(b: BasesKind) -> &'static str {
    match b {
        BasesKind::Clamped => "clamped",
        BasesKind::Sliding => "sliding",
    }
}

/// One homogeneous curve to compute.
enum Curve {
    Passive(Energy),
    Constant(f64),
    Active(ModelChoice),
}

/// Runs every study of `scene`.
pub fn run(scene: &Scene, options: &RunOptions) -> Result<Results, RunError> {
    let rep = Reporter {
        bars: MultiProgress::with_draw_target(if options.verbose && options.progress {
            ProgressDrawTarget::stdout()
        } else {
            ProgressDrawTarget::hidden()
        }),
        verbose: options.verbose,
        progress: options.progress,
    };
    let mut out = Results::default();
    for (i, study) in scene.studies.iter().enumerate() {
        let t0 = Instant::now();
        let summary = match study {
            Study::Uniaxial(s) => uniaxial(scene, i, s, &rep, &mut out)?,
            Study::Cylinder(s) => cylinder(scene, i, s, &rep, options, &mut out)?,
            Study::Fit(s) => {
                rep.log(&format!(
                    "{}: {} fit(s), {}",
                    s.name,
                    s.cases.len(),
                    s.source
                ));
                let (fits, messages) = run_fit(i, s, &scene.material, scene.curve);
                let converged = fits.iter().filter(|f| f.converged).count();
                let mut details = vec![format!("data: {}", s.source)];
                for f in &fits {
                    details.push(format!(
                        "{}: {} points, {} iterations, RMS {:.3e} {}, {}",
                        f.case,
                        f.points,
                        f.iterations,
                        f.rms,
                        f.unit,
                        if f.converged {
                            "converged"
                        } else {
                            "NOT converged"
                        }
                    ));
                }
                out.notes.extend(messages.into_iter().map(|m| Note {
                    study: s.name.clone(),
                    model: "fit".into(),
                    message: m,
                }));
                let summary = StudySummary {
                    name: s.name.clone(),
                    kind: "fit",
                    models: s.cases.len(),
                    points: converged,
                    requested: s.cases.len(),
                    elapsed: Duration::ZERO,
                    details,
                };
                out.fits.extend(fits);
                summary
            }
            Study::Stability(s) => {
                rep.log(&format!(
                    "{}: {} model(s) × {} stretches, {} normals",
                    s.name,
                    s.models.len() + usize::from(s.passive),
                    s.stretches.len(),
                    s.normals
                ));
                let (curves, messages) =
                    run_stability(scene, i, s).map_err(|e| RunError(format!("{}: {e}", s.name)))?;
                out.notes.extend(messages.into_iter().map(|m| Note {
                    study: s.name.clone(),
                    model: "stability".into(),
                    message: m,
                }));
                let points = curves.iter().map(|c| c.points.len()).sum();
                let summary = StudySummary {
                    name: s.name.clone(),
                    kind: "stability",
                    models: curves.len(),
                    points,
                    requested: (s.models.len() + usize::from(s.passive)) * s.stretches.len(),
                    elapsed: Duration::ZERO,
                    details: vec![format!(
                        "{} stretches in [{}, {}] along the fibres, {} sampled normals",
                        s.stretches.len(),
                        s.stretches.first().copied().unwrap_or(f64::NAN),
                        s.stretches.last().copied().unwrap_or(f64::NAN),
                        s.normals
                    )],
                };
                out.stability.extend(curves);
                summary
            }
            Study::Tradeoff(s) => {
                rep.log(&format!(
                    "{}: {} option group(s)",
                    s.name,
                    s.options.groups.len()
                ));
                let options = TradeoffOptions {
                    verbose: options.verbose,
                    ..s.options.clone()
                };
                let results = run_tradeoff(scene, &options)
                    .map_err(|e| RunError(format!("{}: {e}", s.name)))?;
                let measured = results
                    .rows
                    .iter()
                    .filter(|r| r.error.max_rel.is_finite())
                    .count();
                let mut details = results.findings.clone();
                details.extend(results.rows.iter().map(crate::tradeoff::report::line));
                let summary = StudySummary {
                    name: s.name.clone(),
                    kind: "tradeoff",
                    models: results.rows.len(),
                    points: measured,
                    requested: results.rows.len(),
                    elapsed: Duration::ZERO,
                    details,
                };
                out.tradeoff = Some(results);
                summary
            }
        };
        let summary = StudySummary {
            elapsed: t0.elapsed(),
            ..summary
        };
        rep.log(&format!(
            "{}: {} points in {:.2} s",
            summary.name,
            summary.points,
            summary.elapsed.as_secs_f64()
        ));
        out.studies.push(summary);
    }
    Ok(out)
}

fn uniaxial(
    scene: &Scene,
    index: usize,
    s: &UniaxialStudy,
    rep: &Reporter,
    out: &mut Results,
) -> Result<StudySummary, RunError> {
    let direction = direction_name(s.direction);
    let mut curves = Vec::new();
    if s.passive {
        curves.push(Curve::Passive(scene.material.clone()));
    }
    curves.extend(s.compare.iter().cloned().map(Curve::Passive));
    curves.extend(s.constant_gamma.iter().copied().map(Curve::Constant));
    curves.extend(s.models.iter().copied().map(Curve::Active));
    for c in &curves {
        let what = match c {
            Curve::Passive(e) => format!("{}, passive", e.name()),
            Curve::Constant(g) => format!("{}, constant gamma = {g}", scene.material.name()),
            Curve::Active(m) => model_label(scene, m),
        };
        rep.log(&format!("{}: {what}", s.name));
    }
    let passive = Muscle::passive(scene.material.clone());
    let pb = rep.bar(curves.len() * s.stretches.len(), &s.name);
    type CurveRows = Result<(Vec<Row>, Vec<Note>), RunError>;
    let computed: Vec<CurveRows> = curves
        .par_iter()
        .map(|c| {
            let (muscle, law, coupling, d, energy) = match c {
                Curve::Passive(e) => (Muscle::passive(e.clone()), "passive", None, None, e.name()),
                Curve::Constant(g) => (
                    scene
                        .constant(*g)
                        .map_err(|e| RunError(format!("{}: {e}", s.name)))?,
                    "constant",
                    None,
                    None,
                    scene.material.name(),
                ),
                Curve::Active(m) => (
                    scene.muscle(*m).map_err(|e| {
                        RunError(format!("{}: {}: {e}", s.name, model_label(scene, m)))
                    })?,
                    law_name(m.law),
                    Some(coupling_name(m.coupling)),
                    Some(m.damage),
                    scene.material.name(),
                ),
            };
            let energy = energy.to_string();
            let mut rows = Vec::with_capacity(s.stretches.len());
            let mut notes = Vec::new();
            let mut failed = 0usize;
            let mut first: Option<(f64, String)> = None;
            for &lambda in &s.stretches {
                pb.inc(1);
                let point = |m: &Muscle<Energy>| -> crate::Result<UniaxialPoint> {
                    match s.direction {
                        DirectionKind::Along => along_fibres(m, lambda),
                        DirectionKind::Across => across_fibres(m, lambda),
                    }
                };
                let result = point(&muscle).and_then(|p| {
                    let extra = match (c, s.direction) {
                        (Curve::Active(m), DirectionKind::Along) => Some((
                            point(&passive)?.stress,
                            (1.0 - m.damage) * scene.curve.value(lambda),
                        )),
                        _ => None,
                    };
                    Ok((p, extra))
                });
                match result {
                    Ok((p, extra)) => rows.push(Row {
                        study: index,
                        model: "uniaxial",
                        direction: Some(direction),
                        bases: None,
                        energy: energy.clone(),
                        law,
                        coupling,
                        d,
                        lambda,
                        gamma: Some(p.gamma),
                        p: p.stress,
                        p_pas: extra.map(|e| e.0),
                        p_act: extra.map(|e| e.1),
                        newton_iterations: None,
                    }),
                    Err(e) => {
                        failed += 1;
                        if first.is_none() {
                            first = Some((lambda, e.to_string()));
                        }
                    }
                }
            }
            if let Some((lambda, why)) = first {
                let model = match c {
                    Curve::Passive(e) => format!("{}, passive", e.name()),
                    Curve::Constant(g) => format!("constant gamma = {g}"),
                    Curve::Active(m) => model_label(scene, m),
                };
                notes.push(Note {
                    study: s.name.clone(),
                    model,
                    message: format!(
                        "{failed} of {} stretches failed; first at lambda = {lambda}: {why}",
                        s.stretches.len()
                    ),
                });
            }
            Ok((rows, notes))
        })
        .collect();
    pb.finish_and_clear();
    let mut points = 0;
    for c in computed {
        let (rows, notes) = c?;
        points += rows.len();
        out.rows.extend(rows);
        out.notes.extend(notes);
    }
    Ok(StudySummary {
        name: s.name.clone(),
        kind: "uniaxial",
        models: curves.len(),
        points,
        requested: curves.len() * s.stretches.len(),
        elapsed: Duration::ZERO,
        details: vec![format!(
            "{} curves × {} stretches in [{}, {}], {direction} the fibres",
            curves.len(),
            s.stretches.len(),
            s.stretches.first().copied().unwrap_or(f64::NAN),
            s.stretches.last().copied().unwrap_or(f64::NAN),
        )],
    })
}

fn cylinder(
    scene: &Scene,
    index: usize,
    s: &CylinderStudy,
    rep: &Reporter,
    options: &RunOptions,
    out: &mut Results,
) -> Result<StudySummary, RunError> {
    let bases = bases_name(s.bases);
    let models: Vec<ModelChoice> = s
        .damages
        .iter()
        .map(|&d| ModelChoice {
            law: s.law,
            coupling: s.coupling,
            damage: d,
        })
        .collect();
    for m in &models {
        rep.log(&format!(
            "{}: {} bases, {}, R = {}, L = {}, {} × {} {} cells (grading {})",
            s.name,
            bases,
            model_label(scene, m),
            s.radius,
            s.length,
            s.nr,
            s.nz,
            fe_element(s.element),
            s.grading
        ));
    }
    let pb = rep.bar(models.len() * s.stretches.len(), &s.name);
    let fail = |m: &ModelChoice, e: String| {
        RunError(format!("{}: {}: {e}", s.name, model_label(scene, m)))
    };
    type Sweep = (
        ModelChoice,
        Vec<Row>,
        Vec<Note>,
        FeComparison,
        Vec<PathBuf>,
        usize,
    );
    let sweeps: Vec<Result<Sweep, RunError>> = models
        .par_iter()
        .map(|m| {
            let muscle = scene.muscle(*m).map_err(|e| fail(m, e.to_string()))?;
            let mesh = Mesh::structured(s.radius, s.length, s.nr, s.nz, s.grading)
                .map_err(|e| fail(m, e.to_string()))?;
            let sub = PathBuf::from(format!(
                "{}_d{}",
                crate::output::figures::slug(&s.name),
                m.damage
            ));
            let vtk = match (&options.vtk_dir, s.vtk.is_empty()) {
                (Some(dir), false) => Some(VtkOutput {
                    directory: dir.join(&sub),
                    stretches: s.vtk.clone(),
                }),
                _ => None,
            };
            let opts = SolverOptions {
                tolerance: s.tolerance,
                element: fe_element(s.element),
                vtk,
                ..SolverOptions::default()
            };
            let fe_bases = match s.bases {
                BasesKind::Clamped => Bases::Clamped,
                BasesKind::Sliding => Bases::Sliding,
            };
            let mut solver = AxisymmetricSolver::new(mesh, fe_bases, &muscle, opts)
                .map_err(|e| fail(m, e.to_string()))?;
            let dofs = solver.n_free_dofs();
            let sweep = solver
                .sweep(&s.stretches)
                .map_err(|e| fail(m, e.to_string()))?;
            pb.inc(sweep.results.len() as u64);
            let mut rows = Vec::new();
            let mut comparison = FeComparison {
                study: index,
                bases,
                d: m.damage,
                label: model_label(scene, m),
                points: Vec::new(),
            };
            let mut vtk_files = Vec::new();
            for r in &sweep.results {
                let iterations = r.steps.iter().map(|st| st.iterations.len()).sum();
                rows.push(Row {
                    study: index,
                    model: "cylinder",
                    direction: None,
                    bases: Some(bases),
                    energy: scene.material.name().to_string(),
                    law: law_name(m.law),
                    coupling: Some(coupling_name(m.coupling)),
                    d: Some(m.damage),
                    lambda: r.stretch,
                    gamma: Some(r.gamma_centre),
                    p: r.nominal_stress,
                    p_pas: None,
                    p_act: None,
                    newton_iterations: Some(iterations),
                });
                if let Ok(p0) = along_fibres(&muscle, r.stretch) {
                    comparison
                        .points
                        .push((r.stretch, r.nominal_stress, p0.stress));
                }
                if let Some(file) = r.vtk_file.as_ref().and_then(|f| f.file_name()) {
                    vtk_files.push(sub.join(file));
                }
            }
            let notes = sweep
                .failures
                .iter()
                .zip(&sweep.failed_trials)
                .map(|(f, trial)| {
                    let mut message = describe_failure(f);
                    if let Some(points) = trial {
                        let f: Vec<_> = points.iter().map(|q| q.f).collect();
                        let diagnosis = diagnose_axisymmetric(&muscle, &f, 100);
                        message.push_str(&format!("; material diagnosis: {diagnosis}"));
                    }
                    Note {
                        study: s.name.clone(),
                        model: model_label(scene, m),
                        message,
                    }
                })
                .collect();
            Ok((*m, rows, notes, comparison, vtk_files, dofs))
        })
        .collect();
    pb.finish_and_clear();
    let mut points = 0;
    let mut details = vec![format!(
        "R = {}, L = {}, {} × {} {} cells (grading {}), {bases} bases, {} stretches",
        s.radius,
        s.length,
        s.nr,
        s.nz,
        fe_element(s.element),
        s.grading,
        s.stretches.len()
    )];
    for sw in sweeps {
        let (m, rows, notes, comparison, vtk, dofs) = sw?;
        points += rows.len();
        let max_rel = comparison
            .points
            .iter()
            .map(|(_, fe, zero)| (fe - zero).abs() / zero.abs().max(1.0))
            .fold(0.0f64, f64::max);
        details.push(format!(
            "d = {}: {}/{} stretches, {dofs} dofs, max |P_FE − P_0D| / max(|P_0D|, 1 kPa) = {max_rel:.2e}{}",
            m.damage,
            rows.len(),
            s.stretches.len(),
            if notes.is_empty() { "" } else { " (stopped: see notes)" }
        ));
        out.rows.extend(rows);
        out.notes.extend(notes);
        out.fe_vs_0d.push(comparison);
        out.vtk_files.extend(vtk);
    }
    Ok(StudySummary {
        name: s.name.clone(),
        kind: "cylinder",
        models: models.len(),
        points,
        requested: models.len() * s.stretches.len(),
        elapsed: Duration::ZERO,
        details,
    })
}

/// A sweep that stopped, in words: how far it got and why.
fn describe_failure(f: &FemError) -> String {
    match f {
        FemError::TargetNotReached {
            target,
            reached,
            attempted,
            cause,
            ..
        } => format!(
            "stopped before target lambda = {target}: converged up to lambda = {reached}; \
             the step to {attempted:.5} failed even at the smallest load step ({cause})"
        ),
        other => other.to_string(),
    }
}

/// The FE element a scene names.
fn fe_element(e: ElementKind) -> crate::fem::Element {
    match e {
        ElementKind::Q2Q1 => crate::fem::Element::Q2Q1,
        ElementKind::Q1P0 => crate::fem::Element::Q1P0,
    }
}
