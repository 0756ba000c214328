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

use super::spec::{damages, fmt_list, optional_stretches, Defaults, StretchSpec};
use super::{Failure, Outcome, RunContext, StudyKind, StudyResult};
use crate::active::{ActivationLaw, ActiveCurve, ExplicitLaw, ImplicitLaw};
use crate::app_error::{AppError, SpecError};
use crate::energy::{Energy, GiantesioMusesti, Parametric};
use crate::fit::{
    active_from_total, default_passive_free, explicit_law_errors, fit_active_curve, fit_damage,
    fit_explicit_law, fit_passive, Bounds, Data, ExplicitTarget, FitError, FitOptions, FitReport,
    FitSetup, Method, CURVE_PARAMETERS,
};
use crate::models::EnergySpec;
use crate::random::Sampler;
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
    /// Maximum Gauss–Newton iterations (default 100).
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

/// How the figure of a case shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct Shown {
    /// y-axis label with unit.
    pub y_label: &'static str,
    /// The data as plotted.
    pub data: Vec<(f64, f64)>,
    /// Label of the data.
    pub data_label: String,
    /// Label of the model at the reference (or starting) values.
    pub reference_label: &'static str,
}

/// One kind of fit as a study runs it.
pub trait Problem: fmt::Debug + Send + Sync {
    /// What is fitted.
    fn kind(&self) -> FitKind;
    /// Names of all the model's parameters, in order.
    fn names(&self) -> Vec<&'static str>;
    /// The model's own values of all parameters (the default starts).
    fn values(&self) -> Vec<f64>;
    /// The parameters freed when the scene does not say.
    fn default_free(&self) -> Vec<&'static str>;
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
    /// How the figure shows the case.
    fn shown(&self, case: &FitCase) -> Shown;
    /// Unit of the residuals (`kPa`, or `-` for γ).
    fn unit(&self) -> &'static str {
        "kPa"
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
    fn kind(&self) -> FitKind {
        FitKind::Passive
    }
    fn names(&self) -> Vec<&'static str> {
        self.energy.parameter_names()
    }
    fn values(&self) -> Vec<f64> {
        self.energy.parameter_values()
    }
    fn default_free(&self) -> Vec<&'static str> {
        default_passive_free(&self.names())
    }
    fn cases(
        &self,
        spec: &FitSpec,
        stretches: Option<&[f64]>,
        source: &mut DataSource,
    ) -> Result<(Vec<FitCase>, String), SpecError> {
        match (&spec.data, &spec.reference) {
            (Some(file), None) => source.file(file, stretches, Some(self.values()), ""),
            (None, Some(r)) => {
                let reference = r.build().map_err(|e| e.within("reference"))?;
                let lambdas = need(stretches, "a reference curve")?;
                let muscle = Muscle::passive(reference.clone());
                let data =
                    source.synthetic(lambdas, |l| Ok(self.direction.point(&muscle, l)?.stress))?;
                let name = reference.name();
                Ok((
                    vec![case(&format!("{name} curve"), data, Some(self.values()))],
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
    fn shown(&self, case: &FitCase) -> Shown {
        Shown {
            y_label: "P_pas [kPa]",
            data: case.data.points(),
            data_label: case.label.clone(),
            reference_label: "scene's material",
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
    fn kind(&self) -> FitKind {
        FitKind::ActiveCurve
    }
    fn names(&self) -> Vec<&'static str> {
        CURVE_PARAMETERS.to_vec()
    }
    fn values(&self) -> Vec<f64> {
        let c = &self.curve;
        vec![c.lambda_min(), c.lambda_opt(), c.k(), c.p_opt()]
    }
    fn default_free(&self) -> Vec<&'static str> {
        CURVE_PARAMETERS[..3].to_vec()
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
            vec![case("synthetic active curve", data, Some(self.values()))],
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
        match ActiveCurve::new(v[0], v[1], v[2], v[3]) {
            Ok(c) => sample(grid, |l| Ok(c.value(l))),
            Err(_) => vec![],
        }
    }
    fn shown(&self, case: &FitCase) -> Shown {
        Shown {
            y_label: "P_act [kPa]",
            data: self.active(case).map(|d| d.points()).unwrap_or_default(),
            data_label: match self.stress {
                StressKind::Active => case.label.clone(),
                StressKind::Total => format!("{} − P_pas", case.label),
            },
            reference_label: "scene's active curve",
        }
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
    fn kind(&self) -> FitKind {
        FitKind::ExplicitLaw
    }
    fn names(&self) -> Vec<&'static str> {
        vec!["a", "b"]
    }
    fn values(&self) -> Vec<f64> {
        let (a, b) = ExplicitLaw::paper().coefficients();
        vec![a, b]
    }
    fn default_free(&self) -> Vec<&'static str> {
        self.names()
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
                reference: Some(self.values()),
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
    fn shown(&self, case: &FitCase) -> Shown {
        let implicit = ImplicitLaw::new(self.energy, self.curve);
        let d = case.damage.unwrap_or(0.0);
        Shown {
            y_label: "activation γ [-]",
            data: sample(case.data.lambda(), |l| Ok(implicit.evaluate(l, d)?.gamma)),
            data_label: "implicit γ (eq. (13))".into(),
            reference_label: "chapter's (a, b)",
        }
    }
    fn unit(&self) -> &'static str {
        match self.residual {
            ExplicitTarget::Stress => "kPa",
            ExplicitTarget::Activation => "-",
        }
    }
}

/// The damage d of a weakened total curve, P_pas + (1 − d) P_act.
#[derive(Debug, Clone)]
struct DamageFit {
    energy: Energy,
    curve: ActiveCurve,
}

impl Problem for DamageFit {
    fn kind(&self) -> FitKind {
        FitKind::Damage
    }
    fn names(&self) -> Vec<&'static str> {
        vec!["d"]
    }
    fn values(&self) -> Vec<f64> {
        vec![0.0]
    }
    fn default_free(&self) -> Vec<&'static str> {
        self.names()
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
                        Ok(along_fibres(&passive, l)?.stress + (1.0 - d) * self.curve.value(l))
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
            Ok(along_fibres(&passive, l)?.stress + (1.0 - d) * self.curve.value(l))
        })
    }
    fn shown(&self, case: &FitCase) -> Shown {
        Shown {
            y_label: "P_total [kPa]",
            data: case.data.points(),
            data_label: case.label.clone(),
            reference_label: "healthy muscle (d = 0)",
        }
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
    /// The model that is fitted.
    pub problem: Arc<dyn Problem>,
}

impl PartialEq for FitStudy {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
            && self.source == other.source
            && self.cases == other.cases
            && self.setup == other.setup
            && self.free == other.free
            && self.problem.kind() == other.problem.kind()
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

    // Solver settings.
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
    let max_iterations = spec.max_iterations.unwrap_or(100);
    if !(1..=100_000).contains(&max_iterations) {
        return Err(SpecError::new(
            "max_iterations",
            max_iterations,
            "must be an integer in [1, 100000]",
        ));
    }
    let method = spec.method.unwrap_or_default();
    let options = FitOptions {
        method,
        max_iterations: max_iterations as u64,
        ..FitOptions::default()
    };

    let problem: Arc<dyn Problem> = match kind {
        FitKind::Passive => Arc::new(Passive {
            energy: d.models.energy.clone(),
            direction: spec.direction.unwrap_or_default(),
        }),
        FitKind::ActiveCurve => Arc::new(ActiveCurveFit {
            energy: d.models.energy.clone(),
            curve: d.models.curve,
            stress: spec.stress.unwrap_or_default(),
        }),
        FitKind::ExplicitLaw => match &d.models.energy {
            Energy::GiantesioMusesti(gm) => Arc::new(ExplicitLawFit {
                energy: *gm,
                curve: d.models.curve,
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
        FitKind::Damage => Arc::new(DamageFit {
            energy: d.models.energy.clone(),
            curve: d.models.curve,
        }),
    };

    let free = free_parameters(spec, &problem.names(), &problem.default_free())?;
    let setup = setup(spec, &free, options)?;

    let mut source = DataSource {
        base: d.base,
        noise: (noise > 0.0).then(|| (noise, Sampler::new(seed as u64))),
        noise_text: if noise > 0.0 {
            format!(", Gaussian noise σ = {noise} kPa (seed {seed})")
        } else {
            String::new()
        },
    };
    let (cases, source) = problem.cases(spec, stretches.as_deref(), &mut source)?;
    for c in &cases {
        if c.data.len() <= free.len() {
            let (key, what) = match &spec.data {
                Some(file) if kind != FitKind::ExplicitLaw => {
                    ("data", format!("data file {file:?}"))
                }
                _ => ("stretch", "stretch".to_string()),
            };
            return Err(SpecError::new(
                key,
                format!("{} points", c.data.len()),
                format!(
                    "{what}: {} points for {} free parameters: need at least {}",
                    c.data.len(),
                    free.len(),
                    free.len() + 1
                ),
            ));
        }
    }

    let name = spec
        .name
        .clone()
        .unwrap_or_else(|| format!("fit {}", kind.name()));
    let mut resolved = spec.clone();
    resolved.name = Some(name.clone());
    resolved.free = Some(free.clone());
    resolved.method = Some(method);
    resolved.max_iterations = Some(max_iterations);
    resolved.reference = spec
        .reference
        .as_ref()
        .map(|r| r.build().map(|e| EnergySpec::written(&e)))
        .transpose()
        .map_err(|e| e.within("reference"))?;
    match kind {
        FitKind::Passive => resolved.direction = Some(spec.direction.unwrap_or_default()),
        FitKind::ActiveCurve => resolved.stress = Some(spec.stress.unwrap_or_default()),
        FitKind::ExplicitLaw => {
            resolved.residual = Some(spec.residual.unwrap_or_default());
            resolved.damage = Some(cases.iter().filter_map(|c| c.damage).collect());
        }
        FitKind::Damage => {}
    }
    Ok((
        FitStudy {
            name,
            source,
            cases,
            setup,
            free,
            problem,
        },
        resolved,
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

/// Bounds and starts of the free parameters, checked.
fn setup(spec: &FitSpec, free: &[String], options: FitOptions) -> Result<FitSetup, SpecError> {
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
        let names = self.problem.names();
        let mut all = self.problem.values();
        for (name, x) in self.free.iter().zip(free_values) {
            if let Some(i) = names.iter().position(|n| n == name) {
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
        let problem = &*self.problem;
        let names = problem.names();
        let mut outcomes = Vec::new();
        let mut failures = Vec::new();
        let mut fail = |message: String| {
            failures.push(Failure {
                model: "fit".into(),
                message,
            })
        };
        for case in &self.cases {
            let (report, extra, converged) = match problem.fit(case, &self.setup) {
                Ok((report, extra)) => (report, extra, true),
                Err(FitError::NotConverged { reason, best }) => {
                    fail(format!(
                        "{}: did not converge ({reason}); best point found {:?} = {:?} (reported, NOT a solution)",
                        case.label, best.names, best.values
                    ));
                    (*best, vec![], false)
                }
                Err(e) => {
                    fail(format!("{}: fit failed: {e}", case.label));
                    continue;
                }
            };
            let grid = dense(&case.data);
            let model =
                |free_values: &[f64]| problem.curve(&self.assemble(free_values), case, &grid);
            // The reference values of the free parameters.
            let reference: Vec<Option<f64>> = match &case.reference {
                Some(all) => self
                    .free
                    .iter()
                    .map(|f| names.iter().position(|n| n == f).map(|i| all[i]))
                    .collect(),
                None => vec![None; self.free.len()],
            };
            // The dashed curve: the model at the reference values (the damage fit's: d = 0).
            let start: Option<Vec<f64>> = match problem.kind() {
                FitKind::Damage => Some(problem.values()),
                _ => reference.iter().copied().collect(),
            };
            let shown = problem.shown(case);
            outcomes.push(FitOutcome {
                kind: problem.kind(),
                case: case.label.clone(),
                source: self.source.clone(),
                points: case.data.len(),
                names: report.names.clone(),
                values: report.values.clone(),
                standard_errors: report.standard_errors.iter().map(|&x| finite(x)).collect(),
                reference,
                correlation: report
                    .correlation
                    .iter()
                    .map(|row| row.iter().map(|&x| finite(x)).collect())
                    .collect(),
                rms: report.rms,
                unit: problem.unit(),
                residual_norm: report.residual_norm,
                iterations: report.iterations,
                converged,
                termination: report.termination.clone(),
                extra,
                plot: FitCurves {
                    y_label: shown.y_label.into(),
                    data: shown.data,
                    data_label: shown.data_label,
                    fitted: model(&report.values),
                    start: start.map(|s| (shown.reference_label.to_string(), model(&s))),
                },
            });
        }
        let converged = outcomes.iter().filter(|f| f.converged).count();
        let mut details = vec![format!("data: {}", self.source)];
        for f in &outcomes {
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
}
