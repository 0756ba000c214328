"""activemuscle as a quadrature-point material in legacy FEniCS (DOLFIN 2019, Debian's
python3-dolfin), under MPI: the route for problems larger than one machine.

A block [0, L] × [0, 1] × [0, 1] of Taylor–Hood P2/P1 tetrahedra, exact incompressibility
(Π = Ŵ(F) + p (J − 1)); the stress P and the exact tangent A of activemuscle enter the weak form as
quadrature functions, filled on each process for the cells it owns (no communication: a material
point needs only its own F):

    R(u, p; v, q) = ∫ (P + p J F⁻ᵀ) : ∇v dX + ∫ q (J − 1) dX,
    dR = ∫ (A : ∇du) : ∇v dX + [the pressure terms, by UFL's derivative],

Newton with MUMPS's parallel LU. Bases: "clamped" (x = 0 fixed, x = L moved by (λ − 1) L) or
"sliding" (symmetry planes x = 0, y = 0, z = 0: homogeneous uniaxial tension, which must equal the
0D curve). Prints the nominal axial stress (reaction on x = L / cross-section).

    mpirun -n 2 /usr/bin/python3 -m activemuscle.examples.dolfin_mpi [clamped|sliding] [N]

(PYTHONPATH must reach the activemuscle package; Debian's python3 is CPython 3.11 like the
module's build.)
"""

import sys
import time
import warnings

import dolfin as df
import numpy as np
import ufl

import activemuscle as am

df.set_log_level(df.LogLevel.WARNING)
# Quadrature elements need FFC's quadrature representation in DOLFIN 2019 (uflacs fails to compile
# forms with them: "FE…_Q… was not declared"); it is deprecated, and this silences the notice.
df.parameters["form_compiler"]["representation"] = "quadrature"
df.parameters["form_compiler"]["optimize"] = False  # its symbolic simplification takes minutes here
warnings.simplefilter("ignore", getattr(__import__("ffc.quadrature.deprecation", fromlist=["x"]),
                                        "QuadratureRepresentationDeprecationWarning", Warning))
DEGREE = 2  # quadrature degree: exact for the P2 × P2 mass terms, the usual choice for P2/P1
DX = df.dx(metadata={"quadrature_degree": DEGREE, "quadrature_scheme": "default"})


def quadrature_space(mesh, shape):
    element = ufl.TensorElement("Quadrature", mesh.ufl_cell(), degree=DEGREE,
                                quad_scheme="default", shape=shape)
    return df.FunctionSpace(mesh, element)


def component_dofs(space, ncomp):
    """Owned dofs of a quadrature tensor space as (points, components)."""
    return np.column_stack([space.sub(c).dofmap().dofs() for c in range(ncomp)])


def block(material, stretches, bases="clamped", n=4, length=2.0, fibre=(1.0, 0.0, 0.0)):
    comm = df.MPI.comm_world
    mesh = df.BoxMesh(comm, df.Point(0, 0, 0), df.Point(length, 1, 1), 2 * n, n, n)
    cell = mesh.ufl_cell()
    W = df.FunctionSpace(mesh, df.MixedElement([df.VectorElement("P", cell, 2), df.FiniteElement("P", cell, 1)]))
    w, dw, wt = df.Function(W), df.TrialFunction(W), df.TestFunction(W)
    u, p = df.split(w)
    v, q = df.split(wt)
    du, _ = df.split(dw)
    F = df.Identity(3) + df.grad(u)
    J = df.det(F)

    # F at the quadrature points by a local (cell-wise) projection, exact on a quadrature space.
    QF, QA = quadrature_space(mesh, (3, 3)), quadrature_space(mesh, (3, 3, 3, 3))
    Fq, Pq, Aq = df.Function(QF), df.Function(QF), df.Function(QA)
    tF, sF = df.TrialFunction(QF), df.TestFunction(QF)
    project_F = df.LocalSolver(df.inner(tF, sF) * DX, df.inner(F, sF) * DX)
    project_F.factorize()
    dofs_F, dofs_A = component_dofs(QF, 9), component_dofs(QA, 81)
    local_F = dofs_F - QF.dofmap().ownership_range()[0]
    local_A = dofs_A - QA.dofmap().ownership_range()[0]

    def update_material():
        project_F.solve_local_rhs(Fq)
        f = Fq.vector().get_local()[local_F].reshape(-1, 3, 3)
        r = material.evaluate(f, fibre, layout="leading")
        for target, values, index in ((Pq, r["stress"].reshape(-1, 9), local_F),
                                      (Aq, r["tangent"].reshape(-1, 81), local_A)):
            local = target.vector().get_local()
            local[index] = values
            target.vector().set_local(local)
            target.vector().apply("insert")

    i, j, k, l = ufl.indices(4)
    A_du = ufl.as_tensor(Aq[i, j, k, l] * df.grad(du)[k, l], (i, j))
    pressure = p * J * df.inner(df.inv(F).T, df.grad(v)) * DX + q * (J - 1) * DX
    residual = df.inner(Pq, df.grad(v)) * DX + pressure
    jacobian = df.inner(A_du, df.grad(v)) * DX + df.derivative(pressure, w, dw)

    x0 = df.CompiledSubDomain("near(x[0], 0.0) && on_boundary")
    x1 = df.CompiledSubDomain("near(x[0], L) && on_boundary", L=length)

    def boundary_conditions(move):
        """u_x = move on x = L; the rest fixed (clamped) or on symmetry planes (sliding)."""
        zero = df.Constant(0.0)
        if bases == "clamped":
            return [df.DirichletBC(W.sub(0), df.Constant((0, 0, 0)), x0),
                    df.DirichletBC(W.sub(0).sub(0), move, x1),
                    df.DirichletBC(W.sub(0).sub(1), zero, x1),
                    df.DirichletBC(W.sub(0).sub(2), zero, x1)]
        return [df.DirichletBC(W.sub(0).sub(0), zero, x0),
                df.DirichletBC(W.sub(0).sub(1), zero, "near(x[1], 0.0) && on_boundary"),
                df.DirichletBC(W.sub(0).sub(2), zero, "near(x[2], 0.0) && on_boundary"),
                df.DirichletBC(W.sub(0).sub(0), move, x1)]

    # Each load step's first Newton iteration prescribes the boundary increment (a linearised
    # predictor, no kink at the moved face); the next ones prescribe zero corrections.
    increment = df.Constant(0.0)
    predictor, homogeneous = boundary_conditions(increment), boundary_conditions(df.Constant(0.0))
    # The reaction on x = L: the residual tested with 1 in u_x on that face.
    marker = df.Function(W)
    df.DirichletBC(W.sub(0).sub(0), df.Constant(1.0), x1).apply(marker.vector())
    correction = df.Function(W)

    out, start, iterations, lam = [], time.perf_counter(), 0, 1.0
    for target in stretches:
        for step in np.linspace(lam, target, int(np.ceil(abs(target - lam) / 0.05)) + 1)[1:]:
            increment.assign((step - lam) * length)
            for it in range(30):
                update_material()
                K, b = df.assemble_system(jacobian, -residual, predictor if it == 0 else homogeneous)
                df.solve(K, correction.vector(), b, "mumps")
                w.vector().axpy(1.0, correction.vector())
                iterations += 1
                if correction.vector().norm("l2") < 1e-10 * max(1.0, w.vector().norm("l2")):
                    break
            else:
                raise RuntimeError(f"Newton did not converge at stretch {step}")
            lam = step
        update_material()
        out.append(df.assemble(residual).inner(marker.vector()))  # cross-section 1 × 1
    return {"stretch": np.array(stretches), "stress": np.array(out), "iterations": iterations,
            "seconds": time.perf_counter() - start, "dofs": W.dim(), "processes": comm.size}


def main(argv):
    bases = argv[1] if len(argv) > 1 else "clamped"
    n = int(argv[2]) if len(argv) > 2 else 2
    material = am.Material(law="explicit", coupling="frozen")
    r = block(material, [1.05, 1.1], bases=bases, n=n)
    if df.MPI.comm_world.rank == 0:
        zero_d = material.uniaxial(list(r["stretch"]))["stress"]
        print(f"# DOLFIN + activemuscle, {bases} block, {r['dofs']} dofs, {r['processes']} process(es), "
              f"{r['iterations']} Newton iterations, {r['seconds']:.2f} s")
        print("lambda P_kPa P_0D_kPa")
        for lam, P, P0 in zip(r["stretch"], r["stress"], zero_d):
            print(f"{lam:.3f} {P:.12f} {P0:.12f}")


if __name__ == "__main__":
    main(sys.argv)
