//! The axisymmetric cylinder solver: the mixed u–p problem ([`super::problem`]) driven through
//! the requested stretches by the load-stepping Newton driver ([`super::continuation`]), with
//! results, VTK fields ([`super::vtk`]) and progress reported per stretch.
//!
//! Work is bounded before it starts: the memory the mesh needs is estimated from its counts
//! ([`super::memory`]) and a mesh above [`SolverOptions::memory_limit`] is refused with
//! [`FemError::MemoryLimit`] before anything large is allocated.

use super::assembly::Assembler;
pub use super::assembly::QuadraturePoint;
pub use super::continuation::{Cancel, IterationRecord, State, StepRecord, Stepping};
use super::continuation::{Continuation, Observer};
use super::dofs::{Bases, DofMap};
use super::element::{jacobian, Element};
use super::error::{FemError, FemResult};
use super::ldlt::SymmetricPartLdlt;
pub use super::linear_solver::LinearSolver;
use super::material::AxisymmetricMaterial;
use super::memory::MemoryEstimate;
use super::mesh::Mesh;
use super::problem::MixedProblem;
use super::tangent_solver::TangentSolver;
pub use super::timings::Timings;
use super::vtk;
use std::path::PathBuf;

/// Where and when to write VTK fields during a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct VtkOutput {
    /// Output directory (created if missing).
    pub directory: PathBuf,
    /// Stretches (among the sweep targets) at which to write the fields, as
    /// [`vtk::file_name`] names them (the path is returned in [`StretchResult::vtk_file`]).
    pub stretches: Vec<f64>,
}

/// The smallest admissible [`Stepping::tolerance`], 4 ε: the scaled residual and
/// increment of a solution in f64 are at least of the order of one rounding.
pub const MIN_TOLERANCE: f64 = 4.0 * f64::EPSILON;

/// Tolerances, load-stepping controls and limits.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverOptions {
    /// The driver's tolerance, load steps and Newton controls. Its tolerance applies to the
    /// scaled residual and increment of [`super::problem`] and is at least [`MIN_TOLERANCE`]; a
    /// sweep whose farthest target needs more than [`Stepping::max_steps`] steps of
    /// [`Stepping::max_step`] is refused before it starts.
    pub stepping: Stepping,
    /// Stress floor added to σ in the force scale \[kPa\] (guards the stress-free state).
    pub stress_floor: f64,
    /// Linear solver of the Newton system.
    pub linear_solver: LinearSolver,
    /// The element (the solver turns the mesh's cells into this element's: [`Mesh::with_element`]).
    pub element: Element,
    /// Optional VTK output.
    pub vtk: Option<VtkOutput>,
    /// Near incompressibility: Ψ + U(J) by the perturbed Lagrangian of
    /// [`super::element::ReferenceElement::residual_tangent`]; `None`: exact, J = 1.
    pub volumetric: Option<crate::volumetric::Volumetric>,
    /// Largest memory estimate accepted \[bytes\]; `None`: [`super::memory::default_limit`]
    /// (half the memory available when the solver is built).
    pub memory_limit: Option<u64>,
    /// When set (from another thread, a signal handler or the progress observer), the sweep
    /// stops before the next Newton iteration and returns what it solved.
    pub cancel: Option<Cancel>,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            stepping: Stepping::default(),
            stress_floor: 1e-6,
            linear_solver: LinearSolver::SymmetricPartGmres,
            element: Element::Q2Q1,
            vtk: None,
            volumetric: None,
            memory_limit: None,
            cancel: None,
        }
    }
}

impl SolverOptions {
    /// Every option in its admissible range.
    fn validate(&self) -> FemResult<()> {
        let stepping = &self.stepping;
        check_positive("tolerance", stepping.tolerance)?;
        if stepping.tolerance < MIN_TOLERANCE {
            return Err(FemError::InvalidInput {
                name: "tolerance",
                value: crate::text::shortest(stepping.tolerance),
                rule:
                    "must be ≥ 4 ε ≈ 8.9e-16: a scaled residual of f64 numbers does not go below \
                       its round-off",
            });
        }
        check_positive("initial_step", stepping.initial_step)?;
        check_positive("max_step", stepping.max_step)?;
        check_positive("min_step", stepping.min_step)?;
        if !(self.stress_floor.is_finite() && self.stress_floor >= 0.0) {
            return Err(FemError::InvalidInput {
                name: "stress_floor",
                value: crate::text::shortest(self.stress_floor),
                rule: "must be finite and ≥ 0",
            });
        }
        for (name, value) in [
            ("max_iterations", stepping.max_iterations),
            ("max_steps", stepping.max_steps),
        ] {
            if value == 0 {
                return Err(FemError::InvalidInput {
                    name,
                    value: "0".into(),
                    rule: "must be ≥ 1",
                });
            }
        }
        Ok(())
    }
}

/// Everything reported at a converged target stretch.
#[derive(Debug, Clone, PartialEq)]
pub struct StretchResult {
    /// Applied stretch λ.
    pub stretch: f64,
    /// Nominal axial stress = reaction / (πR²) \[kPa\].
    pub nominal_stress: f64,
    /// Axial reaction on the moving base (virtual-work reaction from the discrete residual).
    pub reaction: f64,
    /// Activation γ at the quadrature point nearest to the centre (r = 0, z = L/2).
    pub gamma_centre: f64,
    /// Fibre stretch at the same point.
    pub fibre_stretch_centre: f64,
    /// max |J − 1| over all quadrature points.
    pub max_volume_error: f64,
    /// Where: the reference (r, z) of that quadrature point.
    pub max_volume_error_at: [f64; 2],
    /// max |J̄ − 1| over the cells, J̄ the volume-weighted mean of J over a cell (what the VTK
    /// files show), and the reference (r, z) of that cell's centroid.
    pub max_cell_volume_error: (f64, [f64; 2]),
    /// Load steps (accepted and rejected) taken since the previous target.
    pub steps: Vec<StepRecord>,
    /// The solution.
    pub state: State,
    /// The VTK file written for this stretch ([`SolverOptions::vtk`]), if any.
    pub vtk_file: Option<PathBuf>,
}

/// Outcome of a sweep: the converged targets (ascending λ) and, per direction that stopped, its error.
#[derive(Debug)]
pub struct Sweep {
    /// Converged targets, ascending in λ.
    pub results: Vec<StretchResult>,
    /// Errors of directions that could not reach all their targets ([`FemError::Cancelled`]
    /// when the sweep was cancelled).
    pub failures: Vec<FemError>,
    /// For each failure, the quadrature points of its last rejected trial state (for a
    /// material-stability diagnosis, e.g. [`crate::stability::diagnose_axisymmetric`]).
    pub failed_trials: Vec<Option<Vec<QuadraturePoint>>>,
}

impl Sweep {
    /// The results if every target was reached, else the first failure.
    pub fn into_result(self) -> FemResult<Vec<StretchResult>> {
        match self.failures.into_iter().next() {
            Some(e) => Err(e),
            None => Ok(self.results),
        }
    }
}

/// What a running sweep reports ([`AxisymmetricSolver::sweep_with`]).
#[derive(Debug, Clone, Copy)]
pub enum Progress<'a> {
    /// A load step converged.
    Step(&'a StepRecord),
    /// A target stretch was solved (in the order solved: λ = 1, then upwards, then downwards).
    Stretch(&'a StretchResult),
}

/// The axisymmetric mixed u–p solver for one mesh, boundary-condition variant and material.
pub struct AxisymmetricSolver<'m, M: AxisymmetricMaterial + ?Sized> {
    problem: MixedProblem<'m, M>,
    driver: Continuation,
    options: SolverOptions,
    /// Index, among the quadrature points, of the one nearest to the centre (r = 0, z = L/2).
    centre: usize,
    estimate: MemoryEstimate,
}

impl<M: AxisymmetricMaterial + ?Sized> std::fmt::Debug for AxisymmetricSolver<'_, M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AxisymmetricSolver")
            .field("element", &self.problem.mesh.element)
            .field("elements", &self.problem.mesh.n_elements())
            .field("dofs", &self.problem.dofs.n_total)
            .field("free_dofs", &self.problem.dofs.n_free)
            .finish()
    }
}

fn check_positive(name: &'static str, v: f64) -> FemResult<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(FemError::InvalidInput {
            name,
            value: crate::text::shortest(v),
            rule: "must be finite and > 0",
        })
    }
}

impl<'m, M: AxisymmetricMaterial + ?Sized> AxisymmetricSolver<'m, M> {
    /// Sets up dofs, pattern and symbolic factorisation for `mesh` with `bases` and `material`.
    /// The cells are those of `options.element` on `mesh`'s geometry ([`Mesh::with_element`]:
    /// Q1/P0 on a 9-node mesh uses its corners). Refuses with [`FemError::MemoryLimit`], before
    /// allocating the system, a mesh whose estimated memory exceeds the limit.
    pub fn new(
        mesh: Mesh,
        bases: Bases,
        material: &'m M,
        options: SolverOptions,
    ) -> FemResult<Self> {
        options.validate()?;
        let limit = options
            .memory_limit
            .unwrap_or_else(super::memory::default_limit);
        let mesh = mesh.with_element(options.element);
        let estimate = mesh.memory_estimate(options.linear_solver);
        estimate.check(limit)?;
        let dofs = DofMap::new(&mesh, bases);
        let asm = Assembler::with_volumetric(&mesh, &dofs, options.volumetric)?;
        let ldlt = match options.linear_solver {
            LinearSolver::Lu => None,
            LinearSolver::SymmetricPartGmres => Some(
                SymmetricPartLdlt::for_mesh(&asm.pattern, &mesh, &dofs, asm.system_index())
                    .map_err(FemError::LinearSolver)?,
            ),
        };
        // The exact counts, before any factor value is written.
        let factor_values = ldlt.as_ref().map(|l| l.symbolic().len_val());
        let estimate = estimate.with_counts(dofs.n_free, asm.pattern.row_idx.len(), factor_values);
        estimate.check(limit)?;
        let linear = TangentSolver::new(
            asm.pattern.n,
            ldlt,
            material.symmetric_tangent(),
            rayon::current_num_threads(),
        );
        let centre = nearest_to_centre(&asm.quadrature_points(&vec![0.0; dofs.n_total]), &mesh);
        let driver = Continuation::new(dofs.n_total, options.stepping, options.cancel.clone());
        let problem = MixedProblem::new(mesh, dofs, asm, linear, material, options.stress_floor);
        Ok(Self {
            problem,
            driver,
            options,
            centre,
            estimate,
        })
    }

    /// The memory estimate of this solve (exact dofs, nonzeros and factor size) checked
    /// against [`SolverOptions::memory_limit`].
    pub fn memory_estimate(&self) -> &MemoryEstimate {
        &self.estimate
    }

    /// The mesh solved on: the cells of [`SolverOptions::element`] (for Q1/P0 on a 9-node mesh,
    /// its corners), numbered as [`Self::dofs`] numbers them.
    pub fn mesh(&self) -> &Mesh {
        &self.problem.mesh
    }

    /// The dof numbering.
    pub fn dofs(&self) -> &DofMap {
        &self.problem.dofs
    }

    /// Number of free dofs (the unknowns of the discrete problem; the linear system of a
    /// Newton iteration has fewer when the Q2/Q1 centre nodes are condensed out, see
    /// [`super::condensation`]).
    pub fn n_free_dofs(&self) -> usize {
        self.problem.dofs.n_free
    }

    /// Accumulated timings.
    pub fn timings(&self) -> Timings {
        Timings {
            newton_iterations: self.driver.newton_iterations(),
            ..self.problem.timings
        }
    }

    /// Resets the accumulated timings.
    pub fn reset_timings(&mut self) {
        self.problem.timings = Timings::default();
        self.driver.reset_count();
    }

    /// The trial state at which the last rejected Newton step failed (material error, last
    /// iterate, …), kept for diagnostics. See [`Self::failed_trial_quadrature_points`].
    pub fn failed_trial(&self) -> Option<&State> {
        self.driver.failed_trial()
    }

    /// The deformation gradients at every quadrature point of the last failed trial state:
    /// the hook for a material-stability (strong-ellipticity) check after a failure.
    pub fn failed_trial_quadrature_points(&self) -> Option<Vec<QuadraturePoint>> {
        self.failed_trial().map(|s| self.quadrature_points(s))
    }

    /// F, p, position and volume weight at every quadrature point of `state`.
    pub fn quadrature_points(&self, state: &State) -> Vec<QuadraturePoint> {
        self.problem.asm.quadrature_points(&state.x)
    }

    /// The element in use.
    pub fn element(&self) -> Element {
        self.problem.mesh.element
    }

    /// Runs the load path through every target stretch (λ = 1 outwards in both directions).
    ///
    /// Targets must be finite and > 0; a target of 1 reports the reference state. A direction
    /// that cannot reach a target stops there with [`FemError::TargetNotReached`] in
    /// [`Sweep::failures`]; the other direction is still run.
    pub fn sweep(&mut self, targets: &[f64]) -> FemResult<Sweep> {
        self.sweep_with(targets, &mut |_| {})
    }

    /// [`Self::sweep`], reporting every converged load step and every solved target to
    /// `observer` as it happens. A cancelled sweep ([`SolverOptions::cancel`]) returns the
    /// targets solved before, with [`FemError::Cancelled`] as its failure.
    pub fn sweep_with(
        &mut self,
        targets: &[f64],
        observer: &mut dyn FnMut(Progress<'_>),
    ) -> FemResult<Sweep> {
        self.check_targets(targets)?;
        let mut reporter = Reporter {
            centre: self.centre,
            vtk: self.options.vtk.as_ref(),
            results: Vec::new(),
            observer,
        };
        let failures = self
            .driver
            .sweep(&mut self.problem, targets, &mut reporter)?;
        let mut results = reporter.results;
        results.sort_by(|a, b| a.stretch.total_cmp(&b.stretch));
        let (failures, failed_trials) = failures
            .into_iter()
            .map(|(e, trial)| (e, trial.map(|s| self.quadrature_points(&s))))
            .unzip();
        Ok(Sweep {
            results,
            failures,
            failed_trials,
        })
    }

    /// Targets: at least one, each finite and > 0, the farthest reachable within
    /// [`Stepping::max_steps`] steps of [`Stepping::max_step`].
    fn check_targets(&self, targets: &[f64]) -> FemResult<()> {
        if targets.is_empty() {
            return Err(FemError::InvalidInput {
                name: "targets",
                value: "[]".into(),
                rule: "need at least one target stretch",
            });
        }
        for &t in targets {
            check_positive("target stretch", t)?;
            let stepping = &self.options.stepping;
            if (t - 1.0).abs() / stepping.max_step > stepping.max_steps as f64 {
                return Err(FemError::InvalidInput {
                    name: "target stretch",
                    value: crate::text::shortest(t),
                    rule: "needs more load steps of max_step from λ = 1 than max_steps allows",
                });
            }
        }
        Ok(())
    }

    /// Writes `state` as a VTK XML unstructured grid (see [`vtk::write_state`]).
    pub fn write_vtu(&self, state: &State, path: &std::path::Path) -> FemResult<()> {
        let p = &self.problem;
        let qps = self.quadrature_points(state);
        vtk::write_state(path, &p.mesh, &p.dofs, p.material, &qps, &state.x)
    }
}

/// Index of the quadrature point nearest to the centre (r = 0, z = L/2) of `mesh`.
fn nearest_to_centre(qps: &[QuadraturePoint], mesh: &Mesh) -> usize {
    let target = [0.0, 0.5 * mesh.length];
    let mut centre = 0;
    let mut best = f64::INFINITY;
    for (i, q) in qps.iter().enumerate() {
        let d = (q.r - target[0]).powi(2) + (q.z - target[1]).powi(2);
        if d < best {
            best = d;
            centre = i;
        }
    }
    centre
}

/// The largest |J̄ − 1| over the cells, J̄ the volume-weighted mean of J over a cell's
/// quadrature points, and the reference (r, z) of that cell's centroid.
fn cell_volume_error(qps: &[QuadraturePoint], n_cells: usize) -> (f64, [f64; 2]) {
    // Per cell: ∫ J, ∫ r, ∫ z, ∫ dV.
    let mut sums = vec![[0.0f64; 4]; n_cells];
    for q in qps {
        let c = &mut sums[q.element];
        c[0] += jacobian(&q.f) * q.dv;
        c[1] += q.r * q.dv;
        c[2] += q.z * q.dv;
        c[3] += q.dv;
    }
    sums.iter()
        .filter(|c| c[3] > 0.0)
        .map(|c| ((c[0] / c[3] - 1.0).abs(), [c[1] / c[3], c[2] / c[3]]))
        .fold((0.0, [0.0; 2]), |m, e| if e.0 > m.0 { e } else { m })
}

/// Turns the driver's reached targets into results, writes the requested VTK files and passes
/// the progress on.
struct Reporter<'a, 'o> {
    centre: usize,
    vtk: Option<&'a VtkOutput>,
    results: Vec<StretchResult>,
    observer: &'o mut dyn FnMut(Progress<'_>),
}

impl<M: AxisymmetricMaterial + ?Sized> Observer<MixedProblem<'_, M>> for Reporter<'_, '_> {
    fn reached(
        &mut self,
        problem: &mut MixedProblem<'_, M>,
        stretch: f64,
        x: &[f64],
        steps: Vec<StepRecord>,
    ) -> FemResult<()> {
        let reaction = problem.reaction();
        let qps = problem.asm.quadrature_points(x);
        let (max_volume_error, max_volume_error_at) = qps
            .iter()
            .map(|q| ((jacobian(&q.f) - 1.0).abs(), [q.r, q.z]))
            .fold((0.0f64, [0.0; 2]), |m, e| if e.0 > m.0 { e } else { m });
        let max_cell_volume_error = cell_volume_error(qps.as_slice(), problem.mesh.n_elements());
        let centre = qps.get(self.centre).ok_or(FemError::InvalidInput {
            name: "mesh",
            value: format!("{} quadrature points", qps.len()),
            rule: "must keep the quadrature point nearest to the centre",
        })?;
        let (gamma_centre, fibre_stretch_centre) = problem
            .material
            .point_fields_at(&centre.f, [centre.r, centre.z])?;
        let vtk_file = match self.vtk {
            Some(v) if v.stretches.iter().any(|&s| (s - stretch).abs() < 1e-12) => {
                let (mesh, dofs) = (&problem.mesh, &problem.dofs);
                let dir = &v.directory;
                let material = problem.material;
                Some(vtk::write_stretch(
                    dir, stretch, mesh, dofs, material, &qps, x,
                )?)
            }
            _ => None,
        };
        let result = StretchResult {
            stretch,
            nominal_stress: reaction / (std::f64::consts::PI * problem.mesh.radius.powi(2)),
            reaction,
            gamma_centre,
            fibre_stretch_centre,
            max_volume_error,
            max_volume_error_at,
            max_cell_volume_error,
            steps,
            state: State {
                stretch,
                x: x.to_vec(),
            },
            vtk_file,
        };
        (self.observer)(Progress::Stretch(&result));
        self.results.push(result);
        Ok(())
    }

    fn step_accepted(&mut self, record: &StepRecord) {
        (self.observer)(Progress::Step(record));
    }
}
