"""The chapter's muscle cylinder in felupe's axisymmetric mixed formulation, with activemuscle's
material: Taylor–Hood Q2/Q1, exact incompressibility (the element and the weak form of
activemuscle's own solver), displacement-controlled stretch λ of the base z = L.

felupe's axisymmetric coordinates: x₁ = z (axis), x₂ = r; fibres along the axis, m = (1, 0, 0).
Boundary conditions (the chapter's section "Numerical validation"): u_r = 0 on the axis, u_z = 0 on
z = 0, u_z = (λ − 1) L on z = L; "sliding" bases leave u_r free there (exact solution: homogeneous
uniaxial tension, so the stress must equal the 0D curve), "clamped" bases fix u_r = 0.
Output: the nominal axial stress = axial reaction on z = L / (π R²).

    python -m activemuscle.examples.felupe_cylinder [clamped|sliding] [NR NZ]
"""

import sys
import time

import felupe as fem
import numpy as np

from activemuscle import Material
from activemuscle.felupe import Incompressible, MuscleMaterial, taylor_hood


def cylinder(
    material,
    stretches,
    bases="clamped",
    nr=6,
    nz=24,
    radius=1.0,
    length=4.0,
    max_step=0.05,
    tol=1e-10,
):
    """Nominal axial stress [kPa] at each stretch (ascending or not: the sweep runs from λ = 1
    outwards in both directions, in increments ≤ ``max_step``, halved when Newton fails).
    Returns a dict: "stretch", "stress", "iterations" (Newton iterations per target), "seconds"."""
    mesh = fem.Rectangle(a=(0.0, 0.0), b=(length, radius), n=(nz + 1, nr + 1))
    region, field = taylor_hood(mesh, axisymmetric=True)
    umat = Incompressible(MuscleMaterial(material, fibre=(1.0, 0.0, 0.0)))
    solid = fem.SolidBody(umat, field)
    skip_r = (0, 0) if bases == "clamped" else (0, 1)
    boundaries = {
        "axis": fem.Boundary(field[0], fy=0.0, skip=(1, 0)),
        "fixed": fem.Boundary(field[0], fx=0.0, skip=skip_r),
        "move": fem.Boundary(field[0], fx=length, skip=skip_r),
    }

    def solve(lam):
        boundaries["move"].value = np.array([(lam - 1.0) * length, 0.0])[
            [i for i, s in enumerate(skip_r) if not s]
        ]
        dof0, dof1 = fem.dof.partition(field, boundaries)
        ext0 = fem.dof.apply(field, boundaries, dof0)
        return fem.newtonraphson(
            items=[solid], x0=field, dof1=dof1, dof0=dof0, ext0=ext0, tol=tol, verbose=0
        )

    def snapshot():
        return [f.values.copy() for f in field.fields]

    def restore(values):
        for f, v in zip(field.fields, values):
            f.values[:] = v

    results = {}
    start = time.perf_counter()
    targets = np.asarray(stretches, dtype=float)
    for branch in (targets[targets >= 1.0], targets[targets < 1.0][::-1]):
        restore([np.zeros_like(f.values) for f in field.fields])
        lam = 1.0
        for target in sorted(branch, key=lambda t: abs(t - 1.0)):
            iterations = 0
            while lam != target:
                step = np.clip(target - lam, -max_step, max_step)
                saved = snapshot()
                while True:
                    try:
                        res = solve(lam + step)
                        ok = res.success
                    except (ValueError, FloatingPointError, ArithmeticError):
                        ok = False
                    if ok:
                        iterations += res.iterations
                        lam = target if abs(lam + step - target) < 1e-14 else lam + step
                        break
                    restore(saved)
                    step /= 2.0
                    if abs(step) < 1e-6:
                        raise RuntimeError(f"no convergence from stretch {lam} towards {target}")
            if iterations == 0:  # the target is where the sweep stands (λ = 1)
                res = solve(lam)
                iterations = res.iterations
            force = fem.tools.force(field, res.fun, boundaries["move"])[0]
            results[target] = (force / (np.pi * radius**2), iterations)
    seconds = time.perf_counter() - start
    order = sorted(results)
    return {
        "stretch": np.array(order),
        "stress": np.array([results[t][0] for t in order]),
        "iterations": np.array([results[t][1] for t in order]),
        "seconds": seconds,
    }


def main(argv):
    bases = argv[1] if len(argv) > 1 else "clamped"
    nr, nz = (int(argv[2]), int(argv[3])) if len(argv) > 3 else (6, 24)
    material = Material(law="explicit", coupling="frozen")
    stretches = [0.8, 0.9, 1.0, 1.1, 1.17, 1.2, 1.3]
    r = cylinder(material, stretches, bases=bases, nr=nr, nz=nz)
    zero_d = material.uniaxial(list(r["stretch"]))["stress"]
    print(f"# felupe + activemuscle, {bases} bases, {nr} x {nz} Q2/Q1 cells: {r['seconds']:.2f} s")
    print("lambda P_kPa P_0D_kPa newton_iterations")
    for lam, p, p0, its in zip(r["stretch"], r["stress"], zero_d, r["iterations"]):
        print(f"{lam:.2f} {p:.6f} {p0:.6f} {its}")


if __name__ == "__main__":
    main(sys.argv)
