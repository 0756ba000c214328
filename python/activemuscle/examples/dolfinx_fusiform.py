"""A fusiform muscle in 3D on DOLFINx under MPI: the spindle of examples/felupe_fusiform.py
(length L = 4, radius r(x) = r_t + (r_b − r_t) sin(π x / L) from the tendon radius 0.4 to the
belly radius 1), fibres along the spindle's generatrices (one direction per quadrature point),
the ends glued to the tendons (u = 0 at x = 0, u = ((λ − 1) L, 0, 0) at x = L), Taylor–Hood
P2/P1 tetrahedra with exact incompressibility, Newton with a line search, MUMPS. A shape
activemuscle's axisymmetric solver cannot take (its fibres are along the axis).

Models: passive; explicit law, frozen, d = 0 and 0.5; energy law, frozen; and the energy law with
the consistent (hyperelastic) coupling, which felupe's Newton without a line search cannot start
from the undeformed spindle. `--models explicit-consistent` (or implicit-consistent) does not
converge, and should not: with the explicit or implicit law the consistent model's uniaxial
stress falls with the stretch from λ ≈ 0.8 to 1.25 (−33 kPa per unit stretch at λ = 1 for the
explicit law), a material instability at rest (docs/distributed.md).

    mpirun -n 2 /usr/bin/python3 -m activemuscle.examples.dolfinx_fusiform [--stretch 1.1] [--mesh 4x12]

Prints one line per model: `<model> force <axial reaction at x = L> iterations <n> seconds <s>`
(the force in kPa × the length unit squared, as felupe_fusiform.py prints it), then `dofs <n>
processes <n>`. A model that fails prints `<model> FAILED` and the exit status is 1.
"""

import argparse
import sys
import time

from mpi4py import MPI

import activemuscle as am
from activemuscle.dolfinx import MuscleBody, Newton, ends, meshes, sweep

LENGTH, BELLY, TENDON = 4.0, 1.0, 0.4
MODELS = {
    "passive": dict(law="passive"),
    "explicit-frozen": dict(law="explicit", coupling="frozen"),
    "explicit-frozen-d0.5": dict(law="explicit", coupling="frozen", damage=0.5),
    "energy-frozen": dict(law="energy", coupling="frozen"),
    "energy-consistent": dict(law="energy", coupling="consistent"),
    "explicit-consistent": dict(law="explicit", coupling="consistent"),
    "implicit-consistent": dict(law="implicit", coupling="consistent"),
}
DEFAULT = [name for name in MODELS if name not in ("explicit-consistent", "implicit-consistent")]


def fibres(X):
    return meshes.generatrix_fibres(X, LENGTH, BELLY, TENDON)


def fusiform(mesh, material, stretch, degree=2, verbose=None):
    """The axial reaction at x = L at `stretch` (None if not reached) and the Newton solver."""
    body = MuscleBody(mesh, material, fibres, degree=degree)
    newton = Newton(body, *ends(body, LENGTH, "clamped"))
    newton.log = verbose
    forces = {}
    sweep(newton, [stretch], LENGTH, lambda lam, force, _: forces.update({lam: force}), verbose)
    return forces.get(stretch), newton


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--stretch", type=float, default=1.1)
    p.add_argument("--mesh", default="4x12", help="RINGSxLAYERS (default 4x12)")
    p.add_argument("--degree", type=int, default=2, help="quadrature degree (default 2)")
    p.add_argument("--models", default=",".join(DEFAULT),
                   help=f"comma-separated, of: {', '.join(MODELS)} (default: {', '.join(DEFAULT)})")
    p.add_argument("--verbose", action="store_true")
    args = p.parse_args(argv[1:])
    comm = MPI.COMM_WORLD
    rings, layers = (int(n) for n in args.mesh.split("x"))
    mesh = meshes.spindle(rings, layers, LENGTH, BELLY, TENDON, comm=comm)

    def say(*line):
        if comm.rank == 0:
            print(*line, flush=True)

    say(f"# fusiform muscle on DOLFINx, {rings} rings x {layers} layers of P2/P1 tetrahedra, "
        f"stretch {args.stretch}, {comm.size} process(es)")
    failed, dofs = [], 0
    for name in args.models.split(","):
        start = time.perf_counter()
        log = (lambda line: print(line, file=sys.stderr)) if args.verbose and comm.rank == 0 else None
        force, newton = fusiform(mesh, am.Material(**MODELS[name]), args.stretch, args.degree, log)
        dofs = newton.body.dofs
        if force is None:
            say(f"{name} FAILED ({newton.error or 'Newton did not converge'})")
            failed.append(name)
            continue
        say(f"{name} force {force:.9f} iterations {newton.iterations} "
            f"seconds {time.perf_counter() - start:.2f}")
    say(f"dofs {dofs} processes {comm.size}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
