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
//!
//! Each kind is a [`Problem`]: the model's parameters (names, values, default free set), how to
//! fit one data set, and the model's curve at any parameter values; resolution and the run are
//! the same for all four.

mod output;

use super::spec::{damages, fmt_list, optional_stretches, Defaults, StretchSpec};
use super::{Failure, Outcome, RunContext, StudyKind, StudyResult};
use crate::active::drive::Drive;
use crate::active::{ActivationLaw, ActiveCurve, ExplicitLaw, ImplicitLaw};
use crate::app_error::{AppError, SpecError};
use crate::energy::{Energy, GiantesioMusesti, Parametric};
use crate::fit::{
    active_from_total, default_passive_free, explicit_law_errors, fit_active_curve, fit_damage,
    fit_explicit_law, fit_passive, Bounds, Data, ExplicitTarget, FitError, FitOptions, FitReport,
    FitSetup, Method,
};
use crate::models::EnergySpec;
use crate::random::Sampler;
use crate::text::shortest;
use crate::uniaxial::{along_fibres, Direction};
use crate::{Muscle, StrainEnergy};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
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
            FitKind::Passive => &["data", "reference", "direction"],
            FitKind::ActiveCurve => &["data", "stress"],
            FitKind::ExplicitLaw => &["residual", "damage"],
            FitKind::Damage => &["data", "true_damage"],
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
    /// Free parameters (default: the fit's own choice).
    pub free: Option<Vec<String>>,
    /// Starting values by parameter name (default: the model's values).
    pub start: Option<BTreeMap<String, f64>>,
    /// Bounds [lower, upper] by parameter name (default: the admissible range).
    pub bounds: Option<BTreeMap<String, [f64; 2]>>,
    /// `gauss-newton` (default) or `nelder-mead`.
    pub method: Option<Method>,
    /// Maximum Levenberg–Marquardt iterations (default 1000).
    pub max_iterations: Option<i64>,
}

/// Keys a fit study does not take, and what to write instead.
pub const HINTS: &[(&str, &str)] = &[];

/// One data set of a fit study and what is known about it.
#[derive(Debug, Clone, PartialEq)]
pub struct FitCase {
    /// Label in the report (e.g. `true d = 0.3`, or the data file).
    pub label: String,
    /// The data (for `explicit-law`: the stretches, stresses unused).
    pub data: Data,
    /// Damage of the model (explicit-law) or the true damage of synthetic data (damage).
    pub damage: Option<f64>,
    /// Reference values of all the model's parameters, if the data have any (the chapter's, or
    /// the truth of synthetic data).
    pub reference: Option<Vec<f64>>,
}

/// What a kind of fit is: its model's parameters and how its figure and table show it.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// What is fitted.
    pub kind: FitKind,
    /// Names of all the model's parameters, in order.
    pub names: Vec<&'static str>,
    /// The model's own values of all parameters (the default starts).
    pub values: Vec<f64>,
    /// The parameters freed when the scene does not say.
    pub default_free: Vec<&'static str>,
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
    /// The model over `grid` with all parameters at `values` (points that cannot be computed
    /// left out; none if the values are not a valid model).
    fn curve(&self, values: &[f64], case: &FitCase, grid: &[f64]) -> Vec<(f64, f64)>;
    /// The data as the figure shows them, and their label.
    fn shown(&self, case: &FitCase) -> (Vec<(f64, f64)>, String) {
        (case.data.points(), case.label.clone())
    }
}

/// Where a fit's data come from: the scene file's directory for data files, and the seeded
/// noise of synthetic data.
pub struct DataSource<'a> {
    base: &'a Path,
    noise: Option<(f64, Sampler)>,
    noise_text: String,
}

impl DataSource<'_> {
    /// The one case of a data file named relative to the scene file (then `stretch` must not
    /// be given), with the source in words (`data file <path><what>`); errors name `data`.
    fn file(
        &self,
        name: &str,
        stretches: Option<&[f64]>,
        reference: Option<Vec<f64>>,
        what: &str,
    ) -> Result<(Vec<FitCase>, String), SpecError> {
        if stretches.is_some() {
            return Err(SpecError::new(
                "stretch",
                "(given)",
                "the data file gives the stretches: remove stretch",
            ));
        }
        let path: PathBuf = if Path::new(name).is_absolute() {
            PathBuf::from(name)
        } else {
            self.base.join(name)
        };
        let data = Data::from_csv_path(&path).map_err(|e| {
            SpecError::new(
                "data",
                format!("{name:?}"),
                format!("unusable data file: {e}"),
            )
        })?;
        Ok((
            vec![case(name, data, reference)],
            format!("data file {}{what}", path.display()),
        ))
    }

    /// Samples `model` at `lambdas`, adding the noise; errors name `stretch`.
    fn synthetic(
        &mut self,
        lambdas: &[f64],
        model: impl Fn(f64) -> crate::Result<f64>,
    ) -> Result<Data, SpecError> {
        let mut stress = Vec::with_capacity(lambdas.len());
        for &l in lambdas {
            let p = model(l).map_err(|e| {
                SpecError::new(
                    "stretch",
                    l,
                    format!("the synthetic data cannot be computed at this stretch: {e}"),
                )
            })?;
            stress.push(match &mut self.noise {
                Some((sigma, rng)) => p + *sigma * rng.normal(),
                None => p,
            });
        }
        Data::new(lambdas.to_vec(), stress)
            .map_err(|e| SpecError::new("stretch", "", e.to_string()))
    }
}

fn need<'a>(stretches: Option<&'a [f64]>, what: &str) -> Result<&'a [f64], SpecError> {
    stretches.ok_or_else(|| {
        SpecError::new(
            "stretch",
            "(missing)",
            format!("{what} needs the stretches at which to sample it"),
        )
    })
}

/// A fit with two sources of data given both or neither.
fn one_source(fit: &str, other: &str) -> SpecError {
    SpecError::new(
        "",
        "",
        format!("a {fit} fit needs exactly one of data = \"file.csv\" and {other}"),
    )
}

fn case(label: &str, data: Data, reference: Option<Vec<f64>>) -> FitCase {
    FitCase {
        label: label.to_string(),
        data,
        damage: None,
        reference,
    }
}

fn sample(lambdas: &[f64], f: impl Fn(f64) -> crate::Result<f64>) -> Vec<(f64, f64)> {
    lambdas
        .iter()
        .filter_map(|&l| f(l).ok().filter(|y| y.is_finite()).map(|y| (l, y)))
        .collect()
}

/// Passive parameters of the material's energy (eq. (11)).
#[derive(Debug, Clone)]
struct Passive {
    energy: Energy,
    direction: Direction,
}

impl Problem for Passive {
    fn model(&self) -> Model {
        let names = self.energy.parameter_names();
        Model {
            kind: FitKind::Passive,
            default_free: default_passive_free(&names),
            names,
            values: self.energy.parameter_values(),
            y_label: "P_pas [kPa]",
            reference_label: "scene's material",
            unit: "kPa",
        }
    }
    fn cases(
        &self,
        spec: &FitSpec,
        stretches: Option<&[f64]>,
        source: &mut DataSource,
    ) -> Result<(Vec<FitCase>, String), SpecError> {
        match (&spec.data, &spec.reference) {
            (Some(file), None) => {
                source.file(file, stretches, Some(self.energy.parameter_values()), "")
            }
            (None, Some(r)) => {
                let reference = r.build().map_err(|e| e.within("reference"))?;
                let lambdas = need(stretches, "a reference curve")?;
                let muscle = Muscle::passive(reference.clone());
                let data =
                    source.synthetic(lambdas, |l| Ok(self.direction.point(&muscle, l)?.stress))?;
                let name = reference.name();
                Ok((
                    vec![case(
                        &format!("{name} curve"),
                        data,
                        Some(self.energy.parameter_values()),
                    )],
                    format!(
                        "{name} passive curve {} the fibres{}",
                        self.direction.name(),
                        source.noise_text
                    ),
                ))
            }
            _ => Err(one_source("passive", "reference = { energy = ... }")),
        }
    }
    fn fit(&self, case: &FitCase, setup: &FitSetup) -> Result<(FitReport, Vec<String>), FitError> {
        fit_passive(&self.energy, &[(self.direction, &case.data)], setup)
            .map(|f| (f.report, vec![]))
    }
    fn curve(&self, values: &[f64], _: &FitCase, grid: &[f64]) -> Vec<(f64, f64)> {
        match self.energy.rebuilt(values) {
            Ok(e) => {
                let muscle = Muscle::passive(e);
                sample(grid, |l| Ok(self.direction.point(&muscle, l)?.stress))
            }
            Err(_) => vec![],
        }
    }
}

/// The active curve (eq. (8)).
#[derive(Debug, Clone)]
struct ActiveCurveFit {
    energy: Energy,
    curve: ActiveCurve,
    stress: StressKind,
}

impl ActiveCurveFit {
    /// The active stresses of a case: as given, or total minus the model's passive stress.
    fn active(&self, case: &FitCase) -> Result<Data, FitError> {
        match self.stress {
            StressKind::Active => Ok(case.data.clone()),
            StressKind::Total => active_from_total(&self.energy, &case.data),
        }
    }
}

impl Problem for ActiveCurveFit {
    fn model(&self) -> Model {
        let c = &self.curve;
        Model {
            kind: FitKind::ActiveCurve,
            names: c.parameters().iter().map(|p| p.name).collect(),
            values: c.parameter_values(),
            default_free: c
                .parameters()
                .iter()
                .map(|p| p.name)
                .filter(|n| *n != "p_opt")
                .collect(),
            y_label: "P_act [kPa]",
            reference_label: "scene's active curve",
            unit: "kPa",
        }
    }
    fn cases(
        &self,
        spec: &FitSpec,
        stretches: Option<&[f64]>,
        source: &mut DataSource,
    ) -> Result<(Vec<FitCase>, String), SpecError> {
        if let Some(file) = &spec.data {
            let what = match self.stress {
                StressKind::Active => " (active stress)",
                StressKind::Total => " (total stress)",
            };
            return source.file(file, stretches, None, what);
        }
        let lambdas = need(stretches, "a synthetic active curve")?;
        let passive = Muscle::passive(self.energy.clone());
        let data = source.synthetic(lambdas, |l| {
            let p = self.curve.value(l);
            Ok(match self.stress {
                StressKind::Active => p,
                StressKind::Total => p + along_fibres(&passive, l)?.stress,
            })
        })?;
        Ok((
            vec![case(
                "synthetic active curve",
                data,
                Some(self.model().values),
            )],
            format!(
                "the scene's active curve ([activation]){}",
                source.noise_text
            ),
        ))
    }
    fn fit(&self, case: &FitCase, setup: &FitSetup) -> Result<(FitReport, Vec<String>), FitError> {
        self.active(case)
            .and_then(|d| fit_active_curve(&self.curve, &d, setup).map(|f| (f.report, vec![])))
    }
    fn curve(&self, v: &[f64], _: &FitCase, grid: &[f64]) -> Vec<(f64, f64)> {
        match self.curve.rebuilt(v) {
            Ok(c) => sample(grid, |l| Ok(c.value(l))),
            Err(_) => vec![],
        }
    }
    fn shown(&self, case: &FitCase) -> (Vec<(f64, f64)>, String) {
        (
            self.active(case).map(|d| d.points()).unwrap_or_default(),
            match self.stress {
                StressKind::Active => case.label.clone(),
                StressKind::Total => format!("{} − P_pas", case.label),
            },
        )
    }
}

/// (a, b) of the explicit law (eq. (14)) against the implicit law (eq. (13)).
#[derive(Debug, Clone)]
struct ExplicitLawFit {
    energy: GiantesioMusesti,
    curve: ActiveCurve,
    residual: ExplicitTarget,
}

impl Problem for ExplicitLawFit {
    fn model(&self) -> Model {
        let (a, b) = ExplicitLaw::paper().coefficients();
        Model {
            kind: FitKind::ExplicitLaw,
            names: vec!["a", "b"],
            values: vec![a, b],
            default_free: vec!["a", "b"],
            y_label: "activation γ [-]",
            reference_label: "chapter's (a, b)",
            unit: match self.residual {
                ExplicitTarget::Stress => "kPa",
                ExplicitTarget::Activation => "-",
            },
        }
    }
    fn cases(
        &self,
        spec: &FitSpec,
        stretches: Option<&[f64]>,
        _: &mut DataSource,
    ) -> Result<(Vec<FitCase>, String), SpecError> {
        let lambdas = need(stretches, "an explicit-law fit")?;
        let lambda_min = self.curve.lambda_min();
        if let Some(bad) = lambdas.iter().find(|&&l| l <= lambda_min) {
            return Err(SpecError::new(
                "stretch",
                bad,
                format!("the implicit law is defined above lambda_min = {lambda_min}"),
            ));
        }
        let ds = damages("damage", spec.damage.as_deref().unwrap_or(&[0.0]))?;
        if ds.iter().any(|&d| d >= 1.0) {
            return Err(SpecError::new(
                "damage",
                fmt_list(&ds),
                "at d = 1 there is no activation to fit: each d must be < 1",
            ));
        }
        let mut cases = Vec::with_capacity(ds.len());
        for d in ds {
            cases.push(FitCase {
                label: format!("d = {d}"),
                data: Data::new(lambdas.to_vec(), vec![0.0; lambdas.len()])
                    .map_err(|e| SpecError::new("stretch", "", e.to_string()))?,
                damage: Some(d),
                reference: Some(self.model().values),
            });
        }
        let residual = match self.residual {
            ExplicitTarget::Stress => "the total stress [kPa]",
            ExplicitTarget::Activation => "γ [-]",
        };
        Ok((
            cases,
            format!("the implicit law (eq. (13)), residual in {residual}"),
        ))
    }
    fn fit(&self, case: &FitCase, setup: &FitSetup) -> Result<(FitReport, Vec<String>), FitError> {
        let (gm, curve) = (&self.energy, &self.curve);
        let d = case.damage.unwrap_or(0.0);
        let lambdas = case.data.lambda();
        fit_explicit_law(gm, curve, lambdas, d, self.residual, setup).map(|f| {
            let mut extra = vec![format!(
                "fitted (a, b): max |Δγ| = {:.3e}, max |ΔP| = {:.4} kPa",
                f.max_activation_error, f.max_stress_error
            )];
            let (a, b) = ExplicitLaw::paper().coefficients();
            if let Ok(law) = ExplicitLaw::new(a, b, *gm, *curve) {
                if let Ok((dg, dp)) = explicit_law_errors(&law, gm, curve, lambdas, d) {
                    extra.push(format!(
                        "chapter's (a, b) = ({a:.4}, {b:.4}): max |Δγ| = {dg:.3e}, max |ΔP| = {dp:.4} kPa"
                    ));
                }
            }
            (f.report, extra)
        })
    }
    fn curve(&self, v: &[f64], case: &FitCase, grid: &[f64]) -> Vec<(f64, f64)> {
        let d = case.damage.unwrap_or(0.0);
        match ExplicitLaw::new(v[0], v[1], self.energy, self.curve) {
            Ok(law) => sample(grid, |l| law.gamma(l, d)),
            Err(_) => vec![],
        }
    }
    fn shown(&self, case: &FitCase) -> (Vec<(f64, f64)>, String) {
        let implicit = ImplicitLaw::new(self.energy, self.curve);
        let d = case.damage.unwrap_or(0.0);
        (
            sample(case.data.lambda(), |l| Ok(implicit.evaluate(l, d)?.gamma)),
            "implicit γ (eq. (13))".into(),
        )
    }
}

/// The damage d of a weakened total curve, P_pas + (1 − d) P_act.
#[derive(Debug, Clone)]
struct DamageFit {
    energy: Energy,
    curve: ActiveCurve,
}

impl Problem for DamageFit {
    fn model(&self) -> Model {
        Model {
            kind: FitKind::Damage,
            names: vec!["d"],
            values: vec![0.0],
            default_free: vec!["d"],
            y_label: "P_total [kPa]",
            reference_label: "healthy muscle (d = 0)",
            unit: "kPa",
        }
    }
    fn cases(
        &self,
        spec: &FitSpec,
        stretches: Option<&[f64]>,
        source: &mut DataSource,
    ) -> Result<(Vec<FitCase>, String), SpecError> {
        match (&spec.data, &spec.true_damage) {
            (Some(file), None) => {
                source.file(file, stretches, None, " (total stress along the fibres)")
            }
            (None, Some(ds)) => {
                let ds = damages("true_damage", ds)?;
                let lambdas = need(stretches, "a synthetic weakened curve")?;
                let passive = Muscle::passive(self.energy.clone());
                let mut cases = Vec::with_capacity(ds.len());
                for d in ds {
                    let data = source.synthetic(lambdas, |l| {
                        Ok(along_fibres(&passive, l)?.stress
                            + Drive::from(d).target(&self.curve, l))
                    })?;
                    cases.push(FitCase {
                        label: format!("true d = {d}"),
                        data,
                        damage: Some(d),
                        reference: Some(vec![d]),
                    });
                }
                Ok((
                    cases,
                    format!(
                        "synthetic weakened total curves P_pas + (1 − d) P_act{}",
                        source.noise_text
                    ),
                ))
            }
            _ => Err(one_source("damage", "true_damage = [...]")),
        }
    }
    fn fit(&self, case: &FitCase, setup: &FitSetup) -> Result<(FitReport, Vec<String>), FitError> {
        fit_damage(&self.energy, &self.curve, &case.data, setup).map(|f| (f.report, vec![]))
    }
    fn curve(&self, v: &[f64], _: &FitCase, grid: &[f64]) -> Vec<(f64, f64)> {
        let passive = Muscle::passive(self.energy.clone());
        let d = v[0];
        sample(grid, |l| {
            Ok(along_fibres(&passive, l)?.stress + Drive::from(d).target(&self.curve, l))
        })
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
        ) == (
            &other.name,
            &other.source,
            &other.cases,
            &other.setup,
            &other.free,
            &other.model,
        )
    }
}

/// Validates `spec`, reads or samples its data; returns the study and the spec with every
/// default written out.
pub fn resolve(spec: &FitSpec, d: &Defaults) -> Result<(FitStudy, FitSpec), SpecError> {
    let stretches = optional_stretches(&spec.stretch)?;
    let Some(kind) = spec.fit else {
        return Err(SpecError::new(
            "fit",
            "(missing)",
            "a fit study needs fit = \"passive\" | \"active-curve\" | \"explicit-law\" | \"damage\"",
        ));
    };
    check_keys(spec, kind)?;
    let (options, mut source) = solver(spec, d.base)?;
    let problem = problem(spec, kind, d)?;
    let model = problem.model();
    let free = free_parameters(spec, &model.names, &model.default_free)?;
    let setup = setup(spec, &model, &free, options)?;
    let (cases, source) = problem.cases(spec, stretches.as_deref(), &mut source)?;
    enough_points(spec, kind, &cases, free.len())?;
    let name = spec
        .name
        .clone()
        .unwrap_or_else(|| format!("fit {}", kind.name()));
    let resolved = FitSpec {
        name: Some(name.clone()),
        free: Some(free.clone()),
        method: Some(options.method),
        max_iterations: Some(options.max_iterations as i64),
        reference: spec
            .reference
            .as_ref()
            .map(|r| r.build().map(|e| EnergySpec::written(&e)))
            .transpose()
            .map_err(|e| e.within("reference"))?,
        direction: (kind == FitKind::Passive).then(|| spec.direction.unwrap_or_default()),
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
        free,
        model,
        problem,
    };
    Ok((study, resolved))
}

/// The solver settings and the noise of synthetic data, checked.
fn solver<'a>(spec: &FitSpec, base: &'a Path) -> Result<(FitOptions, DataSource<'a>), SpecError> {
    let noise = spec.noise.unwrap_or(0.0);
    if !(noise.is_finite() && noise >= 0.0) {
        return Err(SpecError::new(
            "noise",
            noise,
            "must be finite and ≥ 0 [kPa]",
        ));
    }
    let seed = spec.seed.unwrap_or(1);
    if seed < 0 {
        return Err(SpecError::new("seed", seed, "must be ≥ 0"));
    }
    let max_iterations = spec.max_iterations.unwrap_or(1000);
    if !(1..=100_000).contains(&max_iterations) {
        return Err(SpecError::new(
            "max_iterations",
            max_iterations,
            "must be an integer in [1, 100000]",
        ));
    }
    let options = FitOptions {
        method: spec.method.unwrap_or_default(),
        max_iterations: max_iterations as u64,
        ..FitOptions::default()
    };
    let source = DataSource {
        base,
        noise: (noise > 0.0).then(|| (noise, Sampler::new(seed as u64))),
        noise_text: if noise > 0.0 {
            format!(", Gaussian noise σ = {noise} kPa (seed {seed})")
        } else {
            String::new()
        },
    };
    Ok((options, source))
}

/// The problem of a fit of `kind` on the scene's material and curve.
fn problem(spec: &FitSpec, kind: FitKind, d: &Defaults) -> Result<Arc<dyn Problem>, SpecError> {
    let (energy, curve) = (d.models.energy.clone(), d.models.curve);
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

/// Every data set has more points than free parameters.
fn enough_points(
    spec: &FitSpec,
    kind: FitKind,
    cases: &[FitCase],
    free: usize,
) -> Result<(), SpecError> {
    let Some(c) = cases.iter().find(|c| c.data.len() <= free) else {
        return Ok(());
    };
    let (key, what) = match &spec.data {
        Some(file) if kind != FitKind::ExplicitLaw => ("data", format!("data file {file:?}")),
        _ => ("stretch", "stretch".to_string()),
    };
    Err(SpecError::new(
        key,
        format!("{} points", c.data.len()),
        format!(
            "{what}: {} points for {free} free parameters: need at least {}",
            c.data.len(),
            free + 1
        ),
    ))
}

/// Rejects the keys of other kinds of fit (`reference` in a damage fit).
fn check_keys(spec: &FitSpec, kind: FitKind) -> Result<(), SpecError> {
    let given = [
        ("data", spec.data.is_some()),
        ("reference", spec.reference.is_some()),
        ("direction", spec.direction.is_some()),
        ("stress", spec.stress.is_some()),
        ("residual", spec.residual.is_some()),
        ("damage", spec.damage.is_some()),
        ("true_damage", spec.true_damage.is_some()),
    ];
    for (key, present) in given {
        if present && !kind.own_keys().contains(&key) {
            let rule = if key == "damage" {
                "damage is a key of fit = \"explicit-law\" only (damage fits take true_damage for synthetic data)".to_string()
            } else {
                format!("not a key of a fit = \"{}\" study", kind.name())
            };
            return Err(SpecError::new(key, "(given)", rule));
        }
    }
    Ok(())
}

/// The free parameters: given or the fit's default, each a parameter of the model, once.
fn free_parameters(
    spec: &FitSpec,
    names: &[&str],
    default_free: &[&str],
) -> Result<Vec<String>, SpecError> {
    let free: Vec<String> = match &spec.free {
        Some(f) => f.clone(),
        None => default_free.iter().map(|n| n.to_string()).collect(),
    };
    if free.is_empty() {
        return Err(SpecError::new(
            "free",
            "[]",
            format!("free at least one parameter of {names:?}"),
        ));
    }
    for (j, f) in free.iter().enumerate() {
        if !names.contains(&f.as_str()) {
            return Err(SpecError::new(
                format!("free[{j}]"),
                format!("{f:?}"),
                format!("not a parameter of this fit; it has {names:?}"),
            ));
        }
        if free[..j].contains(f) {
            return Err(SpecError::new(
                format!("free[{j}]"),
                format!("{f:?}"),
                "freed twice",
            ));
        }
    }
    Ok(free)
}

/// Bounds and starts of the free parameters, checked: every start, given or the model's own
/// value, lies within its bounds (the fit would refuse it only when it runs).
fn setup(
    spec: &FitSpec,
    model: &Model,
    free: &[String],
    options: FitOptions,
) -> Result<FitSetup, SpecError> {
    let mut setup = FitSetup::new()
        .free(&free.iter().map(String::as_str).collect::<Vec<_>>())
        .options(options);
    let bounds = spec.bounds.clone().unwrap_or_default();
    for (name, b) in &bounds {
        let key = format!("bounds.{name}");
        if !free.contains(name) {
            return Err(SpecError::new(
                key,
                fmt_list(b),
                format!("not a free parameter; free = {free:?}"),
            ));
        }
        if b[0].is_nan() || b[1].is_nan() || b[0] >= b[1] {
            return Err(SpecError::new(
                key,
                fmt_list(b),
                "bounds must be [lower, upper] with lower < upper (± inf allowed)",
            ));
        }
        setup = setup.bounds(name, Bounds::new(b[0], b[1]));
        let given = spec.start.as_ref().is_some_and(|s| s.contains_key(name));
        let own = model
            .names
            .iter()
            .position(|n| n == name)
            .map(|i| model.values[i]);
        if let (false, Some(v)) = (given, own) {
            if !(b[0] <= v && v <= b[1]) {
                return Err(SpecError::new(
                    key,
                    fmt_list(b),
                    format!(
                        "the start of {name}, the model's value {}, lies outside: \
                         widen the bounds or give start.{name} within them",
                        shortest(v)
                    ),
                ));
            }
        }
    }
    for (name, &v) in spec.start.iter().flatten() {
        let key = format!("start.{name}");
        if !free.contains(name) {
            return Err(SpecError::new(
                key,
                v,
                format!("not a free parameter; free = {free:?}"),
            ));
        }
        if !v.is_finite() {
            return Err(SpecError::new(key, v, "a starting value must be finite"));
        }
        if let Some(b) = bounds.get(name) {
            if !(b[0] <= v && v <= b[1]) {
                return Err(SpecError::new(
                    key,
                    v,
                    format!("must lie within bounds.{name} = {}", fmt_list(b)),
                ));
            }
        }
        setup = setup.start(name, v);
    }
    Ok(setup)
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
    /// Further facts (e.g. the explicit law's max stress error), one line each.
    pub extra: Vec<String>,
    /// Data and curves for the figure.
    pub plot: FitCurves,
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

/// What the data-vs-fit figure of one case shows.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FitCurves {
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
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// A dense grid over the data's stretches for the curves.
fn dense(data: &Data) -> Vec<f64> {
    let (a, b) = (data.lambda()[0], data.lambda()[data.len() - 1]);
    (0..=200).map(|i| a + (b - a) * i as f64 / 200.0).collect()
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
            match self.problem.fit(case, &self.setup) {
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
        let grid = dense(&case.data);
        let curve =
            |free_values: &[f64]| self.problem.curve(&self.assemble(free_values), case, &grid);
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
        let (data, data_label) = self.problem.shown(case);
        FitOutcome {
            kind: self.model.kind,
            case: case.label.clone(),
            source: self.source.clone(),
            points: case.data.len(),
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
            plot: FitCurves {
                y_label: self.model.y_label.into(),
                data,
                data_label,
                fitted: curve(&report.values),
                start: start.map(|s| (self.model.reference_label.to_string(), curve(&s))),
            },
            names: report.names,
            values: report.values,
            termination: report.termination,
        }
    }
}
