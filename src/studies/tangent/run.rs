//! Running a tangent study: every model (× stretch rate) in parallel, each through every state
//! and direction ([`crate::tangent_check`]), then the finite-element level. A model that cannot
//! be built is a failure of the study; a state where a model cannot be evaluated is a result
//! (a flagged row with its reason).

use super::states::NamedState;
use super::{FeResult, TangentStudy};
use crate::active::{FrozenTangent, LawRepresentation, OutsideDomain, StretchRate, TableSpec};
use crate::app_error::AppError;
use crate::energy::Energy;
use crate::models::Models;
use crate::studies::domain::{lines, LeftDomain, Tally, Words};
use crate::studies::spec::ApproachModel;
use crate::studies::{Failure, Outcome, RunContext, StudyKind, StudyResult};
use crate::tangent_check::taylor::check_state;
use crate::tangent_check::TangentMaterial;
use crate::tangent_check::{remainders, state_report, MusclePoint, Remainders, StateReport};
use crate::{Muscle, StrainEnergy};
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

/// What a tangent study computed.
#[derive(Debug, Clone, PartialEq)]
pub struct TangentResult {
    /// The energy's name.
    pub energy: String,
    /// The volumetric energy's formula (`None`: exactly incompressible, the pressure held).
    pub volumetric: Option<String>,
    /// The scene's frozen tangent (the study tests the exact one; the symmetric one is an
    /// approximation it reports).
    pub frozen_tangent: FrozenTangent,
    /// The steps h, descending.
    pub h: Vec<f64>,
    /// The states.
    pub states: Vec<NamedState>,
    /// The directions' names.
    pub directions: Vec<String>,
    /// One entry per model (and stretch rate).
    pub models: Vec<ModelTests>,
    /// The finite-element level, if asked for.
    pub fe: Option<FeResult>,
}

/// One model's tests.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelTests {
    /// The model.
    pub model: ApproachModel,
    /// Its label.
    pub label: String,
    /// The fibre stretch rate λ̇ \[1/s\] (force–velocity), if any.
    pub rate: Option<f64>,
    /// One entry per state (`Err`: the model cannot be evaluated there, and why).
    pub states: Vec<Result<StateTest, String>>,
}

/// One model at one state.
#[derive(Debug, Clone, PartialEq)]
pub struct StateTest {
    /// γ (ω for the structural approach; 0 for active stress) [-].
    pub gamma: f64,
    /// λ_f [-].
    pub fibre_stretch: f64,
    /// Where the law at λ_f is outside its domain, if it is (the explicit law's:
    /// [`crate::Muscle::outside_domain`]); the state is tested all the same.
    pub outside: Option<OutsideDomain>,
    /// What is checked at the state.
    pub report: StateReport,
    /// One entry per direction (`Err`: the test could not be run, and why).
    pub directions: Vec<Result<Remainders, String>>,
}

/// The Taylor tests of `point` at `f` along every direction.
fn state_test<M>(
    point: &MusclePoint<M>,
    f: &Matrix3<f64>,
    directions: &[(String, Matrix3<f64>)],
    h: &[f64],
) -> Result<StateTest, String>
where
    M: StrainEnergy,
{
    let text = |e: crate::Error| e.to_string();
    check_state(f).map_err(text)?;
    let (p, a) = point.stress_and_tangent(f).map_err(text)?;
    let known = point.known(f, &a).map_err(text)?;
    let report = state_report(point, f, (&p, &a), &known);
    let (gamma, fibre_stretch) = point.activation(f).map_err(text)?;
    let outside = point.muscle().outside_domain(fibre_stretch);
    let directions = directions
        .iter()
        .map(|(_, d)| remainders(point, f, (&p, &a), (&known, report.fd_error), d, h).map_err(text))
        .collect();
    Ok(StateTest {
        gamma,
        fibre_stretch,
        outside,
        report,
        directions,
    })
}

/// The summary's file: one row per model and state (its table: `tables`).
pub const SUMMARY_FILE: &str = "tangent_summary.csv";

/// How the tangent kind's `OUTSIDE:` lines name its states. A tangent check compares each
/// model's derivatives with themselves: no target, no distance from one.
const WORDS: Words = Words {
    points: "states",
    x: "λ_f",
    unit: "",
    target: "",
    file: SUMMARY_FILE,
};

/// One line per law and coupling whose states left the law's domain ([`lines`]), each state
/// placed at its fibre stretch; states that could not be evaluated are not counted.
fn left_domain(tests: &[ModelTests]) -> Vec<LeftDomain> {
    let tallies = tests
        .iter()
        .filter_map(|t| {
            let mut tally = Tally::of(t.model.model.as_ref()?)?;
            for s in t.states.iter().flatten() {
                tally.add(s.fibre_stretch, s.outside, None);
            }
            Some((t.label.clone(), tally))
        })
        .collect();
    lines(tallies, &WORDS)
}

/// The muscle of `m` under test: the frozen model with its exact tangent.
fn muscle_of(models: &Models, m: &ApproachModel) -> crate::Result<Muscle<Energy>> {
    let exact = Models {
        frozen_tangent: FrozenTangent::Exact,
        ..models.clone()
    };
    match m.model {
        None => Ok(exact.passive()),
        Some(c) => exact.muscle(c),
    }
}

/// The point of `muscle` at F with the stretch rate `rate` [1/s] over the time step `dt`:
/// λ_prev = λ_f(F) − λ̇ Δt.
fn with_rate(
    muscle: &Muscle<Energy>,
    models: &Models,
    f: &Matrix3<f64>,
    (rate, dt): (f64, f64),
) -> crate::Result<MusclePoint<Energy>> {
    let fibre = Vector3::from(models.fibre);
    let mut muscle = muscle.clone();
    if let Some(law) = models.force_velocity {
        let previous = (f * fibre.normalize()).norm() - rate * dt;
        muscle.set_rate(Some(StretchRate { law, previous, dt }))?;
    }
    Ok(MusclePoint::new(muscle, fibre)?.with_volumetric(models.volumetric))
}

impl TangentStudy {
    /// The tests of one model (at one stretch rate) at every state.
    fn model_tests(
        &self,
        models: &Models,
        m: &ApproachModel,
        rate: Option<f64>,
        states: &[NamedState],
        ctx: &RunContext,
    ) -> Result<ModelTests, Failure> {
        let label = m.label(models);
        let failure = |e: crate::Error| Failure {
            model: label.clone(),
            message: e.to_string(),
        };
        let muscle = muscle_of(models, m).map_err(failure)?;
        let table = match models.representation {
            LawRepresentation::Tabulated(spec) => spec,
            LawRepresentation::Exact => TableSpec::default(),
        };
        let point = match rate {
            None => Some(
                MusclePoint::new(muscle.clone(), Vector3::from(models.fibre))
                    .map(|p| p.with_volumetric(models.volumetric))
                    .and_then(|p| p.with_table_comparison(table))
                    .map_err(failure)?,
            ),
            Some(_) => None,
        };
        let dt = self.rates.as_ref().map_or(0.0, |r| r.1);
        let tests = states
            .iter()
            .map(|s| {
                ctx.progress.advance(1);
                match &point {
                    Some(p) => state_test(p, &s.f, &self.directions, &self.h),
                    None => with_rate(&muscle, models, &s.f, (rate.unwrap_or_default(), dt))
                        .map_err(|e| e.to_string())
                        .and_then(|p| state_test(&p, &s.f, &self.directions, &self.h)),
                }
            })
            .collect();
        Ok(ModelTests {
            model: m.clone(),
            label: label.clone(),
            rate,
            states: tests,
        })
    }

    /// Every model at every state and direction, in parallel; then the finite-element level.
    pub fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
        ctx.progress.log(&self.describe());
        let states = self.states(models);
        let rates: Vec<Option<f64>> = match &self.rates {
            Some((r, _)) => r.iter().copied().map(Some).collect(),
            None => vec![None],
        };
        // The passive material has no activation for a stretch rate to act on: tested once.
        let jobs: Vec<(&ApproachModel, Option<f64>)> = self
            .models
            .iter()
            .flat_map(|m| match m.model {
                None => vec![(m, None)],
                Some(_) => rates.iter().map(|r| (m, *r)).collect(),
            })
            .collect();
        ctx.progress.start(&self.name, jobs.len() * states.len());
        let computed: Vec<Result<ModelTests, Failure>> = jobs
            .par_iter()
            .map(|&(m, r)| self.model_tests(models, m, r, &states, ctx))
            .collect();
        ctx.progress.finish();
        let (mut tests, mut failures) = (Vec::new(), Vec::new());
        for c in computed {
            match c {
                Ok(t) => tests.push(t),
                Err(f) => failures.push(f),
            }
        }
        let fe = self
            .fe
            .as_ref()
            .map(|f| f.run(models, &self.h, self.sources.seed, ctx));
        if let Some(fe) = &fe {
            failures.extend(fe.failures.iter().cloned());
        }
        let per_model = states.len() * self.directions.len();
        let mut details = vec![self.describe()];
        let unevaluable: usize = tests
            .iter()
            .map(|t| t.states.iter().filter(|s| s.is_err()).count())
            .sum();
        if unevaluable > 0 {
            details.push(format!("{unevaluable} (model, state) pairs could not be evaluated: flagged rows with their reason in tangent_summary.csv"));
        }
        Ok(Outcome {
            name: self.name.clone(),
            kind: StudyKind::Tangent,
            models: tests.len(),
            points: tests.len() * per_model,
            requested: jobs.len() * per_model,
            elapsed: Default::default(),
            details,
            failures,
            left_domain: left_domain(&tests),
            result: StudyResult::Tangent(TangentResult {
                energy: models.energy.name().to_string(),
                volumetric: models.volumetric.map(|v| v.form().formula()),
                frozen_tangent: models.frozen_tangent,
                h: self.h.clone(),
                states,
                directions: self.directions.iter().map(|d| d.0.clone()).collect(),
                models: tests,
                fe,
            }),
        })
    }
}
