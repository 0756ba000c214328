"""Newton's method with a line search for a MuscleBody under displacement control, LU by MUMPS,
and the load path through a list of stretches: activemuscle's axisymmetric solver's algorithm
(and python/bench/dolfinx_muscle.py's, its line-for-line DOLFINx port).

Each load step starts with a linearised predictor (K δ = −R with the boundary increment
prescribed, lifted into the free rows), then corrects: K δ = −R with homogeneous conditions,
w ← w + α δ, α halved (at most 8 times) until ‖R‖ falls by the Armijo factor 1 − 10⁻⁴ α. A step
has converged when α ‖δ‖ ≤ tol max(1, ‖w‖) and the residual either fell below tol times its
first value or stalled at a full step (rounding). A step that fails, or meets a point the
material cannot evaluate (det F ≤ 0, an overflow), is halved; two easy steps (≤ 5 corrections)
double the next, up to 0.1 in λ.

K is created once from the form's sparsity and refilled, so MUMPS analyses it once (PETSc's KSP
preonly + LU; later factorisations are numeric only). Every norm and the decision to reject a
state are collective; filling the material's quadrature spaces is not (each process its own
cells).

Written against DOLFINx 0.5 / petsc4py 3.18: `fem.petsc.create_matrix`, `assemble_matrix`,
`assemble_vector`, `apply_lifting`, `set_bc`, `fem.dirichletbc`, `Function.vector` (0.7+ also
offers `Function.x.petsc_vec`; `jit_params` is `jit_options` from 0.6).
"""

import math
import time

from petsc4py import PETSc
from dolfinx import fem
from dolfinx.fem import petsc as fpetsc

from .quadrature import MATERIAL_ERRORS

TOLERANCE = 1e-10
MAX_CORRECTIONS, EASY, FIRST_STEP, MAX_STEP, MIN_STEP, MAX_BACKTRACKS = 25, 5, 0.05, 0.1, 1e-4, 8
PHASES = ("material", "assembly", "factorisation", "solve")


class Newton:
    """Newton for `body` with the dofs `fixed` held at 0 and `moved` displaced by the load:
    each a list of (subspace of body.W, dofs in W's numbering)."""

    def __init__(self, body, fixed, moved, tolerance=TOLERANCE, solver="mumps", jit_params=None):
        self.body, self.tolerance = body, tolerance
        W, mesh = body.W, body.mesh
        self.comm = mesh.comm
        zero = fem.Constant(mesh, PETSc.ScalarType(0.0))
        self.increment = fem.Constant(mesh, PETSc.ScalarType(0.0))
        held = [fem.dirichletbc(zero, d, V) for V, d in fixed]
        self.predictor = held + [fem.dirichletbc(self.increment, d, V) for V, d in moved]
        self.homogeneous = held + [fem.dirichletbc(zero, d, V) for V, d in moved]
        self.marker = fem.Function(W)
        for _, d in moved:
            self.marker.x.array[d] = 1.0
        jit = jit_params or {}
        self.a_form = fem.form(body.jacobian, jit_params=jit)
        self.L_form = fem.form(-body.residual, jit_params=jit)
        self.K = fpetsc.create_matrix(self.a_form)
        self.b = fpetsc.create_vector(self.L_form)
        self.correction = fem.Function(W)
        self.ksp = PETSc.KSP().create(self.comm)
        self.ksp.setType("preonly")
        self.pc = self.ksp.getPC()
        self.pc.setType("lu")
        self.pc.setFactorSolverType(solver)
        self.iterations, self.predictors, self.assemblies, self.error = 0, 0, 0, None
        self.timings = dict.fromkeys(PHASES, 0.0)
        self.log = None  # a function of one line, called on every correction

    def _timed(self, phase, f, *args):
        t = time.perf_counter()
        r = f(*args)
        self.timings[phase] += time.perf_counter() - t
        return r

    def update_material(self, tangent):
        """The material at w on every process; False (and self.error: the first process's
        message) if any process met a point it cannot evaluate."""
        try:
            self._timed("material", self.body.material.update, tangent)
            error = ""
        except MATERIAL_ERRORS as e:
            error = f"{type(e).__name__}: {e}"
        errors = [e for e in self.comm.allgather(error) if e]
        self.error = errors[0] if errors else None
        return not errors

    def _vector(self, bcs, lifting=False):
        with self.b.localForm() as local:
            local.set(0.0)
        fpetsc.assemble_vector(self.b, self.L_form)
        if lifting:
            fpetsc.apply_lifting(self.b, [self.a_form], [bcs])
        self.b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fpetsc.set_bc(self.b, bcs)

    def _matrix(self, bcs):
        self.K.zeroEntries()
        fpetsc.assemble_matrix(self.K, self.a_form, bcs)
        self.K.assemble()

    def assemble(self, bcs, lifting=False):
        """K and b = −R at w with the conditions `bcs` (rows and columns of K zeroed, 1 on the
        diagonal; b_g = g, with lifting b −= K_·g g). False if the material failed."""
        if not self.update_material(True):
            return False
        self.assemblies += 1
        self._timed("assembly", self._matrix, bcs)
        self._timed("assembly", self._vector, bcs, lifting)
        return True

    def merit(self):
        """‖R_free‖₂ at w (stress and vector only), inf where the material fails or R is not
        finite."""
        if not self.update_material(False):
            return math.inf
        self._timed("assembly", self._vector, self.homogeneous)
        norm = self.b.norm()
        return norm if math.isfinite(norm) else math.inf

    def direction(self):
        """Solves K δ = b for the K and b just assembled; δ's vector."""
        self.ksp.setOperators(self.K)
        self._timed("factorisation", self.pc.setUp)
        self._timed("solve", self.ksp.solve, self.b, self.correction.vector)
        self.correction.x.scatter_forward()
        self.iterations += 1
        return self.correction.vector

    def step(self, increment):
        """Newton from the converged state in w with the moved dofs displaced by a further
        `increment` (None: no predictor). The corrections taken, or None (w is then garbage)."""
        x = self.body.w.vector
        if increment is not None:
            self.increment.value = increment
            if not self.assemble(self.predictor, lifting=True):
                return None
            x.axpy(1.0, self.direction())
            self.body.w.x.scatter_forward()
            self.predictors += 1
        if not self.assemble(self.homogeneous):
            return None
        phi = first = self.b.norm()
        for it in range(MAX_CORRECTIONS):
            if not math.isfinite(phi):
                return None
            delta = self.direction()
            size = delta.norm()
            if not math.isfinite(size):
                return None
            small = size <= self.tolerance * max(1.0, x.norm())
            alpha = self._line_search(x, delta, phi, small)
            if alpha is None:
                return None
            trial = self.b.norm()
            if self.log:
                self.log(f"  correction {it + 1}: |R| {trial:.3e} (relative {trial / first:.3e}) "
                         f"|dw| {alpha * size:.3e} alpha {alpha}")
            converged = alpha * size <= self.tolerance * max(1.0, x.norm()) and (
                trial <= self.tolerance * first or (alpha == 1.0 and trial > 0.5 * phi))
            phi = trial
            if converged:
                return it + 1
        return None

    def _line_search(self, x, delta, phi, small):
        """w ← w + α δ with α = 1, 1/2, … until the residual falls (always α = 1 for a step
        below the tolerance); K and b assembled at the new w. α, or None."""
        x.axpy(1.0, delta)
        self.body.w.x.scatter_forward()
        alpha = 1.0
        if self.assemble(self.homogeneous) and (small or self.b.norm() <= (1 - 1e-4) * phi):
            return alpha
        for _ in range(MAX_BACKTRACKS):
            x.axpy(-0.5 * alpha, delta)
            self.body.w.x.scatter_forward()
            alpha *= 0.5
            if self.merit() <= (1 - 1e-4 * alpha) * phi:
                return alpha if self.assemble(self.homogeneous) else None
        return None

    def force(self):
        """The reaction on the moved dofs: R (no conditions) at w tested with 1 there."""
        if not self.update_material(False):
            raise ArithmeticError(self.error)
        self._vector([])
        return -self.b.dot(self.marker.vector)

    def memory(self):
        """Peak resident memory [MiB] of each process (rank order), on every process."""
        import resource
        return self.comm.allgather(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)


def sweep(newton, stretches, length, report, verbose=None):
    """The load path: λ = 1, then up through the stretches above 1 and down through those below,
    the moved dofs at (λ − 1) length; report(λ, force, corrections) at each target reached.
    Returns the targets not reached."""
    body, x = newton.body, newton.body.w.vector
    body.reset()
    its0 = newton.iterations
    if newton.step(None) is None:
        return sorted(stretches)
    if 1.0 in stretches:
        report(1.0, newton.force(), newton.iterations - its0)
    reference = x.copy()
    up = sorted(t for t in set(stretches) if t > 1.0)
    down = sorted((t for t in set(stretches) if t < 1.0), reverse=True)
    failed = []
    for path in (up, down):
        reference.copy(x)
        body.w.x.scatter_forward()
        load, h, easy = 1.0, FIRST_STEP, 0
        for n, target in enumerate(path):
            its0 = newton.iterations
            while load != target:
                remaining = target - load
                nxt = target if abs(remaining) <= h * (1 + 1e-9) else load + math.copysign(h, remaining)
                saved = x.copy()
                corrections = newton.step((nxt - load) * length)
                if verbose:
                    verbose(f"step {load:.6f} -> {nxt:.6f}: "
                            f"{newton.error or 'failed' if corrections is None else corrections}")
                if corrections is None:
                    saved.copy(x)
                    body.w.x.scatter_forward()
                    easy, h = 0, 0.5 * abs(nxt - load)
                    if h < MIN_STEP:
                        break
                    continue
                load = nxt
                easy = easy + 1 if corrections <= EASY else 0
                if easy >= 2:
                    h, easy = min(2 * h, MAX_STEP), 0
            if load != target:
                failed += path[n:]
                break
            report(target, newton.force(), newton.iterations - its0)
    return sorted(failed)
