"""A fusiform muscle in 3D with felupe: a spindle of length L whose circular cross-section
grows from the tendon radius at the ends to the belly radius in the middle, fibres along the
spindle's generatrices (one direction per quadrature point), exact incompressibility with the
hybrid Q1/P0 hexahedron (trilinear displacement, one pressure per cell). The ends are glued to
the tendons: u = 0 at x = 0, u = ((λ − 1) L, 0, 0) at x = L. activemuscle's own solver is
axisymmetric with fibres along the axis; this shape and these fibres need felupe's 3D elements.

    python -m activemuscle.examples.felupe_fusiform [LAMBDA] [NX NR]

Models: passive, explicit law (frozen, d = 0 and 0.5) and energy law (frozen). The consistent
coupling does not converge here, with any law: felupe's Newton–Raphson has no line search, and
from the undeformed spindle its first step inverts cells (det F < 0), even with the activation
ramped in from d = 1 in steps of 2 % (tried with felupe 11.3); its stress and tangent are exact
(P = ∂Ψ/∂F and A = ∂P/∂F to finite-difference accuracy). activemuscle's own axisymmetric solver,
with its line search, runs the consistent models on the cylinder. A model that fails is reported
and the exit status is 1.
"""

import sys
import time

import felupe as fem
import numpy as np

from activemuscle import Material
from activemuscle.felupe import Incompressible, MuscleMaterial


def spindle(nx=12, nr=4, length=4.0, belly=1.0, tendon=0.4):
    """A hexahedral spindle: radius r(x) = tendon + (belly − tendon) sin(π x / L); the square
    cross-section of a cube mesh mapped onto the disc (u, v) → (u √(1 − v²/2), v √(1 − u²/2))."""
    mesh = fem.Cube(a=(0.0, -1.0, -1.0), b=(length, 1.0, 1.0), n=(nx + 1, nr + 1, nr + 1))
    x, u, v = mesh.points.T.copy()
    r = tendon + (belly - tendon) * np.sin(np.pi * x / length)
    mesh.points[:, 1] = r * u * np.sqrt(1 - v**2 / 2)
    mesh.points[:, 2] = r * v * np.sqrt(1 - u**2 / 2)
    return mesh


def generatrix_fibres(region, length=4.0, belly=1.0, tendon=0.4):
    """Unit fibre directions (3, q, c) at the quadrature points: tangent to the curves
    (x, y, z) = (x, a r(x), b r(x)), i.e. m ∝ (1, y r′/r, z r′/r)."""
    X = fem.Field(region, dim=3, values=region.mesh.points).interpolate()
    x, y, z = X
    r = tendon + (belly - tendon) * np.sin(np.pi * x / length)
    dr = (belly - tendon) * np.pi / length * np.cos(np.pi * x / length)
    m = np.stack([np.ones_like(x), y * dr / r, z * dr / r])
    return m / np.linalg.norm(m, axis=0)


def fusiform(umat, stretch, nx=12, nr=4, length=4.0, steps=None):
    """Stretch the spindle to ``stretch``; returns a dict: "force" (axial reaction at x = L),
    "iterations", "seconds", "dofs"."""
    mesh = spindle(nx, nr, length)
    region = fem.RegionHexahedron(mesh)
    field = fem.FieldsMixed(region, n=2)
    solid = fem.SolidBody(Incompressible(umat), field)
    boundaries = {
        "fixed": fem.Boundary(field[0], fx=0.0),
        "move": fem.Boundary(field[0], fx=length),
    }
    steps = steps or max(1, int(np.ceil(abs(stretch - 1.0) / 0.025)))
    start, iterations = time.perf_counter(), 0
    for lam in np.linspace(1.0, stretch, steps + 1)[1:]:
        boundaries["move"].value = np.array([(lam - 1.0) * length, 0.0, 0.0])
        dof0, dof1 = fem.dof.partition(field, boundaries)
        ext0 = fem.dof.apply(field, boundaries, dof0)
        res = fem.newtonraphson(
            items=[solid], x0=field, dof1=dof1, dof0=dof0, ext0=ext0, tol=1e-10, verbose=0
        )
        if not res.success:
            raise RuntimeError(f"no convergence at stretch {lam}")
        iterations += res.iterations
    return {
        "force": fem.tools.force(field, res.fun, boundaries["move"])[0],
        "iterations": iterations,
        "seconds": time.perf_counter() - start,
        "dofs": sum(f.values.size for f in field.fields),
    }


def main(argv):
    stretch = float(argv[1]) if len(argv) > 1 else 1.1
    nx, nr = (int(argv[2]), int(argv[3])) if len(argv) > 3 else (12, 4)
    region = fem.RegionHexahedron(spindle(nx, nr))
    fibres = generatrix_fibres(region)
    print(f"# fusiform muscle, {nx} x {nr} x {nr} Q1/P0 hexahedra, stretch {stretch}")
    print("model axial_force_kPa_x_area iterations seconds dofs")
    failed = []
    for name, material in [
        ("passive", Material(law="passive")),
        ("explicit-frozen", Material(law="explicit", coupling="frozen")),
        ("explicit-frozen-d0.5", Material(law="explicit", coupling="frozen", damage=0.5)),
        ("energy-frozen", Material(law="energy", coupling="frozen")),
    ]:
        try:
            r = fusiform(MuscleMaterial(material, fibre=fibres), stretch, nx, nr)
        except (RuntimeError, ValueError, ArithmeticError) as e:
            print(f"{name} FAILED: {e}")
            failed.append(name)
            continue
        print(f"{name} {r['force']:.6f} {r['iterations']} {r['seconds']:.2f} {r['dofs']}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
