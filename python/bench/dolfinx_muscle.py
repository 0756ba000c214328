"""DOLFINx 0.5 on the muscle cylinder sweep of issue 26 item 2: python/bench/fenics_muscle.py (legacy
DOLFIN 2019) ported to DOLFINx 0.5.2 (Debian's python3-dolfinx), the same problem, discretisation,
load path and Newton, for the wall time of a whole sweep on the newer FEniCS (python/bench/
muscle_sweep.py --dolfinx alternates it with ours and legacy FEniCS). Not a test: timings and the
stress per stretch.

Problem, elements, boundary conditions, P, load path, Newton with its line search and its
convergence test: exactly as fenics_muscle.py's docstring (the equations are there), the UFL
expressions of the energy, of the explicit law and of the frozen stress written the same (UFL
2022.2, which both use). P at every stretch agrees with fenics_muscle.py's to the Newton
tolerance: on 8 × 32 the largest relative difference is 8e-12 for P2/P1 (9e-12 with umfpack) and
1e-11 for Q2/Q1, both at λ = 0.70 (P ≈ 0.15 kPa; ≤ 2e-12 at every other stretch), with the same
Newton iterations at every stretch (129 and 126 in all, 19 predictors). `P2P1` = Taylor–Hood on the
nr × nz rectangles each split by the "right" diagonal (create_rectangle, DiagonalType.right: the
same triangles as DOLFIN's "right", checked cell by cell), `Q2Q1` = Taylor–Hood on the quadrilaterals;
quadrature degree 4 unless --degree (Basix's default rules: the same 6 points per triangle and
3 × 3 Gauss per quadrilateral as FIAT's, to the last bit).

Where DOLFINx 0.5 forced another way to the same numbers:
  * no SystemAssembler: K (assemble_matrix with the conditions: their rows and columns zeroed,
    1 on the diagonal) and b = −R (assemble_vector, then set_bc) are assembled by two cell loops,
    not one; the predictor's b gets the prescribed increment g by apply_lifting (b −= K_·g g, a
    third cell loop, once per load step) and set_bc (b_g = g), which is what DOLFIN's symmetric
    SystemAssembler gives;
  * conditions are given by dofs located on the boundary facets (locate_entities_boundary, every
    vertex of the facet on the plane, then locate_dofs_topological: DOLFIN's "topological"), the
    clamped base as two scalar conditions (u_r, u_z) instead of one on the vector subspace;
  * the reaction is −(−R)·marker with the −R form already compiled (no separate R form);
  * forms compiled by FFCx + CFFI with -O3 -march=native (jit_params), cached on disk
    (~/.cache/fenics), the matrix created once from the form's sparsity (create_matrix), zeroed and
    refilled per assembly, so its nonzero pattern, and with it the LU's symbolic analysis, is kept.

Linear solver: PETSc KSP preonly + LU, --solver mumps (default) or umfpack (SuiteSparse), one KSP
for the whole sweep: setOperators each iteration, PCSetUp then refactorises numerically only (same
nonzero state: MUMPS JOB = 2 on the first analysis, UMFPACK's numeric factorisation on its symbolic
one; PETSc's log counts one MatLUFactorSym for the sweep). The solver's defaults as PETSc 3.18
sets them otherwise (MUMPS: ICNTL(7) = 7, its own choice of ordering; ICNTL(14) = 20;
CNTL(1) = 0.01). Forms compiled by a warm-up sweep of two stretches on a 2 × 8 mesh, not timed.
One process (the mesh on MPI.COMM_SELF); OMP_NUM_THREADS=1.

Run (Debian's python3-dolfinx, on /usr/bin/python3):

    OMP_NUM_THREADS=1 /usr/bin/python3 python/bench/dolfinx_muscle.py --element P2P1 16 64

(`--stretches 1.05,1.1`: only those stretches, a truncated sweep; python/bench/cost_curve.py's
--truncate, for the time per iteration on a mesh whose whole sweep takes too long.)

Prints as fenics_muscle.py: a line `lambda <λ> P <kPa> newton_its <n>` per reached stretch in the
order solved, `failed <λ>` per stretch not reached, then `dolfinx <element> <nr>x<nz> dofs <total>
free <free> stretches <reached>/<asked> its <total> predictors <n> sweep <s> iteration <s> setup
<s> P(1.17) <kPa> solver <mumps|umfpack>` with the same meanings (sweep = wall time of the load
path: assemblies, factorisations, solves, reactions; its = every Newton iteration, one assembly of
K and b, one LU and one solve each, predictor iterations and rejected steps included; setup = mesh,
spaces, forms from the JIT cache, matrix, vectors and KSP; iteration = sweep / its).
"""

import argparse
import logging
import math
import sys
import time
import warnings

import numpy as np
import ufl
from mpi4py import MPI
from petsc4py import PETSc

import dolfinx
from dolfinx import fem, mesh as dmesh
from dolfinx.fem import petsc as fpetsc

warnings.simplefilter("ignore")
logging.disable(logging.INFO)  # CFFI/setuptools's compiler lines on a JIT cache miss
dolfinx.log.set_log_level(dolfinx.log.LogLevel.WARNING)
JIT = {"cffi_extra_compile_args": ["-O3", "-march=native"]}

RADIUS, LENGTH = 1.0, 4.0
MU, ALPHA, W0 = 0.1599, 19.35, 0.7335  # Table D:parpass
LMIN, LOPT, K, POPT = 0.6243, 1.1704, 0.4342, 73.52  # Table D:paract
A, B = 1.0133, 0.2050  # eq. D:gamma
STRETCHES = [round(0.70 + 0.05 * i, 10) for i in range(19)] + [1.17]
TOLERANCE = 1e-10
MAX_CORRECTIONS, EASY, FIRST_STEP, MAX_STEP, MIN_STEP = 25, 5, 0.05, 0.1, 1e-4
MAX_BACKTRACKS = 8


def passive_stress(l, exp):
    f = 1 - 2 * W0 / 3
    e = exp(ALPHA * (l * l * f + 2 * W0 / (3 * l) - 1))
    return MU / 2 * ((l * f - W0 / (3 * l * l)) * e - f / l**3 + W0 / 3)


def explicit_g(l, active, exp, ln, sqrt):
    f = 1 - 2 * W0 / 3
    q = W0 / (3 * l) + 1 / ALPHA
    ratio = f / q
    bracket = (active + passive_stress(l, exp)) * (2 * B / MU) + sqrt(ratio) * (f * f / q - l * W0 / 3)
    return ALPHA * (1 - W0 / l) + math.log(ALPHA) - 0.5 * ln(ratio) + ln(bracket)


def scaled_root(g, l, sqrt):
    f = 1 - 2 * W0 / 3
    return sqrt(f / (g / ALPHA + W0 / (3 * l))) * l


START = scaled_root(explicit_g(LMIN, 0.0, math.exp, math.log, math.sqrt), LMIN, math.sqrt)


def gamma_of(l):
    """γ(λ_f) of the explicit law as a UFL expression, 0 at and below λ_min and where negative.
    Below λ_min the formula is evaluated at λ = 1 (and discarded), so that no branch is NaN."""
    above = ufl.gt(l, LMIN)
    s = ufl.conditional(above, l, 1.0)
    active = POPT * ufl.exp(-K * (s * s - LOPT**2) ** 2 / (s - LMIN))
    g = explicit_g(s, active, ufl.exp, ufl.ln, ufl.sqrt)
    formula = A * (START - scaled_root(g, s, ufl.sqrt))
    return ufl.conditional(above, ufl.conditional(ufl.gt(formula, 0.0), formula, 0.0), 0.0)


def mesh_of(element, nr, nz):
    corners = [np.array([0.0, 0.0]), np.array([RADIUS, LENGTH])]
    if element == "Q2Q1":
        return dmesh.create_rectangle(MPI.COMM_SELF, corners, [nr, nz], dmesh.CellType.quadrilateral)
    return dmesh.create_rectangle(MPI.COMM_SELF, corners, [nr, nz], dmesh.CellType.triangle,
                                  diagonal=dmesh.DiagonalType.right)


class Sweep:
    """Mesh, space, forms, tensors and the KSP of one nr × nz problem."""

    def __init__(self, element, nr, nz, degree, solver):
        mesh = mesh_of(element, nr, nz)
        family = "Q" if element == "Q2Q1" else "P"
        cell = mesh.ufl_cell()
        W = fem.FunctionSpace(
            mesh,
            ufl.MixedElement([ufl.VectorElement(family, cell, 2), ufl.FiniteElement(family, cell, 1)]),
        )
        self.W = W
        self.dim = W.dofmap.index_map.size_global * W.dofmap.index_map_bs
        self.w, dw, v = fem.Function(W), ufl.TrialFunction(W), ufl.TestFunction(W)
        u, p = ufl.split(self.w)
        r = ufl.SpatialCoordinate(mesh)[0]

        def gradient(u):
            return ufl.as_matrix(
                [
                    [u[0].dx(0), 0, u[0].dx(1)],
                    [0, u[0] / r, 0],
                    [u[1].dx(0), 0, u[1].dx(1)],
                ]
            )

        F = ufl.Identity(3) + gradient(u)
        gamma = gamma_of(ufl.sqrt((F.T * F)[2, 2]))  # built from F, not from Fv: held in diff
        Fv = ufl.variable(F)
        C = Fv.T * Fv
        Ci = ufl.inv(C)
        c = 1 - gamma
        tr_ce = ufl.tr(C) + (1 / c**2 - 1) * C[2, 2]
        ce_m = C[2, 2] / c**2
        tr_ce_inv = ufl.tr(Ci) + (c**2 - 1) * Ci[2, 2]
        ce_inv_m = c**2 * Ci[2, 2]
        i_p = W0 / 3 * tr_ce + (1 - W0) * ce_m
        k_p = W0 / 3 * tr_ce_inv + (1 - W0) * ce_inv_m
        energy = c * (MU / (4 * ALPHA) * (ufl.exp(ALPHA * (i_p - 1)) - 1) + MU / 4 * (k_p - 1))
        P = ufl.diff(energy, Fv)  # ∂Ŵ/∂F at γ held: the frozen stress
        J = ufl.det(F)
        du, dp = ufl.split(v)
        dx = ufl.dx(metadata={"quadrature_degree": degree})
        residual = (
            ufl.inner(P, gradient(du)) + dp * (J - 1) + p * ufl.derivative(J, self.w, v)
        ) * 2 * ufl.pi * r * dx
        jacobian = ufl.derivative(residual, self.w, dw)

        fdim = mesh.topology.dim - 1
        axis = dmesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[0], 0.0))
        bottom = dmesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[1], 0.0))
        top = dmesh.locate_entities_boundary(mesh, fdim, lambda x: np.isclose(x[1], LENGTH))
        ur, uz = W.sub(0).sub(0), W.sub(0).sub(1)

        def dofs(V, facets):
            return fem.locate_dofs_topological(V, fdim, facets)

        self.increment = fem.Constant(mesh, PETSc.ScalarType(0.0))
        zero = fem.Constant(mesh, PETSc.ScalarType(0.0))
        top_uz = dofs(uz, top)
        fixed = [(ur, dofs(ur, axis)), (ur, dofs(ur, bottom)), (uz, dofs(uz, bottom)), (ur, dofs(ur, top))]
        homogeneous = [fem.dirichletbc(zero, d, V) for V, d in fixed]
        self.bcs = [
            homogeneous + [fem.dirichletbc(self.increment, top_uz, uz)],  # predictor
            homogeneous + [fem.dirichletbc(zero, top_uz, uz)],
        ]
        self.marker = fem.Function(W)
        self.marker.x.array[top_uz] = 1.0
        self.free = self.dim - np.unique(np.concatenate([d for _, d in fixed] + [top_uz])).size

        self.a_form = fem.form(jacobian, jit_params=JIT)
        self.L_form = fem.form(-residual, jit_params=JIT)
        self.K = fpetsc.create_matrix(self.a_form)
        self.b = fpetsc.create_vector(self.L_form)
        self.R = fpetsc.create_vector(self.L_form)
        self.assemble(self.bcs[1])  # the tensors filled once: set-up, as DOLFIN's first assembly
        self.correction = fem.Function(W)
        self.ksp = PETSc.KSP().create(mesh.comm)
        self.ksp.setType("preonly")
        self.pc = self.ksp.getPC()
        self.pc.setType("lu")
        self.pc.setFactorSolverType(solver)
        self.iterations = 0
        self.verbose = False
        self.predictors = 0  # of the iterations, the predictor ones

    def assemble_vector(self, bcs, lifting=False):
        """b = −R with the conditions bcs set (b_g = g; with lifting, b_free −= K_free,g g)."""
        with self.b.localForm() as local:
            local.set(0.0)
        fpetsc.assemble_vector(self.b, self.L_form)
        if lifting:
            fpetsc.apply_lifting(self.b, [self.a_form], [bcs])
        self.b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fpetsc.set_bc(self.b, bcs)

    def assemble(self, bcs, lifting=False):
        """K (conditions' rows and columns zeroed, 1 on their diagonal) and b, into the tensors kept."""
        self.K.zeroEntries()
        fpetsc.assemble_matrix(self.K, self.a_form, bcs)
        self.K.assemble()
        self.assemble_vector(bcs, lifting)

    def merit(self):
        """‖R_free‖₂ at w (vector-only assembly, homogeneous conditions), inf if not finite."""
        self.assemble_vector(self.bcs[1])
        norm = self.b.norm()
        return norm if math.isfinite(norm) else math.inf

    def direction(self):
        """Factorises the K just assembled and solves K δ = b into self.correction."""
        self.ksp.setOperators(self.K)
        self.pc.setUp()
        self.ksp.solve(self.b, self.correction.vector)
        self.iterations += 1
        return self.correction.vector

    def newton(self, increment):
        """Newton at the load already reached in w plus `increment` (None: the λ = 1 solve from
        w, no predictor). Returns the corrections taken, or None (w then is garbage).
        fenics_muscle.py's Sweep.newton line for line (its docstring says the test)."""
        x = self.w.vector
        if increment is not None:  # the linearised predictor: K δ = b with the increment prescribed
            self.increment.value = increment
            self.assemble(self.bcs[0], lifting=True)
            x.axpy(1.0, self.direction())
            self.predictors += 1
        self.assemble(self.bcs[1])
        phi = self.b.norm()
        if not math.isfinite(phi):
            return None
        first = phi
        for it in range(MAX_CORRECTIONS):
            delta = self.direction()
            size = delta.norm()
            if not math.isfinite(size):
                return None
            small = size <= TOLERANCE * max(1.0, x.norm())
            x.axpy(1.0, delta)
            self.assemble(self.bcs[1])
            trial, alpha = self.b.norm(), 1.0
            if not (small or trial <= (1 - 1e-4) * phi):
                for _ in range(MAX_BACKTRACKS):
                    x.axpy(-0.5 * alpha, delta)
                    alpha *= 0.5
                    trial = self.merit()
                    if trial <= (1 - 1e-4 * alpha) * phi:
                        break
                else:
                    return None
                self.assemble(self.bcs[1])
            if self.verbose:
                print(f"    correction {it + 1}: |R| {trial:.3e} (relative {trial / first:.3e}) "
                      f"|dw| {alpha * size:.3e} alpha {alpha}", file=sys.stderr)
            converged = alpha * size <= TOLERANCE * max(1.0, x.norm()) and (
                trial <= TOLERANCE * first or (alpha == 1.0 and trial > 0.5 * phi)
            )
            phi = trial
            if converged:
                return it + 1
        return None

    def restore(self, saved):
        saved.copy(self.w.vector)

    def stress(self):
        """Reaction on z = L / (πR²): R (no conditions) tested with u_z = 1 on z = L."""
        with self.R.localForm() as local:
            local.set(0.0)
        fpetsc.assemble_vector(self.R, self.L_form)  # −R
        self.R.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        return -self.R.dot(self.marker.vector) / (math.pi * RADIUS**2)

    def run(self, targets, report):
        """The load path through `targets` (λ = 1 first); report(λ, P, its) per reached target.
        Returns the targets not reached."""
        self.w.vector.zeroEntries()
        its0 = self.iterations
        if self.newton(None) is None:
            return sorted(targets)
        if 1.0 in targets:
            report(1.0, self.stress(), self.iterations - its0)
        reference = self.w.vector.copy()
        up = sorted(t for t in set(targets) if t > 1.0)
        down = sorted((t for t in set(targets) if t < 1.0), reverse=True)
        failed = []
        for path in (up, down):
            self.restore(reference)
            load, h, easy = 1.0, FIRST_STEP, 0
            for n, target in enumerate(path):
                its0 = self.iterations
                while load != target:
                    remaining = target - load
                    nxt = target if abs(remaining) <= h * (1 + 1e-9) else load + math.copysign(h, remaining)
                    saved = self.w.vector.copy()
                    corrections = self.newton((nxt - load) * LENGTH)
                    if self.verbose:
                        print(f"step {load:.6f} -> {nxt:.6f}: "
                              f"{'failed' if corrections is None else corrections}", file=sys.stderr)
                    if corrections is None:
                        self.restore(saved)
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
                report(target, self.stress(), self.iterations - its0)
        return sorted(failed)


def stretch_list(text):
    """`1.05,1.1` → [1.05, 1.1] (rounded as STRETCHES are), each positive and finite."""
    try:
        values = [round(float(v), 10) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a comma-separated list of stretches")
    if not all(math.isfinite(v) and v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"{text!r}: every stretch must be positive and finite")
    return values


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("nr", type=int)
    parser.add_argument("nz", type=int)
    parser.add_argument("--element", choices=["P2P1", "Q2Q1"], default="P2P1")
    parser.add_argument("--degree", type=int, default=4, help="quadrature degree")
    parser.add_argument("--solver", choices=["mumps", "umfpack"], default="mumps",
                        help="LU of PETSc's KSP preonly (default mumps)")
    parser.add_argument("--verbose", action="store_true",
                        help="log every load step and Newton correction to stderr")
    parser.add_argument("--no-warmup", action="store_true", help="skip the JIT warm-up sweep")
    parser.add_argument("--stretches", type=stretch_list, default=STRETCHES, metavar="L1,L2,...",
                        help="the stretches to reach (default: the 20 of the sweep; fewer: a "
                             "truncated sweep, for the time per iteration on a large mesh)")
    args = parser.parse_args(argv[1:])
    if not args.no_warmup:  # compiles the forms (FFCx + CFFI JIT, cached on disk)
        Sweep(args.element, 2, 8, args.degree, args.solver).run([1.0, 1.05], lambda *_: None)
    t0 = time.perf_counter()
    sweep = Sweep(args.element, args.nr, args.nz, args.degree, args.solver)
    sweep.verbose = args.verbose
    t1 = time.perf_counter()
    rows = []
    failed = sweep.run(args.stretches, lambda l, P, n: rows.append((l, P, n)))
    t2 = time.perf_counter()
    for l, P, n in rows:
        print(f"lambda {l:.2f} P {P:.15g} newton_its {n}")
    for l in failed:
        print(f"failed {l:.2f}")
    p117 = next((P for l, P, _ in rows if abs(l - 1.17) < 1e-12), float("nan"))
    its = sweep.iterations
    print(
        f"dolfinx {args.element} {args.nr}x{args.nz} dofs {sweep.dim} free {sweep.free} "
        f"stretches {len(rows)}/{len(set(args.stretches))} its {its} predictors {sweep.predictors} sweep {t2 - t1:.6f} "
        f"iteration {(t2 - t1) / max(its, 1):.6f} setup {t1 - t0:.6f} P(1.17) {p117:.15g} "
        f"solver {args.solver}"
    )


if __name__ == "__main__":
    main(sys.argv)
