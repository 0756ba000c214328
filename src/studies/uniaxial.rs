//! Uniaxial studies (`kind = "uniaxial"`): homogeneous tension along or across the fibres
//! ([`crate::uniaxial`]) of the material's passive curve, other passive energies, constant
//! activations and every law × coupling × damage, the curves in parallel.

mod figures;

use super::domain::{lines, Tally, Words};
use super::rules::{each, something};
use super::spec::{required_stretches, Defaults, ModelKeys, StretchSpec};
use super::{Failure, Outcome, RunContext, StudyKind, StudyResult};
use crate::active::drive::Drive;
use crate::active::{Approach, OutsideDomain};
use crate::app_error::{AppError, SpecError};
use crate::energy::Energy;
use crate::models::{CouplingKind, EnergySpec, LawKind, ModelChoice, Models};
use crate::uniaxial::Direction;
use crate::volumetric::Volumetric;
use crate::{Muscle, StrainEnergy};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// `[[study]] kind = "uniaxial"` as written; `None` is a key left to its default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UniaxialSpec {
    /// Label in logs and the report (default: `uniaxial along fibres` or `… across …`).
    pub name: Option<String>,
    /// Stretches λ (required).
    pub stretch: Option<StretchSpec>,
    /// Damage values of the active models (default: `activation.damage`).
    pub damage: Option<Vec<f64>>,
    /// `along` (default) or `across` the fibres.
    pub direction: Option<Direction>,
    /// Include the passive curve of the material (default true).
    pub passive: Option<bool>,
    /// Extra passive energies (default none).
    pub compare: Option<Vec<EnergySpec>>,
    /// Activation laws (default `[activation.law]`; `[]` for none).
    pub laws: Option<Vec<LawKind>>,
    /// Couplings (default `[activation.coupling]`).
    pub couplings: Option<Vec<CouplingKind>>,
    /// Constant activations γ ∈ [0, 1) (default none).
    pub constant_gamma: Option<Vec<f64>>,
}

/// Keys a uniaxial study does not take, and what to write instead.
pub const HINTS: &[(&str, &str)] = &[
    ("law", "it takes a list: laws = [...]"),
    ("coupling", "it takes a list: couplings = [...]"),
];

/// A validated uniaxial study.
#[derive(Debug, Clone, PartialEq)]
pub struct UniaxialStudy {
    /// Label.
    pub name: String,
    /// Loading direction relative to the fibres.
    pub direction: Direction,
    /// Stretches, ascending, without duplicates.
    pub stretches: Vec<f64>,
    /// Whether to include the material's passive curve.
    pub passive: bool,
    /// Extra passive energies.
    pub compare: Vec<Energy>,
    /// Active models: laws × couplings × damages of the scene's approach.
    pub models: Vec<ModelChoice>,
    /// Constant activations.
    pub constant_gamma: Vec<f64>,
    /// The approach of the constant activations (the scene's).
    pub approach: Approach,
}

/// Validates `spec` against the scene's defaults; returns the study and the spec with every
/// default written out.
pub fn resolve(
    spec: &UniaxialSpec,
    d: &Defaults,
) -> Result<(UniaxialStudy, UniaxialSpec), SpecError> {
    let stretches = required_stretches(&spec.stretch)?;
    let direction = spec.direction.unwrap_or_default();
    let set = ModelKeys::lists(&spec.laws, &spec.couplings, &spec.damage).of_scene(d)?;
    let mut compare = Vec::new();
    for (j, c) in spec.compare.iter().flatten().enumerate() {
        compare.push(c.build().map_err(|e| e.within(&format!("compare[{j}]")))?);
    }
    let constant_gamma = spec.constant_gamma.clone().unwrap_or_default();
    if let (false, None) = (constant_gamma.is_empty(), d.approach.variable()) {
        return Err(SpecError::new(
            "constant_gamma",
            crate::studies::spec::fmt_list(&constant_gamma),
            format!(
                "a constant activation holds the approach's activation variable; approach = {:?} has none: {}",
                d.approach.name(),
                d.approach.no_law()
            ),
        ));
    }
    each(
        "constant_gamma",
        &constant_gamma,
        |g| crate::active::ConstantLaw::new(*g).is_ok(),
        "activation gamma must lie in [0, 1) (γ = 1 is infinite contraction)",
    )?;
    let models = set.choices;
    let passive = spec.passive.unwrap_or(true);
    something(
        "uniaxial",
        passive || !compare.is_empty() || !models.is_empty() || !constant_gamma.is_empty(),
        "passive = true, compare, laws or constant_gamma",
    )?;
    let name = spec
        .name
        .clone()
        .unwrap_or_else(|| format!("uniaxial {} fibres", direction.name()));
    let resolved = UniaxialSpec {
        name: Some(name.clone()),
        stretch: spec.stretch.clone(),
        damage: Some(set.damage),
        direction: Some(direction),
        passive: Some(passive),
        compare: Some(compare.iter().map(EnergySpec::written).collect()),
        laws: set.laws,
        couplings: set.couplings,
        constant_gamma: Some(constant_gamma.clone()),
    };
    Ok((
        UniaxialStudy {
            name,
            direction,
            stretches,
            passive,
            compare,
            models,
            constant_gamma,
            approach: d.approach,
        },
        resolved,
    ))
}

/// What a curve shows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CurveModel {
    /// A passive energy (γ ≡ 0).
    Passive,
    /// The material with constant activation γ.
    Constant(f64),
    /// An activation model.
    Active(ModelChoice),
}

/// One point of a uniaxial curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePoint {
    /// Stretch λ [-].
    pub lambda: f64,
    /// Activation γ [-].
    pub gamma: f64,
    /// Nominal stress along the stretch \[kPa\].
    pub stress: f64,
    /// Cauchy stress along the stretch σ = J⁻¹ P Fᵀ \[kPa\] (= λ P: incompressible, lateral
    /// faces traction free).
    pub cauchy: f64,
    /// Passive stress of the material P_pas(λ) \[kPa\] (active curves along the fibres).
    pub passive: Option<f64>,
    /// Target active stress (1 − d) P_act(λ) \[kPa\] (the same curves).
    pub active_target: Option<f64>,
    /// Volume ratio J = λ λ₂ λ₃ [-] of a nearly incompressible scene (`None`: J = 1 exactly).
    pub volume: Option<f64>,
    /// Where the law at the point's fibre stretch is outside its domain, if it is (the explicit
    /// law's: [`crate::active::Domain`]).
    pub outside: Option<OutsideDomain>,
}

/// One computed curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// What it shows.
    pub model: CurveModel,
    /// The energy's name.
    pub energy: String,
    /// The points that could be computed, in stretch order.
    pub points: Vec<CurvePoint>,
}

/// The curves of a uniaxial study.
#[derive(Debug, Clone, PartialEq)]
pub struct UniaxialResult {
    /// Loading direction relative to the fibres.
    pub direction: Direction,
    /// The activation approach of the active and constant-activation curves.
    pub approach: crate::active::Approach,
    /// Curves: passive material, compared energies, constant γ, active models, in that order.
    pub curves: Vec<Curve>,
}

impl UniaxialStudy {
    /// The points of `muscle` at the study's stretches, with the (P_pas, (1 − d) P_act) of
    /// `target` where it has them; stretches that cannot be computed are counted in a message.
    fn points(
        &self,
        volumetric: Option<&Volumetric>,
        muscle: &Muscle<Energy>,
        target: impl Fn(f64) -> crate::Result<Option<(f64, f64)>>,
        ctx: &RunContext,
    ) -> (Vec<CurvePoint>, Option<String>) {
        let mut points = Vec::with_capacity(self.stretches.len());
        let mut failed = 0usize;
        let mut first: Option<(f64, String)> = None;
        for &lambda in &self.stretches {
            ctx.progress.advance(1);
            let point = crate::uniaxial::point(muscle, volumetric, self.direction, lambda)
                .and_then(|p| {
                    let extra = target(lambda)?;
                    Ok(CurvePoint {
                        lambda,
                        gamma: p.gamma,
                        stress: p.stress,
                        cauchy: p.cauchy,
                        passive: extra.map(|e| e.0),
                        active_target: extra.map(|e| e.1),
                        volume: volumetric.map(|_| lambda * p.lateral[0] * p.lateral[1]),
                        outside: muscle.outside_domain(p.fibre_stretch),
                    })
                });
            match point {
                Ok(p) => points.push(p),
                Err(e) => {
                    failed += 1;
                    first.get_or_insert((lambda, e.to_string()));
                }
            }
        }
        let message = first.map(|(lambda, why)| {
            format!(
                "{failed} of {} stretches failed; first at lambda = {}: {why}",
                self.stretches.len(),
                crate::text::shortest(lambda)
            )
        });
        (points, message)
    }

    /// One line for `check`.
    pub fn describe(&self) -> String {
        format!(
            "{}: {} stretches, {} passive curve(s), {} constant-γ curve(s), {} active model(s)",
            self.name,
            self.stretches.len(),
            usize::from(self.passive) + self.compare.len(),
            self.constant_gamma.len(),
            self.models.len()
        )
    }

    /// Computes every curve (in parallel). A stretch that cannot be computed is counted in a
    /// failure, not dropped silently; a model that cannot be built is an error.
    pub fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
        let mut curves: Vec<(CurveModel, &Energy)> = Vec::new();
        if self.passive {
            curves.push((CurveModel::Passive, &models.energy));
        }
        curves.extend(self.compare.iter().map(|e| (CurveModel::Passive, e)));
        curves.extend(
            self.constant_gamma
                .iter()
                .map(|&g| (CurveModel::Constant(g), &models.energy)),
        );
        curves.extend(
            self.models
                .iter()
                .map(|&m| (CurveModel::Active(m), &models.energy)),
        );
        for (model, e) in &curves {
            ctx.progress
                .log(&format!("{}: {}", self.name, label(models, model, e)));
        }
        ctx.progress
            .start(&self.name, curves.len() * self.stretches.len());
        let computed: Vec<Result<CurveOutcome, AppError>> = curves
            .par_iter()
            .map(|&(model, energy)| self.curve(models, model, energy, ctx))
            .collect();
        ctx.progress.finish();
        let mut result = UniaxialResult {
            direction: self.direction,
            approach: self.approach,
            curves: Vec::with_capacity(computed.len()),
        };
        let (mut failures, mut tallies) = (Vec::new(), Vec::new());
        for c in computed {
            let (curve, failure, tally) = c?;
            result.curves.push(curve);
            failures.extend(failure);
            tallies.extend(tally);
        }
        let words = Words {
            points: "points",
            x: "λ",
            unit: "",
            target: "P_pas + (1 − d) P_act",
            file: super::table::CURVES_FILE,
        };
        let points = result.curves.iter().map(|c| c.points.len()).sum();
        let mut details = vec![format!(
            "{} curves × {} stretches in [{}, {}], {} the fibres",
            curves.len(),
            self.stretches.len(),
            self.stretches.first().copied().unwrap_or(f64::NAN),
            self.stretches.last().copied().unwrap_or(f64::NAN),
            self.direction.name()
        )];
        details.extend(extreme_activation(&result));
        Ok(Outcome {
            name: self.name.clone(),
            kind: StudyKind::Uniaxial,
            models: curves.len(),
            points,
            requested: curves.len() * self.stretches.len(),
            elapsed: Default::default(),
            details,
            failures,
            left_domain: lines(tallies, &words),
            result: StudyResult::Uniaxial(result),
        })
    }

    /// The curve of `model` on `energy`, the failure of the stretches it could not compute and
    /// the points outside its law's domain.
    fn curve(
        &self,
        models: &Models,
        model: CurveModel,
        energy: &Energy,
        ctx: &RunContext,
    ) -> Result<CurveOutcome, AppError> {
        let muscle = match model {
            CurveModel::Passive => Muscle::passive(energy.clone()),
            CurveModel::Constant(g) => models
                .constant(self.approach, g)
                .map_err(|e| AppError::from(e).within(&self.name))?,
            CurveModel::Active(m) => models.muscle(m).map_err(|e| {
                AppError::from(e).within(format!("{}: {}", self.name, models.label(&m)))
            })?,
        };
        // A compared energy gets the scene's volumetric form with its own reference stress, so
        // that it too is stress free at F = I (the material's linear term is the material's).
        let volumetric = match (model, models.volumetric.as_ref()) {
            (CurveModel::Passive, Some(v)) => {
                let own = crate::uniaxial::reference_stress(energy)
                    .and_then(|s0| Volumetric::new(v.form(), s0))
                    .map_err(|e| AppError::from(e).within(&self.name))?;
                Some(own)
            }
            _ => models.volumetric,
        };
        let passive = models.passive();
        // Along the fibres an active curve is shown with its target P_pas + (1 − d) P_act.
        let target = |lambda: f64| -> crate::Result<Option<(f64, f64)>> {
            Ok(match (model, self.direction) {
                (CurveModel::Active(m), Direction::Along) => Some((
                    models.uniaxial(&passive, self.direction, lambda)?.stress,
                    Drive::from(m.damage).target(&models.curve, lambda),
                )),
                _ => None,
            })
        };
        let (points, failure) = self.points(volumetric.as_ref(), &muscle, target, ctx);
        let failure = failure.map(|message| Failure {
            model: match model {
                CurveModel::Constant(g) => format!("constant gamma = {g}"),
                _ => label(models, &model, energy),
            },
            message,
        });
        let tally = match model {
            CurveModel::Active(m) => tally(&m, &points).map(|t| (label(models, &model, energy), t)),
            _ => None,
        };
        let curve = Curve {
            model,
            energy: energy.name().to_string(),
            points,
        };
        Ok((curve, failure, tally))
    }
}

/// A computed curve, the failure of the stretches it could not compute, and, for a law with a
/// domain, the tally of its points (with the model's label).
type CurveOutcome = (Curve, Option<Failure>, Option<(String, Tally)>);

/// Where the `points` of model `m` are outside its law's domain, with their distance from the
/// target P_pas + (1 − d) P_act along the fibres (`None`: a law that holds everywhere).
fn tally(m: &ModelChoice, points: &[CurvePoint]) -> Option<Tally> {
    let mut tally = Tally::of(m)?;
    for p in points {
        let distance = p
            .passive
            .zip(p.active_target)
            .map(|(pas, act)| p.stress - (pas + act));
        tally.add(p.lambda, p.outside, distance);
    }
    Some(tally)
}

/// A curve in words: `giantesio-musesti, passive`, `…, constant gamma = 0.2`, or the model.
fn label(models: &Models, model: &CurveModel, energy: &Energy) -> String {
    match model {
        CurveModel::Passive => format!("{}, passive", energy.name()),
        CurveModel::Constant(g) => format!("{}, constant gamma = {g}", models.energy.name()),
        CurveModel::Active(m) => models.label(m),
    }
}

/// γ above which a note says how extreme the activation is: F_a = I − γ m⊗m shortens the
/// fibre to 1 − γ of its length in the intermediate configuration (the chapter's γ stays below
/// about 0.4).
const EXTREME_GAMMA: f64 = 0.9;

/// A note on the largest γ of `result`, if it exceeds [`EXTREME_GAMMA`].
fn extreme_activation(result: &UniaxialResult) -> Option<String> {
    // Activation models only: a constant γ is the user's own choice.
    let (gamma, lambda, model) = result
        .curves
        .iter()
        .filter_map(|c| match c.model {
            CurveModel::Active(m) => Some((m, c)),
            _ => None,
        })
        .flat_map(|(m, c)| c.points.iter().map(move |p| (p.gamma, p.lambda, m)))
        .filter(|(g, _, _)| g.is_finite())
        .max_by(|a, b| a.0.total_cmp(&b.0))?;
    (gamma > EXTREME_GAMMA).then(|| {
        format!(
            "γ reaches {gamma:.3} ({} law, {} coupling, d = {}, λ = {lambda}): F_a = I − γ m⊗m shortens the fibre to {:.1} % of its length, nearly singular; the active curve may be too strong for this energy",
            model.law.name(),
            model.coupling.name(),
            model.damage,
            100.0 * (1.0 - gamma)
        )
    })
}
