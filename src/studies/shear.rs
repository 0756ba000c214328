//! Simple-shear studies (`kind = "shear"`): homogeneous simple shear F = I + k e₁⊗e₂ of an
//! incompressible block, the fibre in the shear plane at an angle θ to e₁, the faces normal to
//! e₃ traction free (σ₃₃ = 0 gives the pressure; [`crate::homogeneous`]). Every approach × law ×
//! coupling × damage the scene asks for, all calibrated to the same uniaxial target along the
//! fibres (P_pas + (1 − d) P_act): they agree there and differ here. With the fibre along the
//! shear direction (θ = 0) the fibre stretch stays 1, so active stress adds only
//! σ₁₁ = T(1) while active strain changes the shear stiffness itself (Giantesio, Musesti &
//! Riccobelli 2019).

mod output;

use super::domain::{in_domain, lines, Tally, Words, IN_DOMAIN};
use super::rules::{each, non_empty, once, required};
use super::spec::{approach_models, ApproachModel, Defaults, ModelKeys, StretchSpec};
use super::table::{every_row, Table};
use super::{Failure, Outcome, RunContext, StudyKind, StudyResult};
use crate::active::{Approach, OutsideDomain};
use crate::app_error::{AppError, SpecError};
use crate::homogeneous::simple_shear;
use crate::models::{CouplingKind, LawKind, Models};
use crate::StrainEnergy;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// `[[study]] kind = "shear"` as written; `None` is a key left to its default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShearSpec {
    /// Label (default `simple shear`).
    pub name: Option<String>,
    /// Amounts of shear k [-] (required): a list or `{ from, to, step }`.
    pub shear: Option<StretchSpec>,
    /// Fibre angles θ to the shear direction e₁, in degrees (default `[0, 45, 90]`).
    pub fibre_angles: Option<Vec<f64>>,
    /// Approaches (default `["active-strain", "active-stress"]`).
    pub approaches: Option<Vec<Approach>>,
    /// Activation laws of the approaches that have one (default `[activation.law]`).
    pub laws: Option<Vec<LawKind>>,
    /// Couplings (default `[activation.coupling]`).
    pub couplings: Option<Vec<CouplingKind>>,
    /// Damage values (default `activation.damage`).
    pub damage: Option<Vec<f64>>,
    /// Include the passive material (default true).
    pub passive: Option<bool>,
}

/// Keys a shear study does not take, and what to write instead.
pub const HINTS: &[(&str, &str)] = &[
    (
        "stretch",
        "a shear study takes amounts of shear: shear = [...]",
    ),
    ("approach", "it takes a list: approaches = [...]"),
    ("law", "it takes a list: laws = [...]"),
    ("coupling", "it takes a list: couplings = [...]"),
];

/// A validated shear study.
#[derive(Debug, Clone, PartialEq)]
pub struct ShearStudy {
    /// Label.
    pub name: String,
    /// Amounts of shear, ascending.
    pub shear: Vec<f64>,
    /// Fibre angles \[degrees\].
    pub angles: Vec<f64>,
    /// The models, passive first if asked.
    pub models: Vec<ApproachModel>,
}

/// Validates `spec`; returns the study and the spec with every default written out.
pub fn resolve(spec: &ShearSpec, d: &Defaults) -> Result<(ShearStudy, ShearSpec), SpecError> {
    let shear = required(
        spec.shear.as_ref(),
        "shear",
        "give the amounts of shear k: shear = { from = 0, to = 0.5, step = 0.05 } or a list",
    )?
    .resolve_amounts("shear")?;
    let angles = spec
        .fibre_angles
        .clone()
        .unwrap_or_else(|| vec![0.0, 45.0, 90.0]);
    fibre_angles(&angles)?;
    if d.models.volumetric.is_some() {
        return Err(SpecError::new(
            "kind",
            "\"shear\"",
            "simple shear is computed exactly incompressible (σ₃₃ = 0 by the pressure); the scene's [incompressibility] is nearly incompressible",
        ));
    }
    let passive = spec.passive.unwrap_or(true);
    let keys = ModelKeys {
        approaches: spec.approaches.as_deref(),
        ..ModelKeys::lists(&spec.laws, &spec.couplings, &spec.damage)
    };
    let defaults = [Approach::ActiveStrain, Approach::ActiveStress];
    let (models, set) = approach_models(keys, passive, d, &defaults, "shear")?;
    let name = spec.name.clone().unwrap_or_else(|| "simple shear".into());
    let resolved = ShearSpec {
        name: Some(name.clone()),
        shear: spec.shear.clone(),
        fibre_angles: Some(angles.clone()),
        approaches: Some(set.approaches),
        laws: set.laws,
        couplings: set.couplings,
        damage: Some(set.damage),
        passive: Some(passive),
    };
    Ok((
        ShearStudy {
            name,
            shear,
            angles,
            models,
        },
        resolved,
    ))
}

/// The fibre angles θ: at least one, each finite and each one fibre. θ and θ + 180° give the
/// same fibre tensor M = a⊗a: the same curve twice.
fn fibre_angles(angles: &[f64]) -> Result<(), SpecError> {
    let key = "fibre_angles";
    non_empty(key, angles, "give at least one fibre angle in degrees")?;
    each(key, angles, |a| a.is_finite(), "must be finite (degrees)")?;
    let same = |a: &f64, b: &f64| {
        let r = (a - b).rem_euclid(180.0);
        r.min(180.0 - r) < 1e-9
    };
    once(key, angles, same, |i| {
        format!("fibre_angles[{i}] = {} is the same fibre (θ and θ + 180° give the same M = a⊗a): each angle is one curve per model, give it once", angles[i])
    })
}

/// One state of simple shear.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShearPoint {
    /// Amount of shear k [-].
    pub k: f64,
    /// Activation γ (ω for the structural approach; 0 for active stress) [-].
    pub gamma: f64,
    /// Fibre stretch λ_f [-].
    pub fibre_stretch: f64,
    /// Cauchy stresses σ₁₂, σ₁₁, σ₂₂, σ₃₃ \[kPa\].
    pub sigma: [f64; 4],
    /// Where the law at λ_f is outside its domain, if it is (the explicit law's:
    /// [`crate::active::Domain`]).
    pub outside: Option<OutsideDomain>,
}

/// One curve: a model at one fibre angle.
#[derive(Debug, Clone, PartialEq)]
pub struct ShearCurve {
    /// The model.
    pub model: ApproachModel,
    /// Fibre angle θ \[degrees\].
    pub angle: f64,
    /// The amounts of shear that could be computed.
    pub points: Vec<ShearPoint>,
}

impl ShearCurve {
    /// Where its points left its law's domain (`None`: passive, or a law that holds
    /// everywhere).
    fn tally(&self) -> Option<Tally> {
        let mut tally = Tally::of(self.model.model.as_ref()?)?;
        for p in &self.points {
            tally.add(p.k, p.outside, None);
        }
        Some(tally)
    }
}

/// What a shear study computed.
#[derive(Debug, Clone, PartialEq)]
pub struct ShearResult {
    /// The energy's name.
    pub energy: String,
    /// One curve per model and fibre angle.
    pub curves: Vec<ShearCurve>,
}

impl ShearStudy {
    /// One line for `check`.
    pub fn describe(&self) -> String {
        format!(
            "{}: {} amounts of shear in [{}, {}], fibre angles {}°, {} model(s)",
            self.name,
            self.shear.len(),
            self.shear.first().copied().unwrap_or(f64::NAN),
            self.shear.last().copied().unwrap_or(f64::NAN),
            super::outputs::list(&self.angles),
            self.models.len()
        )
    }

    /// The study in words, and, for a scene whose `material.fibre` is not e₁, that simple shear
    /// sets its own fibres.
    fn details(&self, models: &Models) -> Vec<String> {
        let mut details = vec![self.describe()];
        if models.fibre != [1.0, 0.0, 0.0] {
            let shown: Vec<String> = models.fibre.iter().map(|x| format!("{x:.4}")).collect();
            details.push(format!(
                "material.fibre = [{}] does not apply: simple shear sets the fibre in the shear plane at the fibre angles to the shear direction e₁",
                shown.join(", ")
            ));
        }
        details
    }

    /// Every curve, in parallel; a state that cannot be computed is counted in a failure.
    pub fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
        ctx.progress.log(&self.describe());
        let jobs: Vec<(&ApproachModel, f64)> = self
            .models
            .iter()
            .flat_map(|m| self.angles.iter().map(move |&a| (m, a)))
            .collect();
        ctx.progress
            .start(&self.name, jobs.len() * self.shear.len());
        let computed: Vec<Result<(ShearCurve, Option<Failure>), AppError>> = jobs
            .par_iter()
            .map(|&(m, angle)| self.curve(models, m, angle, ctx))
            .collect();
        ctx.progress.finish();
        let mut curves = Vec::with_capacity(computed.len());
        let (mut failures, mut tallies) = (Vec::new(), Vec::new());
        for c in computed {
            let (curve, failure) = c?;
            tallies.extend(curve.tally().map(|t| {
                let label = format!("{}, θ = {}°", curve.model.label(models), curve.angle);
                (label, t)
            }));
            curves.push(curve);
            failures.extend(failure);
        }
        let words = Words {
            points: "points",
            x: "k",
            unit: "",
            target: "",
            file: output::FILE,
        };
        let points = curves.iter().map(|c| c.points.len()).sum();
        Ok(Outcome {
            name: self.name.clone(),
            kind: StudyKind::Shear,
            models: curves.len(),
            points,
            requested: jobs.len() * self.shear.len(),
            elapsed: Default::default(),
            details: self.details(models),
            failures,
            left_domain: lines(tallies, &words),
            result: StudyResult::Shear(ShearResult {
                energy: models.energy.name().to_string(),
                curves,
            }),
        })
    }

    fn curve(
        &self,
        models: &Models,
        m: &ApproachModel,
        angle: f64,
        ctx: &RunContext,
    ) -> Result<(ShearCurve, Option<Failure>), AppError> {
        let label = m.label(models);
        let muscle = m.muscle(models, &self.name)?;
        let mut points = Vec::with_capacity(self.shear.len());
        let mut first: Option<(f64, String)> = None;
        let mut failed = 0usize;
        for &k in &self.shear {
            ctx.progress.advance(1);
            match simple_shear(&muscle, None, k, angle) {
                Ok(s) => points.push(ShearPoint {
                    k,
                    gamma: s.gamma,
                    fibre_stretch: s.fibre_stretch,
                    sigma: [
                        s.cauchy[(0, 1)],
                        s.cauchy[(0, 0)],
                        s.cauchy[(1, 1)],
                        s.cauchy[(2, 2)],
                    ],
                    outside: muscle.outside_domain(s.fibre_stretch),
                }),
                Err(e) => {
                    failed += 1;
                    first.get_or_insert((k, e.to_string()));
                }
            }
        }
        let failure = first.map(|(k, why)| Failure {
            model: format!("{label}, θ = {angle}°"),
            message: format!(
                "{failed} of {} amounts of shear failed; first at k = {}: {why}",
                self.shear.len(),
                crate::text::shortest(k)
            ),
        });
        Ok((
            ShearCurve {
                model: m.clone(),
                angle,
                points,
            },
            failure,
        ))
    }
}

impl ShearResult {
    /// The study's table (`shear.csv` and Python's table): one row per curve point.
    pub fn table(&self, study: &str) -> Table {
        let rows: Vec<(&ShearCurve, &ShearPoint)> = self
            .curves
            .iter()
            .flat_map(|c| c.points.iter().map(move |p| (c, p)))
            .collect();
        let cell = |i: usize| rows.iter().map(move |(c, _)| c.model.cells()[i].clone());
        let at = |f: fn(&ShearPoint) -> f64| rows.iter().map(move |(_, p)| Some(f(p)));
        let sigma = |i: usize| rows.iter().map(move |(_, p)| Some(p.sigma[i]));
        let damage = rows.iter().map(|(c, _)| c.model.model.map(|m| m.damage));
        let angle = rows.iter().map(|(c, _)| Some(c.angle));
        let domain = rows
            .iter()
            .map(|(c, p)| in_domain(c.model.model.as_ref(), p.outside));
        Table::default()
            .text("study", "the study's name", every_row(study, rows.len()))
            .text(
                "energy",
                "the passive energy",
                every_row(&self.energy, rows.len()),
            )
            .text("approach", "activation approach (empty: passive)", cell(0))
            .text(
                "law",
                "activation law (passive for the passive material)",
                cell(1),
            )
            .text("coupling", "coupling", cell(2))
            .number("d", "-", "damage", damage)
            .number(
                "fibre_angle",
                "degree",
                "fibre angle θ to the shear direction e₁",
                angle,
            )
            .number(
                "shear",
                "-",
                "amount of shear k, F = I + k e₁⊗e₂",
                at(|p| p.k),
            )
            .number(
                "gamma",
                "-",
                "activation γ (ω for the structural approach)",
                at(|p| p.gamma),
            )
            .number(
                "fibre_stretch",
                "-",
                "fibre stretch λ_f = |F m|",
                at(|p| p.fibre_stretch),
            )
            .number("sigma_12", "kPa", "Cauchy shear stress σ₁₂", sigma(0))
            .number("sigma_11", "kPa", "Cauchy normal stress σ₁₁", sigma(1))
            .number("sigma_22", "kPa", "Cauchy normal stress σ₂₂", sigma(2))
            .number(
                "sigma_33",
                "kPa",
                "Cauchy normal stress σ₃₃ (0: traction free)",
                sigma(3),
            )
            .boolean("in_domain", IN_DOMAIN, domain)
    }
}
