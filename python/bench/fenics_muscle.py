"""Legacy FEniCS (DOLFIN 2019) on the muscle cylinder sweep of issue 26 item 2: the reference for
the wall time of a whole sweep (python/bench/muscle_sweep.py alternates it with ours). Not a test:
timings and the stress per stretch.

Problem (as python/bench/muscle_sweep.toml, the chapter's cylinder study): the clamped
incompressible muscle cylinder, R = 1 mm, L = 4 mm, fibres along the axis z (m = e_z), the
chapter's energy (Giantesio & Musesti, eq. D:Wpassiva; src/energy/giantesio_musesti.rs) in active
strain with the explicit activation law (eq. D:gamma; src/active/law/explicit.rs), d = 0, frozen
coupling, axisymmetric in (r, z) as python/bench/fenics_cylinder.py:

    F = [[1 + ∂u_r/∂r, 0, ∂u_r/∂z], [0, 1 + u_r/r, 0], [∂u_z/∂r, 0, 1 + ∂u_z/∂z]],  C = FᵀF,
    j = (tr C, C_zz, tr C⁻¹, (C⁻¹)_zz),  λ_f = sqrt(C_zz),  γ = g(λ_f),  c = 1 − γ,
    C_e = F_a⁻ᵀ C F_a⁻¹, F_a = I − γ m⊗m:  tr C_e = tr C + (c⁻² − 1) C_zz,  C_e:M = c⁻² C_zz,
        tr C_e⁻¹ = tr C⁻¹ + (c² − 1) (C⁻¹)_zz,  C_e⁻¹:M = c² (C⁻¹)_zz      (src/active/map.rs),
    W = μ/4 {[e^{α(I_p − 1)} − 1]/α + K_p − 1},  I_p = (w0/3) tr C_e + (1 − w0) C_e:M,
        K_p = (w0/3) tr C_e⁻¹ + (1 − w0) C_e⁻¹:M,  Ŵ(F, γ) = (1 − γ) W   (det F_a = 1 − γ),
    μ = 0.1599 kPa, α = 19.35, w0 = 0.7335; P_act = 73.52 exp(−0.4342 (λ² − 1.1704²)²/(λ − 0.6243)).

Frozen coupling (src/active/coupling.rs, src/material.rs): the stress is P = ∂Ŵ/∂F at γ held,
γ = g(λ_f(F)) (UFL: diff with respect to a `variable` F that γ's expression does not contain), and
R = ∫ [P : δF + δ(p (J − 1))] 2πr dr dz, not the derivative of an energy. K = δR (UFL's
derivative, γ(F) included): the exact, non-symmetric frozen tangent ∂²Ŵ/∂F² + (∂P/∂γ) ⊗ ∂γ/∂F, as
ours with frozen_tangent = "exact". The explicit law, written as in explicit.rs:

    γ(λ) = a [r(g(λ_min, 0), λ_min) λ_min − r(g(λ, P_act(λ)), λ) λ] for λ > λ_min, else 0;
    clamped at 0 where the formula is negative; a = 1.0133, b = 0.2050,
    r(g, λ) = sqrt(f / (g/α + w0/(3λ))),  f = 1 − 2w0/3,  q = 1/α + w0/(3λ),
    g(λ, T) = α(1 − w0/λ) + ln α − ½ ln(f/q) + ln{b (2/μ)(T + P_pas(λ)) + sqrt(f/q)(f²/q − λ w0/3)},
    P_pas(λ) = μ/2 {(λ f − w0/(3λ²)) e^{α(λ² f + 2w0/(3λ) − 1)} − f/λ³ + w0/3}.

Boundary conditions and P as fenics_cylinder.py: u_r = 0 on r = 0; u = 0 on z = 0; u_r = 0,
u_z = (λ − 1) L on z = L; r = R traction free; P = reaction on z = L / (πR²) [kPa] (the residual
tested with u_z = 1 on z = L). Newton: each load step starts with the linearised predictor (one
assembly, LU and solve with the boundary increment prescribed, as ours' tangent predictor), then
corrections with ours' backtracking line search on φ = ‖R_free‖₂ (Armijo factor 1 − 10⁻⁴ α, at most
8 halvings); converged when ‖α δw‖ ≤ 1e-10 max(1, ‖w‖) and φ ≤ 1e-10 φ₁ (φ₁ after the predictor;
at λ = 1, solved from w = 0, φ at w = 0) or φ stopped falling at a full step (φ > φ_prev / 2: the
round-off floor). fenics_cylinder.py's criterion (φ ≤ 1e-10 φ₁ only, no line search) fails here:
on 16 × 64 P2/P1 the step 1.35 → 1.40 diverges without the line search, and the halved steps then
start so close to the solution that 1e-10 φ₁ is below φ's round-off floor (≈ 1e-10), so every
step is rejected down to the minimum step and 1.40–1.60 are lost.

Load path as ours (src/fem/continuation.rs): λ = 1 first, then upwards through the targets above
1, then downwards from the λ = 1 state through those below; each step from the last converged
state, first step 0.05, at most 0.1, halved when Newton fails (25 corrections, or a non-finite
residual), doubled after two steps of at most 5 corrections, a direction abandoned below a step
of 1e-4 (its remaining targets are reported as failed).

Elements: `P2P1` = Taylor–Hood on the nr × nz rectangles each split by the "right" diagonal (the
same nodes as Q2/Q1, the same dof count), quadrature degree 4 (6 points per triangle) unless
--degree; `Q2Q1` = Taylor–Hood on the quadrilaterals with degree 4 = 3 × 3 Gauss: ours'
discretisation (the check that both codes solve the same problem). Linear solver: UMFPACK LU
through PETSc (KSP preonly, symbolic analysis reused), assembly by SystemAssembler into reused
tensors, forms compiled (FFC JIT, -O3 -march=native) by a warm-up sweep of two stretches on a
2 × 8 mesh, not timed.

Run (Debian's python3-dolfin; optionally on OpenBLAS, see muscle_sweep.py):

    OMP_NUM_THREADS=1 /usr/bin/python3 python/bench/fenics_muscle.py --element P2P1 16 64

Prints a line `lambda <λ> P <kPa> newton_its <n>` per reached stretch in the order solved,
`failed <λ>` per stretch not reached, then `fenics <element> <nr>x<nz> dofs <total> free <free>
stretches <reached>/<asked> its <total> predictors <n> sweep <s> iteration <s> setup <s> P(1.17) <kPa>`: sweep =
wall time of the load path (assembly, factorisation, solves and the reactions), its = every
Newton iteration (each one assembly, one LU, one solve), the predictor iterations (one per load
step, counted in its; ours counts its predictor solve in no iteration) and those of rejected
steps included, setup = mesh,
spaces, forms and assemblers before it, iteration = sweep / its.
"""

import argparse
import math
import sys
import time
import warnings

import dolfin as df
from petsc4py import PETSc

warnings.simplefilter("ignore")
df.set_log_level(df.LogLevel.WARNING)
df.parameters["linear_algebra_backend"] = "PETSc"
df.parameters["form_compiler"]["cpp_optimize"] = True
df.parameters["form_compiler"]["cpp_optimize_flags"] = "-O3 -march=native"

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
    above = df.gt(l, LMIN)
    s = df.conditional(above, l, 1.0)
    active = POPT * df.exp(-K * (s * s - LOPT**2) ** 2 / (s - LMIN))
    g = explicit_g(s, active, df.exp, df.ln, df.sqrt)
    formula = A * (START - scaled_root(g, s, df.sqrt))
    return df.conditional(above, df.conditional(df.gt(formula, 0.0), formula, 0.0), 0.0)


def mesh_of(element, nr, nz):
    corners = [df.Point(0.0, 0.0), df.Point(RADIUS, LENGTH)]
    if element == "Q2Q1":
        return df.RectangleMesh.create(corners, [nr, nz], df.CellType.Type.quadrilateral)
    return df.RectangleMesh(corners[0], corners[1], nr, nz, "right")


class Sweep:
    """Mesh, spaces, forms, assemblers and the LU of one nr × nz problem."""

    def __init__(self, element, nr, nz, degree):
        mesh = mesh_of(element, nr, nz)
        family = "Q" if element == "Q2Q1" else "P"
        cell = mesh.ufl_cell()
        W = df.FunctionSpace(
            mesh,
            df.MixedElement([df.VectorElement(family, cell, 2), df.FiniteElement(family, cell, 1)]),
        )
        self.W = W
        self.w, dw, v = df.Function(W), df.TrialFunction(W), df.TestFunction(W)
        u, p = df.split(self.w)
        r = df.SpatialCoordinate(mesh)[0]

        def gradient(u):
            return df.as_matrix(
                [
                    [u[0].dx(0), 0, u[0].dx(1)],
                    [0, u[0] / r, 0],
                    [u[1].dx(0), 0, u[1].dx(1)],
                ]
            )

        F = df.Identity(3) + gradient(u)
        gamma = gamma_of(df.sqrt((F.T * F)[2, 2]))  # built from F, not from Fv: held in diff
        Fv = df.variable(F)
        C = Fv.T * Fv
        Ci = df.inv(C)
        c = 1 - gamma
        tr_ce = df.tr(C) + (1 / c**2 - 1) * C[2, 2]
        ce_m = C[2, 2] / c**2
        tr_ce_inv = df.tr(Ci) + (c**2 - 1) * Ci[2, 2]
        ce_inv_m = c**2 * Ci[2, 2]
        i_p = W0 / 3 * tr_ce + (1 - W0) * ce_m
        k_p = W0 / 3 * tr_ce_inv + (1 - W0) * ce_inv_m
        energy = c * (MU / (4 * ALPHA) * (df.exp(ALPHA * (i_p - 1)) - 1) + MU / 4 * (k_p - 1))
        P = df.diff(energy, Fv)  # ∂Ŵ/∂F at γ held: the frozen stress
        J = df.det(F)
        du, dp = df.split(v)
        dx = df.dx(metadata={"quadrature_degree": degree})
        residual = (
            df.inner(P, gradient(du)) + dp * (J - 1) + p * df.derivative(J, self.w, v)
        ) * 2 * df.pi * r * dx
        jacobian = df.derivative(residual, self.w, dw)

        axis = "near(x[0], 0.0) && on_boundary"
        bottom = "near(x[1], 0.0) && on_boundary"
        top = f"near(x[1], {LENGTH}) && on_boundary"
        self.increment = df.Constant(0.0)

        def conditions(displacement):
            zero = df.Constant(0.0)
            return [
                df.DirichletBC(W.sub(0).sub(0), zero, axis),
                df.DirichletBC(W.sub(0), df.Constant((0.0, 0.0)), bottom),
                df.DirichletBC(W.sub(0).sub(0), zero, top),
                df.DirichletBC(W.sub(0).sub(1), displacement, top),
            ]

        predictor, homogeneous = conditions(self.increment), conditions(df.Constant(0.0))
        self.marker = df.Function(W)
        df.DirichletBC(W.sub(0).sub(1), df.Constant(1.0), top).apply(self.marker.vector())
        self.free = W.dim() - len(
            set().union(*(bc.get_boundary_values().keys() for bc in homogeneous))
        )
        a_form, L_form = df.Form(jacobian), df.Form(-residual)
        self.residual_form = df.Form(residual)
        self.assemblers = [
            df.cpp.fem.SystemAssembler(a_form, L_form, bcs) for bcs in (predictor, homogeneous)
        ]
        self.K, self.b, self.R = df.PETScMatrix(), df.PETScVector(), df.PETScVector()
        self.assemblers[1].assemble(self.K, self.b)  # sparsity pattern and tensors: set-up
        df.assemble(self.residual_form, tensor=self.R)
        self.correction = df.Function(W)
        self.ksp = PETSc.KSP().create(PETSc.COMM_SELF)
        self.ksp.setType("preonly")
        self.pc = self.ksp.getPC()
        self.pc.setType("lu")
        self.pc.setFactorSolverType("umfpack")
        self.iterations = 0
        self.verbose = False
        self.predictors = 0  # of the iterations, the predictor ones

    def merit(self):
        """‖R_free‖₂ at w (vector-only assembly, homogeneous conditions), inf if not finite."""
        self.assemblers[1].assemble(self.b)
        norm = self.b.norm("l2")
        return norm if math.isfinite(norm) else math.inf

    def direction(self):
        """Factorises the K just assembled and solves K δ = b into self.correction."""
        self.ksp.setOperators(self.K.mat())
        self.pc.setUp()
        self.ksp.solve(self.b.vec(), self.correction.vector().vec())
        self.iterations += 1
        return self.correction.vector()

    def newton(self, increment):
        """Newton at the load already reached in w plus `increment` (None: the λ = 1 solve from
        w, no predictor). Returns the corrections taken, or None (w then is garbage).

        Each correction: assembly of K and b = −R_free, LU, solve, then ours' backtracking line
        search on φ = ‖R_free‖₂: the full step is taken when φ falls by the Armijo factor
        (1 − 10⁻⁴ α), else α = ½, ¼, … (at most 8 halvings, vector-only assemblies). Converged
        when ‖α δ‖ ≤ 1e-10 max(1, ‖w‖) and φ ≤ 1e-10 φ₁ (φ₁ after the predictor) or φ has stopped
        falling at a full step (φ > φ_previous / 2: the round-off floor, met when a load step is small)."""
        x = self.w.vector()
        if increment is not None:  # the linearised predictor: K δ = b with the increment prescribed
            self.increment.assign(increment)
            self.assemblers[0].assemble(self.K, self.b)
            x.axpy(1.0, self.direction())
            self.predictors += 1
        self.assemblers[1].assemble(self.K, self.b)
        phi = self.b.norm("l2")
        if not math.isfinite(phi):
            return None
        first = phi
        for it in range(MAX_CORRECTIONS):
            delta = self.direction()
            size = delta.norm("l2")
            if not math.isfinite(size):
                return None
            small = size <= TOLERANCE * max(1.0, x.norm("l2"))
            x.axpy(1.0, delta)
            self.assemblers[1].assemble(self.K, self.b)
            trial, alpha = self.b.norm("l2"), 1.0
            if not (small or trial <= (1 - 1e-4) * phi):
                for _ in range(MAX_BACKTRACKS):
                    x.axpy(-0.5 * alpha, delta)
                    alpha *= 0.5
                    trial = self.merit()
                    if trial <= (1 - 1e-4 * alpha) * phi:
                        break
                else:
                    return None
                self.assemblers[1].assemble(self.K, self.b)
            if self.verbose:
                print(f"    correction {it + 1}: |R| {trial:.3e} (relative {trial / first:.3e}) "
                      f"|dw| {alpha * size:.3e} alpha {alpha}", file=sys.stderr)
            converged = alpha * size <= TOLERANCE * max(1.0, x.norm("l2")) and (
                trial <= TOLERANCE * first or (alpha == 1.0 and trial > 0.5 * phi)
            )
            phi = trial
            if converged:
                return it + 1
        return None

    def restore(self, saved):
        self.w.vector().zero()
        self.w.vector().axpy(1.0, saved)

    def stress(self):
        df.assemble(self.residual_form, tensor=self.R)
        return self.R.inner(self.marker.vector()) / (math.pi * RADIUS**2)

    def run(self, targets, report):
        """The load path through `targets` (λ = 1 first); report(λ, P, its) per reached target.
        Returns the targets not reached."""
        self.w.vector().zero()
        its0 = self.iterations
        if self.newton(None) is None:
            return sorted(targets)
        if 1.0 in targets:
            report(1.0, self.stress(), self.iterations - its0)
        reference = self.w.vector().copy()
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
                    saved = self.w.vector().copy()
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


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("nr", type=int)
    parser.add_argument("nz", type=int)
    parser.add_argument("--element", choices=["P2P1", "Q2Q1"], default="P2P1")
    parser.add_argument("--degree", type=int, default=4, help="quadrature degree")
    parser.add_argument("--verbose", action="store_true",
                        help="log every load step and Newton correction to stderr")
    parser.add_argument("--no-warmup", action="store_true", help="skip the JIT warm-up sweep")
    args = parser.parse_args(argv[1:])
    if not args.no_warmup:  # compiles the forms (FFC JIT, cached on disk)
        Sweep(args.element, 2, 8, args.degree).run([1.0, 1.05], lambda *_: None)
    t0 = time.perf_counter()
    sweep = Sweep(args.element, args.nr, args.nz, args.degree)
    sweep.verbose = args.verbose
    t1 = time.perf_counter()
    rows = []
    failed = sweep.run(STRETCHES, lambda l, P, n: rows.append((l, P, n)))
    t2 = time.perf_counter()
    for l, P, n in rows:
        print(f"lambda {l:.2f} P {P:.15g} newton_its {n}")
    for l in failed:
        print(f"failed {l:.2f}")
    p117 = next((P for l, P, _ in rows if abs(l - 1.17) < 1e-12), float("nan"))
    its = sweep.iterations
    print(
        f"fenics {args.element} {args.nr}x{args.nz} dofs {sweep.W.dim()} free {sweep.free} "
        f"stretches {len(rows)}/{len(set(STRETCHES))} its {its} predictors {sweep.predictors} sweep {t2 - t1:.6f} "
        f"iteration {(t2 - t1) / max(its, 1):.6f} setup {t1 - t0:.6f} P(1.17) {p117:.15g}"
    )


if __name__ == "__main__":
    main(sys.argv)
