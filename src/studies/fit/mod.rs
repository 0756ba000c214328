//! Fit studies (`kind = "fit"`): the chapter's least-squares fits ([`crate::fit`]) from a scene.
//!
//! | `fit =` | data | free parameters (default) |
//! |---|---|---|
//! | `passive` | `data` (CSV `lambda,P`) or `reference = { energy = ... }` sampled at `stretch` | the material's, all but μ |
//! | `active-curve` | `data` (`stress = "active"` or `"total"`) or the scene's curve sampled at `stretch` | λ_min, λ_opt, k |
//! | `explicit-law` | the implicit law at `stretch`, one fit per `damage` | a, b |
//! | `damage` | `data` (total stress) or synthetic curves with `true_damage = [...]` at `stretch` | d |
//!
//! `noise` \[kPa\] adds seeded Gaussian noise to synthetic data. Data files are read and checked
//! when the scene is validated, so a bad file is reported by `check` with its name and line.
//! `weights` divides each residual by a scale ([`WeightsKind`]: `sigma`, a `sigma` column of the
//! data, the default where it has one; `relative`, the datum itself; `equal`). A minimum on a
//! bound is a result, the parameter marked at its bound ([`crate::fit::AtBound`]). Besides the
//! figures and `fits.csv`, each fit writes its data, the fitted model at each datum and the
//! residuals, and the fitted curve, to `fit_points.csv` ([`output`]).
//!
//! Each kind is a [`Problem`]: the model's parameters (names, values, default free set), how to
//! fit one data set, and the model's curve at any parameter values; resolution and the run are
//! the same for all four, here. One file per kind (`passive.rs`, `active.rs`, `explicit.rs`,
//! `damage.rs`), beside where the data come from (`source.rs`), the settings checked against
//! the spec (`setup.rs`) and the figures and report table (`output.rs`). A new kind of fit: its
//! file with `impl Problem`, a [`FitKind`] variant and its line in `problem`.

mod active;
mod damage;
mod explicit;
mod output;
mod passive;
mod points;
mod setup;
mod source;

use super::rules::required;
use super::spec::{optional_stretches, Defaults, StretchSpec};
use super::{Failure, Outcome, RunContext, StudyKind, StudyResult};
use crate::app_error::{AppError, SpecError};
use crate::energy::Energy;
use crate::fit::{
    AtBound, BiaxialData, Data, ExplicitTarget, FitError, FitReport, FitSetup, Method,
};
use crate::models::EnergySpec;
use crate::uniaxial::Direction;
use active::ActiveCurveFit;
use damage::DamageFit;
use explicit::ExplicitLawFit;
use passive::Passive;
pub use points::rows_of as fit_points_rows;
use serde::{Deserialize, Serialize};
use setup::{check_keys, enough_points, free_parameters, setup, solver};
pub use source::DataSource;
use std::collections::BTreeMap;
use std::fmt;
use std::sync::Arc;

/// What a fit study fits (`fit = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FitKind {
    /// Passive parameters of the material's energy to (λ, P) data (eq. (11)).
    Passive,
    /// (λ_min, λ_opt, k, P_opt) of the active curve (eq. (8)).
    ActiveCurve,
    /// (a, b) of the explicit law (eq. (14)) against the implicit law.
    ExplicitLaw,
    /// The damage d of a weakened total curve.
    Damage,
}

impl FitKind {
    /// Name in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            FitKind::Passive => "passive",
            FitKind::ActiveCurve => "active-curve",
            FitKind::ExplicitLaw => "explicit-law",
            FitKind::Damage => "damage",
        }
    }

    /// The keys only this kind of fit takes (the others take none of them).
    fn own_keys(self) -> &'static [&'static str] {
        match self {
            FitKind::Passive => &["data", "reference", "direction", "weights"],
            FitKind::ActiveCurve => &["data", "stress", "weights"],
            FitKind::ExplicitLaw => &["residual", "damage"],
            FitKind::Damage => &["data", "true_damage", "weights"],
        }
    }
}

/// What the stresses of active-curve data are (`stress = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StressKind {
    /// Active stress P_act.
    #[default]
    Active,
    /// Total stress of a tetanised muscle; the model's passive stress is subtracted.
    Total,
}

/// `[[study]] kind = "fit"` as written; `None` is a key left to its default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitSpec {
    /// Label (default `fit <kind>`).
    pub name: Option<String>,
    /// What to fit (required).
    pub fit: Option<FitKind>,
    /// Stretches at which synthetic data are sampled.
    pub stretch: Option<StretchSpec>,
    /// Damage values of the explicit-law fit, one fit each (default 0).
    pub damage: Option<Vec<f64>>,
    /// CSV data file with header `lambda,P` (λ [-], P \[kPa\]), relative to the scene file.
    pub data: Option<String>,
    /// Passive energy whose curve is the data (passive fits; instead of `data`).
    pub reference: Option<EnergySpec>,
    /// Direction of passive data: `along` (default) or `across` the fibres.
    pub direction: Option<Direction>,
    /// Stresses of active-curve data: `active` (default) or `total`.
    pub stress: Option<StressKind>,
    /// Residual of the explicit-law fit: `stress` (default) or `activation`.
    pub residual: Option<ExplicitTarget>,
    /// Damage values of synthetic weakened curves, one fit each (damage fits; instead of `data`).
    pub true_damage: Option<Vec<f64>>,
    /// Standard deviation of Gaussian noise added to synthetic data \[kPa\] (default 0).
    pub noise: Option<f64>,
    /// Seed of the noise (default 1).
    pub seed: Option<i64>,
    /// How residuals are weighted: `sigma` (the data's `sigma` column; the default where the
    /// data have one), `relative` or `equal` (the default otherwise).
    pub weights: Option<WeightsKind>,
    /// Free parameters (default: the fit's own choice).
    pub free: Option<Vec<String>>,
    /// Starting values by parameter name (default: the model's values).
    pub start: Option<BTreeMap<String, f64>>,
    /// Bounds [lower, upper] by parameter name (default: the admissible range).
    #[serde(default, deserialize_with = "crate::fixed_length::exact")]
    pub bounds: Option<BTreeMap<String, [f64; 2]>>,
    /// `gauss-newton` (default) or `nelder-mead`.
    pub method: Option<Method>,
    /// Maximum Levenberg–Marquardt iterations (default 1000).
    pub max_iterations: Option<i64>,
}

/// How a fit study weights its residuals (`weights = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WeightsKind {
    /// Residuals in kPa, every point alike.
    Equal,
    /// Residuals relative to the datum, (model − P_i)/|P_i| (noise proportional to the data).
    Relative,
    /// Residuals over each point's standard deviation, the data file's `sigma` column.
    Sigma,
}

impl WeightsKind {
    /// Name in scene files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            WeightsKind::Equal => "equal",
            WeightsKind::Relative => "relative",
            WeightsKind::Sigma => "sigma",
        }
    }
}

/// Keys a fit study does not take, and what to write instead.
pub const HINTS: &[(&str, &str)] = &[];

/// One data set of a fit study and what is known about it.
#[derive(Debug, Clone, PartialEq)]
pub struct FitCase {
    /// Label in the report (e.g. `true d = 0.3`, or the data file).
    pub label: String,
    /// The data (for `explicit-law`: the stretches, stresses unused).
    pub data: CaseData,
    /// Damage of the model (explicit-law) or the true damage of synthetic data (damage).
    pub damage: Option<f64>,
    /// Reference values of all the model's parameters, if the data have any (the chapter's, or
    /// the truth of synthetic data).
    pub reference: Option<Vec<f64>>,
}

/// The data of one case: a uniaxial curve, or the rows of a planar biaxial test.
#[derive(Debug, Clone, PartialEq)]
pub enum CaseData {
    /// (λ, P) along one direction.
    Uniaxial(Data),
    /// (λ₁, λ₂, P₁₁, P₂₂), λ₁ along the fibres, λ₂ across (passive fits).
    Biaxial(BiaxialData),
}

impl CaseData {
    /// Number of data points (rows).
    pub fn points(&self) -> usize {
        match self {
            CaseData::Uniaxial(d) => d.len(),
            CaseData::Biaxial(b) => b.len(),
        }
    }

    /// Number of residuals a fit to them has (two per biaxial row).
    pub fn residuals(&self) -> usize {
        match self {
            CaseData::Uniaxial(d) => d.len(),
            CaseData::Biaxial(b) => 2 * b.len(),
        }
    }

    /// The uniaxial curve; biaxial rows are an error naming the fit that got them.
    pub fn uniaxial(&self, fit: FitKind) -> Result<&Data, FitError> {
        match self {
            CaseData::Uniaxial(d) => Ok(d),
            CaseData::Biaxial(_) => Err(FitError::WrongTest {
                fit: fit.name(),
                takes: "uniaxial (lambda,P)",
                given: "planar biaxial (lambda1,lambda2,P11,P22)",
            }),
        }
    }

    /// The stretches at which a fit's curves are drawn: 201 evenly spaced over a uniaxial
    /// curve's stretches; none for biaxial rows (the model is drawn at the rows).
    fn grid(&self) -> Vec<f64> {
        match self {
            CaseData::Uniaxial(d) => {
                let (a, b) = (d.lambda()[0], d.lambda()[d.len() - 1]);
                (0..=200).map(|i| a + (b - a) * i as f64 / 200.0).collect()
            }
            CaseData::Biaxial(_) => Vec::new(),
        }
    }
}

/// One stress of a case as its figure shows it: the data, their label and the axes.
#[derive(Debug, Clone, PartialEq)]
pub struct Shown {
    /// What the panel shows (empty for a case with one stress; `P₁₁, along the fibres`).
    pub what: String,
    /// x-axis label with unit.
    pub x_label: &'static str,
    /// y-axis label with unit.
    pub y_label: String,
    /// Label of the data.
    pub label: String,
    /// The data points.
    pub data: Vec<(f64, f64)>,
}

impl Shown {
    /// The one stress of a uniaxial case, its data as given.
    pub fn uniaxial(model: &Model, case: &FitCase) -> Vec<Shown> {
        let data = case.data.uniaxial(model.kind).map(Data::points);
        Shown::curve(model, case.label.clone(), data.unwrap_or_default())
    }

    /// The one stress of a uniaxial case: `data` over λ, labelled `label`.
    pub fn curve(model: &Model, label: String, data: Vec<(f64, f64)>) -> Vec<Shown> {
        vec![Shown {
            what: String::new(),
            x_label: crate::studies::outputs::LAMBDA,
            y_label: model.y_label.to_string(),
            label,
            data,
        }]
    }
}

/// What a kind of fit is: its model's parameters and how its figure and table show it.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// What is fitted.
    pub kind: FitKind,
    /// Names of all the model's parameters, in order.
    pub names: Vec<String>,
    /// The model's own values of all parameters (the default starts).
    pub values: Vec<f64>,
    /// The default bounds of each parameter (its admissible range), in the order of `names`.
    pub bounds: Vec<crate::fit::Bounds>,
    /// The parameters freed when the scene does not say.
    pub default_free: Vec<String>,
    /// y-axis label of the figure, with unit.
    pub y_label: &'static str,
    /// Label of the model at the reference values in the figure.
    pub reference_label: &'static str,
    /// Unit of the residuals (`kPa`, or `-` for γ).
    pub unit: &'static str,
}

/// One kind of fit as a study runs it.
pub trait Problem: fmt::Debug + Send + Sync {
    /// The model's parameters and labels.
    fn model(&self) -> Model;
    /// The data sets, one fit each, and their source in words; errors name keys of the study.
    fn cases(
        &self,
        spec: &FitSpec,
        stretches: Option<&[f64]>,
        source: &mut DataSource,
    ) -> Result<(Vec<FitCase>, String), SpecError>;
    /// Fits one data set; the report and extra lines for the report.
    fn fit(&self, case: &FitCase, setup: &FitSetup) -> Result<(FitReport, Vec<String>), FitError>;
    /// The model over `grid` with all parameters at `values`, one curve per stress of
    /// [`Problem::shown`] (points that cannot be computed left out; none if the values are not a
    /// valid model).
    fn curves(&self, values: &[f64], case: &FitCase, grid: &[f64]) -> Vec<Vec<(f64, f64)>>;
    /// The data as the figure shows them: one stress, a uniaxial curve over λ.
    fn shown(&self, case: &FitCase) -> Vec<Shown> {
        Shown::uniaxial(&self.model(), case)
    }
}

/// A validated fit study.
#[derive(Debug, Clone)]
pub struct FitStudy {
    /// Label.
    pub name: String,
    /// Where the data come from, in words.
    pub source: String,
    /// Data sets, one fit each.
    pub cases: Vec<FitCase>,
    /// Free parameters, starts, bounds and solver options.
    pub setup: FitSetup,
    /// How the residuals are weighted (the scales of each case from its data).
    pub weights: WeightsKind,
    /// Names of the free parameters (resolved).
    pub free: Vec<String>,
    /// What is fitted: parameters and labels.
    pub model: Model,
    /// How it is fitted.
    pub problem: Arc<dyn Problem>,
}

impl PartialEq for FitStudy {
    fn eq(&self, other: &Self) -> bool {
        (
            &self.name,
            &self.source,
            &self.cases,
            &self.setup,
            &self.free,
            &self.model,
            self.weights,
        ) == (
            &other.name,
            &other.source,
            &other.cases,
            &other.setup,
            &other.free,
            &other.model,
            other.weights,
        )
    }
}

/// Validates `spec`, reads or samples its data; returns the study and the spec with every
/// default written out.
pub fn resolve(spec: &FitSpec, d: &Defaults) -> Result<(FitStudy, FitSpec), SpecError> {
    let stretches = optional_stretches(&spec.stretch)?;
    let kind = required(
        spec.fit,
        "fit",
        "a fit study needs fit = \"passive\" | \"active-curve\" | \"explicit-law\" | \"damage\"",
    )?;
    check_keys(spec, kind)?;
    let (options, mut source) = solver(spec, d.base)?;
    let problem = problem(spec, kind, d)?;
    let model = problem.model();
    let free = free_parameters(spec, &model.names, &model.default_free)?;
    let setup = setup(spec, &model, &free, options)?;
    let (cases, source) = problem.cases(spec, stretches.as_deref(), &mut source)?;
    enough_points(spec, kind, &cases, free.len())?;
    let weights = setup::weights(spec, &cases)?;
    let name = spec
        .name
        .clone()
        .unwrap_or_else(|| format!("fit {}", kind.name()));
    let resolved = FitSpec {
        name: Some(name.clone()),
        free: Some(free.clone()),
        method: Some(options.method),
        max_iterations: Some(options.max_iterations as i64),
        weights: (kind != FitKind::ExplicitLaw).then_some(weights),
        reference: spec
            .reference
            .as_ref()
            .map(|r| r.build().map(|e| EnergySpec::written(&e)))
            .transpose()
            .map_err(|e| e.within("reference"))?,
        // Biaxial data load both directions: a passive fit to them has no direction.
        direction: (kind == FitKind::Passive
            && cases
                .iter()
                .all(|c| matches!(c.data, CaseData::Uniaxial(_))))
        .then(|| spec.direction.unwrap_or_default()),
        stress: (kind == FitKind::ActiveCurve).then(|| spec.stress.unwrap_or_default()),
        residual: (kind == FitKind::ExplicitLaw).then(|| spec.residual.unwrap_or_default()),
        damage: (kind == FitKind::ExplicitLaw)
            .then(|| cases.iter().filter_map(|c| c.damage).collect()),
        ..spec.clone()
    };
    let study = FitStudy {
        name,
        source,
        cases,
        setup,
        weights,
        free,
        model,
        problem,
    };
    Ok((study, resolved))
}

/// The problem of a fit of `kind` on the scene's material and curve.
fn problem(spec: &FitSpec, kind: FitKind, d: &Defaults) -> Result<Arc<dyn Problem>, SpecError> {
    let (energy, curve) = (d.models.energy.clone(), d.models.curve);
    if kind == FitKind::ExplicitLaw {
        // The fit is of the chapter's active-strain γ: the scene's approach must take it.
        d.models
            .explicit_fit_for(d.approach)
            .map_err(|rule| SpecError::new("fit", "\"explicit-law\"", rule))?;
    }
    Ok(match kind {
        FitKind::Passive => Arc::new(Passive {
            energy,
            direction: spec.direction.unwrap_or_default(),
        }),
        FitKind::ActiveCurve => Arc::new(ActiveCurveFit {
            energy,
            curve,
            stress: spec.stress.unwrap_or_default(),
        }),
        FitKind::ExplicitLaw => match energy {
            Energy::GiantesioMusesti(gm) => Arc::new(ExplicitLawFit {
                energy: gm,
                curve,
                residual: spec.residual.unwrap_or_default(),
            }),
            _ => {
                return Err(SpecError::new(
                    "fit",
                    "\"explicit-law\"",
                    "the explicit law (eq. (14)) is derived for the giantesio-musesti energy; material.energy is another",
                ))
            }
        },
        FitKind::Damage => Arc::new(DamageFit { energy, curve }),
    })
}

/// The outcome of one fit: a row of `fits.csv` and of the report's table. Statistics that do not
/// exist (a singular JᵀJ) are `None`, never NaN.
#[derive(Debug, Clone, PartialEq)]
pub struct FitOutcome {
    /// What was fitted.
    pub kind: FitKind,
    /// Data set label.
    pub case: String,
    /// Where the data come from.
    pub source: String,
    /// Number of data points.
    pub points: usize,
    /// Free parameters.
    pub names: Vec<String>,
    /// Values at the best point found.
    pub values: Vec<f64>,
    /// Standard errors.
    pub standard_errors: Vec<Option<f64>>,
    /// Reference values (the chapter's, or the truth of synthetic data).
    pub reference: Vec<Option<f64>>,
    /// Correlation matrix of the estimates.
    pub correlation: Vec<Vec<Option<f64>>>,
    /// RMS error (units of the residual: kPa, or - for γ).
    pub rms: f64,
    /// Unit of the residuals.
    pub unit: &'static str,
    /// Residual norm.
    pub residual_norm: f64,
    /// Iterations.
    pub iterations: u64,
    /// Whether the fit converged. A false here is the best point found, not a solution.
    pub converged: bool,
    /// Solver termination, and why it did not converge.
    pub termination: String,
    /// Per free parameter: the bound it is held at, if the minimum lies beyond it.
    pub at_bound: Vec<Option<AtBound>>,
    /// How the residuals were weighted.
    pub weights: WeightsKind,
    /// The scale σ_i each residual was divided by (`None`: equal weights).
    pub sigma: Option<Vec<f64>>,
    /// Residuals model − datum at the fitted values, in the data's order (biaxial rows: P₁₁,
    /// P₂₂ of each row in turn), in the unit of the residuals.
    pub residuals: Vec<f64>,
    /// Further facts (e.g. the explicit law's max stress error), one line each.
    pub extra: Vec<String>,
    /// Data and curves for the figure, one per stress of the data.
    pub plot: Vec<FitCurves>,
}

impl FitOutcome {
    /// The fitted values with their standard errors, for the console: `chapter's data: mu =
    /// 0.1599 ± 0.0021, w0 = 0.7335 ± 0.0034 (RMS 0.118 kPa, converged)`; `± n/a` where the
    /// error could not be estimated. Four significant digits.
    pub fn summary(&self) -> String {
        let digits = |x: f64| crate::text::significant(x, 4);
        let values: Vec<String> = self
            .names
            .iter()
            .zip(&self.values)
            .enumerate()
            .map(|(j, (name, v))| {
                if let Some(b) = self.at_bound.get(j).copied().flatten() {
                    return format!("{name} = {} (at its bound {})", digits(*v), digits(b.bound));
                }
                let error = self.standard_errors.get(j).copied().flatten();
                format!(
                    "{name} = {} ± {}",
                    digits(*v),
                    error.map_or("n/a".into(), digits)
                )
            })
            .collect();
        format!(
            "{}: {} (RMS {} {}, {})",
            self.case,
            values.join(", "),
            digits(self.rms),
            self.unit,
            if self.converged {
                "converged"
            } else {
                "NOT converged"
            }
        )
    }
}

/// What the data-vs-fit figure of one case shows, for one of its stresses.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FitCurves {
    /// What the panel shows (empty for a case with one stress).
    pub what: String,
    /// x-axis label with unit.
    pub x_label: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// Data points.
    pub data: Vec<(f64, f64)>,
    /// Label of the data.
    pub data_label: String,
    /// The fitted model.
    pub fitted: Vec<(f64, f64)>,
    /// The model at the reference values (label, points).
    pub start: Option<(String, Vec<(f64, f64)>)>,
    /// The model is evaluated at the data's rows (a biaxial path, which may turn back), so it
    /// is drawn as points, not as a curve.
    pub at_rows: bool,
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl FitStudy {
    /// One line for `check`.
    pub fn describe(&self) -> String {
        format!(
            "{}: {} fit(s) of {} parameter(s) {:?} to {}",
            self.name,
            self.cases.len(),
            self.free.len(),
            self.free,
            self.source
        )
    }

    /// All parameters of the model with the free ones at `free_values`.
    fn assemble(&self, free_values: &[f64]) -> Vec<f64> {
        let mut all = self.model.values.clone();
        for (name, x) in self.free.iter().zip(free_values) {
            if let Some(i) = self.model.names.iter().position(|n| n == name) {
                all[i] = *x;
            }
        }
        all
    }

    /// Fits every case. A fit that does not converge gives an outcome with
    /// `converged = false` (the best point) and a failure; a fit that fails outright gives only
    /// the failure. Neither stops the run.
    pub fn run(&self, ctx: &RunContext) -> Result<Outcome, AppError> {
        ctx.progress.log(&format!(
            "{}: {} fit(s), {}",
            self.name,
            self.cases.len(),
            self.source
        ));
        let mut outcomes = Vec::new();
        let mut failures = Vec::new();
        let mut fail = |message: String| {
            failures.push(Failure {
                model: "fit".into(),
                message,
            })
        };
        for case in &self.cases {
            let setup = match setup::case_weights(self.weights, &case.data) {
                Ok(w) => self.setup.clone().weights(w),
                Err(e) => {
                    fail(format!("{}: fit failed: {e}", case.label));
                    continue;
                }
            };
            match self.problem.fit(case, &setup) {
                Ok((report, extra)) => outcomes.push(self.outcome(case, report, extra, true)),
                Err(e @ FitError::NotConverged { .. }) => {
                    fail(format!("{}: {e} (reported, NOT a solution)", case.label));
                    if let FitError::NotConverged { best, .. } = e {
                        outcomes.push(self.outcome(case, *best, vec![], false));
                    }
                }
                Err(e) => fail(format!("{}: fit failed: {e}", case.label)),
            }
        }
        let converged = outcomes.iter().filter(|f| f.converged).count();
        let mut details = vec![format!("data: {}", self.source)];
        details.extend(outcomes.iter().map(|f| {
            format!(
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
            )
        }));
        Ok(Outcome {
            name: self.name.clone(),
            kind: StudyKind::Fit,
            models: self.cases.len(),
            points: converged,
            requested: self.cases.len(),
            elapsed: Default::default(),
            details,
            failures,
            left_domain: Vec::new(),
            result: StudyResult::Fit(outcomes),
        })
    }

    /// The outcome of `case` from the fit's `report` (converged or the best point found).
    fn outcome(
        &self,
        case: &FitCase,
        report: FitReport,
        extra: Vec<String>,
        converged: bool,
    ) -> FitOutcome {
        let grid = case.data.grid();
        let curves = |free_values: &[f64]| {
            self.problem
                .curves(&self.assemble(free_values), case, &grid)
        };
        // The reference values of the free parameters.
        let reference: Vec<Option<f64>> = match &case.reference {
            Some(all) => self
                .free
                .iter()
                .map(|f| self.model.names.iter().position(|n| n == f).map(|i| all[i]))
                .collect(),
            None => vec![None; self.free.len()],
        };
        // The dashed curve: the model at the reference values (the damage fit's: d = 0).
        let start: Option<Vec<f64>> = match self.model.kind {
            FitKind::Damage => Some(self.model.values.clone()),
            _ => reference.iter().copied().collect(),
        };
        let fitted = curves(&report.values);
        let start = start.map(|s| curves(&s));
        let at_rows = matches!(case.data, CaseData::Biaxial(_));
        let plot = self
            .problem
            .shown(case)
            .into_iter()
            .enumerate()
            .map(|(k, shown)| FitCurves {
                what: shown.what,
                x_label: shown.x_label.to_string(),
                y_label: shown.y_label,
                data: shown.data,
                data_label: shown.label,
                fitted: fitted.get(k).cloned().unwrap_or_default(),
                start: start.as_ref().map(|s| {
                    (
                        self.model.reference_label.to_string(),
                        s.get(k).cloned().unwrap_or_default(),
                    )
                }),
                at_rows,
            })
            .collect();
        FitOutcome {
            kind: self.model.kind,
            case: case.label.clone(),
            source: self.source.clone(),
            points: case.data.points(),
            standard_errors: report.standard_errors.iter().map(|&x| finite(x)).collect(),
            reference,
            correlation: report
                .correlation
                .iter()
                .map(|row| row.iter().map(|&x| finite(x)).collect())
                .collect(),
            rms: report.rms,
            unit: self.model.unit,
            residual_norm: report.residual_norm,
            iterations: report.iterations,
            converged,
            extra,
            plot,
            at_bound: report.at_bound,
            weights: self.weights,
            sigma: report.sigma,
            residuals: report.residuals,
            names: report.names,
            values: report.values,
            termination: report.termination,
        }
    }
}

/// The correlations of parameter `j` with the others, readable: `w0: 0.99988; beta: -0.12000`
/// (`n/a` where the fit could not estimate one), each number written by `number`.
pub fn correlations(
    row: &[Option<f64>],
    names: &[String],
    j: usize,
    number: impl Fn(f64) -> Result<String, AppError>,
) -> Result<String, AppError> {
    let mut parts = Vec::new();
    for (k, (c, other)) in row.iter().zip(names).enumerate() {
        if k != j {
            parts.push(format!(
                "{other}: {}",
                c.map_or(Ok("n/a".to_string()), &number)?
            ));
        }
    }
    Ok(parts.join("; "))
}
