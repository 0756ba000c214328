//! Trade-off studies (`kind = "tradeoff"`): speed versus accuracy, measured on both axes at once.
//!
//! Every option a user can turn to trade accuracy for speed (activation law, derivative route,
//! frozen tangent, mesh, element, Newton tolerance, 0D versus FE, incompressibility) is run at each of its variants,
//! timed (wall time \[s\]: the median and the spread of at least three runs, see
//! [`measure::time_median`])
//! and compared with a reference computed at the accurate end of the same option, on what a user
//! reads off a run: the nominal stress P(λ) over the sweep \[kPa\] (max abs and max rel error), the
//! activation γ [-] (0D) or the centre γ (FE). The error machinery ([`measure`]) is independent
//! of the options and is tested on cases with a known answer.
//!
//! - [`measure`]: timing, curve errors, speed-up and error ratio, the Pareto front.
//! - [`routes`]: derivative routes as [`crate::fem::AxisymmetricMaterial`] wrappers (the 9-entry
//!   oracle route and a central-difference tangent).
//! - [`groups`]: the options and their variants.
//!
//! A scene holds at most one trade-off study: its outputs are `tradeoff.csv`, `tradeoff.md`,
//! `tradeoff.html` and one `tradeoff_*.png`/`.svg` per option (written by the output layer).
//!
//! | key | meaning | default |
//! |---|---|---|
//! | `options` | option groups: `activation-law`, `activation-law-fe`, `law-representation`, `derivative-route`, `frozen-tangent`, `mesh`, `element`, `newton-tolerance`, `zero-d-vs-fe`, `incompressibility`, `formula-energy` | all |
//! | `stretch` | stretches of every sweep (FE and 0D) | FE: 0.8, 1, 1.17, 1.3; 0D: the first uniaxial study along the fibres, or 0.65:0.01:1.60 |
//! | `meshes` | `[[nr, nz], ...]` of the mesh option, coarse to fine (the last is the reference) | 2 × 8, 4 × 16, 8 × 32, 16 × 64 |
//! | `nr`, `nz` | mesh of the other FE options | the first cylinder study's, or 4 × 16 |
//! | `radius`, `length`, `grading` | the cylinder | the first cylinder study's, or 1, 4, 3 |
//! | `tolerances` | Newton tolerances, loose to tight (the last is the reference) | 1e-6, 1e-8, 1e-10, 1e-12 |

pub mod groups;
pub mod measure;
pub mod output;
pub mod routes;

pub use groups::{activation_law_fe_rows, fe_row, fe_run, FeRun};
pub use measure::{
    curve_error, pareto_front, time_median, time_runs, CurveError, Measurement, Timing,
};
pub use routes::{FiniteDifferenceTangent, OracleRoute};

use super::rules::{cell_count, grading, non_empty, once, positive};
use super::spec::{optional_stretches, Defaults, StretchSpec};
use super::{Failure, KindSpec, KindStudy, Outcome, RunContext, Study, StudyKind, StudyResult};
use crate::active::Approach;
use crate::app_error::{AppError, SpecError};
use crate::fem::solver::MIN_TOLERANCE;
use crate::models::{ModelDefaults, Models};
use crate::text::shortest;
use crate::uniaxial::Direction;
use groups::{Resolved, Runner};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The options a user trades, in run order; a scene names them in `options = [...]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum OptionGroup {
    /// Activation law, 0D along the fibres.
    ActivationLaw,
    /// Activation law in the clamped cylinder (FE).
    ActivationLawFe,
    /// Exact solve versus table of the implicit and energy laws, 0D and FE.
    LawRepresentation,
    /// Derivative route, at one material point and in the FE.
    DerivativeRoute,
    /// Exact versus symmetric frozen tangent (FE).
    FrozenTangent,
    /// Mesh refinement of the clamped cylinder.
    Mesh,
    /// Element (Q2/Q1 or Q1/P0) in the clamped cylinder.
    Element,
    /// Newton tolerance (FE).
    NewtonTolerance,
    /// 0D versus FE on the sliding cylinder (homogeneous exact solution).
    ZeroDVsFe,
    /// Exact incompressibility versus a quadratic volumetric energy of growing κ (0D and FE).
    Incompressibility,
    /// The material's energy written as a formula versus compiled (point and FE).
    FormulaEnergy,
}

impl OptionGroup {
    /// Every group, in run order.
    pub const ALL: [Self; 11] = [
        Self::ActivationLaw,
        Self::ActivationLawFe,
        Self::LawRepresentation,
        Self::DerivativeRoute,
        Self::FrozenTangent,
        Self::Mesh,
        Self::Element,
        Self::NewtonTolerance,
        Self::ZeroDVsFe,
        Self::Incompressibility,
        Self::FormulaEnergy,
    ];

    /// Whether the group measures with [`Resolved::working_law`] (every group but those that
    /// trade the law itself).
    fn uses_working_law(self) -> bool {
        !matches!(
            self,
            Self::ActivationLaw | Self::ActivationLawFe | Self::LawRepresentation
        )
    }

    /// The name a scene uses (`activation-law-fe`).
    pub fn key(self) -> &'static str {
        match self {
            Self::ActivationLaw => "activation-law",
            Self::ActivationLawFe => "activation-law-fe",
            Self::LawRepresentation => "law-representation",
            Self::DerivativeRoute => "derivative-route",
            Self::FrozenTangent => "frozen-tangent",
            Self::Mesh => "mesh",
            Self::Element => "element",
            Self::NewtonTolerance => "newton-tolerance",
            Self::ZeroDVsFe => "zero-d-vs-fe",
            Self::Incompressibility => "incompressibility",
            Self::FormulaEnergy => "formula-energy",
        }
    }
}

/// The cylinder every FE variant runs on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// Radius R.
    pub radius: f64,
    /// Length L.
    pub length: f64,
    /// Middle/base cell-height ratio in z (≥ 1).
    pub grading: f64,
}

/// What to run.
#[derive(Debug, Clone, PartialEq)]
pub struct TradeoffOptions {
    /// The option groups to measure (run in the order of [`OptionGroup::ALL`]).
    pub groups: Vec<OptionGroup>,
    /// The approach whose laws, couplings and muscles are measured (the scene's; one with a
    /// law, [`refuse_lawless`]).
    pub approach: Approach,
    /// The scene's damage values (`activation.damage`): not traded, every variant runs at
    /// d = 0, and a finding says so when one of them is not 0.
    pub damage: Vec<f64>,
    /// The cylinder of every FE variant; `None`: the [`Fallback`]'s.
    pub geometry: Option<Geometry>,
    /// Meshes (cells in r, cells in z) of the mesh option, coarse to fine; the last is the reference.
    pub meshes: Vec<(usize, usize)>,
    /// Mesh of the FE derivative-route, frozen-tangent, tolerance and sliding (0D vs FE)
    /// options; `None`: the [`Fallback`]'s.
    pub fe_mesh: Option<(usize, usize)>,
    /// Stretches of every FE sweep.
    pub fe_stretches: Vec<f64>,
    /// Stretches of the 0D activation-law curves; `None`: the [`Fallback`]'s.
    pub curve_stretches: Option<Vec<f64>>,
    /// Newton tolerances, loose to tight; the last is the reference.
    pub tolerances: Vec<f64>,
    /// Relative step of the central-difference tangent.
    pub fd_step: f64,
}

impl Default for TradeoffOptions {
    fn default() -> Self {
        Self {
            groups: OptionGroup::ALL.to_vec(),
            approach: Approach::default(),
            damage: vec![0.0],
            geometry: None,
            meshes: vec![(2, 8), (4, 16), (8, 32), (16, 64)],
            fe_mesh: None,
            fe_stretches: vec![0.8, 1.0, 1.17, 1.3],
            curve_stretches: None,
            tolerances: vec![1e-6, 1e-8, 1e-10, 1e-12],
            fd_step: 1e-6,
        }
    }
}

/// What the options leave out, taken from the scene: the first cylinder study's cylinder and mesh
/// and the first uniaxial study along the fibres' stretches (or, without them, the defaults).
#[derive(Debug, Clone, PartialEq)]
pub struct Fallback {
    /// The cylinder.
    pub geometry: Geometry,
    /// Its mesh (nr, nz).
    pub cells: (usize, usize),
    /// Stretches of the 0D curves.
    pub curve_stretches: Vec<f64>,
}

impl Default for Fallback {
    /// R = 1, L = 4, grading 3 on 4 × 16 cells; 0D curves on 0.65:0.01:1.60.
    fn default() -> Self {
        Self {
            geometry: Geometry {
                radius: 1.0,
                length: 4.0,
                grading: 3.0,
            },
            cells: (4, 16),
            curve_stretches: (0..=95).map(|i| 0.65 + 0.01 * i as f64).collect(),
        }
    }
}

impl Fallback {
    /// What a trade-off takes from the scene's `studies`: the first cylinder study's cylinder
    /// and mesh, the first uniaxial study along the fibres' stretches (or the defaults).
    pub fn of(studies: &[Study]) -> Self {
        let mut f = Self::default();
        if let Some(c) = studies.iter().find_map(|s| match s {
            Study::Cylinder(c) => Some(c),
            _ => None,
        }) {
            f.geometry = Geometry {
                radius: c.radius,
                length: c.length,
                grading: c.grading,
            };
            f.cells = (c.nr, c.nz);
        }
        if let Some(u) = studies.iter().find_map(|s| match s {
            Study::Uniaxial(u) if u.direction == Direction::Along => Some(u),
            _ => None,
        }) {
            f.curve_stretches = u.stretches.clone();
        }
        f
    }
}

/// The options a `tradeoff` command measures on a scene: those of its trade-off study if it has
/// one, else every option group with what the scene's `studies` give ([`Fallback::of`]) and its
/// approach and damage values.
pub fn scene_options(studies: &[Study], defaults: &ModelDefaults) -> TradeoffOptions {
    if let Some(t) = studies.iter().find_map(|s| match s {
        Study::Tradeoff(t) => Some(t),
        _ => None,
    }) {
        return t.options.clone();
    }
    let f = Fallback::of(studies);
    TradeoffOptions {
        approach: defaults.approach,
        damage: defaults.damage.clone(),
        geometry: Some(f.geometry),
        fe_mesh: Some(f.cells),
        curve_stretches: Some(f.curve_stretches),
        ..TradeoffOptions::default()
    }
}

/// Refuses a trade-off of an approach without a law: the trade-off measures the choices of an
/// activation law (the law, its table, the frozen tangent) and runs every other option with one.
pub fn refuse_lawless(approach: Approach) -> Result<(), String> {
    if approach.laws().is_empty() {
        Err(format!(
            "a trade-off measures the choices of an activation law (the law, its table, the frozen tangent) and runs its other options with one; approach = {:?} has none: {}",
            approach.name(),
            approach.no_law()
        ))
    } else {
        Ok(())
    }
}

/// Everything measured.
#[derive(Debug, Clone, PartialEq)]
pub struct TradeoffResults {
    /// One row per variant, options in run order (speed-up, error ratio and Pareto filled in).
    pub rows: Vec<Measurement>,
    /// Conclusions with their numbers, one line each.
    pub findings: Vec<String>,
    /// Option groups that could not be measured (their reference failed), with the reason; the
    /// rows measured before the failure are kept.
    pub failures: Vec<(String, String)>,
}

impl TradeoffResults {
    /// What failed of what was asked, each with its reason: whole option groups
    /// ([`Self::failures`]) and references that did not run to the end (nothing of their option
    /// can be compared). A variant other than the reference that does not converge is a measured
    /// result (its row says so), not a failure.
    pub fn failed(&self) -> Vec<Failure> {
        let groups = self.failures.iter().map(|(group, why)| Failure {
            model: format!("option group {group}"),
            message: why.clone(),
        });
        let references = self
            .rows
            .iter()
            .filter(|r| r.reference && !r.measured())
            .map(|r| Failure {
                model: format!("{} · {} (reference)", r.option, r.variant),
                message: r.note.clone(),
            });
        groups.chain(references).collect()
    }
}

/// Runs the chosen option groups on `models`, with the geometry and stretches of `o`, or the
/// defaults ([`Fallback::default`]) where `o` leaves them out; one line per measured variant
/// goes to `progress`.
pub fn run(
    models: &Models,
    o: &TradeoffOptions,
    progress: &dyn super::Progress,
) -> Result<TradeoffResults, AppError> {
    run_until(models, o, progress, None)
}

/// [`run`], until `stop` is requested: the group running then is finished, the groups after it
/// are listed in [`TradeoffResults::failures`] as not run, with the stop's reason.
pub fn run_until(
    models: &Models,
    o: &TradeoffOptions,
    progress: &dyn super::Progress,
    stop: Option<&super::Stop>,
) -> Result<TradeoffResults, AppError> {
    let plan = &plan(models, o)?;
    let mut runner = Runner {
        progress,
        rows: Vec::new(),
        started: Instant::now(),
    };
    let mut findings = Vec::new();
    let mut failures = Vec::new();
    for group in OptionGroup::ALL {
        if !o.groups.contains(&group) {
            continue;
        }
        if let Some(reason) = stop.and_then(super::Stop::reason) {
            failures.push((group.key().to_string(), format!("not run: {reason}")));
            continue;
        }
        // One group's failure does not cost the others.
        if let Err(e) = measure_group(group, models, plan, &mut runner, &mut findings) {
            runner
                .progress
                .log(&format!("{}: FAILED: {e}", group.key()));
            findings.push(format!("Option group {} not measured: {e}.", group.key()));
            failures.push((group.key().to_string(), e.to_string()));
        }
    }
    if let Err(why) = &plan.explicit_working {
        if o.groups.iter().any(|g| g.uses_working_law()) {
            findings.push(format!(
                "The groups that trade something other than the law ran with the {} law: {why}.",
                plan.working_law().name()
            ));
        }
    }
    let damaged: Vec<String> = o
        .damage
        .iter()
        .filter(|&&d| d != 0.0)
        .map(|d| d.to_string())
        .collect();
    if !damaged.is_empty() {
        findings.push(format!(
            "Every variant runs at d = 0 (full activation): the scene's damage {} is not traded.",
            damaged.join(", ")
        ));
    }
    let mut rows = runner.rows;
    measure::finalise(&mut rows);
    Ok(TradeoffResults {
        rows,
        findings,
        failures,
    })
}

/// The options `o` resolved for `models`: the defaults ([`Fallback::default`]) where `o` leaves
/// the cylinder, mesh or 0D stretches out, whether the explicit law is measured and works for
/// the other groups; refuses an approach without a law ([`refuse_lawless`]) or not possible on
/// the material, and meshes beyond the memory limit, before anything is computed.
fn plan(models: &Models, o: &TradeoffOptions) -> Result<Resolved, AppError> {
    if o.meshes.is_empty() || o.tolerances.is_empty() || o.fe_stretches.is_empty() {
        return Err(AppError::Invalid(
            "need at least one mesh, tolerance and FE stretch".into(),
        ));
    }
    refuse_lawless(o.approach).map_err(AppError::Invalid)?;
    models
        .activation_map(o.approach)
        .map_err(AppError::Invalid)?;
    let fallback = Fallback::default();
    let explicit = groups::explicit_measured(models, o.approach);
    let plan = Resolved {
        approach: o.approach,
        geom: o.geometry.unwrap_or(fallback.geometry),
        fe_mesh: o.fe_mesh.unwrap_or(fallback.cells),
        meshes: o.meshes.clone(),
        fe_stretches: o.fe_stretches.clone(),
        curve_stretches: o
            .curve_stretches
            .clone()
            .unwrap_or_else(|| fallback.curve_stretches.clone()),
        tolerances: o.tolerances.clone(),
        fd_step: o.fd_step,
        explicit_working: explicit
            .clone()
            .and_then(|()| models.explicit_fit_applies()),
        explicit,
    };
    check_memory(plan.fe_mesh, &plan.meshes, &o.groups)
        .map_err(|e| AppError::from(e).within("before computing"))?;
    Ok(plan)
}

/// Measures one option group, its rows to `run` and its conclusions to `findings`.
fn measure_group(
    group: OptionGroup,
    models: &Models,
    plan: &Resolved,
    run: &mut Runner<'_>,
    findings: &mut Vec<String>,
) -> Result<(), AppError> {
    match group {
        OptionGroup::ActivationLaw => groups::activation_law(models, plan, run, findings),
        OptionGroup::ActivationLawFe => groups::activation_law_fe(models, plan, run, findings),
        OptionGroup::LawRepresentation => groups::law_representation(models, plan, run, findings),
        OptionGroup::DerivativeRoute => groups::derivative_route(models, plan, run),
        OptionGroup::FrozenTangent => groups::frozen_tangent(models, plan, run),
        OptionGroup::Mesh => groups::mesh(models, plan, run, findings),
        OptionGroup::Element => groups::element(models, plan, run, findings),
        OptionGroup::NewtonTolerance => groups::tolerance(models, plan, run, findings),
        OptionGroup::ZeroDVsFe => groups::zero_d_vs_fe(models, plan, run),
        OptionGroup::Incompressibility => groups::incompressibility(models, plan, run, findings),
        OptionGroup::FormulaEnergy => groups::formula_energy(models, plan, run, findings),
    }
}

/// Checks every mesh the chosen groups solve against the memory limit
/// ([`crate::fem::memory::default_limit`]) before anything is computed: the FE mesh `fe_mesh`,
/// the mesh option's `meshes`, and the element option's Q2/Q1 reference on twice the FE mesh's
/// cells and its finest Q1/P0 mesh on four times. Run when the scene is resolved (so `check`
/// refuses what could not run) and again before a run of [`TradeoffOptions`] built in code.
fn check_memory(
    fe_mesh: (usize, usize),
    meshes: &[(usize, usize)],
    groups: &[OptionGroup],
) -> crate::fem::FemResult<()> {
    use crate::fem::{Element, MemoryEstimate, SolverOptions};
    let (nr, nz) = fe_mesh;
    let mut solved = vec![(nr, nz, Element::Q2Q1)];
    if groups.contains(&OptionGroup::Mesh) {
        solved.extend(meshes.iter().map(|&(r, z)| (r, z, Element::Q2Q1)));
    }
    if groups.contains(&OptionGroup::Element) {
        solved.push((2 * nr, 2 * nz, Element::Q2Q1));
        solved.push((4 * nr, 4 * nz, Element::Q1P0));
    }
    let limit = crate::fem::memory::default_limit();
    let linear = SolverOptions::default().linear_solver;
    solved.into_iter().try_for_each(|(r, z, element)| {
        MemoryEstimate::structured(r, z, element, linear).check(limit)
    })
}

/// `[[study]] kind = "tradeoff"` as written; `None` is a key left to its default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TradeoffSpec {
    /// Label (default `speed versus accuracy`).
    pub name: Option<String>,
    /// Stretches of every sweep, FE and 0D.
    pub stretch: Option<StretchSpec>,
    /// Radius R of the cylinder.
    pub radius: Option<f64>,
    /// Length L of the cylinder.
    pub length: Option<f64>,
    /// Cells in r of the FE mesh.
    pub nr: Option<i64>,
    /// Cells in z of the FE mesh.
    pub nz: Option<i64>,
    /// Middle/base cell-height ratio of the cylinder's mesh.
    pub grading: Option<f64>,
    /// Option groups to measure (default all).
    pub options: Option<Vec<OptionGroup>>,
    /// Meshes `[nr, nz]` of the mesh option, coarse to fine (the last is the reference).
    #[serde(default, deserialize_with = "crate::fixed_length::exact")]
    pub meshes: Option<Vec<[i64; 2]>>,
    /// Newton tolerances of the tolerance option, loose to tight (the last is the reference).
    pub tolerances: Option<Vec<f64>>,
}

/// Keys a trade-off study does not take, and why.
pub const HINTS: &[(&str, &str)] = &[("damage", "every variant runs at d = 0")];

/// A validated trade-off study.
#[derive(Debug, Clone, PartialEq)]
pub struct TradeoffStudy {
    /// Label.
    pub name: String,
    /// What to run (geometry and FE mesh resolved).
    pub options: TradeoffOptions,
}

/// Validates `spec` against the scene's defaults (a trade-off of an approach without a law is
/// refused, [`refuse_lawless`]); returns the study and the spec with every default written out,
/// except the cylinder and mesh, which [`complete`] fills from the scene's first cylinder study.
pub fn resolve(
    spec: &TradeoffSpec,
    d: &Defaults,
) -> Result<(TradeoffStudy, TradeoffSpec), SpecError> {
    refuse_lawless(d.approach).map_err(|rule| SpecError::new("kind", "\"tradeoff\"", rule))?;
    let stretches = optional_stretches(&spec.stretch)?;
    let defaults = TradeoffOptions::default();
    let groups = spec
        .options
        .clone()
        .unwrap_or_else(|| defaults.groups.clone());
    non_empty(
        "options",
        &groups,
        &format!(
            "name at least one option group of {:?}",
            OptionGroup::ALL.map(OptionGroup::key)
        ),
    )?;
    let keys: Vec<String> = groups.iter().map(|g| format!("{:?}", g.key())).collect();
    once("options", &keys, |a, b| a == b, |_| "named twice".into())?;
    let meshes = match &spec.meshes {
        None => defaults.meshes.clone(),
        Some(v) => meshes(v)?,
    };
    let tolerances = match &spec.tolerances {
        None => defaults.tolerances.clone(),
        Some(v) => tolerances(v)?,
    };
    // Checked here; filled in by `complete`.
    spec.radius.map(|v| positive("radius", v)).transpose()?;
    spec.length.map(|v| positive("length", v)).transpose()?;
    spec.grading.map(|g| grading("grading", g)).transpose()?;
    spec.nr.map(|v| cell_count("nr", v)).transpose()?;
    spec.nz.map(|v| cell_count("nz", v)).transpose()?;

    let name = spec
        .name
        .clone()
        .unwrap_or_else(|| "speed versus accuracy".into());
    let options = TradeoffOptions {
        groups: groups.clone(),
        approach: d.approach,
        damage: d.damage.to_vec(),
        meshes: meshes.clone(),
        fe_stretches: stretches.clone().unwrap_or(defaults.fe_stretches.clone()),
        curve_stretches: stretches,
        tolerances: tolerances.clone(),
        ..defaults
    };
    // Without `stretch` the FE and 0D sweeps take different defaults; the printed scene leaves
    // it out so that it runs as this one does.
    let resolved = TradeoffSpec {
        name: Some(name.clone()),
        options: Some(groups),
        meshes: Some(meshes.iter().map(|&(a, b)| [a as i64, b as i64]).collect()),
        tolerances: Some(tolerances),
        ..spec.clone()
    };
    Ok((TradeoffStudy { name, options }, resolved))
}

fn meshes(v: &[[i64; 2]]) -> Result<Vec<(usize, usize)>, SpecError> {
    non_empty(
        "meshes",
        v,
        "give at least one mesh [nr, nz] (the last is the reference)",
    )?;
    let mut meshes: Vec<(usize, usize)> = Vec::with_capacity(v.len());
    for (j, [nr, nz]) in v.iter().enumerate() {
        let at = format!("meshes[{j}]");
        let cells = (cell_count(&at, *nr)?, cell_count(&at, *nz)?);
        if let Some(&(pr, pz)) = meshes.last() {
            if cells.0 * cells.1 <= pr * pz {
                return Err(SpecError::new(
                    at,
                    format!("[{nr}, {nz}]"),
                    format!(
                        "meshes go from coarse to fine (the last is the reference): \
                         {nr} × {nz} cells is not finer than the {pr} × {pz} before it"
                    ),
                ));
            }
        }
        meshes.push(cells);
    }
    Ok(meshes)
}

fn tolerances(v: &[f64]) -> Result<Vec<f64>, SpecError> {
    non_empty(
        "tolerances",
        v,
        "give at least one Newton tolerance (the last is the reference)",
    )?;
    for (j, t) in v.iter().enumerate() {
        let at = format!("tolerances[{j}]");
        if !(t.is_finite() && *t >= MIN_TOLERANCE && *t < 1.0) {
            return Err(SpecError::new(
                at,
                shortest(*t),
                format!(
                    "a Newton tolerance must lie in [4 ε, 1) = [{MIN_TOLERANCE:.1e}, 1): \
                     a scaled residual of f64 numbers does not go below its round-off"
                ),
            ));
        }
        if j > 0 && *t >= v[j - 1] {
            return Err(SpecError::new(
                at,
                t,
                format!(
                    "tolerances go from loose to tight (the last is the reference): \
                     not below the {} before it",
                    shortest(v[j - 1])
                ),
            ));
        }
    }
    Ok(v.to_vec())
}

/// Fills what `spec` left out from the scene's other studies (`fallback`): in the study, the
/// cylinder, the mesh and the 0D stretches; in its resolved spec, the cylinder and mesh (without
/// `stretch` the FE and 0D sweeps take different defaults, so the printed scene leaves it out to
/// run as this one does); refuses meshes that would exceed the memory limit (so `check` refuses
/// what `run` could not solve).
pub fn complete(
    study: &mut TradeoffStudy,
    spec: &TradeoffSpec,
    resolved: &mut TradeoffSpec,
    fallback: &Fallback,
) -> Result<(), SpecError> {
    let g = Geometry {
        radius: spec.radius.unwrap_or(fallback.geometry.radius),
        length: spec.length.unwrap_or(fallback.geometry.length),
        grading: spec.grading.unwrap_or(fallback.geometry.grading),
    };
    // Validated by `resolve`: in [1, 10000].
    let cells = |v: Option<i64>, fallback: usize| v.map_or(fallback, |v| v as usize);
    let fe_mesh = (
        cells(spec.nr, fallback.cells.0),
        cells(spec.nz, fallback.cells.1),
    );
    study.options.geometry = Some(g);
    study.options.fe_mesh = Some(fe_mesh);
    study
        .options
        .curve_stretches
        .get_or_insert_with(|| fallback.curve_stretches.clone());
    resolved.radius = Some(g.radius);
    resolved.length = Some(g.length);
    resolved.grading = Some(g.grading);
    resolved.nr = Some(fe_mesh.0 as i64);
    resolved.nz = Some(fe_mesh.1 as i64);
    check_memory(fe_mesh, &study.options.meshes, &study.options.groups).map_err(|e| {
        let key = if spec.meshes.is_some() && study.options.groups.contains(&OptionGroup::Mesh) {
            "meshes"
        } else {
            "nr"
        };
        SpecError::new(key, format!("{:?}", study.options.meshes), e.to_string())
    })
}

impl KindSpec for TradeoffSpec {
    type Study = TradeoffStudy;

    fn resolve(&self, d: &Defaults) -> Result<(TradeoffStudy, Self), SpecError> {
        resolve(self, d)
    }

    /// Completed from the scene's other studies ([`complete`]).
    fn completed(
        &self,
        study: &TradeoffStudy,
        resolved: &Self,
        studies: &[Study],
        _: &Defaults,
    ) -> Result<Option<(TradeoffStudy, Self)>, SpecError> {
        let (mut study, mut resolved) = (study.clone(), resolved.clone());
        complete(&mut study, self, &mut resolved, &Fallback::of(studies))?;
        Ok(Some((study, resolved)))
    }
}

impl KindStudy for TradeoffStudy {
    /// It measures run times: alone, after the scene's other studies.
    const ALONE: bool = true;
    const ONE_PER_SCENE: Option<&'static str> =
        Some("its outputs are tradeoff.csv, tradeoff.md and the tradeoff figures");
    /// Its FE options solve the axisymmetric cylinder.
    const AXIAL_FIBRES: bool = true;

    fn name(&self) -> &str {
        &self.name
    }

    fn describe(&self) -> String {
        TradeoffStudy::describe(self)
    }

    fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
        TradeoffStudy::run(self, models, ctx)
    }
}

impl TradeoffStudy {
    /// One line for `check`.
    pub fn describe(&self) -> String {
        format!(
            "{}: option groups {}",
            self.name,
            self.options
                .groups
                .iter()
                .map(|g| g.key())
                .collect::<Vec<_>>()
                .join(", ")
        )
    }

    /// Measures the study's option groups on `models`.
    pub fn run(&self, models: &Models, ctx: &RunContext) -> Result<Outcome, AppError> {
        ctx.progress.log(&format!(
            "{}: {} option group(s)",
            self.name,
            self.options.groups.len()
        ));
        let results = run_until(models, &self.options, ctx.progress, ctx.stop)
            .map_err(|e| e.within(&self.name))?;
        let mut details = results.findings.clone();
        details.extend(results.rows.iter().map(Measurement::line));
        // The rule of `activemuscle tradeoff`, so that both commands exit alike: a variant that
        // did not converge is a measured result (its row says so); a group or a reference that
        // could not be measured is a failure.
        let failures = results.failed();
        Ok(Outcome {
            name: self.name.clone(),
            kind: StudyKind::Tradeoff,
            models: results.rows.len(),
            points: results.rows.len(),
            requested: results.rows.len(),
            elapsed: Default::default(),
            details,
            failures,
            left_domain: Vec::new(),
            result: StudyResult::Tradeoff(results),
        })
    }
}
