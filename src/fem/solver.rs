//! Newton's method with load stepping for the axisymmetric mixed problem.
//!
//! Load path: from λ = 1 outwards in both directions (each direction starts from the λ = 1
//! state), landing exactly on every requested stretch. Each load step uses a tangent predictor
//! (x ← x_k + Δλ dx/dλ with K dx/dλ = −K_fc d_c at the last converged state), then Newton with
//! backtracking line search on a scaled residual norm. A rejected step (no convergence, material
//! error at a trial state, failed line search, singular tangent) is halved; after easy steps the
//! step grows back. Below the minimum step the sweep stops with [`FemError::TargetNotReached`].
//!
//! Convergence (both required), with σ the largest stress magnitude at the quadrature points
//! (plus a small floor), A = πR², V = πR²L:
//!
//! ‖R_u‖₂ / (σ A) ≤ tol   and   ‖R_p‖₂ / V ≤ tol   (residual),
//! ‖Δu‖_∞ / L ≤ tol   and   ‖Δp‖_∞ / σ ≤ tol   (last Newton increment).

pub use super::assembly::QuadraturePoint;
use super::assembly::{Assembler, Pattern};
use super::dofs::{Bases, DofMap};
use super::element::{jacobian, jacobian_gradient, Element};
use super::error::{FemError, FemResult, StepFailure};
use super::ldlt::{SymmetricPartLdlt, Trailing};
use super::material::AxisymmetricMaterial;
use super::mesh::Mesh;
use super::tangent_solver::TangentSolver;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Where and when to write VTK fields during a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct VtkOutput {
    /// Output directory (created if missing).
    pub directory: PathBuf,
    /// Stretches (among the sweep targets) at which to write `lambda_<λ>.vtu`.
    pub stretches: Vec<f64>,
}

/// How the Newton system K Δx = −R is solved. Both give the exact Newton direction (to round-off).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinearSolver {
    /// GMRES on K preconditioned by LDLᵀ of (K + Kᵀ)/2 (fast; for a symmetric K one iteration),
    /// then by the LU on the LDLᵀ's pattern when GMRES does not converge, faer's LU as last
    /// resort (see [`super::tangent_solver`]).
    SymmetricPartGmres,
    /// faer's sparse LU with partial pivoting (COLAMD ordering) only.
    Lu,
}

/// Tolerances and load-stepping controls.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverOptions {
    /// Relative tolerance on the scaled residual and increment (see module docs).
    pub tolerance: f64,
    /// Stress floor added to σ in the force scale \[kPa\] (guards the stress-free state).
    pub stress_floor: f64,
    /// Newton iterations per load step before the step is cut.
    pub max_iterations: usize,
    /// First load step |Δλ|.
    pub initial_step: f64,
    /// Largest load step |Δλ|.
    pub max_step: f64,
    /// Smallest load step |Δλ| before giving up.
    pub min_step: f64,
    /// A step that converged in at most this many iterations counts as easy; two easy steps in a row double the step.
    pub easy_iterations: usize,
    /// Backtracking halvings in the line search (0: full Newton steps only).
    pub max_backtracks: usize,
    /// Linear solver of the Newton system.
    pub linear_solver: LinearSolver,
    /// The element (the solver turns the mesh's cells into this element's: [`Mesh::with_element`]).
    pub element: Element,
    /// Optional VTK output.
    pub vtk: Option<VtkOutput>,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-10,
            stress_floor: 1e-6,
            max_iterations: 25,
            initial_step: 0.05,
            max_step: 0.1,
            min_step: 1e-4,
            easy_iterations: 5,
            max_backtracks: 8,
            linear_solver: LinearSolver::SymmetricPartGmres,
            element: Element::Q2Q1,
            vtk: None,
        }
    }
}

/// One Newton iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationRecord {
    /// Scaled residual norm after the iteration (max of the displacement and pressure parts).
    pub residual: f64,
    /// Scaled increment norm of the iteration (step length included).
    pub increment: f64,
    /// Line-search step length.
    pub step_length: f64,
}

/// One attempted load step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRecord {
    /// Stretch the step started from.
    pub from: f64,
    /// Stretch the step aimed at.
    pub to: f64,
    /// Scaled residual of the predictor.
    pub initial_residual: f64,
    /// Newton iterations.
    pub iterations: Vec<IterationRecord>,
    /// `None` if converged, else why it was rejected.
    pub failure: Option<StepFailure>,
}

/// A discrete solution: all dofs (numbering of [`DofMap`]) at a stretch.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Applied stretch λ.
    pub stretch: f64,
    /// Dof values.
    pub x: Vec<f64>,
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
    /// Load steps (accepted and rejected) taken since the previous target.
    pub steps: Vec<StepRecord>,
    /// The solution.
    pub state: State,
}

/// Outcome of a sweep: the converged targets (ascending λ) and, per direction that stopped, its error.
#[derive(Debug)]
pub struct Sweep {
    /// Converged targets, ascending in λ.
    pub results: Vec<StretchResult>,
    /// Errors of directions that could not reach all their targets.
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

/// Accumulated wall-clock time of the solver phases.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Timings {
    /// Full assemblies (residual + tangent).
    pub assembly: Duration,
    /// Number of full assemblies.
    pub assemblies: usize,
    /// Residual-only assemblies (line search).
    pub residual_assembly: Duration,
    /// Number of residual-only assemblies.
    pub residual_assemblies: usize,
    /// Newton iterations (each: one full assembly, one tangent update, one solve).
    pub newton_iterations: usize,
    /// Numeric factorisations (LDLᵀ or LU).
    pub factorisation: Duration,
    /// Number of factorisations.
    pub factorisations: usize,
    /// Linear solves (GMRES and triangular solves, factorisations excluded).
    pub solve: Duration,
    /// Number of solves.
    pub solves: usize,
    /// GMRES iterations in all solves.
    pub krylov_iterations: usize,
    /// Solves that fell back to the sparse LU.
    pub lu_fallbacks: usize,
    /// Factorisations by the LU on the LDLᵀ's pattern (non-symmetric tangents).
    pub pattern_lu_factorisations: usize,
}

impl Timings {
    /// Wall-clock seconds per Newton iteration: all assemblies, factorisations and solves
    /// divided by the Newton iterations.
    pub fn per_newton_iteration(&self) -> f64 {
        let total = self.assembly + self.residual_assembly + self.factorisation + self.solve;
        total.as_secs_f64() / self.newton_iterations.max(1) as f64
    }
}

struct Converged {
    stretch: f64,
    x: Vec<f64>,
    rate: Vec<f64>,
}

/// The axisymmetric mixed u–p solver for one mesh, boundary-condition variant and material.
pub struct AxisymmetricSolver<'m, M: AxisymmetricMaterial + ?Sized> {
    mesh: Mesh,
    dofs: DofMap,
    asm: Assembler,
    linear: TangentSolver,
    material: &'m M,
    options: SolverOptions,
    timings: Timings,
    centre: (usize, usize),
    failed_trial: Option<State>,
    trial: Vec<f64>,
    delta: Vec<f64>,
}

impl<M: AxisymmetricMaterial + ?Sized> std::fmt::Debug for AxisymmetricSolver<'_, M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AxisymmetricSolver")
            .field("element", &self.mesh.element)
            .field("elements", &self.mesh.n_elements())
            .field("dofs", &self.dofs.n_total)
            .field("free_dofs", &self.dofs.n_free)
            .finish()
    }
}

fn check_positive(name: &'static str, v: f64) -> FemResult<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(FemError::InvalidInput {
            name,
            value: v.to_string(),
            rule: "must be finite and > 0",
        })
    }
}

/// Euclidean norm, scaled by the largest entry so that squares of huge residuals (stresses near
/// the exp-overflow limit) do not overflow.
fn norm2(v: &[f64]) -> f64 {
    let scale = norm_inf(v);
    if scale == 0.0 || !scale.is_finite() {
        return scale;
    }
    scale
        * v.iter()
            .map(|a| (a / scale) * (a / scale))
            .sum::<f64>()
            .sqrt()
}

fn norm_inf(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, a| m.max(a.abs()))
}

impl<'m, M: AxisymmetricMaterial + ?Sized> AxisymmetricSolver<'m, M> {
    /// Sets up dofs, pattern and symbolic factorisation for `mesh` with `bases` and `material`.
    /// The cells are those of `options.element` on `mesh`'s geometry ([`Mesh::with_element`]:
    /// Q1/P0 on a 9-node mesh uses its corners).
    pub fn new(
        mesh: Mesh,
        bases: Bases,
        material: &'m M,
        options: SolverOptions,
    ) -> FemResult<Self> {
        check_positive("tolerance", options.tolerance)?;
        check_positive("initial_step", options.initial_step)?;
        check_positive("max_step", options.max_step)?;
        check_positive("min_step", options.min_step)?;
        if !(options.stress_floor.is_finite() && options.stress_floor >= 0.0) {
            return Err(FemError::InvalidInput {
                name: "stress_floor",
                value: options.stress_floor.to_string(),
                rule: "must be finite and ≥ 0",
            });
        }
        if options.max_iterations == 0 {
            return Err(FemError::InvalidInput {
                name: "max_iterations",
                value: "0".into(),
                rule: "must be ≥ 1",
            });
        }
        let mesh = mesh.with_element(options.element);
        let dofs = DofMap::new(&mesh, bases);
        let asm = Assembler::new(&mesh, &dofs)?;
        let ldlt = match options.linear_solver {
            LinearSolver::Lu => None,
            LinearSolver::SymmetricPartGmres => {
                let (node_dofs, adjacency, trailing) = node_structure(&mesh, &dofs);
                Some(
                    SymmetricPartLdlt::new(&asm.pattern, &node_dofs, &adjacency, &trailing)
                        .map_err(FemError::LinearSolver)?,
                )
            }
        };
        let linear = TangentSolver::new(dofs.n_free, ldlt);
        // Quadrature point nearest to the centre (r = 0, z = L/2).
        let target = [0.0, 0.5 * mesh.length];
        let mut centre = (0, 0);
        let mut best = f64::INFINITY;
        for q in asm.quadrature_points(&vec![0.0; dofs.n_total]) {
            let d = (q.r - target[0]).powi(2) + (q.z - target[1]).powi(2);
            if d < best {
                best = d;
                centre = (q.element, q.point);
            }
        }
        let n = dofs.n_total;
        Ok(Self {
            mesh,
            dofs,
            asm,
            linear,
            material,
            options,
            timings: Timings::default(),
            centre,
            failed_trial: None,
            trial: vec![0.0; n],
            delta: vec![0.0; n],
        })
    }

    /// The mesh solved on: the cells of [`SolverOptions::element`] (for Q1/P0 on a 9-node mesh,
    /// its corners), numbered as [`Self::dofs`] numbers them.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The dof numbering.
    pub fn dofs(&self) -> &DofMap {
        &self.dofs
    }

    /// Number of dofs in the linear system (free dofs).
    pub fn n_free_dofs(&self) -> usize {
        self.dofs.n_free
    }

    /// Accumulated timings.
    pub fn timings(&self) -> Timings {
        self.timings
    }

    /// Resets the accumulated timings.
    pub fn reset_timings(&mut self) {
        self.timings = Timings::default();
    }

    /// The trial state at which the last rejected Newton step failed (material error, last
    /// iterate, …), kept for diagnostics. See [`Self::failed_trial_quadrature_points`].
    pub fn failed_trial(&self) -> Option<&State> {
        self.failed_trial.as_ref()
    }

    /// The deformation gradients at every quadrature point of the last failed trial state:
    /// the hook for a material-stability (strong-ellipticity) check after a failure.
    pub fn failed_trial_quadrature_points(&self) -> Option<Vec<QuadraturePoint>> {
        self.failed_trial
            .as_ref()
            .map(|s| self.quadrature_points(s))
    }

    /// F, p, position and volume weight at every quadrature point of `state`.
    pub fn quadrature_points(&self, state: &State) -> Vec<QuadraturePoint> {
        self.asm.quadrature_points(&state.x)
    }

    /// The element in use.
    pub fn element(&self) -> Element {
        self.mesh.element
    }

    fn assemble(&mut self, x: &[f64], tangent: bool) -> crate::Result<()> {
        let t = Instant::now();
        let r = self.asm.assemble(x, self.material, tangent);
        if tangent {
            self.timings.assembly += t.elapsed();
            self.timings.assemblies += 1;
        } else {
            self.timings.residual_assembly += t.elapsed();
            self.timings.residual_assemblies += 1;
        }
        r
    }

    fn force_scale(&self) -> f64 {
        (self.asm.stress_scale + self.options.stress_floor)
            * std::f64::consts::PI
            * self.mesh.radius.powi(2)
    }

    fn volume(&self) -> f64 {
        std::f64::consts::PI * self.mesh.radius.powi(2) * self.mesh.length
    }

    /// Scaled residual norm of the last assembly for a given force scale.
    fn scaled_residual(&self, force_scale: f64) -> f64 {
        let nu = self.dofs.n_free_u;
        let nf = self.dofs.n_free;
        let ru = norm2(&self.asm.residual[..nu]) / force_scale;
        let rp = norm2(&self.asm.residual[nu..nf]) / self.volume();
        ru.max(rp)
    }

    /// Factorises the tangent just assembled (see [`TangentSolver`]).
    fn factorise(&mut self) -> Result<(), StepFailure> {
        if let Some(k) = self.asm.values.iter().position(|v| !v.is_finite()) {
            return Err(StepFailure::Material(crate::Error::NonFinite {
                quantity: "assembled tangent",
                value: self.asm.values[k],
                context: format!("at nonzero {k}"),
            }));
        }
        self.linear
            .factorise(&self.asm.pattern, &self.asm.values, &mut self.timings)
            .map_err(|detail| StepFailure::SingularTangent { detail })
    }

    /// Solves K y = rhs in place, exactly to round-off (see [`TangentSolver`]).
    fn solve(&mut self, rhs: &mut [f64]) -> Result<(), StepFailure> {
        let t = Instant::now();
        let factorising = self.timings.factorisation;
        let r = self
            .linear
            .solve(&self.asm.pattern, &self.asm.values, rhs, &mut self.timings)
            .map_err(|detail| StepFailure::SingularTangent { detail });
        // Factorisations triggered inside the solve are counted as factorisation only.
        self.timings.solve += t.elapsed() - (self.timings.factorisation - factorising);
        self.timings.solves += 1;
        r
    }

    /// Newton's method at the stretch already set in `x` (prescribed dofs included).
    ///
    /// Each iteration solves K Δx = −R on the free dofs, then backtracks x + α Δx (α = 1, ½, …)
    /// until the scaled residual decreases (Armijo, c = 10⁻⁴), or accepts α = 1 when the
    /// residual is already at the tolerance (round-off floor). On success `x` holds the
    /// converged state and the assembler holds its residual (and tangent, unless the last step
    /// was backtracked).
    fn newton(&mut self, x: &mut Vec<f64>, record: &mut StepRecord) -> Result<(), StepFailure> {
        let tol = self.options.tolerance;
        let nf = self.dofs.n_free;
        let nu = self.dofs.n_free_u;
        if let Err(e) = self.assemble(x, true) {
            self.failed_trial = Some(State {
                stretch: record.to,
                x: x.clone(),
            });
            return Err(StepFailure::Material(e));
        }
        let mut have_tangent = true;
        let mut scale = self.force_scale();
        let mut phi = self.scaled_residual(scale);
        record.initial_residual = phi;
        for _ in 0..self.options.max_iterations {
            self.timings.newton_iterations += 1;
            if !have_tangent {
                if let Err(e) = self.assemble(x, true) {
                    self.failed_trial = Some(State {
                        stretch: record.to,
                        x: x.clone(),
                    });
                    return Err(StepFailure::Material(e));
                }
            }
            self.factorise()?;
            let mut delta = std::mem::take(&mut self.delta);
            for (d, r) in delta[..nf].iter_mut().zip(&self.asm.residual[..nf]) {
                *d = -r;
            }
            let solved = self.solve(&mut delta[..nf]);
            self.delta = delta;
            solved?;
            // Backtracking line search on the scaled residual, σ frozen at the current state.
            let mut alpha = 1.0;
            let mut accepted = false;
            let mut last_error = None;
            for k in 0..=self.options.max_backtracks {
                let full = k == 0;
                let mut trial = std::mem::take(&mut self.trial);
                trial.copy_from_slice(x);
                for (t, d) in trial[..nf].iter_mut().zip(&self.delta[..nf]) {
                    *t += alpha * d;
                }
                let result = self.assemble(&trial, full);
                self.trial = trial;
                match result {
                    Ok(()) => {
                        let phi_trial = self.scaled_residual(scale);
                        if phi_trial <= (1.0 - 1e-4 * alpha) * phi || (full && phi <= tol) {
                            accepted = true;
                            have_tangent = full;
                            phi = phi_trial;
                            break;
                        }
                        last_error = None;
                    }
                    Err(e) => last_error = Some(e),
                }
                alpha *= 0.5;
            }
            if !accepted {
                self.failed_trial = Some(State {
                    stretch: record.to,
                    x: self.trial.clone(),
                });
                return Err(match last_error {
                    Some(e) => StepFailure::Material(e),
                    None => StepFailure::LineSearch { residual: phi },
                });
            }
            std::mem::swap(x, &mut self.trial);
            scale = self.force_scale();
            let nu_inc = norm_inf(&self.delta[..nu]) * alpha / self.mesh.length;
            let np_inc = norm_inf(&self.delta[nu..nf]) * alpha
                / (self.asm.stress_scale + self.options.stress_floor);
            let increment = nu_inc.max(np_inc);
            let residual = self.scaled_residual(scale);
            record.iterations.push(IterationRecord {
                residual,
                increment,
                step_length: alpha,
            });
            phi = residual;
            if residual <= tol && increment <= tol {
                if !have_tangent {
                    // Leave the assembler consistent with the converged state (reaction, rate force).
                    if let Err(e) = self.assemble(x, true) {
                        return Err(StepFailure::Material(e));
                    }
                }
                return Ok(());
            }
        }
        self.failed_trial = Some(State {
            stretch: record.to,
            x: x.clone(),
        });
        Err(StepFailure::MaxIterations {
            iterations: self.options.max_iterations,
            residual: phi,
        })
    }

    /// dx/dλ at the converged state held by the assembler: K_ff v_f = −K_fc d_c, v_c = d_c.
    /// Uses the last factorisation (the tangent at the previous iterate, within tolerance).
    fn rate(&mut self) -> Result<Vec<f64>, StepFailure> {
        let nf = self.dofs.n_free;
        let mut v = vec![0.0; self.dofs.n_total];
        for (vi, g) in v[..nf].iter_mut().zip(&self.asm.rate_force[..nf]) {
            *vi = -g;
        }
        self.solve(&mut v[..nf])?;
        v[nf..].copy_from_slice(&self.dofs.prescribed_rate);
        Ok(v)
    }

    /// Axial reaction on z = L from the discrete residual at the prescribed u_z dofs.
    fn reaction(&self) -> f64 {
        self.dofs
            .top_axial
            .iter()
            .map(|&g| self.asm.residual[g as usize])
            .sum()
    }

    fn result_at(
        &self,
        x: &[f64],
        stretch: f64,
        steps: Vec<StepRecord>,
    ) -> FemResult<StretchResult> {
        let reaction = self.reaction();
        let state = State {
            stretch,
            x: x.to_vec(),
        };
        let qps = self.quadrature_points(&state);
        let max_volume_error = qps
            .iter()
            .fold(0.0f64, |m, q| m.max((jacobian(&q.f) - 1.0).abs()));
        let (gamma_centre, fibre_stretch_centre) = match qps
            .iter()
            .find(|q| q.element == self.centre.0 && q.point == self.centre.1)
        {
            Some(q) => self.material.point_fields(&q.f)?,
            None => (f64::NAN, f64::NAN),
        };
        Ok(StretchResult {
            stretch,
            nominal_stress: reaction / (std::f64::consts::PI * self.mesh.radius.powi(2)),
            reaction,
            gamma_centre,
            fibre_stretch_centre,
            max_volume_error,
            steps,
            state,
        })
    }

    /// Solves the reference state λ = 1 (the pressure balancing P(I)) from x = 0.
    fn reference_state(&mut self) -> Result<(Converged, StepRecord), StepFailure> {
        let mut x = vec![0.0; self.dofs.n_total];
        self.dofs.apply_stretch(&mut x, 1.0);
        let mut rec = StepRecord {
            from: 1.0,
            to: 1.0,
            initial_residual: 0.0,
            iterations: Vec::new(),
            failure: None,
        };
        match self.newton(&mut x, &mut rec).and_then(|_| self.rate()) {
            Ok(rate) => Ok((
                Converged {
                    stretch: 1.0,
                    x,
                    rate,
                },
                rec,
            )),
            Err(e) => Err(e),
        }
    }

    /// Runs the load path through every target stretch (λ = 1 outwards in both directions).
    ///
    /// Targets must be finite and > 0; a target of 1 reports the reference state. A direction
    /// that cannot reach a target stops there with [`FemError::TargetNotReached`] in
    /// [`Sweep::failures`]; the other direction is still run.
    pub fn sweep(&mut self, targets: &[f64]) -> FemResult<Sweep> {
        if targets.is_empty() {
            return Err(FemError::InvalidInput {
                name: "targets",
                value: "[]".into(),
                rule: "need at least one target stretch",
            });
        }
        for &t in targets {
            check_positive("target stretch", t)?;
        }
        let mut up: Vec<f64> = targets.iter().copied().filter(|&t| t > 1.0).collect();
        let mut down: Vec<f64> = targets.iter().copied().filter(|&t| t < 1.0).collect();
        up.sort_by(f64::total_cmp);
        up.dedup();
        down.sort_by(|a, b| b.total_cmp(a));
        down.dedup();
        let mut results = Vec::new();
        let mut failures = Vec::new();
        let mut failed_trials = Vec::new();
        let (reference, rec) = match self.reference_state() {
            Ok(v) => v,
            Err(cause) => {
                failures.push(FemError::ReferenceState { cause });
                return Ok(Sweep {
                    results,
                    failures,
                    failed_trials: vec![None],
                });
            }
        };
        if targets.contains(&1.0) {
            let r = self.result_at(&reference.x, 1.0, vec![rec])?;
            self.write_requested(&r)?;
            results.push(r);
        }
        for list in [&up, &down] {
            if list.is_empty() {
                continue;
            }
            let start = Converged {
                stretch: reference.stretch,
                x: reference.x.clone(),
                rate: reference.rate.clone(),
            };
            if let Err(e) = self.path(start, list, &mut results) {
                failures.push(e);
                failed_trials.push(self.failed_trial_quadrature_points());
            }
        }
        results.sort_by(|a, b| a.stretch.total_cmp(&b.stretch));
        Ok(Sweep {
            results,
            failures,
            failed_trials,
        })
    }

    fn path(
        &mut self,
        mut cur: Converged,
        targets: &[f64],
        results: &mut Vec<StretchResult>,
    ) -> FemResult<()> {
        let o = self.options.clone();
        let mut h = o.initial_step.min(o.max_step);
        let mut easy = 0usize;
        let mut x = vec![0.0; self.dofs.n_total];
        for &target in targets {
            let mut steps = Vec::new();
            while cur.stretch != target {
                let remaining = target - cur.stretch;
                let next = if remaining.abs() <= h * (1.0 + 1e-9) {
                    target
                } else {
                    cur.stretch + h * remaining.signum()
                };
                let dl = next - cur.stretch;
                // Tangent predictor.
                for ((xi, c), v) in x.iter_mut().zip(&cur.x).zip(&cur.rate) {
                    *xi = c + dl * v;
                }
                self.dofs.apply_stretch(&mut x, next);
                let mut rec = StepRecord {
                    from: cur.stretch,
                    to: next,
                    initial_residual: f64::NAN,
                    iterations: Vec::new(),
                    failure: None,
                };
                let outcome = self.newton(&mut x, &mut rec).and_then(|_| self.rate());
                match outcome {
                    Ok(rate) => {
                        let n_it = rec.iterations.len();
                        steps.push(rec);
                        cur = Converged {
                            stretch: next,
                            x: x.clone(),
                            rate,
                        };
                        if n_it <= o.easy_iterations {
                            easy += 1;
                            if easy >= 2 {
                                h = (2.0 * h).min(o.max_step);
                                easy = 0;
                            }
                        } else {
                            easy = 0;
                        }
                    }
                    Err(cause) => {
                        rec.failure = Some(cause.clone());
                        steps.push(rec);
                        easy = 0;
                        h = 0.5 * dl.abs();
                        if h < o.min_step {
                            return Err(FemError::TargetNotReached {
                                target,
                                reached: cur.stretch,
                                attempted: next,
                                step: dl.abs(),
                                cause,
                            });
                        }
                    }
                }
            }
            // The assembler holds the converged state's residual (see `newton`).
            let r = self.result_at(&cur.x, target, steps)?;
            self.write_requested(&r)?;
            results.push(r);
        }
        Ok(())
    }

    fn write_requested(&self, r: &StretchResult) -> FemResult<()> {
        if let Some(v) = &self.options.vtk {
            if v.stretches.iter().any(|&s| (s - r.stretch).abs() < 1e-12) {
                std::fs::create_dir_all(&v.directory).map_err(|source| FemError::Io {
                    path: v.directory.display().to_string(),
                    source,
                })?;
                let path = v.directory.join(format!("lambda_{:.4}.vtu", r.stretch));
                self.write_vtu(&r.state, &path)?;
            }
        }
        Ok(())
    }

    /// Writes `state` as a VTK XML unstructured grid (ASCII) in the (r, z) plane: point data u
    /// (u_r, u_z, 0) and p (Q2/Q1: Q1-interpolated to all nodes; Q1/P0: volume-weighted mean of
    /// the cell pressures around each node); cell data J, γ, λ_f, P_zz (nominal,
    /// pressure included) as volume-weighted averages over the cell's quadrature points.
    pub fn write_vtu(&self, state: &State, path: &std::path::Path) -> FemResult<()> {
        let qps = self.quadrature_points(state);
        let n_el = self.mesh.n_elements();
        let mut cell = vec![[0.0f64; 5]; n_el]; // J, γ, λ_f, P_zz, Σ dV
        for q in &qps {
            let (gamma, lf) = self.material.point_fields(&q.f)?;
            let pk = self.material.stress(&q.f)?;
            let pzz = pk[3] - q.pressure * jacobian_gradient(&q.f)[3];
            let c = &mut cell[q.element];
            c[0] += jacobian(&q.f) * q.dv;
            c[1] += gamma * q.dv;
            c[2] += lf * q.dv;
            c[3] += pzz * q.dv;
            c[4] += q.dv;
        }
        let mut pressure = vec![0.0f64; self.mesh.n_nodes()];
        match self.mesh.element {
            Element::Q2Q1 => {
                for conn in self.mesh.elements() {
                    let pc: Vec<f64> = conn[..4]
                        .iter()
                        .map(|&a| state.x[self.dofs.node_p[a as usize] as usize])
                        .collect();
                    // Q1 interpolation at the reference positions of the 9 nodes.
                    let vals = [
                        pc[0],
                        pc[1],
                        pc[2],
                        pc[3],
                        0.5 * (pc[0] + pc[1]),
                        0.5 * (pc[1] + pc[2]),
                        0.5 * (pc[2] + pc[3]),
                        0.5 * (pc[3] + pc[0]),
                        0.25 * (pc[0] + pc[1] + pc[2] + pc[3]),
                    ];
                    for (a, v) in conn.iter().zip(vals) {
                        pressure[*a as usize] = v;
                    }
                }
            }
            Element::Q1P0 => {
                // The cell-constant pressure, volume-averaged over the cells around each node.
                let mut weight = vec![0.0f64; self.mesh.n_nodes()];
                for (e, conn) in self.mesh.elements().enumerate() {
                    let pe = state.x[self.dofs.element_p[e] as usize];
                    for &a in conn {
                        pressure[a as usize] += pe * cell[e][4];
                        weight[a as usize] += cell[e][4];
                    }
                }
                for (p, w) in pressure.iter_mut().zip(&weight) {
                    if *w > 0.0 {
                        *p /= w;
                    }
                }
            }
        }
        let u: Vec<[f64; 2]> = self
            .dofs
            .node_u
            .iter()
            .map(|d| [state.x[d[0] as usize], state.x[d[1] as usize]])
            .collect();
        let cells: Vec<[f64; 4]> = cell
            .iter()
            .map(|c| [c[0] / c[4], c[1] / c[4], c[2] / c[4], c[3] / c[4]])
            .collect();
        super::vtk::write_vtu(path, &self.mesh, &u, &pressure, &cells).map_err(|source| {
            FemError::Io {
                path: path.display().to_string(),
                source,
            }
        })
    }
}

/// Dof groups for the LDLᵀ ordering and their adjacency graph. One group per node with free
/// displacement dofs: those dofs, then the node's pressure dof (Q2/Q1). A pressure dof whose node
/// has no free displacement (e.g. on a clamped base) would be a zero pivot if eliminated first,
/// so it joins the group of a neighbouring node (sharing an element) and is eliminated after that
/// node's displacement dofs, which couple to it. A Q1/P0 cell pressure is eliminated right after
/// the last of its cell's node groups (the third return value).
fn node_structure(mesh: &Mesh, dofs: &DofMap) -> (Vec<Vec<u32>>, Pattern, Vec<Trailing>) {
    let nf = dofs.n_free as u32;
    let nn_all = mesh.n_nodes();
    let mut group_of = vec![u32::MAX; nn_all];
    let mut groups: Vec<Vec<u32>> = Vec::new();
    for (a, g) in group_of.iter_mut().enumerate() {
        let d: Vec<u32> = dofs.node_u[a].iter().copied().filter(|&g| g < nf).collect();
        if !d.is_empty() {
            *g = groups.len() as u32;
            groups.push(d);
        }
    }
    // Node neighbours through elements.
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); nn_all];
    for e in mesh.elements() {
        for &a in e {
            neighbours[a as usize].extend(e.iter().copied().filter(|&b| b != a));
        }
    }
    let mut orphans = Vec::new();
    for a in 0..nn_all {
        let p = dofs.node_p[a];
        if p >= nf {
            continue;
        }
        let host = if group_of[a] != u32::MAX {
            Some(group_of[a])
        } else {
            neighbours[a]
                .iter()
                .map(|&b| group_of[b as usize])
                .find(|&g| g != u32::MAX)
        };
        match host {
            Some(g) => groups[g as usize].push(p),
            None => orphans.push(p),
        }
    }
    if !orphans.is_empty() {
        // No displacement dof anywhere near (degenerate mesh): keep them, the LU will cope.
        groups.push(orphans);
    }
    let trailing = dofs
        .element_p
        .iter()
        .zip(mesh.elements())
        .filter(|(&p, _)| p < nf)
        .map(|(&p, e)| Trailing {
            after: e
                .iter()
                .map(|&a| group_of[a as usize])
                .filter(|&g| g != u32::MAX)
                .collect(),
            dofs: vec![p],
        })
        .collect();
    let ng = groups.len();
    let mut cols: Vec<Vec<u32>> = vec![Vec::new(); ng];
    for e in mesh.elements() {
        for &a in e {
            let ga = group_of[a as usize];
            if ga == u32::MAX {
                continue;
            }
            for &b in e {
                let gb = group_of[b as usize];
                if gb != u32::MAX {
                    cols[ga as usize].push(gb);
                }
            }
        }
    }
    if cols.len() < ng {
        cols.resize(ng, Vec::new());
    }
    let mut col_ptr = vec![0u32];
    let mut row_idx = Vec::new();
    for (j, c) in cols.iter_mut().enumerate() {
        c.push(j as u32);
        c.sort_unstable();
        c.dedup();
        row_idx.extend_from_slice(c);
        col_ptr.push(row_idx.len() as u32);
    }
    (
        groups,
        Pattern {
            n: ng,
            col_ptr,
            row_idx,
        },
        trailing,
    )
}
