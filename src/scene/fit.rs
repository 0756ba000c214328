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

use super::resolve::{damages, energy, fmt_list, only_keys, written, Ctx};
use super::schema::{DirectionKind, FitKind, MethodKind, ResidualKind, StressKind, StudySpec};
use super::SceneError;
use crate::active::ActiveCurve;
use crate::energy::Energy;
use crate::fit::{Bounds, Data, FitOptions, FitSetup, Method, Parametric, CURVE_PARAMETERS};
use crate::uniaxial::{across_fibres, along_fibres};
use crate::Muscle;
use std::path::{Path, PathBuf};

/// One data set of a fit study and what is known about it.
#[derive(Debug, Clone)]
pub struct FitCase {
    /// Label in the report (e.g. `true d = 0.3`, or the data file).
    pub label: String,
    /// The data (for `explicit-law`: the stretches, stresses unused).
    pub data: Data,
    /// Damage of the model (explicit-law) or the true damage of synthetic data (damage).
    pub damage: Option<f64>,
}

/// A validated fit study.
#[derive(Debug, Clone)]
pub struct FitStudy {
    /// Label.
    pub name: String,
    /// What is fitted.
    pub fit: FitKind,
    /// Direction of the passive data.
    pub direction: DirectionKind,
    /// Active-curve data: active or total stress.
    pub stress: StressKind,
    /// Explicit-law residual.
    pub residual: ResidualKind,
    /// Where the data come from, in words.
    pub source: String,
    /// Data sets, one fit each.
    pub cases: Vec<FitCase>,
    /// Free parameters, starts, bounds and solver options.
    pub setup: FitSetup,
    /// Names of the free parameters (resolved).
    pub free: Vec<String>,
    /// Reference values of the free parameters (the chapter's, or the truth of synthetic data).
    pub reference: Vec<Option<f64>>,
}

/// A seeded normal generator (SplitMix64 and Box–Muller), so that synthetic data are the same on
/// every machine without a random-number dependency.
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
}

/// Parameter names of the model a fit adjusts, and the defaults of the free set.
fn parameters(fit: FitKind, material: &Energy) -> (Vec<&'static str>, Vec<&'static str>) {
    match fit {
        FitKind::Passive => {
            let all = material.parameter_names().to_vec();
            let mut free: Vec<&str> = all.iter().copied().filter(|n| *n != "mu").collect();
            if free.is_empty() {
                free = all.clone();
            }
            (all, free)
        }
        FitKind::ActiveCurve => (CURVE_PARAMETERS.to_vec(), CURVE_PARAMETERS[..3].to_vec()),
        FitKind::ExplicitLaw => (vec!["a", "b"], vec!["a", "b"]),
        FitKind::Damage => (vec!["d"], vec!["d"]),
    }
}

fn fit_name(fit: FitKind) -> &'static str {
    match fit {
        FitKind::Passive => "passive",
        FitKind::ActiveCurve => "active-curve",
        FitKind::ExplicitLaw => "explicit-law",
        FitKind::Damage => "damage",
    }
}

/// Reads a data file named relative to the scene file.
fn read_data(ctx: &Ctx, key: &str, name: &str) -> Result<(Data, String), SceneError> {
    let base = Path::new(ctx.file).parent().unwrap_or(Path::new(""));
    let path: PathBuf = if Path::new(name).is_absolute() {
        PathBuf::from(name)
    } else {
        base.join(name)
    };
    let shown = path.display().to_string();
    let data = Data::from_csv_path(&path)
        .map_err(|e| ctx.err(key, format!("{name:?}"), format!("unusable data file: {e}")))?;
    Ok((data, shown))
}

/// Samples `model` at `lambdas`, adding noise; errors name the key of the stretches.
fn synthetic(
    ctx: &Ctx,
    key: &str,
    lambdas: &[f64],
    noise: &mut Option<(f64, Noise)>,
    model: impl Fn(f64) -> crate::Result<f64>,
) -> Result<Data, SceneError> {
    let mut stress = Vec::with_capacity(lambdas.len());
    for &l in lambdas {
        let p = model(l).map_err(|e| {
            ctx.err(
                key,
                l,
                format!("the synthetic data cannot be computed at this stretch: {e}"),
            )
        })?;
        let p = match noise {
            Some((sigma, rng)) => p + *sigma * rng.normal(),
            None => p,
        };
        stress.push(p);
    }
    Data::new(lambdas.to_vec(), stress).map_err(|e| ctx.err(key, "", e.to_string()))
}

pub(super) fn resolve_fit(
    ctx: &Ctx,
    key: &str,
    s: &StudySpec,
    material: &Energy,
    curve: ActiveCurve,
    lambdas: Option<Vec<f64>>,
) -> Result<(FitStudy, StudySpec), SceneError> {
    let k = |name: &str| format!("{key}.{name}");
    let Some(fit) = s.fit else {
        return Err(ctx.err(
            k("fit"),
            "(missing)",
            "a fit study needs fit = \"passive\" | \"active-curve\" | \"explicit-law\" | \"damage\"",
        ));
    };
    let common = [
        "fit",
        "free",
        "start",
        "bounds",
        "method",
        "max_iterations",
        "noise",
        "seed",
    ];
    let own: &[&str] = match fit {
        FitKind::Passive => &["data", "reference", "direction"],
        FitKind::ActiveCurve => &["data", "stress"],
        FitKind::ExplicitLaw => &["residual"],
        FitKind::Damage => &["data", "true_damage"],
    };
    let allowed: Vec<&str> = common.iter().chain(own).copied().collect();
    only_keys(
        ctx,
        key,
        s,
        &format!("fit = \"{}\"", fit_name(fit)),
        &allowed,
    )?;
    if s.damage.is_some() && fit != FitKind::ExplicitLaw {
        return Err(ctx.err(
            k("damage"),
            "(given)",
            "damage is a key of fit = \"explicit-law\" only (damage fits take true_damage for synthetic data)",
        ));
    }

    // Solver settings.
    let noise_sigma = s.noise.unwrap_or(0.0);
    if !(noise_sigma.is_finite() && noise_sigma >= 0.0) {
        return Err(ctx.err(k("noise"), noise_sigma, "must be finite and ≥ 0 [kPa]"));
    }
    let seed = s.seed.unwrap_or(1);
    if seed < 0 {
        return Err(ctx.err(k("seed"), seed, "must be ≥ 0"));
    }
    let max_iterations = s.max_iterations.unwrap_or(100);
    if !(1..=100_000).contains(&max_iterations) {
        return Err(ctx.err(
            k("max_iterations"),
            max_iterations,
            "must be an integer in [1, 100000]",
        ));
    }
    let options = FitOptions {
        method: match s.method.unwrap_or(MethodKind::GaussNewton) {
            MethodKind::GaussNewton => Method::GaussNewton,
            MethodKind::NelderMead => Method::NelderMead,
        },
        max_iterations: max_iterations as u64,
        ..FitOptions::default()
    };

    // Free parameters, starts and bounds, checked against the model's names.
    let (names, default_free) = parameters(fit, material);
    let free: Vec<String> = match &s.free {
        Some(f) => f.clone(),
        None => default_free.iter().map(|n| n.to_string()).collect(),
    };
    if free.is_empty() {
        return Err(ctx.err(
            k("free"),
            "[]",
            format!("free at least one parameter of {names:?}"),
        ));
    }
    for (j, f) in free.iter().enumerate() {
        if !names.contains(&f.as_str()) {
            return Err(ctx.err(
                format!("{key}.free[{j}]"),
                format!("{f:?}"),
                format!("not a parameter of this fit; it has {names:?}"),
            ));
        }
        if free[..j].contains(f) {
            return Err(ctx.err(format!("{key}.free[{j}]"), format!("{f:?}"), "freed twice"));
        }
    }
    let mut setup = FitSetup::new()
        .free(&free.iter().map(String::as_str).collect::<Vec<_>>())
        .options(options);
    let bounds = s.bounds.clone().unwrap_or_default();
    for (name, b) in &bounds {
        let bk = format!("{key}.bounds.{name}");
        if !free.contains(name) {
            return Err(ctx.err(
                bk,
                fmt_list(b),
                format!("not a free parameter; free = {free:?}"),
            ));
        }
        if b[0].is_nan() || b[1].is_nan() || b[0] >= b[1] {
            return Err(ctx.err(
                bk,
                fmt_list(b),
                "bounds must be [lower, upper] with lower < upper (± inf allowed)",
            ));
        }
        setup = setup.bounds(name, Bounds::new(b[0], b[1]));
    }
    let start = s.start.clone().unwrap_or_default();
    for (name, &v) in &start {
        let sk = format!("{key}.start.{name}");
        if !free.contains(name) {
            return Err(ctx.err(sk, v, format!("not a free parameter; free = {free:?}")));
        }
        if !v.is_finite() {
            return Err(ctx.err(sk, v, "a starting value must be finite"));
        }
        if let Some(b) = bounds.get(name) {
            if !(b[0] <= v && v <= b[1]) {
                return Err(ctx.err(
                    sk,
                    v,
                    format!("must lie within bounds.{name} = {}", fmt_list(b)),
                ));
            }
        }
        setup = setup.start(name, v);
    }

    // Data.
    let mut noise = (noise_sigma > 0.0).then_some((noise_sigma, Noise(seed as u64)));
    let noise_text = if noise_sigma > 0.0 {
        format!(", Gaussian noise σ = {noise_sigma} kPa (seed {seed})")
    } else {
        String::new()
    };
    let need_stretch = |what: &str| -> Result<Vec<f64>, SceneError> {
        lambdas.clone().ok_or_else(|| {
            ctx.err(
                k("stretch"),
                "(missing)",
                format!("{what} needs the stretches at which to sample it"),
            )
        })
    };
    let no_stretch_with_file = || -> Result<(), SceneError> {
        if lambdas.is_some() {
            Err(ctx.err(
                k("stretch"),
                "(given)",
                "the data file gives the stretches: remove stretch",
            ))
        } else {
            Ok(())
        }
    };
    let direction = s.direction.unwrap_or(DirectionKind::Along);
    let stress = s.stress.unwrap_or(StressKind::Active);
    let residual = s.residual.unwrap_or(ResidualKind::Stress);
    let mut cases = Vec::new();
    let source;
    let mut reference_spec = None;
    let mut truth: Vec<Option<f64>> = vec![None; free.len()];
    match fit {
        FitKind::Passive => match (&s.data, &s.reference) {
            (Some(_), Some(_)) | (None, None) => {
                return Err(ctx.err(
                    key,
                    "",
                    "a passive fit needs exactly one of data = \"file.csv\" and reference = { energy = ... }",
                ))
            }
            (Some(file), None) => {
                no_stretch_with_file()?;
                let (data, shown) = read_data(ctx, &k("data"), file)?;
                source = format!("data file {shown}");
                cases.push(FitCase {
                    label: file.clone(),
                    data,
                    damage: None,
                });
            }
            (None, Some(spec)) => {
                let reference = energy(ctx, &k("reference"), spec)?;
                reference_spec = Some(written(&reference));
                let lambdas = need_stretch("a reference curve")?;
                let muscle = Muscle::passive(reference.clone());
                let data = synthetic(ctx, &k("stretch"), &lambdas, &mut noise, |l| {
                    Ok(match direction {
                        DirectionKind::Along => along_fibres(&muscle, l)?.stress,
                        DirectionKind::Across => across_fibres(&muscle, l)?.stress,
                    })
                })?;
                source = format!(
                    "{} passive curve {} the fibres{noise_text}",
                    reference_name(&reference),
                    match direction {
                        DirectionKind::Along => "along",
                        DirectionKind::Across => "across",
                    }
                );
                cases.push(FitCase {
                    label: format!("{} curve", reference_name(&reference)),
                    data,
                    damage: None,
                });
            }
        },
        FitKind::ActiveCurve => match &s.data {
            Some(file) => {
                no_stretch_with_file()?;
                let (data, shown) = read_data(ctx, &k("data"), file)?;
                source = format!(
                    "data file {shown} ({} stress)",
                    match stress {
                        StressKind::Active => "active",
                        StressKind::Total => "total",
                    }
                );
                cases.push(FitCase {
                    label: file.clone(),
                    data,
                    damage: None,
                });
            }
            None => {
                let lambdas = need_stretch("a synthetic active curve")?;
                let passive = Muscle::passive(material.clone());
                let data = synthetic(ctx, &k("stretch"), &lambdas, &mut noise, |l| {
                    let p = curve.value(l);
                    Ok(match stress {
                        StressKind::Active => p,
                        StressKind::Total => p + along_fibres(&passive, l)?.stress,
                    })
                })?;
                source = format!("the scene's active curve ([activation]){noise_text}");
                let values = [
                    curve.lambda_min(),
                    curve.lambda_opt(),
                    curve.k(),
                    curve.p_opt(),
                ];
                truth = free
                    .iter()
                    .map(|f| CURVE_PARAMETERS.iter().position(|n| n == f).map(|i| values[i]))
                    .collect();
                cases.push(FitCase {
                    label: "synthetic active curve".into(),
                    data,
                    damage: None,
                });
            }
        },
        FitKind::ExplicitLaw => {
            if !matches!(material, Energy::GiantesioMusesti(_)) {
                return Err(ctx.err(
                    k("fit"),
                    "\"explicit-law\"",
                    "eq. D:gamma is derived for the giantesio-musesti energy; material.energy is another",
                ));
            }
            let lambdas = need_stretch("an explicit-law fit")?;
            if let Some(bad) = lambdas.iter().find(|&&l| l <= curve.lambda_min()) {
                return Err(ctx.err(
                    k("stretch"),
                    bad,
                    format!(
                        "the implicit law is defined above lambda_min = {}",
                        curve.lambda_min()
                    ),
                ));
            }
            let ds = damages(ctx, &k("damage"), s.damage.as_deref().unwrap_or(&[0.0]))?;
            if ds.iter().any(|&d| d >= 1.0) {
                return Err(ctx.err(
                    k("damage"),
                    fmt_list(&ds),
                    "at d = 1 there is no activation to fit: each d must be < 1",
                ));
            }
            source = format!(
                "the implicit law (eq. D:eqgammaesplicita), residual in {}",
                match residual {
                    ResidualKind::Stress => "the total stress [kPa]",
                    ResidualKind::Activation => "γ [-]",
                }
            );
            for d in ds {
                cases.push(FitCase {
                    label: format!("d = {d}"),
                    data: Data::new(lambdas.clone(), vec![0.0; lambdas.len()])
                        .map_err(|e| ctx.err(k("stretch"), "", e.to_string()))?,
                    damage: Some(d),
                });
            }
            truth = free
                .iter()
                .map(|f| match f.as_str() {
                    "a" => Some(1.0133),
                    _ => Some(0.2050),
                })
                .collect();
        }
        FitKind::Damage => match (&s.data, &s.true_damage) {
            (Some(_), Some(_)) | (None, None) => {
                return Err(ctx.err(
                    key,
                    "",
                    "a damage fit needs exactly one of data = \"file.csv\" and true_damage = [...]",
                ))
            }
            (Some(file), None) => {
                no_stretch_with_file()?;
                let (data, shown) = read_data(ctx, &k("data"), file)?;
                source = format!("data file {shown} (total stress along the fibres)");
                cases.push(FitCase {
                    label: file.clone(),
                    data,
                    damage: None,
                });
            }
            (None, Some(ds)) => {
                let ds = damages(ctx, &k("true_damage"), ds)?;
                let lambdas = need_stretch("a synthetic weakened curve")?;
                let passive = Muscle::passive(material.clone());
                for d in ds {
                    let data = synthetic(ctx, &k("stretch"), &lambdas, &mut noise, |l| {
                        Ok(along_fibres(&passive, l)?.stress + (1.0 - d) * curve.value(l))
                    })?;
                    cases.push(FitCase {
                        label: format!("true d = {d}"),
                        data,
                        damage: Some(d),
                    });
                }
                source = format!("synthetic weakened total curves P_pas + (1 − d) P_act{noise_text}");
            }
        },
    }
    if fit == FitKind::Passive {
        let values = material.parameter_values();
        truth = free
            .iter()
            .map(|f| names.iter().position(|n| n == f).map(|i| values[i]))
            .collect();
    }
    for c in &cases {
        if c.data.len() <= free.len() {
            let what = match (&s.data, fit) {
                (Some(file), _) if fit != FitKind::ExplicitLaw => format!("data file {file:?}"),
                _ => "stretch".to_string(),
            };
            return Err(ctx.err(
                if s.data.is_some() {
                    k("data")
                } else {
                    k("stretch")
                },
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

    let name = s
        .name
        .clone()
        .unwrap_or_else(|| format!("fit {}", fit_name(fit)));
    let mut r = s.clone();
    r.name = Some(name.clone());
    r.free = Some(free.clone());
    r.method = Some(s.method.unwrap_or(MethodKind::GaussNewton));
    r.max_iterations = Some(max_iterations);
    r.reference = reference_spec;
    if fit == FitKind::Passive {
        r.direction = Some(direction);
    }
    if fit == FitKind::ActiveCurve {
        r.stress = Some(stress);
    }
    if fit == FitKind::ExplicitLaw {
        r.residual = Some(residual);
        r.damage = Some(cases.iter().filter_map(|c| c.damage).collect());
    }
    Ok((
        FitStudy {
            name,
            fit,
            direction,
            stress,
            residual,
            source,
            cases,
            setup,
            free,
            reference: truth,
        },
        r,
    ))
}

fn reference_name(e: &Energy) -> &str {
    use crate::StrainEnergy;
    e.name()
}

/// The outcome of one fit: a row of `fits.csv` and of the report's table. Statistics that do not
/// exist (a singular JᵀJ) are `None`, never NaN.
#[derive(Debug, Clone, PartialEq)]
pub struct FitOutcome {
    /// Study index.
    pub study: usize,
    /// Study label.
    pub study_name: String,
    /// `passive` | `active-curve` | `explicit-law` | `damage`.
    pub fit: &'static str,
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
    /// The model at the starting or reference values (label, points).
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

fn sample(lambdas: &[f64], f: impl Fn(f64) -> crate::Result<f64>) -> Vec<(f64, f64)> {
    lambdas
        .iter()
        .filter_map(|&l| f(l).ok().filter(|y| y.is_finite()).map(|y| (l, y)))
        .collect()
}

fn points(data: &Data) -> Vec<(f64, f64)> {
    data.lambda()
        .iter()
        .copied()
        .zip(data.stress().iter().copied())
        .collect()
}

/// Runs every case of `study`. A fit that does not converge gives an outcome with
/// `converged = false` (the best point) and a message; a fit that fails outright gives only the
/// message. Neither stops the run.
pub fn run_fit(
    index: usize,
    study: &FitStudy,
    material: &Energy,
    curve: ActiveCurve,
) -> (Vec<FitOutcome>, Vec<String>) {
    use crate::active::{ActivationLaw, ExplicitLaw, ImplicitLaw};
    use crate::energy::GiantesioMusesti;
    use crate::fit::{
        active_from_total, explicit_law_errors, fit_active_curve, fit_damage, fit_explicit_law,
        fit_passive, Direction, ExplicitTarget, FitError, FitReport,
    };
    let mut outcomes = Vec::new();
    let mut messages = Vec::new();
    for case in &study.cases {
        // Each arm gives the report (or error), the model curves as a function of the
        // fitted values, and extra lines.
        type Curves = Box<dyn Fn(&[f64]) -> Vec<(f64, f64)>>;
        type Fitted = Result<(FitReport, Vec<String>), FitError>;
        let grid = dense(&case.data);
        // (report, model curves, y label, data points, data label, reference label, unit)
        type Arm = (
            Fitted,
            Curves,
            &'static str,
            Vec<(f64, f64)>,
            String,
            &'static str,
            &'static str,
        );
        let (result, model, y_label, data, data_label, start_label, unit): Arm = match study.fit {
            FitKind::Passive => {
                let direction = match study.direction {
                    DirectionKind::Along => Direction::Along,
                    DirectionKind::Across => Direction::Across,
                };
                let r = fit_passive(material, &[(direction, &case.data)], &study.setup)
                    .map(|f| (f.report, vec![]));
                let m = material.clone();
                let free = study.free.clone();
                let dir = study.direction;
                let g = grid.clone();
                let model: Curves = Box::new(move |v: &[f64]| {
                    let mut values = m.parameter_values();
                    for (name, x) in free.iter().zip(v) {
                        if let Some(i) = m.parameter_names().iter().position(|n| n == name) {
                            values[i] = *x;
                        }
                    }
                    match m.rebuilt(&values) {
                        Ok(e) => {
                            let muscle = Muscle::passive(e);
                            sample(&g, |l| {
                                Ok(match dir {
                                    DirectionKind::Along => along_fibres(&muscle, l)?.stress,
                                    DirectionKind::Across => across_fibres(&muscle, l)?.stress,
                                })
                            })
                        }
                        Err(_) => vec![],
                    }
                });
                (
                    r,
                    model,
                    "P_pas [kPa]",
                    points(&case.data),
                    case.label.clone(),
                    "scene's material",
                    "kPa",
                )
            }
            FitKind::ActiveCurve => {
                let data = match study.stress {
                    StressKind::Active => Ok(case.data.clone()),
                    StressKind::Total => active_from_total(material, &case.data),
                };
                let r = data.clone().and_then(|d| {
                    fit_active_curve(&curve, &d, &study.setup).map(|f| (f.report, vec![]))
                });
                let free = study.free.clone();
                let g = grid.clone();
                let model: Curves = Box::new(move |v: &[f64]| {
                    let mut p = [
                        curve.lambda_min(),
                        curve.lambda_opt(),
                        curve.k(),
                        curve.p_opt(),
                    ];
                    for (name, x) in free.iter().zip(v) {
                        if let Some(i) = CURVE_PARAMETERS.iter().position(|n| n == name) {
                            p[i] = *x;
                        }
                    }
                    match ActiveCurve::new(p[0], p[1], p[2], p[3]) {
                        Ok(c) => sample(&g, |l| Ok(c.value(l))),
                        Err(_) => vec![],
                    }
                });
                (
                    r,
                    model,
                    "P_act [kPa]",
                    data.as_ref().map(points).unwrap_or_default(),
                    match study.stress {
                        StressKind::Active => case.label.clone(),
                        StressKind::Total => format!("{} − P_pas", case.label),
                    },
                    "scene's active curve",
                    "kPa",
                )
            }
            FitKind::ExplicitLaw => {
                let gm = match material {
                    Energy::GiantesioMusesti(gm) => *gm,
                    _ => GiantesioMusesti::paper(),
                };
                let d = case.damage.unwrap_or(0.0);
                let target = match study.residual {
                    ResidualKind::Stress => ExplicitTarget::Stress,
                    ResidualKind::Activation => ExplicitTarget::Activation,
                };
                let lambdas = case.data.lambda().to_vec();
                let r = fit_explicit_law(&gm, &curve, &lambdas, d, target, &study.setup).map(|f| {
                    let mut extra = vec![format!(
                        "fitted (a, b): max |Δγ| = {:.3e}, max |ΔP| = {:.4} kPa",
                        f.max_activation_error, f.max_stress_error
                    )];
                    if let Ok(law) = ExplicitLaw::new(1.0133, 0.2050, gm, curve) {
                        if let Ok((dg, dp)) = explicit_law_errors(&law, &gm, &curve, &lambdas, d) {
                            extra.push(format!(
                                "chapter's (a, b) = (1.0133, 0.2050): max |Δγ| = {dg:.3e}, max |ΔP| = {dp:.4} kPa"
                            ));
                        }
                    }
                    (f.report, extra)
                });
                let implicit = ImplicitLaw::new(gm, curve);
                let data = sample(&lambdas, |l| Ok(implicit.evaluate(l, d)?.gamma));
                let free = study.free.clone();
                let g = grid.clone();
                let model: Curves = Box::new(move |v: &[f64]| {
                    let mut ab = [1.0133, 0.2050];
                    for (name, x) in free.iter().zip(v) {
                        ab[usize::from(name == "b")] = *x;
                    }
                    match ExplicitLaw::new(ab[0], ab[1], gm, curve) {
                        Ok(law) => sample(&g, |l| law.gamma(l, d)),
                        Err(_) => vec![],
                    }
                });
                (
                    r,
                    model,
                    "activation γ [-]",
                    data,
                    "implicit γ (eq. D:eqgammaesplicita)".into(),
                    "chapter's (a, b)",
                    match study.residual {
                        ResidualKind::Stress => "kPa",
                        ResidualKind::Activation => "-",
                    },
                )
            }
            FitKind::Damage => {
                let r = fit_damage(material, &curve, &case.data, &study.setup)
                    .map(|f| (f.report, vec![]));
                let passive = Muscle::passive(material.clone());
                let g = grid.clone();
                let model: Curves = Box::new(move |v: &[f64]| {
                    let d = v.first().copied().unwrap_or(0.0);
                    sample(&g, |l| {
                        Ok(along_fibres(&passive, l)?.stress + (1.0 - d) * curve.value(l))
                    })
                });
                (
                    r,
                    model,
                    "P_total [kPa]",
                    points(&case.data),
                    case.label.clone(),
                    "healthy muscle (d = 0)",
                    "kPa",
                )
            }
        };
        let (report, extra, converged, failure) = match result {
            Ok((report, extra)) => (report, extra, true, None),
            Err(FitError::NotConverged { reason, best }) => (
                *best,
                vec![],
                false,
                Some(format!("did not converge ({reason})")),
            ),
            Err(e) => {
                messages.push(format!("{}: fit failed: {e}", case.label));
                continue;
            }
        };
        if let Some(why) = failure {
            messages.push(format!(
                "{}: {why}; best point found {:?} = {:?} (reported, NOT a solution)",
                case.label, report.names, report.values
            ));
        }
        let start: Vec<f64> = match study.fit {
            FitKind::Damage => vec![0.0],
            _ => study
                .reference
                .iter()
                .map(|r| r.unwrap_or(f64::NAN))
                .collect(),
        };
        let start_curve = (!start.iter().any(|x| x.is_nan())).then(|| model(&start));
        let reference = match study.fit {
            FitKind::Damage => vec![case.damage],
            _ => study.reference.clone(),
        };
        outcomes.push(FitOutcome {
            study: index,
            study_name: study.name.clone(),
            fit: fit_name(study.fit),
            case: case.label.clone(),
            source: study.source.clone(),
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
            unit,
            residual_norm: report.residual_norm,
            iterations: report.iterations,
            converged,
            termination: report.termination.clone(),
            extra,
            plot: FitCurves {
                y_label: y_label.into(),
                data,
                data_label,
                fitted: model(&report.values),
                start: start_curve.map(|c| (start_label.to_string(), c)),
            },
        });
    }
    (outcomes, messages)
}
