//! Stability studies (`kind = "stability"`): along the uniaxial path along the fibres, for each
//! law × coupling × d, where the curve softens (dP/dλ < 0) and where strong ellipticity is lost
//! ([`crate::stability::along_fibres_stability`]).

mod output;

use super::domain::{lines, Tally, Words};
use super::rules::{integer_in, something};
use super::spec::StretchSpec;
use super::spec::{optional_stretches, Defaults, ModelKeys};
use super::{Failure, Outcome, RunContext, StudyKind, StudyResult};
use crate::active::OutsideDomain;
use crate::app_error::{AppError, SpecError};
use crate::energy::Energy;
use crate::models::{CouplingKind, LawKind, ModelChoice, Models};
use crate::stability::along_fibres_stability;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// `[[study]] kind = "stability"` as written; `None` is a key left to its default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StabilitySpec {
    /// Label (default `stability along fibres`).
    pub name: Option<String>,
    /// Stretches along the fibres (default 0.65:0.005:1.60).
    pub stretch: Option<StretchSpec>,
    /// Damage values (default: `activation.damage`).
    pub damage: Option<Vec<f64>>,
    /// Include the passive material (default true).
    pub passive: Option<bool>,
    /// Laws (default all three; without the explicit law for energies it is not derived for).
    pub laws: Option<Vec<LawKind>>,
    /// Couplings (default both).
    pub couplings: Option<Vec<CouplingKind>>,
    /// Sampled reference normals of the strong-ellipticity check (default 300).
    pub normals: Option<i64>,
}

/// Keys a stability study does not take, and what to write instead.
pub const HINTS: &[(&str, &str)] = &[
    ("law", "it takes a list: laws = [...]"),
    ("coupling", "it takes a list: couplings = [...]"),
];

/// A validated stability study.
#[derive(Debug, Clone, PartialEq)]
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

/// Validates `spec`; returns the study and the spec with every default written out.
pub fn resolve(
    spec: &StabilitySpec,
    d: &Defaults,
) -> Result<(StabilityStudy, StabilitySpec), SpecError> {
    let stretch = spec.stretch.clone().unwrap_or(StretchSpec::Range {
        from: 0.65,
        to: 1.6,
        step: 0.005,
        extra: vec![],
    });
    let stretches = match optional_stretches(&spec.stretch)? {
        Some(l) => l,
        None => stretch.resolve("stretch")?,
    };
    // Left out: every law the scene's approach can have on this material.
    let every = d.supported_laws(d.approach);
    let set = ModelKeys::lists(&spec.laws, &spec.couplings, &spec.damage).resolve(
        d,
        &every,
        &CouplingKind::ALL,
    )?;
    let normals = spec.normals.unwrap_or(300);
    let normals = integer_in(
        "normals",
        normals,
        1..=100_000,
        "the number of sampled normals",
    )?;
    let passive = spec.passive.unwrap_or(true);
    let models = set.choices;
    something(
        "stability",
        passive || !models.is_empty(),
        "passive = true or laws",
    )?;
    let name = spec
        .name
        .clone()
        .unwrap_or_else(|| "stability along fibres".into());
    let resolved = StabilitySpec {
        name: Some(name.clone()),
        stretch: Some(stretch),
        damage: Some(set.damage),
        passive: Some(passive),
        laws: set.laws,
        couplings: set.couplings,
        normals: Some(normals as i64),
    };
    Ok((
        StabilityStudy {
            name,
            stretches,
            passive,
            models,
            normals,
        },
        resolved,
    ))
}

/// One point of a stability curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StabilityPoint {
    /// Stretch λ [-].
    pub lambda: f64,
    /// Nominal stress P \[kPa\].
    pub stress: f64,
    /// Cauchy stress along the fibres σ = λ P \[kPa\].
    pub cauchy: f64,
    /// dP/dλ \[kPa\].
    pub slope: f64,
    /// min a·Q(N)a over the sampled normals \[kPa\].
    pub least: f64,
    /// The same relative to the tangent's norm [-].
    pub relative: f64,
    /// Strongly elliptic (relative > −1e-12).
    pub elliptic: bool,
    /// Where the law at λ is outside its domain, if it is (the explicit law's:
    /// [`crate::active::Domain`]).
    pub outside: Option<OutsideDomain>,
}

/// The stability of one model along the fibres.
#[derive(Debug, Clone, PartialEq)]
pub struct StabilityCurve {
    /// The activation approach.
    pub approach: crate::active::Approach,
    /// The activation model; `None`: the passive material.
    pub model: Option<ModelChoice>,
    /// Points that could be computed.
    pub points: Vec<StabilityPoint>,
}

impl StabilityCurve {
    /// `implicit, frozen`, `active-stress` (an approach without a law) or `passive`.
    pub fn label(&self) -> String {
        match self.model.map(|m| (m, m.activation_law())) {
            Some((_, Some((law, coupling)))) => format!("{}, {}", law.name(), coupling.name()),
            Some((m, None)) => m.approach.name().to_string(),
            None => "passive".to_string(),
        }
    }

    /// Where its points left its law's domain (`None`: passive, or a law that holds
    /// everywhere).
    fn tally(&self) -> Option<Tally> {
        let mut tally = Tally::of(self.model.as_ref()?)?;
        for p in &self.points {
            tally.add(p.lambda, p.outside, None);
        }
        Some(tally)
    }

    /// The damage of the model (none for the passive material).
    pub fn damage(&self) -> Option<f64> {
        self.model.map(|m| m.damage)
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

impl StabilityStudy {
    /// One line for `check`.
    pub fn describe(&self) -> String {
        format!(
            "{}: {} model(s) × {} stretches, {} normals",
            self.name,
            self.models.len() + usize::from(self.passive),
            self.stretches.len(),
            self.normals
        )
    }

    /// Computes every curve (models in parallel); points that cannot be computed are counted in
    /// a failure, not silently dropped.
    pub fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
        ctx.progress.log(&self.describe());
        let mut choices: Vec<Option<ModelChoice>> = Vec::new();
        if self.passive {
            choices.push(None);
        }
        choices.extend(self.models.iter().copied().map(Some));
        let computed: Vec<Result<(StabilityCurve, Option<Failure>), AppError>> = choices
            .par_iter()
            .map(|m| {
                let muscle = match m {
                    None => models.passive(),
                    Some(m) => models.muscle(*m)?,
                };
                Ok(self.curve(&muscle, *m))
            })
            .collect();
        let mut curves = Vec::with_capacity(computed.len());
        let (mut failures, mut tallies) = (Vec::new(), Vec::new());
        for c in computed {
            let (curve, failure) = c.map_err(|e| e.within(&self.name))?;
            tallies.extend(
                curve
                    .tally()
                    .zip(curve.model)
                    .map(|(t, m)| (models.label(&m), t)),
            );
            curves.push(curve);
            failures.extend(failure);
        }
        let words = Words {
            points: "points",
            x: "λ",
            unit: "",
            target: "",
            file: output::FILE,
        };
        let points = curves.iter().map(|c| c.points.len()).sum();
        Ok(Outcome {
            name: self.name.clone(),
            kind: StudyKind::Stability,
            models: curves.len(),
            points,
            requested: choices.len() * self.stretches.len(),
            elapsed: Default::default(),
            details: vec![format!(
                "{} stretches in [{}, {}] along the fibres, {} sampled normals",
                self.stretches.len(),
                self.stretches.first().copied().unwrap_or(f64::NAN),
                self.stretches.last().copied().unwrap_or(f64::NAN),
                self.normals
            )],
            failures,
            left_domain: lines(tallies, &words),
            result: StudyResult::Stability(curves),
        })
    }

    fn curve(
        &self,
        muscle: &crate::Muscle<Energy>,
        model: Option<ModelChoice>,
    ) -> (StabilityCurve, Option<Failure>) {
        let mut curve = StabilityCurve {
            // The passive material has none: its cells name no approach.
            approach: model.map(|m| m.approach).unwrap_or_default(),
            model,
            points: Vec::with_capacity(self.stretches.len()),
        };
        let mut failed = 0;
        let mut first = None;
        for &l in &self.stretches {
            match along_fibres_stability(muscle, l, self.normals) {
                Ok(p) => curve.points.push(StabilityPoint {
                    lambda: l,
                    stress: p.stress,
                    cauchy: p.cauchy,
                    slope: p.slope,
                    least: p.ellipticity.least,
                    relative: p.ellipticity.relative,
                    elliptic: p.ellipticity.holds(),
                    outside: muscle.outside_domain(l),
                }),
                Err(e) => {
                    failed += 1;
                    first.get_or_insert((l, e.to_string()));
                }
            }
        }
        let failure = first.map(|(l, e)| Failure {
            model: "stability".into(),
            message: format!(
                "{}{}: {failed} of {} stretches failed; first at lambda = {}: {e}",
                curve.label(),
                curve
                    .damage()
                    .map_or(String::new(), |d| format!(", d = {d}")),
                self.stretches.len(),
                crate::text::shortest(l)
            ),
        });
        (curve, failure)
    }
}
