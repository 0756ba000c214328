//! The axisymmetric mixed u–p problem as a [`NonlinearSystem`]: assembly, scaled norms and the
//! Newton linear solve, with the time spent in each.
//!
//! Norms, with σ the largest stress magnitude at the quadrature points plus a small floor,
//! A = πR², V = πR²L, L the length:
//!
//! ‖R_u‖₂ / (σ A) and ‖R_p‖₂ / V   (residual; the larger of the two),
//! ‖Δu‖_∞ / L and ‖Δp‖_∞ / σ       (increment; the larger of the two).

use super::assembly::Assembler;
use super::continuation::NonlinearSystem;
use super::dofs::DofMap;
use super::error::StepFailure;
use super::finite::first_non_finite;
use super::material::AxisymmetricMaterial;
use super::mesh::Mesh;
use super::relaxation;
use super::tangent_solver::TangentSolver;
use super::timings::Timings;
use std::f64::consts::PI;
use std::time::Instant;

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

/// Normwise backward error of a Newton direction ([`TangentSolver::solve`]): what a direct
/// solve with partial pivoting attains, so that the iterates do not depend on the factorisation
/// that preconditions GMRES.
const DIRECTION_TOLERANCE: f64 = 1e-12;

/// Normwise backward error of the rate dx/dλ at a converged state, which serves only the next
/// load step's predictor x + Δλ dx/dλ, whose own error is O(Δλ²): GMRES on the held (earlier)
/// factorisation stops one or two iterations sooner than at [`DIRECTION_TOLERANCE`]. Frozen
/// explicit sweep (`examples/cylinder_sweep`, d = 0): Krylov iterations 16 × 64 256 → 237,
/// 32 × 128 250 → 223 (10⁻¹¹: 245, 239), the same Newton iterations, P within 1.7e-11; 10⁻⁹
/// and looser cost Newton iterations (32 × 128: 111 instead of 102).
const RATE_TOLERANCE: f64 = 1e-10;

/// The discrete u–p problem on one mesh with one material: what the continuation driver solves.
pub struct MixedProblem<'m, M: AxisymmetricMaterial + ?Sized> {
    /// The mesh (cells of the element in use).
    pub mesh: Mesh,
    /// The dof numbering.
    pub dofs: DofMap,
    /// Residual, tangent and their pattern.
    pub asm: Assembler,
    /// The material.
    pub material: &'m M,
    linear: TangentSolver,
    stress_floor: f64,
    /// Right-hand side on the free dofs, and the system's (condensed) right-hand side.
    rhs: Vec<f64>,
    system_rhs: Vec<f64>,
    /// Time spent per phase (Newton iterations are counted by the driver).
    pub timings: Timings,
}

impl<'m, M: AxisymmetricMaterial + ?Sized> MixedProblem<'m, M> {
    /// The problem with its assembler and linear solver; `stress_floor` \[kPa\] is added to σ.
    pub fn new(
        mesh: Mesh,
        dofs: DofMap,
        asm: Assembler,
        linear: TangentSolver,
        material: &'m M,
        stress_floor: f64,
    ) -> Self {
        Self {
            rhs: vec![0.0; dofs.n_free],
            system_rhs: vec![0.0; asm.pattern.n],
            mesh,
            dofs,
            asm,
            material,
            linear,
            stress_floor,
            timings: Timings::default(),
        }
    }

    /// Axial reaction on z = L from the residual of the last evaluation at the prescribed u_z
    /// dofs.
    pub fn reaction(&self) -> f64 {
        self.dofs
            .top_axial
            .iter()
            .map(|&g| self.asm.residual[g as usize])
            .sum()
    }

    /// x = K⁻¹ f on the free dofs for f in `rhs`: the condensed system solved, then expanded
    /// ([`Assembler::condense`], [`Assembler::expand`]).
    fn solve_free(&mut self, x: &mut [f64], tolerance: f64) -> Result<(), StepFailure> {
        let mut y = std::mem::take(&mut self.system_rhs);
        self.asm.condense(&self.rhs, &mut y);
        let solved = self.solve(&mut y, tolerance);
        if solved.is_ok() {
            self.asm.expand(&self.rhs, &y, x);
        }
        self.system_rhs = y;
        solved
    }

    /// Solves K y = rhs in place for the system matrix, exactly to round-off (see
    /// [`TangentSolver`]).
    fn solve(&mut self, rhs: &mut [f64], tolerance: f64) -> Result<(), StepFailure> {
        let t = Instant::now();
        let factorising = self.timings.factorisation;
        let r = self
            .linear
            .solve(
                &self.asm.pattern,
                &self.asm.values,
                self.asm.values_norm,
                rhs,
                tolerance,
                &mut self.timings,
            )
            .map_err(|detail| StepFailure::SingularTangent { detail });
        // Factorisations triggered inside the solve are counted as factorisation only.
        self.timings.solve += t.elapsed() - (self.timings.factorisation - factorising);
        self.timings.solves += 1;
        r
    }
}

impl<M: AxisymmetricMaterial + ?Sized> NonlinearSystem for MixedProblem<'_, M> {
    fn unknowns(&self) -> usize {
        self.dofs.n_total
    }

    fn free(&self) -> usize {
        self.dofs.n_free
    }

    /// x_c = (λ − 1) d_c on the prescribed dofs.
    fn apply_load(&self, x: &mut [f64], load: f64) {
        self.dofs.apply_stretch(x, load);
    }

    /// No displacement, and the pressure of the undeformed body under a volumetric energy,
    /// p = −U′(1) = s₀ (the passive stress at F = I, μ/2 for 4C's energy, which 4C's
    /// J^(−2κ) balances): that energy's J̃(p) exists only for p above its linear coefficient,
    /// so p = 0 would have no volume ratio at all (4C's form with 4C's energy). 0 under the
    /// exact constraint.
    fn initial_guess(&self, x: &mut [f64]) {
        let Some(v) = self.asm.volumetric() else {
            return;
        };
        let Ok([_, du, _]) = v.derivatives(1.0) else {
            return;
        };
        for p in &mut x[self.dofs.n_free_u..self.dofs.n_free] {
            *p = -du;
        }
    }

    fn evaluate(&mut self, x: &[f64], tangent: bool) -> crate::Result<()> {
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

    /// σ: the largest stress magnitude of the last assembly plus the floor \[kPa\].
    fn scale(&self) -> f64 {
        self.asm.stress_scale + self.stress_floor
    }

    /// max(‖R_u‖₂ / (σ A), ‖R_p‖₂ / V).
    fn residual_norm(&self, scale: f64) -> f64 {
        let (nu, nf) = (self.dofs.n_free_u, self.dofs.n_free);
        let r2 = self.mesh.radius.powi(2);
        let ru = norm2(&self.asm.residual[..nu]) / (scale * PI * r2);
        let rp = norm2(&self.asm.residual[nu..nf]) / (PI * r2 * self.mesh.length);
        ru.max(rp)
    }

    /// max(‖Δu‖_∞ / L, ‖Δp‖_∞ / σ).
    fn increment_norm(&self, dx: &[f64], step: f64, scale: f64) -> f64 {
        let nu = self.dofs.n_free_u;
        let du = norm_inf(&dx[..nu]) * step / self.mesh.length;
        let dp = norm_inf(&dx[nu..]) * step / scale;
        du.max(dp)
    }

    /// Factorises the tangent last assembled and solves K Δx = −R. Unless `refactorise`, the
    /// factorisation held preconditions GMRES on K if it is one that GMRES iterates with
    /// ([`TangentSolver::iterates`]; faer's LU solves directly, so it is always renewed): the
    /// direction is K's all the same, and one that does not precondition K is replaced by K's
    /// own ([`TangentSolver::solve`]).
    fn newton_direction(&mut self, dx: &mut [f64], refactorise: bool) -> Result<(), StepFailure> {
        // ‖K‖_F (summed in the assembly) is finite unless an entry is not (or the sum of
        // squares overflows, which the scan then tells apart): no scan of K when it is.
        let bad = if self.asm.values_norm.is_finite() {
            None
        } else {
            first_non_finite(&self.asm.values)
        };
        if let Some(k) = bad {
            return Err(StepFailure::Material(crate::Error::NonFinite {
                quantity: "assembled tangent",
                value: self.asm.values[k],
                context: format!("at nonzero {k}"),
            }));
        }
        if refactorise || !self.linear.iterates() {
            self.linear
                .factorise(&self.asm.pattern, &self.asm.values, &mut self.timings)
                .map_err(|detail| StepFailure::SingularTangent { detail })?;
        } else {
            self.timings.earlier_factorisations += 1;
        }
        for (f, r) in self.rhs.iter_mut().zip(&self.asm.residual) {
            *f = -r;
        }
        self.solve_free(dx, DIRECTION_TOLERANCE)
    }

    /// The patch of cells over [`relaxation::OVERSHOOT`] × the converged largest stress,
    /// relaxed by Newton on its own unknowns ([`relaxation::relax`]).
    fn relax_predictor(&mut self, x: &mut [f64], converged_scale: f64) -> bool {
        relaxation::relax(&self.asm, &self.dofs, self.material, x, converged_scale)
    }

    /// K_ff v_f = −K_fc d_c, v_c = d_c, for the tangent last assembled (of the converged state,
    /// or of the iterate before it when the last step was evaluated without it), with the last
    /// factorisation (of that tangent or of the iterate before) preconditioning GMRES.
    fn load_rate(&mut self, rate: &mut [f64]) -> Result<(), StepFailure> {
        let nf = self.dofs.n_free;
        for (f, g) in self.rhs.iter_mut().zip(&self.asm.rate_force) {
            *f = -g;
        }
        self.solve_free(&mut rate[..nf], RATE_TOLERANCE)?;
        rate[nf..].copy_from_slice(&self.dofs.prescribed_rate);
        Ok(())
    }
}
