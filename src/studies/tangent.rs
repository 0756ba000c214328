//! Tangent studies (`kind = "tangent"`): is the tangent the solver uses the derivative of the
//! stress, for every model the scene asks for (approach × law × coupling × damage, with the
//! scene's energy, map, active curve, volumetric energy, law representation and force–velocity),
//! at the states a simulation visits? The Taylor test of [`crate::tangent_check`] at every model,
//! state and direction: the remainders r₀(h), r₁(h) over h = 2⁻ᵏ, their orders, the
//! central-difference tangent's error, the major-symmetry defect with its reason, the error of
//! the approximate tangents the solver can use (the frozen model's symmetric approximation, the
//! other representation of a tabulated or exact law), strong ellipticity, and a flag with its
//! cause where an order leaves its band. Models are tested with the frozen model's exact tangent (its
//! symmetric approximation is reported as an approximation); exactly incompressible models with
//! the pressure held fixed, nearly incompressible ones with U(J).
//!
//! States ([`states`]): the user's `deformations`, named paths (`uniaxial_along`,
//! `uniaxial_across`, `simple_shear`, `equibiaxial`), seeded random states (`random_states`,
//! `near_lambda_min`, `large_fibre_stretch`); directions: the user's `directions` and
//! `random_directions`. With the scene's force–velocity, each model is tested at the
//! `stretch_rates` (λ_prev = λ_f − λ̇ Δt at each state, Δt = `time_step`). The optional `fe`
//! table adds the finite-element level ([`fe`]).

mod fe;
mod output;
mod run;
pub mod states;
mod tables;

pub use fe::{FeConfig, FeLevel, FeResult, FeSpec, FeTaylor, NewtonRun};
pub use run::{ModelTests, StateTest, TangentResult};

use super::rules::{each, something};
use super::spec::{damages, ApproachModel, Defaults, ModelKeys, StretchSpec};
use crate::active::Approach;
use crate::app_error::SpecError;
use crate::models::{CouplingKind, LawKind, Models};
use crate::tangent_check::halvings;
use serde::{Deserialize, Serialize};
use states::{amounts, count, matrix, NamedState, StateSources, MAX_DIRECTIONS, MAX_STATES};

/// The most Taylor tests (models × stretch rates × states × directions) a study may run: each
/// is about 40 stress evaluations and a row per step in `tangent.csv`.
pub const MAX_TESTS: usize = 20_000;

/// `[[study]] kind = "tangent"` as written; `None` is a key left to its default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TangentSpec {
    /// Label (default `tangent check`).
    pub name: Option<String>,
    /// The user's states, each [F11, F12, F13, F21, F22, F23, F31, F32, F33] (det F > 0).
    pub deformations: Option<Vec<Vec<f64>>>,
    /// Stretches along the fibres (incompressible uniaxial states).
    pub uniaxial_along: Option<StretchSpec>,
    /// Stretches across the fibres.
    pub uniaxial_across: Option<StretchSpec>,
    /// Amounts of simple shear along the fibres.
    pub simple_shear: Option<StretchSpec>,
    /// Equibiaxial stretches in the plane of the fibre.
    pub equibiaxial: Option<StretchSpec>,
    /// Seeded random states.
    pub random_states: Option<i64>,
    /// Seeded random states with λ_f within 1 % of λ_min.
    pub near_lambda_min: Option<i64>,
    /// Seeded random states with λ_f in [1.3, 1.5].
    pub large_fibre_stretch: Option<i64>,
    /// Seed of the random states and directions (default 1).
    pub seed: Option<i64>,
    /// The user's directions ΔF (row-major, scaled to unit norm).
    pub directions: Option<Vec<Vec<f64>>>,
    /// Seeded random unit directions (default 2, or 0 with `directions`).
    pub random_directions: Option<i64>,
    /// The steps h = 2⁻ᵏ between `largest` and `smallest` (default 2⁻⁶ … 2⁻²⁰).
    pub h: Option<StepsSpec>,
    /// Fibre stretch rates λ̇ \[1/s\] with the scene's force–velocity (default [−1, 0, 1]).
    pub stretch_rates: Option<Vec<f64>>,
    /// The time step Δt \[s\] of the stretch rates (default 0.01).
    pub time_step: Option<f64>,
    /// Approaches (default `[activation.approach]`).
    pub approaches: Option<Vec<Approach>>,
    /// Laws (default: every law the material supports).
    pub laws: Option<Vec<LawKind>>,
    /// Couplings (default both).
    pub couplings: Option<Vec<CouplingKind>>,
    /// Damage values (default `activation.damage`).
    pub damage: Option<Vec<f64>>,
    /// Include the passive material (default true).
    pub passive: Option<bool>,
    /// The finite-element level (default none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fe: Option<Box<FeSpec>>,
}

/// `h = { largest = 0.015625, smallest = 9.5e-7 }`: the steps 2⁻ᵏ between them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepsSpec {
    /// The largest step, in (0, 1).
    pub largest: f64,
    /// The smallest step, in (0, largest).
    pub smallest: f64,
}

/// The default steps: 2⁻⁶ … 2⁻²⁰.
const DEFAULT_STEPS: StepsSpec = StepsSpec {
    largest: 0.015625,
    smallest: 9.5367431640625e-7,
};

/// Keys a tangent study does not take, and what to write instead.
pub const HINTS: &[(&str, &str)] = &[
    ("stretch", "a tangent study takes states: uniaxial_along = [...], deformations = [[...]], ..."),
    ("approach", "it takes a list: approaches = [...]"),
    ("law", "it takes a list: laws = [...]"),
    ("coupling", "it takes a list: couplings = [...]"),
    ("states", "give deformations, uniaxial_along, uniaxial_across, simple_shear, equibiaxial or random_states"),
];

/// A validated tangent study.
#[derive(Debug, Clone, PartialEq)]
pub struct TangentStudy {
    /// Label.
    pub name: String,
    /// Where the states come from.
    pub sources: StateSources,
    /// The directions, named.
    pub directions: Vec<(String, nalgebra::Matrix3<f64>)>,
    /// The steps, descending.
    pub h: Vec<f64>,
    /// Stretch rates \[1/s\] and the time step \[s\] (the scene's force–velocity), if any.
    pub rates: Option<(Vec<f64>, f64)>,
    /// The models, passive first if asked.
    pub models: Vec<ApproachModel>,
    /// The finite-element level.
    pub fe: Option<FeLevel>,
}

/// The state sources of `spec`: the defaults when it names none.
fn sources(spec: &TangentSpec) -> Result<(StateSources, TangentSpec), SpecError> {
    let any = spec.deformations.is_some()
        || spec.uniaxial_along.is_some()
        || spec.uniaxial_across.is_some()
        || spec.simple_shear.is_some()
        || spec.equibiaxial.is_some()
        || spec.random_states.is_some()
        || spec.near_lambda_min.is_some()
        || spec.large_fibre_stretch.is_some();
    let mut s = spec.clone();
    if !any {
        let list = |v: &[f64]| Some(StretchSpec::List(v.to_vec()));
        s.uniaxial_along = list(&[0.8, 1.0, 1.2, 1.4]);
        s.uniaxial_across = list(&[0.9, 1.1]);
        s.simple_shear = list(&[0.1, 0.3]);
        s.equibiaxial = list(&[1.1]);
        (s.random_states, s.near_lambda_min, s.large_fibre_stretch) = (Some(4), Some(2), Some(2));
    }
    let seed = s.seed.unwrap_or(1);
    if seed < 0 {
        return Err(SpecError::new("seed", seed, "must be an integer ≥ 0"));
    }
    s.seed = Some(seed);
    let mut given = Vec::new();
    for (i, v) in s.deformations.iter().flatten().enumerate() {
        given.push(matrix(&format!("deformations[{i}]"), v, true)?);
    }
    let mut random = [0usize; 3];
    for (k, (key, v)) in [
        ("random_states", &mut s.random_states),
        ("near_lambda_min", &mut s.near_lambda_min),
        ("large_fibre_stretch", &mut s.large_fibre_stretch),
    ]
    .into_iter()
    .enumerate()
    {
        let n = v.unwrap_or(0);
        *v = Some(n);
        random[k] = count(key, n, MAX_STATES)?;
    }
    let sources = StateSources {
        given,
        along: amounts("uniaxial_along", &s.uniaxial_along, false)?,
        across: amounts("uniaxial_across", &s.uniaxial_across, false)?,
        shear: amounts("simple_shear", &s.simple_shear, true)?,
        equibiaxial: amounts("equibiaxial", &s.equibiaxial, false)?,
        random,
        seed: seed as u64,
    };
    if sources.is_empty() {
        return Err(SpecError::new(
            "states",
            "(none)",
            "give at least one state",
        ));
    }
    if sources.len() > MAX_STATES {
        return Err(SpecError::new(
            "states",
            sources.len(),
            format!("at most {MAX_STATES} states (deformations, paths and random states together): each is a Taylor test per model and direction"),
        ));
    }
    Ok((sources, s))
}

/// The directions of `spec` (key `directions[i]`, `random_directions`).
fn directions(
    spec: &mut TangentSpec,
    seed: u64,
) -> Result<Vec<(String, nalgebra::Matrix3<f64>)>, SpecError> {
    let mut given = Vec::new();
    for (i, v) in spec.directions.iter().flatten().enumerate() {
        given.push(matrix(&format!("directions[{i}]"), v, false)?);
    }
    let random = spec
        .random_directions
        .unwrap_or(if given.is_empty() { 2 } else { 0 });
    spec.random_directions = Some(random);
    let random = count("random_directions", random, MAX_DIRECTIONS)?;
    let total = given.len() + random;
    if total == 0 {
        return Err(SpecError::new(
            "random_directions",
            0,
            "give at least one direction",
        ));
    }
    if total > MAX_DIRECTIONS {
        return Err(SpecError::new(
            "directions",
            total,
            format!("at most {MAX_DIRECTIONS} directions, given and random together"),
        ));
    }
    Ok(states::directions(&given, random, seed))
}

/// The stretch rates and time step, with the scene's force–velocity; refused without it.
fn rates(spec: &mut TangentSpec, models: &Models) -> Result<Option<(Vec<f64>, f64)>, SpecError> {
    if models.force_velocity.is_none() {
        for (key, given) in [
            ("stretch_rates", spec.stretch_rates.is_some()),
            ("time_step", spec.time_step.is_some()),
        ] {
            if given {
                return Err(SpecError::new(key, "(given)", "the scene has no activation.force_velocity: without it the stress does not depend on the stretch rate"));
            }
        }
        return Ok(None);
    }
    let list = spec
        .stretch_rates
        .clone()
        .unwrap_or_else(|| vec![-1.0, 0.0, 1.0]);
    if list.is_empty() || list.len() > 8 {
        return Err(SpecError::new(
            "stretch_rates",
            list.len(),
            "give 1 to 8 stretch rates [1/s]",
        ));
    }
    each(
        "stretch_rates",
        &list,
        |r| r.is_finite(),
        "must be finite [1/s]",
    )?;
    let dt = spec.time_step.unwrap_or(0.01);
    if !(dt.is_finite() && dt > 0.0) {
        return Err(SpecError::new(
            "time_step",
            dt,
            "must be finite and > 0 [s]",
        ));
    }
    (spec.stretch_rates, spec.time_step) = (Some(list.clone()), Some(dt));
    Ok(Some((list, dt)))
}

/// Every approach × law × coupling × damage `spec` asks for; without `laws`, every law each
/// approach supports on this material; without `couplings`, both.
fn models_of(spec: &mut TangentSpec, d: &Defaults) -> Result<Vec<ApproachModel>, SpecError> {
    let approaches = spec.approaches.clone().unwrap_or_else(|| vec![d.approach]);
    let both = [CouplingKind::Frozen, CouplingKind::Consistent];
    let passive = spec.passive.unwrap_or(true);
    let mut models = Vec::new();
    if passive {
        models.push(ApproachModel::passive(d));
    }
    let (mut laws, mut couplings, mut damage) = (Vec::new(), None, None);
    for (j, approach) in approaches.iter().enumerate() {
        let supported = d.supported_laws(*approach);
        let mut keys = ModelKeys {
            approaches: Some(std::slice::from_ref(approach)),
            ..ModelKeys::lists(&spec.laws, &spec.couplings, &spec.damage)
        };
        if supported.is_empty() && approach.laws().is_empty() && approaches.len() > 1 {
            // An approach without a law among others: the laws are the others'.
            (keys.laws, keys.couplings) = (None, None);
        }
        let set = keys.resolve(d, &supported, &both).map_err(|e| SpecError {
            key: e.key.replace("approaches[0]", &format!("approaches[{j}]")),
            ..e
        })?;
        models.extend(set.choices.iter().copied().map(ApproachModel::of));
        if let Some(l) = set.laws {
            laws.push(l);
        }
        couplings = couplings.or(set.couplings);
        damage = Some(set.damage);
    }
    // One lawful approach: its laws written out (with several, each takes its own).
    if spec.laws.is_none() && laws.len() == 1 {
        spec.laws = laws.pop();
    }
    spec.approaches = Some(approaches);
    spec.couplings = spec.couplings.clone().or(couplings);
    spec.damage = Some(match damage {
        Some(d) => d,
        None => damages("damage", spec.damage.as_deref().unwrap_or(d.damage))?,
    });
    spec.passive = Some(passive);
    something(
        "tangent",
        !models.is_empty(),
        "passive = true or approaches",
    )?;
    Ok(models)
}

/// Validates `spec`; returns the study and the spec with every default written out.
pub fn resolve(spec: &TangentSpec, d: &Defaults) -> Result<(TangentStudy, TangentSpec), SpecError> {
    let (sources, mut resolved) = sources(spec)?;
    let directions = directions(&mut resolved, sources.seed)?;
    let steps = resolved.h.unwrap_or(DEFAULT_STEPS);
    let h = halvings(steps.largest, steps.smallest).map_err(|e| SpecError::model("", e))?;
    resolved.h = Some(steps);
    let rates = rates(&mut resolved, d.models)?;
    let models = models_of(&mut resolved, d)?;
    let tests =
        models.len() * rates.as_ref().map_or(1, |r| r.0.len()) * sources.len() * directions.len();
    if tests > MAX_TESTS {
        return Err(SpecError::new(
            "",
            format!("{tests} Taylor tests"),
            format!("at most {MAX_TESTS} (models × stretch rates × states × directions): give fewer states, directions or models"),
        ));
    }
    let fe = match &spec.fe {
        Some(f) => {
            let (level, written) = fe::resolve(f, d).map_err(|e| e.within("fe"))?;
            resolved.fe = Some(Box::new(written));
            Some(level)
        }
        None => None,
    };
    let name = spec.name.clone().unwrap_or_else(|| "tangent check".into());
    resolved.name = Some(name.clone());
    Ok((
        TangentStudy {
            name,
            sources,
            directions,
            h,
            rates,
            models,
            fe,
        },
        resolved,
    ))
}

impl TangentStudy {
    /// One line for `check`.
    pub fn describe(&self) -> String {
        let rates = self
            .rates
            .as_ref()
            .map_or(String::new(), |r| format!(" × {} stretch rates", r.0.len()));
        let fe = self
            .fe
            .as_ref()
            .map_or(String::new(), |f| format!("; {}", f.describe()));
        format!(
            "{}: {} model(s){rates} × {} states × {} directions, h = 2^-{} … 2^-{}{fe}",
            self.name,
            self.models.len(),
            self.sources.len(),
            self.directions.len(),
            -self.h.first().copied().unwrap_or(1.0).log2().round(),
            -self.h.last().copied().unwrap_or(1.0).log2().round(),
        )
    }

    /// The states for the scene's fibre and active curve.
    pub fn states(&self, models: &Models) -> Vec<NamedState> {
        let m = nalgebra::Vector3::from(models.fibre).normalize();
        self.sources
            .states(&m, models.curve.lambda_min(), models.volumetric.is_some())
    }
}

/// The tangent study `activemuscle tangent` runs on a scene's material (its studies not run):
/// every default, and, if the scene has a cylinder study, the FE level on the first one's
/// geometry (at most 4 × 8 cells), law, coupling and first damage.
pub fn for_scene(
    studies: &[super::Study],
    d: &Defaults,
) -> Result<(TangentStudy, TangentSpec), SpecError> {
    let fe = studies
        .iter()
        .find_map(|s| match s {
            super::Study::Cylinder(c) => Some(c),
            _ => None,
        })
        .map(|c| {
            Box::new(FeSpec {
                radius: Some(c.radius),
                length: Some(c.length),
                nr: Some(c.nr.min(4) as i64),
                nz: Some(c.nz.min(8) as i64),
                law: c.models.first().map(|m| m.law),
                coupling: c.models.first().map(|m| m.coupling),
                damage: c.models.first().map(|m| m.damage),
                ..FeSpec::default()
            })
        });
    resolve(
        &TangentSpec {
            fe,
            ..TangentSpec::default()
        },
        d,
    )
}
