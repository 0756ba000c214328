//! A fit study's settings, checked against its spec: solver options and noise, the keys each kind
//! of fit takes, enough data points, the free parameters, their starts and bounds.

use super::source::DataSource;
use super::{CaseData, FitCase, FitKind, FitSpec, Model, WeightsKind};
use crate::app_error::SpecError;
use crate::fit::{Bounds, FitError, FitOptions, FitSetup, Weights};
use crate::random::Sampler;
use crate::studies::rules::{each, integer_in, non_empty, once};
use crate::studies::spec::fmt_list;
use crate::text::shortest;
use std::collections::BTreeMap;
use std::path::Path;

/// The solver settings and the noise of synthetic data, checked.
pub(super) fn solver<'a>(
    spec: &FitSpec,
    base: &'a Path,
) -> Result<(FitOptions, DataSource<'a>), SpecError> {
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
    let max_iterations = integer_in("max_iterations", max_iterations, 1..=100_000, "")?;
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

/// Every data set has more data (points; stresses of biaxial rows, two per row) than free
/// parameters.
pub(super) fn enough_points(
    spec: &FitSpec,
    kind: FitKind,
    cases: &[FitCase],
    free: usize,
) -> Result<(), SpecError> {
    let Some(c) = cases.iter().find(|c| c.data.residuals() <= free) else {
        return Ok(());
    };
    let (key, what) = match &spec.data {
        Some(file) if kind != FitKind::ExplicitLaw => ("data", format!("data file {file:?}")),
        _ => ("stretch", "stretch".to_string()),
    };
    let (n, unit) = match c.data {
        CaseData::Uniaxial(_) => (c.data.points(), "points"),
        CaseData::Biaxial(_) => (c.data.residuals(), "stresses (two per row)"),
    };
    Err(SpecError::new(
        key,
        format!("{n} {unit}"),
        format!(
            "{what}: {n} {unit} for {free} free parameters: need at least {}",
            free + 1
        ),
    ))
}

/// Rejects the keys of other kinds of fit (`reference` in a damage fit).
pub(super) fn check_keys(spec: &FitSpec, kind: FitKind) -> Result<(), SpecError> {
    let given = [
        ("data", spec.data.is_some()),
        ("reference", spec.reference.is_some()),
        ("direction", spec.direction.is_some()),
        ("stress", spec.stress.is_some()),
        ("residual", spec.residual.is_some()),
        ("damage", spec.damage.is_some()),
        ("true_damage", spec.true_damage.is_some()),
        ("weights", spec.weights.is_some()),
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
pub(super) fn free_parameters(
    spec: &FitSpec,
    names: &[String],
    default_free: &[String],
) -> Result<Vec<String>, SpecError> {
    let free: Vec<String> = match &spec.free {
        Some(f) => f.clone(),
        None => default_free.to_vec(),
    };
    non_empty(
        "free",
        &free,
        &format!("free at least one parameter of {names:?}"),
    )?;
    let quoted: Vec<String> = free.iter().map(|f| format!("{f:?}")).collect();
    let known: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    each(
        "free",
        &quoted,
        |f| known.contains(f),
        &format!("not a parameter of this fit; it has {names:?}"),
    )?;
    once("free", &quoted, |a, b| a == b, |_| "freed twice".into())?;
    Ok(free)
}

/// Bounds and starts of the free parameters, checked: every start, given or the model's own
/// value, lies within its bounds (the fit would refuse it only when it runs).
pub(super) fn setup(
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
        check_start(name, v, &bounds, model, free)?;
        setup = setup.start(name, v);
    }
    Ok(setup)
}

/// The weights of the study: given, or `sigma` if every data set has a `sigma` column, else
/// `equal`; `sigma` without the column and `relative` on a datum of 0 are refused at `weights`.
pub(super) fn weights(spec: &FitSpec, cases: &[FitCase]) -> Result<WeightsKind, SpecError> {
    let with_sigma = |c: &FitCase| matches!(&c.data, CaseData::Uniaxial(d) if d.sigma().is_some());
    let all = !cases.is_empty() && cases.iter().all(with_sigma);
    let kind = spec.weights.unwrap_or(if all {
        WeightsKind::Sigma
    } else {
        WeightsKind::Equal
    });
    let refuse = |rule: String| {
        Err(SpecError::new(
            "weights",
            format!("\"{}\"", kind.name()),
            rule,
        ))
    };
    if kind == WeightsKind::Sigma && !all {
        return refuse("weights = \"sigma\" divides each residual by the data's standard deviation: the data file needs a third column, lambda,P,sigma (planar biaxial and synthetic data have none; use \"relative\" or \"equal\")".into());
    }
    for c in cases {
        if let Err(e) = case_weights(kind, &c.data) {
            return refuse(format!("{}: {e}", c.label));
        }
    }
    Ok(kind)
}

/// The scale of each residual of `data` under `kind`: the data's σ, |datum| (biaxial rows:
/// |P₁₁|, |P₂₂| of each row in turn) or none.
pub(super) fn case_weights(kind: WeightsKind, data: &CaseData) -> Result<Weights, FitError> {
    let observed: Vec<f64> = match data {
        CaseData::Uniaxial(d) => d.stress().to_vec(),
        CaseData::Biaxial(b) => b.stresses().iter().flat_map(|p| [p[0], p[1]]).collect(),
    };
    let weights = match (kind, data) {
        (WeightsKind::Equal, _) => Weights::Equal,
        (WeightsKind::Relative, _) => Weights::Sigma(observed.iter().map(|p| p.abs()).collect()),
        (WeightsKind::Sigma, CaseData::Uniaxial(d)) => {
            Weights::Sigma(d.sigma().map(<[f64]>::to_vec).unwrap_or_default())
        }
        (WeightsKind::Sigma, CaseData::Biaxial(_)) => Weights::Sigma(Vec::new()),
    };
    weights.scales(&observed)?;
    Ok(weights)
}

/// Checks `start.<name> = v`: a free parameter, finite, within its bounds (given, else the
/// model's default bounds, its admissible range: a start outside them would fail at run).
fn check_start(
    name: &str,
    v: f64,
    bounds: &BTreeMap<String, [f64; 2]>,
    model: &Model,
    free: &[String],
) -> Result<(), SpecError> {
    let key = format!("start.{name}");
    if !free.iter().any(|f| f.as_str() == name) {
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
    } else if let Some(b) = model
        .names
        .iter()
        .position(|n| *n == name)
        .and_then(|i| model.bounds.get(i))
    {
        if !b.contains(v) {
            return Err(SpecError::new(
                key,
                v,
                format!(
                    "must lie within the default bounds of {name}, its admissible range {}: \
                     give a start within it, or bounds.{name}",
                    fmt_list(&[b.lower, b.upper])
                ),
            ));
        }
    }
    Ok(())
}
