//! Planar biaxial studies (`kind = "biaxial"`): F = diag(λ₁, λ₂, λ₃), λ₁ along the fibres and
//! λ₂ across them, λ₃ from incompressibility (σ₃₃ = 0 by the pressure) or, with the scene's
//! `[incompressibility]`, from the volumetric energy (P₃₃ = 0; [`crate::homogeneous`]). The load
//! paths of soft-tissue labs: equibiaxial (λ₂ = λ₁), strip biaxial (λ₂ = 1), or a list of
//! (λ₁, λ₂) pairs; nominal and Cauchy stresses in both directions for every approach and law.

mod output;

use super::domain::{in_domain, lines, Tally, Words, IN_DOMAIN};
use super::rules::{non_empty, required};
use super::spec::{approach_models, ApproachModel, Defaults, ModelKeys, StretchSpec};
use super::table::{every_row, Table};
use super::{Failure, Outcome, RunContext, StudyKind, StudyResult};
use crate::active::{Approach, OutsideDomain};
use crate::app_error::{AppError, SpecError};
use crate::homogeneous::planar_biaxial;
use crate::models::{CouplingKind, LawKind, Models};
use crate::text::shortest;
use crate::StrainEnergy;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The load path (`path = "equibiaxial" | "strip"`; a list of pairs is `pairs = [...]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BiaxialPath {
    /// λ₂ = λ₁.
    Equibiaxial,
    /// λ₂ = 1 (strip biaxial: the lateral stretch held).
    Strip,
}

/// `[[study]] kind = "biaxial"` as written; `None` is a key left to its default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BiaxialSpec {
    /// Label (default `planar biaxial`).
    pub name: Option<String>,
    /// `equibiaxial` (default) or `strip`, with `stretch` (λ₁).
    pub path: Option<BiaxialPath>,
    /// Stretches λ₁ along the fibres of the path.
    pub stretch: Option<StretchSpec>,
    /// (λ₁, λ₂) pairs, instead of `path` and `stretch`.
    #[serde(default, deserialize_with = "crate::fixed_length::exact")]
    pub pairs: Option<Vec<[f64; 2]>>,
    /// Approaches (default `[activation.approach]`).
    pub approaches: Option<Vec<Approach>>,
    /// Activation laws (default `[activation.law]`).
    pub laws: Option<Vec<LawKind>>,
    /// Couplings (default `[activation.coupling]`).
    pub couplings: Option<Vec<CouplingKind>>,
    /// Damage values (default `activation.damage`).
    pub damage: Option<Vec<f64>>,
    /// Include the passive material (default true).
    pub passive: Option<bool>,
}

/// Keys a biaxial study does not take, and what to write instead.
pub const HINTS: &[(&str, &str)] = &[
    ("approach", "it takes a list: approaches = [...]"),
    ("law", "it takes a list: laws = [...]"),
    ("coupling", "it takes a list: couplings = [...]"),
];

/// A validated biaxial study.
#[derive(Debug, Clone, PartialEq)]
pub struct BiaxialStudy {
    /// Label.
    pub name: String,
    /// `equibiaxial`, `strip` or `pairs`.
    pub path: &'static str,
    /// (λ₁, λ₂) in order.
    pub pairs: Vec<(f64, f64)>,
    /// The models, passive first if asked.
    pub models: Vec<ApproachModel>,
}

/// Validates `spec`; returns the study and the spec with every default written out.
pub fn resolve(spec: &BiaxialSpec, d: &Defaults) -> Result<(BiaxialStudy, BiaxialSpec), SpecError> {
    let (path, pairs) = match (&spec.pairs, spec.path, &spec.stretch) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            return Err(SpecError::new(
                "pairs",
                "(given)",
                "give either pairs = [[λ₁, λ₂], ...] or path and stretch, not both",
            ))
        }
        (Some(pairs), None, None) => {
            non_empty("pairs", pairs, "give at least one [λ₁, λ₂] pair")?;
            for (j, p) in pairs.iter().enumerate() {
                if !p.iter().all(|x| x.is_finite() && *x > 0.0) {
                    return Err(SpecError::new(
                        format!("pairs[{j}]"),
                        format!("[{}, {}]", shortest(p[0]), shortest(p[1])),
                        "stretches must be finite and > 0",
                    ));
                }
            }
            ("pairs", pairs.iter().map(|p| (p[0], p[1])).collect())
        }
        (None, path, stretch) => {
            let path = path.unwrap_or(BiaxialPath::Equibiaxial);
            let l1 = required(
                stretch.as_ref(),
                "stretch",
                "give the stretches λ₁ along the fibres (or pairs = [[λ₁, λ₂], ...])",
            )?
            .resolve("stretch")?;
            match path {
                BiaxialPath::Equibiaxial => ("equibiaxial", l1.iter().map(|&l| (l, l)).collect()),
                BiaxialPath::Strip => ("strip", l1.iter().map(|&l| (l, 1.0)).collect()),
            }
        }
    };
    let passive = spec.passive.unwrap_or(true);
    let keys = ModelKeys {
        approaches: spec.approaches.as_deref(),
        ..ModelKeys::lists(&spec.laws, &spec.couplings, &spec.damage)
    };
    let (models, set) = approach_models(keys, passive, d, &[d.approach], "biaxial")?;
    let name = spec.name.clone().unwrap_or_else(|| "planar biaxial".into());
    let resolved = BiaxialSpec {
        name: Some(name.clone()),
        path: spec
            .pairs
            .is_none()
            .then(|| spec.path.unwrap_or(BiaxialPath::Equibiaxial)),
        stretch: spec.stretch.clone(),
        pairs: spec.pairs.clone(),
        approaches: Some(set.approaches),
        laws: set.laws,
        couplings: set.couplings,
        damage: Some(set.damage),
        passive: Some(passive),
    };
    Ok((
        BiaxialStudy {
            name,
            path,
            pairs,
            models,
        },
        resolved,
    ))
}

/// One biaxial state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BiaxialPoint {
    /// λ₁ (along the fibres), λ₂ (across), λ₃ [-].
    pub stretches: [f64; 3],
    /// Activation γ (ω, or 0 for active stress) [-].
    pub gamma: f64,
    /// Nominal stresses P₁₁, P₂₂ \[kPa\].
    pub nominal: [f64; 2],
    /// Cauchy stresses σ₁₁, σ₂₂ \[kPa\].
    pub cauchy: [f64; 2],
    /// Where the law at λ_f = λ₁ is outside its domain, if it is (the explicit law's:
    /// [`crate::active::Domain`]).
    pub outside: Option<OutsideDomain>,
}

/// One curve: a model along the path.
#[derive(Debug, Clone, PartialEq)]
pub struct BiaxialCurve {
    /// The model.
    pub model: ApproachModel,
    /// The states that could be computed, in the order of the path.
    pub points: Vec<BiaxialPoint>,
}

impl BiaxialCurve {
    /// Where its points left its law's domain (`None`: passive, or a law that holds
    /// everywhere).
    fn tally(&self) -> Option<Tally> {
        let mut tally = Tally::of(self.model.model.as_ref()?)?;
        for p in &self.points {
            tally.add(p.stretches[0], p.outside, None);
        }
        Some(tally)
    }
}

/// What a biaxial study computed.
#[derive(Debug, Clone, PartialEq)]
pub struct BiaxialResult {
    /// `equibiaxial`, `strip` or `pairs`.
    pub path: &'static str,
    /// The energy's name.
    pub energy: String,
    /// One curve per model.
    pub curves: Vec<BiaxialCurve>,
}

impl BiaxialStudy {
    /// One line for `check`.
    pub fn describe(&self) -> String {
        format!(
            "{}: {} path, {} states, {} model(s)",
            self.name,
            self.path,
            self.pairs.len(),
            self.models.len()
        )
    }

    /// Every curve, in parallel.
    pub fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
        ctx.progress.log(&self.describe());
        ctx.progress
            .start(&self.name, self.models.len() * self.pairs.len());
        let computed: Vec<Result<(BiaxialCurve, Option<Failure>), AppError>> = self
            .models
            .par_iter()
            .map(|m| self.curve(models, m, ctx))
            .collect();
        ctx.progress.finish();
        let mut curves = Vec::with_capacity(computed.len());
        let (mut failures, mut tallies) = (Vec::new(), Vec::new());
        for c in computed {
            let (curve, failure) = c?;
            tallies.extend(curve.tally().map(|t| (curve.model.label(models), t)));
            curves.push(curve);
            failures.extend(failure);
        }
        let words = Words {
            points: "points",
            x: "λ₁",
            unit: "",
            target: "",
            file: output::FILE,
        };
        let points = curves.iter().map(|c| c.points.len()).sum();
        Ok(Outcome {
            name: self.name.clone(),
            kind: StudyKind::Biaxial,
            models: curves.len(),
            points,
            requested: self.models.len() * self.pairs.len(),
            elapsed: Default::default(),
            details: vec![self.describe()],
            failures,
            left_domain: lines(tallies, &words),
            result: StudyResult::Biaxial(BiaxialResult {
                path: self.path,
                energy: models.energy.name().to_string(),
                curves,
            }),
        })
    }

    fn curve(
        &self,
        models: &Models,
        m: &ApproachModel,
        ctx: &RunContext,
    ) -> Result<(BiaxialCurve, Option<Failure>), AppError> {
        let label = m.label(models);
        let muscle = m.muscle(models, &self.name)?;
        let mut points = Vec::with_capacity(self.pairs.len());
        let mut first: Option<((f64, f64), String)> = None;
        let mut failed = 0usize;
        for &(l1, l2) in &self.pairs {
            ctx.progress.advance(1);
            match planar_biaxial(&muscle, models.volumetric.as_ref(), l1, l2) {
                Ok(s) => points.push(BiaxialPoint {
                    stretches: [l1, l2, s.f[(2, 2)]],
                    gamma: s.gamma,
                    nominal: [s.nominal[(0, 0)], s.nominal[(1, 1)]],
                    cauchy: [s.cauchy[(0, 0)], s.cauchy[(1, 1)]],
                    outside: muscle.outside_domain(s.fibre_stretch),
                }),
                Err(e) => {
                    failed += 1;
                    first.get_or_insert(((l1, l2), e.to_string()));
                }
            }
        }
        let failure = first.map(|((l1, l2), why)| Failure {
            model: label,
            message: format!(
                "{failed} of {} states failed; first at (λ₁, λ₂) = ({}, {}): {why}",
                self.pairs.len(),
                crate::text::shortest(l1),
                crate::text::shortest(l2)
            ),
        });
        Ok((
            BiaxialCurve {
                model: m.clone(),
                points,
            },
            failure,
        ))
    }
}

impl BiaxialResult {
    /// The study's table (`biaxial.csv` and Python's table): one row per curve point.
    pub fn table(&self, study: &str) -> Table {
        let rows: Vec<(&BiaxialCurve, &BiaxialPoint)> = self
            .curves
            .iter()
            .flat_map(|c| c.points.iter().map(move |p| (c, p)))
            .collect();
        let cell = |i: usize| rows.iter().map(move |(c, _)| c.model.cells()[i].clone());
        let at = |f: fn(&BiaxialPoint) -> f64| rows.iter().map(move |(_, p)| Some(f(p)));
        Table::default()
            .text("study", "the study's name", every_row(study, rows.len()))
            .text("energy", "the passive energy", every_row(&self.energy, rows.len()))
            .text("path", "equibiaxial, strip or pairs", every_row(self.path, rows.len()))
            .text("approach", "activation approach (empty: passive)", cell(0))
            .text("law", "activation law (passive for the passive material; empty: an approach without a law, active stress)", cell(1))
            .text("coupling", "frozen or consistent (empty: passive, or an approach without a law)", cell(2))
            .number("d", "-", "damage", rows.iter().map(|(c, _)| c.model.model.map(|m| m.damage)))
            .number("lambda_1", "-", "stretch along the fibres λ₁", at(|p| p.stretches[0]))
            .number("lambda_2", "-", "stretch across the fibres λ₂", at(|p| p.stretches[1]))
            .number("lambda_3", "-", "stretch normal to the plane λ₃", at(|p| p.stretches[2]))
            .number("gamma", "-", "activation γ (ω for the structural approach)", at(|p| p.gamma))
            .number("P_11", "kPa", "nominal stress along the fibres", at(|p| p.nominal[0]))
            .number("P_22", "kPa", "nominal stress across the fibres", at(|p| p.nominal[1]))
            .number("sigma_11", "kPa", "Cauchy stress along the fibres", at(|p| p.cauchy[0]))
            .number("sigma_22", "kPa", "Cauchy stress across the fibres", at(|p| p.cauchy[1]))
            .boolean("in_domain", IN_DOMAIN, rows.iter().map(|(c, p)| in_domain(c.model.model.as_ref(), p.outside)))
    }
}
