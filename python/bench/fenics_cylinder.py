"""Legacy FEniCS (DOLFIN 2019) on the problem of examples/fem_scaling.rs: the reference for the
time per Newton iteration (issue 14 item 3). Not a test: timings and one stress value.

Problem (as fem_scaling.rs): the clamped incompressible neo-Hookean cylinder, R = 1 mm,
L = 4 mm, μ = 5 kPa, stretched in one load step λ = 1 → 1.17, axisymmetric in (r, z):

    F = [[1 + ∂u_r/∂r, 0, ∂u_r/∂z], [0, 1 + u_r/r, 0], [∂u_z/∂r, 0, 1 + ∂u_z/∂z]],
    J = det F,  W(F) = μ/2 (tr FᵀF − 3),
    Π(u, p) = ∫ [W(F) + p (J − 1)] 2πr dr dz          (exact incompressibility, p a multiplier),
    R = δΠ (UFL's derivative),  K = δR (UFL's derivative: the exact Jacobian),
    u_r = 0 on r = 0; u = 0 on z = 0; u_r = 0, u_z = (λ − 1) L on z = L; r = R traction free.

The first Newton iteration prescribes the boundary increment (a linearised predictor, as ours'
tangent predictor), the next ones prescribe zero corrections; converged when
‖δw‖ ≤ 1e-10 max(1, ‖w‖) and ‖R_free‖ ≤ 1e-10 ‖R_free at the first iteration‖. Nominal stress
P = reaction on z = L / (πR²) [kPa], the reaction read from the discrete residual tested with
u_z = 1 on z = L (virtual work, as ours).

Elements: `P2P1` = Taylor–Hood on the nr × nz rectangles each split by the "right" diagonal
(2 nr nz triangles; the same nodes as Q2/Q1 on nr × nz quadrilaterals, so the same dof count),
quadrature degree 4 (6 points per triangle) unless --degree; `Q2Q1` = Taylor–Hood on the nr × nz
quadrilaterals with degree 4 = 3 × 3 Gauss, the discretisation of ours (same solution to solver
tolerance: the check that both codes solve the same problem).

Per Newton iteration: assembly = SystemAssembler.assemble(K, b) into reused tensors (boundary
conditions applied symmetrically, as assemble_system; forms and assemblers built once);
factorisation = PETSc's PCSetUp of an LU preconditioner with UMFPACK (DOLFIN's serial "lu"/"umfpack"; symbolic analysis reused across
iterations by the same KSP, numeric factorisation every iteration); solve = KSPSolve (preonly).
Form compilation (FFC JIT, kernels built with -O3 -march=native) is excluded by a warm-up solve on
a 2 × 8 mesh; the first assembly (sparsity pattern, tensors) is set-up, as ours', and not timed.

Run (Debian's python3-dolfin, one process):

    OMP_NUM_THREADS=1 /usr/bin/python3 python/bench/fenics_cylinder.py --element P2P1 16 64

Prints one line `fenics <element> <nr>x<nz> dofs <total> free <free> its <n> assembly <s>
factor <s> solve <s> iteration <s> P <kPa>` (seconds per Newton iteration, the predictor
iteration included).
"""

import argparse
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

RADIUS, LENGTH, MU, STRETCH = 1.0, 4.0, 5.0, 1.17


def mesh_of(element, nr, nz):
    corners = [df.Point(0.0, 0.0), df.Point(RADIUS, LENGTH)]
    if element == "Q2Q1":
        return df.RectangleMesh.create(corners, [nr, nz], df.CellType.Type.quadrilateral)
    return df.RectangleMesh(corners[0], corners[1], nr, nz, "right")


def solve(element, nr, nz, degree):
    mesh = mesh_of(element, nr, nz)
    family = "Q" if element == "Q2Q1" else "P"
    cell = mesh.ufl_cell()
    W = df.FunctionSpace(
        mesh,
        df.MixedElement([df.VectorElement(family, cell, 2), df.FiniteElement(family, cell, 1)]),
    )
    w, dw, v = df.Function(W), df.TrialFunction(W), df.TestFunction(W)
    u, p = df.split(w)
    r = df.SpatialCoordinate(mesh)[0]
    F = df.as_matrix(
        [
            [1 + u[0].dx(0), 0, u[0].dx(1)],
            [0, 1 + u[0] / r, 0],
            [u[1].dx(0), 0, 1 + u[1].dx(1)],
        ]
    )
    J = df.det(F)
    mu = df.Constant(MU)
    dx = df.dx(metadata={"quadrature_degree": degree})
    energy = (mu / 2 * (df.tr(F.T * F) - 3) + p * (J - 1)) * 2 * df.pi * r * dx
    residual = df.derivative(energy, w, v)
    jacobian = df.derivative(residual, w, dw)

    axis = "near(x[0], 0.0) && on_boundary"
    bottom = "near(x[1], 0.0) && on_boundary"
    top = f"near(x[1], {LENGTH}) && on_boundary"

    def conditions(displacement):
        zero = df.Constant(0.0)
        return [
            df.DirichletBC(W.sub(0).sub(0), zero, axis),
            df.DirichletBC(W.sub(0), df.Constant((0.0, 0.0)), bottom),
            df.DirichletBC(W.sub(0).sub(0), zero, top),
            df.DirichletBC(W.sub(0).sub(1), df.Constant(displacement), top),
        ]

    predictor = conditions((STRETCH - 1) * LENGTH)
    homogeneous = conditions(0.0)
    marker = df.Function(W)
    df.DirichletBC(W.sub(0).sub(1), df.Constant(1.0), top).apply(marker.vector())
    free = W.dim() - len(set().union(*(bc.get_boundary_values().keys() for bc in homogeneous)))

    # Forms compiled and assemblers built once (the UFL signature lookup costs tens of ms).
    a_form, L_form = df.Form(jacobian), df.Form(-residual)
    assemblers = [df.cpp.fem.SystemAssembler(a_form, L_form, bcs) for bcs in (predictor, homogeneous)]
    K, b = df.PETScMatrix(), df.PETScVector()
    assemblers[0].assemble(K, b)  # sparsity pattern and tensors: set-up, as ours', not timed
    correction = df.Function(W)
    ksp = PETSc.KSP().create(PETSc.COMM_SELF)
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("lu")
    pc.setFactorSolverType("umfpack")

    times = {"assembly": 0.0, "factor": 0.0, "solve": 0.0}
    per_iteration = []
    first_residual = None
    for it in range(30):
        t0 = time.perf_counter()
        assemblers[min(it, 1)].assemble(K, b)
        t1 = time.perf_counter()
        ksp.setOperators(K.mat())
        pc.setUp()
        t2 = time.perf_counter()
        ksp.solve(b.vec(), correction.vector().vec())
        t3 = time.perf_counter()
        times["assembly"] += t1 - t0
        times["factor"] += t2 - t1
        times["solve"] += t3 - t2
        per_iteration.append((t1 - t0, t2 - t1, t3 - t2))
        w.vector().axpy(1.0, correction.vector())
        norm = b.norm("l2")
        if it == 1:
            first_residual = norm
        if it >= 1 and correction.vector().norm("l2") <= 1e-10 * max(
            1.0, w.vector().norm("l2")
        ) and norm <= 1e-10 * first_residual:
            break
    else:
        raise RuntimeError(f"Newton did not converge on {element} {nr}x{nz}")
    iterations = it + 1
    reaction = df.assemble(residual).inner(marker.vector())
    return {
        "dofs": W.dim(),
        "free": free,
        "its": iterations,
        **{k: t / iterations for k, t in times.items()},
        "iteration": sum(times.values()) / iterations,
        "P": reaction / (df.pi * RADIUS**2),
        "per_iteration": per_iteration,
        "factor_type": pc.getFactorSolverType(),
    }


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("nr", type=int)
    parser.add_argument("nz", type=int)
    parser.add_argument("--element", choices=["P2P1", "Q2Q1"], default="P2P1")
    parser.add_argument("--degree", type=int, default=4, help="quadrature degree")
    parser.add_argument("--verbose", action="store_true", help="print each iteration's times")
    parser.add_argument("--no-warmup", action="store_true", help="skip the JIT warm-up solve")
    args = parser.parse_args(argv[1:])
    if not args.no_warmup:
        solve(args.element, 2, 8, args.degree)  # compiles the forms (FFC JIT, cached on disk)
    s = solve(args.element, args.nr, args.nz, args.degree)
    if args.verbose:
        print(f"LU: {s['factor_type']}")
        for i, (a, f, x) in enumerate(s["per_iteration"]):
            print(f"iteration {i}: assembly {a:.6f} factor {f:.6f} solve {x:.6f}")
    print(
        f"fenics {args.element} {args.nr}x{args.nz} dofs {s['dofs']} free {s['free']} "
        f"its {s['its']} assembly {s['assembly']:.6f} factor {s['factor']:.6f} "
        f"solve {s['solve']:.6f} iteration {s['iteration']:.6f} P {s['P']:.15g}"
    )


if __name__ == "__main__":
    main(sys.argv)
