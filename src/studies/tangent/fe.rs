//! The finite-element level of a tangent study (`fe = { ... }`): a small cylinder of the scene's
//! material with one model (`law`, `coupling`, `damage`), the load step λ₀ → λ₁ with
//! λ₀ = (1 + λ₁)/2 after a first step 1 → λ₀ of the same size, for every element × bases ×
//! incompressibility asked for:
//!
//! - the Taylor test of the assembled residual and tangent
//!   ([`crate::tangent_check::assembled_taylor_test`]) at the step's predictor
//!   x(λ₀) + (λ₁ − λ₀) dx/dλ (the driver's tangent predictor, without its local relaxation) and
//!   at the converged x(λ₁), along a seeded random v (displacements of the size of a cell,
//!   pressures of the largest stress at x(λ₁)), with each tangent the solver can use: the exact
//!   one, the frozen model's symmetric approximation (frozen models whose law varies) and
//!   central differences of the stress at every quadrature point
//!   ([`crate::tangent_check::CentralDifferences`]);
//! - Newton from the predictor with each of them, full steps and the same LU for all: the
//!   solver's scaled residual at every iteration (quadratic with an exact tangent, linear with an
//!   approximate one) and the wall time per iteration (assembly with the tangent, factorisation,
//!   solve).

use crate::active::FrozenTangent;
use crate::app_error::{AppError, SpecError};
use crate::energy::Energy;
use crate::fem::continuation::NonlinearSystem;
use crate::fem::dofs::DofMap;
use crate::fem::problem::MixedProblem;
use crate::fem::tangent_solver::TangentSolver;
use crate::fem::{AxisymmetricMaterial, AxisymmetricSolver, Bases, Element, Mesh, SolverOptions};
use crate::models::{product, CouplingKind, IncompressibilitySpec, LawKind, ModelChoice, Models};
use crate::random::Sampler;
use crate::studies::cylinder::bases_name;
use crate::studies::rules::{cell_count, integer_in, non_empty, positive};
use crate::studies::spec::Defaults;
use crate::studies::{Failure, RunContext};
use crate::tangent_check::{assembled_taylor_test, AssembledTaylor, CentralDifferences};
use crate::volumetric::Volumetric;
use crate::Muscle;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The most cells along r or z of the FE level's mesh (a check, not a simulation).
pub const MAX_CELLS: i64 = 16;
/// The most element × bases × incompressibility configurations.
pub const MAX_CONFIGS: usize = 16;

/// `fe = { ... }` of a tangent study as written; `None` is a key left to its default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeSpec {
    /// Radius R (default 1).
    pub radius: Option<f64>,
    /// Length L (default 3).
    pub length: Option<f64>,
    /// Cells in r (default 2, at most 16).
    pub nr: Option<i64>,
    /// Cells in z (default 4, at most 16).
    pub nz: Option<i64>,
    /// Elements (default `["Q2/Q1", "Q1/P0"]`).
    pub elements: Option<Vec<String>>,
    /// Bases (default `["clamped", "sliding"]`).
    pub bases: Option<Vec<String>>,
    /// Incompressibility, each as `[incompressibility]` (default: the scene's).
    pub incompressibility: Option<Vec<IncompressibilitySpec>>,
    /// The stretch λ₁ of the load step (default 1.1).
    pub stretch: Option<f64>,
    /// Activation law (default `activation.law`).
    pub law: Option<LawKind>,
    /// Coupling (default `activation.coupling`).
    pub coupling: Option<CouplingKind>,
    /// Damage (default: the first of `activation.damage`).
    pub damage: Option<f64>,
    /// Newton iterations from the load step's predictor (default 50).
    pub max_iterations: Option<i64>,
}

/// A validated FE level.
#[derive(Debug, Clone, PartialEq)]
pub struct FeLevel {
    /// Radius and length.
    pub size: (f64, f64),
    /// Cells in r and z.
    pub cells: (usize, usize),
    /// Elements.
    pub elements: Vec<Element>,
    /// Bases.
    pub bases: Vec<Bases>,
    /// Incompressibility: its name and volumetric energy (`None`: exact).
    pub forms: Forms,
    /// λ₁.
    pub stretch: f64,
    /// The model.
    pub model: ModelChoice,
    /// Newton iterations from the predictor.
    pub max_iterations: usize,
}

/// Names from a list, each one of `known` by `name`.
fn named<T: Copy>(
    key: &str,
    given: Option<&[String]>,
    known: &[T],
    name: fn(T) -> &'static str,
) -> Result<Vec<T>, SpecError> {
    let Some(given) = given else {
        return Ok(known.to_vec());
    };
    non_empty(key, given, "give at least one")?;
    let names: Vec<String> = known.iter().map(|k| format!("\"{}\"", name(*k))).collect();
    given
        .iter()
        .enumerate()
        .map(|(j, g)| {
            known
                .iter()
                .copied()
                .find(|k| name(*k) == g)
                .ok_or_else(|| {
                    SpecError::new(
                        format!("{key}[{j}]"),
                        format!("\"{g}\""),
                        format!("expected {}", names.join(" or ")),
                    )
                })
        })
        .collect()
}

/// Incompressibility forms: each one's name and volumetric energy (`None`: exact).
type Forms = Vec<(String, Option<Volumetric>)>;

/// The cylinder's (radius, length) and cells (nr, nz).
type Geometry = ((f64, f64), (usize, usize));

/// The incompressibility forms (default: the scene's), and their specs written out.
fn forms(
    given: Option<&[IncompressibilitySpec]>,
    d: &Defaults,
) -> Result<(Forms, Vec<IncompressibilitySpec>), SpecError> {
    let specs = match given {
        Some(g) => {
            non_empty("incompressibility", g, "give at least one")?;
            g.to_vec()
        }
        None => vec![IncompressibilitySpec::written(d.models.volumetric.as_ref())],
    };
    let mut out = Vec::new();
    for (j, s) in specs.iter().enumerate() {
        let v = s
            .build(&d.models.energy)
            .map_err(|e| e.within(&format!("incompressibility[{j}]")))?;
        out.push((s.kind.unwrap_or_default().name().to_string(), v));
    }
    Ok((out, specs))
}

/// The cylinder's radius, length and cells (nr, nz).
fn mesh_of(spec: &FeSpec) -> Result<Geometry, SpecError> {
    let radius = positive("radius", spec.radius.unwrap_or(1.0))?;
    let length = positive("length", spec.length.unwrap_or(3.0))?;
    let (nr, nz) = (spec.nr.unwrap_or(2), spec.nz.unwrap_or(4));
    for (key, n) in [("nr", nr), ("nz", nz)] {
        if n > MAX_CELLS {
            let rule = format!(
                "at most {MAX_CELLS} cells: the FE level checks a tangent, a small mesh does"
            );
            return Err(SpecError::new(key, n, rule));
        }
    }
    Ok((
        (radius, length),
        (cell_count("nr", nr)?, cell_count("nz", nz)?),
    ))
}

/// The model (default: the scene's law and coupling, its first damage), checked against the
/// material.
fn model_of(spec: &FeSpec, d: &Defaults) -> Result<ModelChoice, SpecError> {
    let law = spec.law.unwrap_or(d.law);
    let damage = spec
        .damage
        .unwrap_or(d.damage.first().copied().unwrap_or(0.0));
    crate::studies::spec::damages("damage", &[damage])?;
    if !d.approach.laws().is_empty() {
        d.models
            .supports(d.approach, law)
            .map_err(|rule| SpecError::new("law", format!("\"{}\"", law.name()), rule))?;
    }
    let coupling = spec.coupling.unwrap_or(d.coupling);
    Ok(product(&[d.approach], &[law], &[coupling], &[damage])[0])
}

/// Validates `spec` against the scene's defaults; keys relative to `fe`.
pub fn resolve(spec: &FeSpec, d: &Defaults) -> Result<(FeLevel, FeSpec), SpecError> {
    let (size, cells) = mesh_of(spec)?;
    let elements = named(
        "elements",
        spec.elements.as_deref(),
        &Element::ALL,
        Element::name,
    )?;
    let both = [Bases::Clamped, Bases::Sliding];
    let bases = named("bases", spec.bases.as_deref(), &both, bases_name)?;
    let (forms, written) = forms(spec.incompressibility.as_deref(), d)?;
    let configs = elements.len() * bases.len() * forms.len();
    if configs > MAX_CONFIGS {
        let rule =
            format!("at most {MAX_CONFIGS} elements × bases × incompressibility configurations");
        return Err(SpecError::new("elements", configs, rule));
    }
    let stretch = spec.stretch.unwrap_or(1.1);
    if !(stretch.is_finite() && stretch > 0.5 && stretch < 2.0 && stretch != 1.0) {
        let rule = "the load step's end λ₁ must lie in (0.5, 2) and differ from 1";
        return Err(SpecError::new("stretch", stretch, rule));
    }
    let model = model_of(spec, d)?;
    let max_iterations = spec.max_iterations.unwrap_or(50);
    let max_iterations = integer_in("max_iterations", max_iterations, 1..=500, "")?;
    let written = FeSpec {
        radius: Some(size.0),
        length: Some(size.1),
        nr: Some(cells.0 as i64),
        nz: Some(cells.1 as i64),
        elements: Some(elements.iter().map(|e| e.name().to_string()).collect()),
        bases: Some(bases.iter().map(|b| bases_name(*b).to_string()).collect()),
        incompressibility: Some(written),
        stretch: Some(stretch),
        law: Some(model.law),
        coupling: Some(model.coupling),
        damage: Some(model.damage),
        max_iterations: Some(max_iterations as i64),
    };
    let level = FeLevel {
        size,
        cells,
        elements,
        bases,
        forms,
        stretch,
        model,
        max_iterations,
    };
    Ok((level, written))
}

/// What the FE level computed.
#[derive(Debug, Clone, PartialEq)]
pub struct FeResult {
    /// The model's label.
    pub model: String,
    /// (λ₀, λ₁).
    pub stretches: (f64, f64),
    /// Cells in r and z.
    pub cells: (usize, usize),
    /// One entry per element × bases × incompressibility.
    pub configs: Vec<FeConfig>,
    /// Configurations that could not be set up or solved, and why.
    pub failures: Vec<Failure>,
}

/// One element × bases × incompressibility.
#[derive(Debug, Clone, PartialEq)]
pub struct FeConfig {
    /// The element.
    pub element: Element,
    /// The bases.
    pub bases: Bases,
    /// The incompressibility's name.
    pub incompressibility: String,
    /// Free dofs.
    pub dofs: usize,
    /// The Taylor tests of the assembled residual.
    pub taylor: Vec<FeTaylor>,
    /// Newton with each tangent.
    pub newton: Vec<NewtonRun>,
}

/// One Taylor test of the assembled residual.
#[derive(Debug, Clone, PartialEq)]
pub struct FeTaylor {
    /// `predictor` or `converged`.
    pub state: &'static str,
    /// The tangent: `exact`, `symmetric frozen` or `finite differences`.
    pub tangent: &'static str,
    /// The remainders, or why there are none.
    pub outcome: Result<AssembledTaylor, String>,
}

/// Newton over the load step with one tangent, from the step's predictor.
#[derive(Debug, Clone, PartialEq)]
pub struct NewtonRun {
    /// The tangent.
    pub tangent: &'static str,
    /// The solver's scaled residual at the predictor, then after each iteration.
    pub residuals: Vec<f64>,
    /// Whether it reached the tolerance within the iterations allowed.
    pub converged: bool,
    /// Wall time per iteration (assembly with the tangent, factorisation, solve) \[s\].
    pub seconds_per_iteration: f64,
    /// Why it stopped before the tolerance, if it did (divergence, a material error).
    pub failure: Option<String>,
}

impl NewtonRun {
    /// Iterations to the tolerance (`None`: not reached).
    pub fn iterations(&self) -> Option<usize> {
        self.converged
            .then(|| self.residuals.len().saturating_sub(1))
    }

    /// The time to the tolerance, iterations × time per iteration \[s\] (`None`: not reached).
    pub fn seconds_to_converge(&self) -> Option<f64> {
        self.iterations()
            .map(|n| n as f64 * self.seconds_per_iteration)
    }
}

/// What a tangent cost Newton over the FE level's configurations.
#[derive(Debug, Clone, PartialEq)]
pub struct TangentCost {
    /// The tangent.
    pub tangent: &'static str,
    /// Configurations run with it.
    pub runs: usize,
    /// How many of them reached the tolerance.
    pub converged: usize,
    /// How many of them failed (diverged, or the material could not be evaluated).
    pub failed: usize,
    /// The fewest and most iterations to the tolerance, over those that reached it.
    pub iterations: Option<(usize, usize)>,
    /// The least and largest time to the tolerance, over those that reached it \[s\].
    pub seconds_to_converge: Option<(f64, f64)>,
    /// The median time per iteration \[s\].
    pub seconds_per_iteration: Option<f64>,
    /// Of the runs that did not reach it: the most iterations run and the largest residual left.
    pub left: Option<(usize, f64)>,
}

/// The least and largest of `values`.
fn range<T: Copy + PartialOrd>(values: impl Iterator<Item = T>) -> Option<(T, T)> {
    values.fold(None, |r, v| match r {
        None => Some((v, v)),
        Some((lo, hi)) => Some((if v < lo { v } else { lo }, if v > hi { v } else { hi })),
    })
}

impl FeResult {
    /// Per tangent (in the order the configurations ran them), what it cost Newton.
    pub fn costs(&self) -> Vec<TangentCost> {
        let runs = || self.configs.iter().flat_map(|c| c.newton.iter());
        let mut names: Vec<&'static str> = Vec::new();
        for n in runs() {
            if !names.contains(&n.tangent) {
                names.push(n.tangent);
            }
        }
        names
            .into_iter()
            .map(|tangent| {
                let of: Vec<&NewtonRun> = runs().filter(|n| n.tangent == tangent).collect();
                let missed = of.iter().filter(|n| !n.converged && n.failure.is_none());
                TangentCost {
                    tangent,
                    runs: of.len(),
                    converged: of.iter().filter(|n| n.converged).count(),
                    failed: of.iter().filter(|n| n.failure.is_some()).count(),
                    iterations: range(of.iter().filter_map(|n| n.iterations())),
                    seconds_to_converge: range(of.iter().filter_map(|n| n.seconds_to_converge())),
                    seconds_per_iteration: crate::tangent_check::taylor::median(
                        of.iter()
                            .filter(|n| n.residuals.len() > 1)
                            .map(|n| n.seconds_per_iteration)
                            .collect(),
                    ),
                    left: missed
                        .filter_map(|n| Some((n.residuals.len() - 1, *n.residuals.last()?)))
                        .reduce(|a, b| (a.0.max(b.0), a.1.max(b.1))),
                }
            })
            .collect()
    }
}

/// The tolerance on the solver's scaled residual (the solver's default).
const TOLERANCE: f64 = 1e-10;
/// The solver's stress floor \[kPa\].
const STRESS_FLOOR: f64 = 1e-6;

/// The tangents the solver can use for a muscle: (name, material).
type Variants<'a> = Vec<(&'static str, Box<dyn AxisymmetricMaterial + 'a>)>;

impl FeLevel {
    /// One line for `check`.
    pub fn describe(&self) -> String {
        format!(
            "FE level: {} × {} cells, {} element(s) × {} bases × {} incompressibility, load step to λ = {}",
            self.cells.0,
            self.cells.1,
            self.elements.len(),
            self.bases.len(),
            self.forms.len(),
            self.stretch
        )
    }

    /// λ₀ and the load step.
    fn steps(&self) -> (f64, f64) {
        let lambda_0 = 0.5 * (1.0 + self.stretch);
        (lambda_0, (self.stretch - 1.0).abs() / 2.0)
    }

    /// Every configuration; one that fails is a failure, the others go on.
    pub fn run(&self, models: &Models, h: &[f64], seed: u64, ctx: &RunContext) -> FeResult {
        let label = models.label(&self.model);
        let mut out = FeResult {
            model: label.clone(),
            stretches: (self.steps().0, self.stretch),
            cells: self.cells,
            configs: Vec::new(),
            failures: Vec::new(),
        };
        for &element in &self.elements {
            for &bases in &self.bases {
                for form in &self.forms {
                    let what = format!(
                        "FE level, {element}, {} bases, {} incompressibility",
                        bases_name(bases),
                        form.0
                    );
                    ctx.progress.log(&what);
                    match self.config(models, (element, bases, form), h, seed) {
                        Ok(c) => out.configs.push(c),
                        Err(e) => out.failures.push(Failure {
                            model: format!("{label}, {what}"),
                            message: e.to_string(),
                        }),
                    }
                }
            }
        }
        out
    }

    /// The muscle of the model with `frozen` as the frozen tangent.
    fn muscle(&self, models: &Models, frozen: FrozenTangent) -> crate::Result<Muscle<Energy>> {
        Models {
            frozen_tangent: frozen,
            ..models.clone()
        }
        .muscle(self.model)
    }

    /// One configuration: the exact solve to λ₀ and λ₁, the predictor, the Taylor tests and
    /// Newton with each tangent.
    fn config(
        &self,
        models: &Models,
        (element, bases, form): (Element, Bases, &(String, Option<Volumetric>)),
        h: &[f64],
        seed: u64,
    ) -> Result<FeConfig, AppError> {
        let exact = self.muscle(models, FrozenTangent::Exact)?;
        let symmetric = self.muscle(models, FrozenTangent::Symmetric)?;
        let mut variants: Variants<'_> = vec![("exact", Box::new(exact.clone()))];
        if !exact.symmetric_tangent() {
            variants.push(("symmetric frozen", Box::new(symmetric)));
        }
        variants.push(("finite differences", Box::new(CentralDifferences(&exact))));
        let mesh = Mesh::structured(self.size.0, self.size.1, self.cells.0, self.cells.1, 1.0)?
            .with_element(element);
        let at = (mesh, bases, form.1, self.cells);
        let lambdas = (self.steps().0, self.stretch);
        let (x0, x1) = converged(&at, &exact, lambdas)?;
        let start = predictor(&at, &exact, &x0, lambdas)?;
        let taylor = taylor_tests(
            &at,
            &variants,
            [("predictor", &start), ("converged", &x1)],
            h,
            seed,
        )?;
        let newton = variants
            .iter()
            .map(|(name, material)| {
                newton(name, &at, material.as_ref(), &start, self.max_iterations)
            })
            .collect();
        Ok(FeConfig {
            element,
            bases,
            incompressibility: form.0.clone(),
            dofs: DofMap::new(&at.0, bases).n_free,
            taylor,
            newton,
        })
    }
}

/// The mesh (with its element), bases, volumetric energy and cells (r, z) of a configuration.
type At = (Mesh, Bases, Option<Volumetric>, (usize, usize));

/// The mixed problem of `material` on a configuration, its tangent solved by LU.
fn problem<'m, M: AxisymmetricMaterial + ?Sized>(
    (mesh, bases, volumetric, _): &At,
    material: &'m M,
) -> Result<MixedProblem<'m, M>, AppError> {
    let dofs = DofMap::new(mesh, *bases);
    let asm = crate::fem::assembly::Assembler::with_volumetric(mesh, &dofs, *volumetric)?;
    let linear = TangentSolver::new(asm.pattern.n, None, material.symmetric_tangent(), 1);
    Ok(MixedProblem::new(
        mesh.clone(),
        dofs,
        asm,
        linear,
        material,
        STRESS_FLOOR,
    ))
}

/// The converged states at λ₀ and λ₁ (the solver's sweep with `exact`).
fn converged(
    at: &At,
    exact: &Muscle<Energy>,
    (lambda_0, lambda_1): (f64, f64),
) -> Result<(Vec<f64>, Vec<f64>), AppError> {
    let options = SolverOptions {
        element: at.0.element,
        volumetric: at.2,
        ..SolverOptions::default()
    };
    let mut solver = AxisymmetricSolver::new(at.0.clone(), at.1, exact, options)?;
    let results = solver.sweep(&[lambda_0, lambda_1])?.into_result()?;
    let state = |l: f64| {
        results
            .iter()
            .find(|r| (r.stretch - l).abs() < 1e-12)
            .map(|r| r.state.x.clone())
            .ok_or_else(|| AppError::Invalid(format!("the sweep did not report λ = {l}")))
    };
    Ok((state(lambda_0)?, state(lambda_1)?))
}

/// The driver's tangent predictor of the step λ₀ → λ₁: x(λ₀) + (λ₁ − λ₀) dx/dλ, with dx/dλ
/// from the exact tangent factorised at x(λ₀).
fn predictor(
    at: &At,
    exact: &Muscle<Energy>,
    x0: &[f64],
    (lambda_0, lambda_1): (f64, f64),
) -> Result<Vec<f64>, AppError> {
    let mut problem = problem(at, exact)?;
    problem.evaluate(x0, true)?;
    let failed = |e: crate::fem::StepFailure| {
        AppError::Invalid(format!("the load rate at λ₀ = {lambda_0}: {e}"))
    };
    // The Newton direction factorises the tangent (≈ 0 itself at a converged state).
    let mut dx = vec![0.0; problem.dofs.n_free];
    problem.newton_direction(&mut dx, true).map_err(failed)?;
    let mut rate = vec![0.0; x0.len()];
    problem.load_rate(&mut rate).map_err(failed)?;
    Ok(x0
        .iter()
        .zip(&rate)
        .map(|(x, r)| x + (lambda_1 - lambda_0) * r)
        .collect())
}

/// Newton from `start` with `material`'s tangent, full steps: the solver's scaled residual
/// before and after each iteration, until it is ≤ [`TOLERANCE`], grows 10³-fold, or
/// `max_iterations`; the median wall time of an iteration (factorisation, solve, assembly with
/// the tangent), after one untimed factorisation at the start (the LU's symbolic analysis).
fn newton(
    name: &'static str,
    at: &At,
    material: &dyn AxisymmetricMaterial,
    start: &[f64],
    max_iterations: usize,
) -> NewtonRun {
    let mut run = NewtonRun {
        tangent: name,
        residuals: Vec::new(),
        converged: false,
        seconds_per_iteration: 0.0,
        failure: None,
    };
    let mut times = Vec::new();
    let mut iterate = || -> Result<(), AppError> {
        let mut problem = problem(at, material)?;
        let nf = problem.dofs.n_free;
        let (mut x, mut dx) = (start.to_vec(), vec![0.0; nf]);
        let direction = |problem: &mut MixedProblem<'_, dyn AxisymmetricMaterial>,
                         dx: &mut [f64]| {
            problem
                .newton_direction(dx, true)
                .map_err(|e| AppError::Invalid(e.to_string()))
        };
        problem.evaluate(&x, true)?;
        run.residuals.push(problem.residual_norm(problem.scale()));
        direction(&mut problem, &mut dx)?;
        for _ in 0..max_iterations {
            let clock = Instant::now();
            direction(&mut problem, &mut dx)?;
            for (xi, di) in x[..nf].iter_mut().zip(&dx) {
                *xi += di;
            }
            problem.evaluate(&x, true)?;
            times.push(clock.elapsed().as_secs_f64());
            let r = problem.residual_norm(problem.scale());
            run.residuals.push(r);
            if r <= TOLERANCE {
                run.converged = true;
                break;
            }
            if r.is_nan() || r >= 1e3 * run.residuals[0] {
                return Err(AppError::Invalid(format!(
                    "diverged: scaled residual {r:.3e}"
                )));
            }
        }
        Ok(())
    };
    if let Err(e) = iterate() {
        run.failure = Some(e.to_string());
    }
    run.seconds_per_iteration = crate::tangent_check::taylor::median(times).unwrap_or(0.0);
    run
}

/// The Taylor tests of every tangent at each of `states`.
fn taylor_tests(
    at: &At,
    variants: &Variants<'_>,
    states: [(&'static str, &[f64]); 2],
    h: &[f64],
    seed: u64,
) -> Result<Vec<FeTaylor>, AppError> {
    let (name, exact) = &variants[0];
    debug_assert_eq!(*name, "exact");
    let mut problem = problem(at, exact.as_ref())?;
    problem.evaluate(states[1].1, false)?;
    let sigma = problem.asm.stress_scale.max(STRESS_FLOOR);
    let (nf, nu) = (problem.dofs.n_free, problem.dofs.n_free_u);
    // Displacements of the size of a cell (ΔF ≈ h), pressures of the largest stress.
    let cell = (at.0.radius / at.3 .0 as f64).min(at.0.length / at.3 .1 as f64);
    let mut s = Sampler::new(seed ^ 0xFE1E_7E57);
    let v: Vec<f64> = (0..nf)
        .map(|k| s.normal() * if k < nu { cell } else { sigma })
        .collect();
    let mut out = Vec::new();
    for (state, x) in states {
        for (name, material) in variants {
            let outcome = assembled_taylor_test(
                &mut problem.asm,
                (&problem.mesh, &problem.dofs),
                material.as_ref(),
                x,
                &v,
                h,
            )
            .map_err(|e| e.to_string());
            out.push(FeTaylor {
                state,
                tangent: name,
                outcome,
            });
        }
    }
    Ok(out)
}
