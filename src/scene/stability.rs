//! Stability studies (`kind = "stability"`): along the uniaxial path along the fibres, for each
//! law × coupling × d, where the curve softens (dP/dλ < 0) and where strong ellipticity is lost
//! ([`crate::stability::along_fibres_stability`]).

use super::resolve::{coupling_name, damages, law_name, models, only_keys, Ctx, ModelChoice};
use super::schema::{CouplingKind, EnergyKind, LawKind, StretchSpec, StudySpec};
use super::{Scene, SceneError};
use crate::stability::along_fibres_stability;
use crate::Muscle;
use rayon::prelude::*;

/// A validated stability study.
#[derive(Debug, Clone)]
pub struct StabilityStudy {
    /// Label.
    pub name: String,
    /// Stretches along the fibres, ascending.
    pub stretches: Vec<f64>,
    /// Whether to include the passive material.
    pub passive: bool,
    /// Active models: laws × couplings × damages.
    pub models: Vec<ModelChoice>,
    /// Sampled reference normals of the ellipticity check.
    pub normals: usize,
}

pub(super) fn resolve_stability(
    ctx: &Ctx,
    key: &str,
    s: &StudySpec,
    energy: EnergyKind,
    lambdas: Option<Vec<f64>>,
) -> Result<(StabilityStudy, StudySpec), SceneError> {
    let k = |name: &str| format!("{key}.{name}");
    only_keys(
        ctx,
        key,
        s,
        "stability",
        &["passive", "laws", "couplings", "normals"],
    )?;
    let stretch_default = StretchSpec::Range {
        from: 0.65,
        to: 1.6,
        step: 0.005,
        extra: vec![],
    };
    let stretches = match lambdas {
        Some(l) => l,
        None => super::resolve::stretches(ctx, &k("stretch"), &stretch_default)?,
    };
    let damage = damages(
        ctx,
        &k("damage"),
        s.damage.as_deref().unwrap_or(&[0.0, 0.5]),
    )?;
    let mut laws = s
        .laws
        .clone()
        .unwrap_or_else(|| vec![LawKind::Implicit, LawKind::Explicit, LawKind::Energy]);
    if s.laws.is_none() && energy != EnergyKind::GiantesioMusesti {
        laws.retain(|l| *l != LawKind::Explicit);
    }
    for (j, l) in laws.iter().enumerate() {
        if *l == LawKind::Explicit && energy != EnergyKind::GiantesioMusesti {
            return Err(ctx.err(
                format!("{key}.laws[{j}]"),
                "\"explicit\"",
                "eq. D:gamma is derived for the giantesio-musesti energy",
            ));
        }
    }
    let couplings = s
        .couplings
        .clone()
        .unwrap_or_else(|| vec![CouplingKind::Frozen, CouplingKind::Consistent]);
    if !laws.is_empty() && couplings.is_empty() {
        return Err(ctx.err(
            k("couplings"),
            "[]",
            "active laws need at least one coupling",
        ));
    }
    let normals = s.normals.unwrap_or(300);
    if !(1..=100_000).contains(&normals) {
        return Err(ctx.err(
            k("normals"),
            normals,
            "the number of sampled normals must be an integer in [1, 100000]",
        ));
    }
    let passive = s.passive.unwrap_or(true);
    let models = models(&laws, &couplings, &damage);
    if !passive && models.is_empty() {
        return Err(ctx.err(
            key,
            "(nothing to compute)",
            "a stability study needs passive = true or laws",
        ));
    }
    let name = s
        .name
        .clone()
        .unwrap_or_else(|| "stability along fibres".into());
    let mut r = s.clone();
    r.name = Some(name.clone());
    r.damage = Some(damage);
    r.laws = Some(laws);
    r.couplings = Some(couplings);
    r.passive = Some(passive);
    r.normals = Some(normals);
    if r.stretch.is_none() {
        r.stretch = Some(stretch_default);
    }
    Ok((
        StabilityStudy {
            name,
            stretches,
            passive,
            models,
            normals: normals as usize,
        },
        r,
    ))
}

/// One point of a stability curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StabilityPoint {
    /// Stretch λ [-].
    pub lambda: f64,
    /// Nominal stress P \[kPa\].
    pub stress: f64,
    /// dP/dλ \[kPa\].
    pub slope: f64,
    /// min a·Q(N)a over the sampled normals \[kPa\].
    pub least: f64,
    /// The same relative to the tangent's norm [-].
    pub relative: f64,
    /// Strongly elliptic (relative > −1e-12).
    pub elliptic: bool,
}

/// The stability of one model along the fibres.
#[derive(Debug, Clone, PartialEq)]
pub struct StabilityCurve {
    /// Study index.
    pub study: usize,
    /// `passive` or the law.
    pub law: &'static str,
    /// Coupling (active laws).
    pub coupling: Option<&'static str>,
    /// Damage (active laws).
    pub d: Option<f64>,
    /// Points that could be computed.
    pub points: Vec<StabilityPoint>,
}

impl StabilityCurve {
    /// `implicit, frozen` or `passive`.
    pub fn label(&self) -> String {
        match self.coupling {
            Some(c) => format!("{}, {c}", self.law),
            None => self.law.to_string(),
        }
    }

    /// Maximal runs of consecutive grid points where `flag` holds, as (first λ, last λ).
    pub fn intervals(&self, flag: impl Fn(&StabilityPoint) -> bool) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        let mut start: Option<f64> = None;
        let mut last = f64::NAN;
        for p in &self.points {
            match (flag(p), start) {
                (true, None) => start = Some(p.lambda),
                (false, Some(s)) => {
                    out.push((s, last));
                    start = None;
                }
                _ => {}
            }
            last = p.lambda;
        }
        if let Some(s) = start {
            out.push((s, last));
        }
        out
    }
}

/// Computes every curve of `study` (models in parallel); points that cannot be computed are
/// counted in a message, not silently dropped.
pub fn run_stability(
    scene: &Scene,
    index: usize,
    study: &StabilityStudy,
) -> Result<(Vec<StabilityCurve>, Vec<String>), String> {
    let mut models: Vec<Option<ModelChoice>> = Vec::new();
    if study.passive {
        models.push(None);
    }
    models.extend(study.models.iter().copied().map(Some));
    let computed: Vec<Result<(StabilityCurve, Option<String>), String>> = models
        .par_iter()
        .map(|m| {
            let muscle = match m {
                None => Muscle::passive(scene.material.clone()),
                Some(m) => scene.muscle(*m).map_err(|e| e.to_string())?,
            };
            let mut curve = StabilityCurve {
                study: index,
                law: m.map_or("passive", |m| law_name(m.law)),
                coupling: m.map(|m| coupling_name(m.coupling)),
                d: m.map(|m| m.damage),
                points: Vec::with_capacity(study.stretches.len()),
            };
            let mut failed = 0;
            let mut first = None;
            for &l in &study.stretches {
                match along_fibres_stability(&muscle, l, study.normals) {
                    Ok(p) => curve.points.push(StabilityPoint {
                        lambda: l,
                        stress: p.stress,
                        slope: p.slope,
                        least: p.ellipticity.least,
                        relative: p.ellipticity.relative,
                        elliptic: p.ellipticity.holds(),
                    }),
                    Err(e) => {
                        failed += 1;
                        first.get_or_insert((l, e.to_string()));
                    }
                }
            }
            let note = first.map(|(l, e)| {
                format!(
                    "{}{}: {failed} of {} stretches failed; first at lambda = {l}: {e}",
                    curve.label(),
                    curve.d.map_or(String::new(), |d| format!(", d = {d}")),
                    study.stretches.len()
                )
            });
            Ok((curve, note))
        })
        .collect();
    let mut curves = Vec::new();
    let mut notes = Vec::new();
    for c in computed {
        let (curve, note) = c?;
        curves.push(curve);
        notes.extend(note);
    }
    Ok((curves, notes))
}
