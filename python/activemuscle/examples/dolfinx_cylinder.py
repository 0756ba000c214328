"""The chapter's cylinder in 3D on DOLFINx under MPI: an independent check of activemuscle's
axisymmetric solver by another finite element code.

R = 1, L = 4, axis and fibres along x; Taylor–Hood P2/P1 tetrahedra (activemuscle.dolfinx:
the disc's rings × layers along x, the layers refined towards the bases by --grading like the
axisymmetric mesh's z), the whole cylinder or with --quarter its part y, z ≥ 0 on two symmetry
planes. Bases "clamped" (u = 0 on x = 0; u = ((λ − 1) L, 0, 0) on x = L) or "sliding" (u_x
only: homogeneous uniaxial tension, so P must equal the 0D curve to the solver's tolerance).
The nominal stress P = axial reaction on x = L / the area of that end (the mesh's polygon).

The model is a scene's (--scene FILE: its [material], [activation], [incompressibility];
default: the chapter's), with --law, --coupling, --damage as a study's keys. For each mesh of
--meshes (RINGSxLAYERS, e.g. 4x16,8x32) one sweep through the stretches; with --axisymmetric
NR NZ also activemuscle's own axisymmetric Q2/Q1 solution of the same scene (on rank 0).

    mpirun -n 2 /usr/bin/python3 -m activemuscle.examples.dolfinx_cylinder \\
        --bases clamped --quarter --meshes 4x16,8x32 --axisymmetric 64 256

Prints a header (lines starting with #), then one row per stretch:
`lambda P_0d [P_axisymmetric] P_<mesh> ...` [kPa], then per mesh a line `mesh <RxN> dofs <n>
processes <n> iterations <n> predictors <n> seconds <s> material <s> assembly <s> factorisation
<s> solve <s> memory_mib <peak RSS per process>` (iterations: every linear solve; the phases sum
over them). A stretch not reached is `nan` and the exit status is 1.
"""

import argparse
import math
import sys
import time

try:
    import tomllib
except ImportError:  # Python < 3.11
    import tomli as tomllib

from mpi4py import MPI

import activemuscle as am
from activemuscle.dolfinx import MuscleBody, Newton, end_area, ends, meshes, model_of_scene, sweep
from activemuscle.dolfinx.newton import PHASES

RADIUS, LENGTH = 1.0, 4.0
CHAPTER_STRETCHES = [round(0.70 + 0.05 * i, 10) for i in range(19)] + [1.17]


def parse(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--bases", choices=["clamped", "sliding"], default="clamped")
    p.add_argument("--meshes", default="4x16", help="RINGSxLAYERS, comma-separated (default 4x16)")
    p.add_argument("--quarter", action="store_true", help="the part y, z ≥ 0 on symmetry planes")
    p.add_argument("--half", action="store_true", help="the part x ≤ L/2 on the mid-plane")
    p.add_argument("--grading", type=float, default=3.0, help="middle/end layer height (default 3)")
    p.add_argument("--degree", type=int, default=2, help="quadrature degree (default 2: 4 points)")
    p.add_argument("--stretches", help="comma-separated (default: the chapter's, 0.70 … 1.60 and 1.17)")
    p.add_argument("--scene", help="a scene file whose model to use (default: the chapter's)")
    p.add_argument("--law")
    p.add_argument("--coupling")
    p.add_argument("--damage", type=float)
    p.add_argument("--axisymmetric", nargs=2, type=int, metavar=("NR", "NZ"),
                   help="also activemuscle's axisymmetric Q2/Q1 solution on NR × NZ cells")
    p.add_argument("--tolerance", type=float, default=1e-10)
    p.add_argument("--verbose", action="store_true", help="every load step on rank 0's stderr")
    args = p.parse_args(argv)
    args.stretches = ([float(s) for s in args.stretches.split(",")] if args.stretches
                      else CHAPTER_STRETCHES)
    args.meshes = [tuple(int(n) for n in m.split("x")) for m in args.meshes.split(",")]
    return args


def scene_of(args):
    """The scene as a dict, without its studies."""
    if args.scene is None:
        return {"title": "dolfinx cylinder"}
    with open(args.scene, "rb") as f:
        scene = tomllib.load(f)
    scene.pop("study", None)
    return scene


def axisymmetric(scene, model, args):
    """activemuscle's axisymmetric Q2/Q1 solution of the same model: P per stretch."""
    study = {"kind": "cylinder", "name": "axisymmetric", "radius": RADIUS, "length": LENGTH,
             "nr": args.axisymmetric[0], "nz": args.axisymmetric[1], "grading": args.grading,
             "bases": args.bases, "damage": [model.damage], "stretch": sorted(set(args.stretches)),
             "tolerance": args.tolerance}
    study.update({k: v for k, v in (("law", args.law), ("coupling", args.coupling)) if v})
    table = am.run_scene(dict(scene, study=[study]))["axisymmetric"].table
    return dict(zip(table["lambda"], table["P"]))


def run_mesh(model, rings, layers, args, comm):
    """One sweep on a rings × layers mesh: ({λ: P}, summary line)."""
    start = time.perf_counter()
    mesh = meshes.cylinder(rings, layers, RADIUS, LENGTH, args.grading, args.quarter, args.half, comm)
    body = MuscleBody(mesh, model.material, model.fibre, model.volumetric, args.degree)
    far = LENGTH / 2 if args.half else LENGTH
    newton = Newton(body, *ends(body, far, args.bases, RADIUS, args.quarter, args.half), args.tolerance)
    area = end_area(mesh, far)
    stresses = {}
    log = (lambda line: print(line, file=sys.stderr, flush=True)) if args.verbose and comm.rank == 0 else None
    newton.log = log
    sweep(newton, args.stretches, far, lambda lam, force, _: stresses.update({lam: force / area}), log)
    seconds = time.perf_counter() - start
    phases = " ".join(f"{k} {newton.timings[k]:.3f}" for k in PHASES)
    memory = ",".join(f"{m:.0f}" for m in newton.memory())
    summary = (f"mesh {rings}x{layers} dofs {body.dofs} processes {comm.size} iterations "
               f"{newton.iterations} predictors {newton.predictors} seconds {seconds:.3f} {phases} "
               f"memory_mib {memory}")
    return stresses, summary


def main(argv):
    args = parse(argv[1:])
    comm = MPI.COMM_WORLD
    scene = scene_of(args)
    model = model_of_scene(scene, args.damage, args.law, args.coupling)
    zero_d = model.material.uniaxial(args.stretches, model.volumetric)["stress"]
    reference = axisymmetric(scene, model, args) if args.axisymmetric and comm.rank == 0 else None
    results = [run_mesh(model, rings, layers, args, comm) for rings, layers in args.meshes]
    if comm.rank != 0:
        return 0
    part = " ".join(w for w, on in (("quarter", args.quarter), ("half", args.half)) if on)
    print(f"# DOLFINx + activemuscle: {part + ' of a ' if part else ''}cylinder R = {RADIUS}, "
          f"L = {LENGTH}, {args.bases} bases, {model.material!r}, {model.volumetric or 'J = 1'}, "
          f"quadrature degree {args.degree}, {comm.size} process(es)")
    columns = ["lambda", "P_0d"] + (["P_axisymmetric"] if reference else [])
    print(" ".join(columns + [f"P_{r}x{n}" for r, n in args.meshes]))
    missing = False
    for lam, p0 in zip(args.stretches, zero_d):
        row = [f"{lam:.4f}", f"{p0:.12f}"] + ([f"{reference.get(lam, math.nan):.12f}"] if reference else [])
        for stresses, _ in results:
            missing |= lam not in stresses
            row.append(f"{stresses.get(lam, math.nan):.12f}")
        print(" ".join(row))
    for _, summary in results:
        print(summary)
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
