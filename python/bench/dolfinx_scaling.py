"""Time per Newton iteration and memory per process of activemuscle.dolfinx on the chapter's
cylinder (the whole of it: R = 1, L = 4, clamped bases, explicit law, frozen coupling, P2/P1
tetrahedra, quadrature degree 2), split into our material (F at the points, Material.evaluate
into the quadrature spaces), DOLFINx's assembly (K and b) and MUMPS (numeric factorisation;
triangular solves). Not a test.

One load step, λ = 1 → 1.05 from the solution at λ = 1 (its predictor and corrections: every
iteration one material evaluation with the tangent, one assembly, one factorisation, one solve);
the figures are per iteration. With --single, the λ = 1 solve alone: one iteration (the pressure
at rest is its solution) and two assemblies (the second checks it). With --analysis-only, no
solve: one material evaluation and assembly at λ = 1, then MUMPS's analysis alone (ordering and
symbolic factorisation), whose estimates of the factorisation's flops and memory say what an
iteration would need where it does not fit.

    mpirun -n 2 /usr/bin/python3 python/bench/dolfinx_scaling.py RINGS LAYERS [--single | --analysis-only]

Prints one line: `rings <n> layers <n> dofs <n> cells <n> points <n> processes <n> iterations <n>
assemblies <n> material <s> assembly <s> factorisation <s> solve <s> iteration <s> memory_mib
<peak RSS per process> mumps_flops <estimated> mumps_factor_entries <estimated> mumps_mib_max
<estimated, the largest process> mumps_mib_sum <estimated, all processes> load <1-min load
average at the start, at the end>` (the phases in seconds per iteration; assemblies: K with the
material's tangent).
"""

import argparse
import ctypes
import os
import sys
import time

from mpi4py import MPI
from petsc4py import PETSc

import activemuscle as am
from activemuscle.dolfinx import MuscleBody, Newton, ends, meshes
from activemuscle.dolfinx.newton import PHASES

LENGTH = 4.0


def analysis(newton):
    """MUMPS's estimates after the analysis alone (as PCSetUp would run it, MUMPS choosing its
    ordering): flops, factor entries, MiB (max, sum). petsc4py 3.18 does not wrap
    MatLUFactorSymbolic (NotImplementedError), so it is called in libpetsc through ctypes, with
    PETSc's default MatFactorInfo (11 PetscReal)."""
    newton.pc.setOperators(newton.K)
    newton.pc.setFactorSetUpSolverType()
    factor = newton.pc.getFactorMatrix()
    petsc = ctypes.CDLL("libpetsc_real.so.3.18", mode=ctypes.RTLD_GLOBAL)
    info = (ctypes.c_double * 11)()
    handle = ctypes.c_void_p
    # No row and column orderings: given ones make PETSc set MUMPS's ICNTL(7) = 1 (use them).
    if petsc.MatFactorInfoInitialize(info) or petsc.MatLUFactorSymbolic(
            handle(factor.handle), handle(newton.K.handle), None, None, info):
        raise RuntimeError("MatLUFactorSymbolic failed")
    return (factor.getMumpsRinfog(1), factor.getMumpsInfog(20), factor.getMumpsInfog(16),
            factor.getMumpsInfog(17))


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("rings", type=int)
    p.add_argument("layers", type=int)
    p.add_argument("--analysis-only", action="store_true")
    p.add_argument("--single", action="store_true",
                   help="time the λ = 1 solve alone (one iteration: p at rest is its solution)")
    args = p.parse_args(argv[1:])
    comm = MPI.COMM_WORLD
    load0 = os.getloadavg()[0]
    mesh = meshes.cylinder(args.rings, args.layers, length=LENGTH, grading=3.0, comm=comm)
    body = MuscleBody(mesh, am.Material(law="explicit", coupling="frozen"))
    newton = Newton(body, *ends(body, LENGTH, "clamped"))
    cells = comm.allreduce(body.material.cells.size)
    points = comm.allreduce(body.material.count)
    if args.analysis_only:
        newton.assemble(newton.homogeneous)
        iterations = 1
        estimates = analysis(newton)
    else:
        if newton.step(None) is None:  # λ = 1: p at rest is the solution, one correction
            sys.exit(f"no solution at λ = 1: {newton.error}")
        if not args.single:
            newton.timings = dict.fromkeys(PHASES, 0.0)
            newton.assemblies = 0
        start = 0 if args.single else newton.iterations
        if not args.single and newton.step(0.05 * LENGTH) is None:
            sys.exit(f"no solution at λ = 1.05: {newton.error}")
        iterations = newton.iterations - start
        factor = newton.pc.getFactorMatrix()
        estimates = (factor.getMumpsRinfog(1), factor.getMumpsInfog(20), factor.getMumpsInfog(16),
                     factor.getMumpsInfog(17))
    memory = ",".join(f"{m:.0f}" for m in newton.memory())
    per = {k: newton.timings[k] / iterations for k in PHASES}
    if comm.rank == 0:
        phases = " ".join(f"{k} {v:.4f}" for k, v in per.items())
        entries = estimates[1] if estimates[1] >= 0 else estimates[1] * -1e6  # MUMPS: < 0 in millions
        print(f"rings {args.rings} layers {args.layers} dofs {body.dofs} cells {cells} points {points} "
              f"processes {comm.size} iterations {iterations} assemblies {newton.assemblies} {phases} iteration {sum(per.values()):.4f} "
              f"memory_mib {memory} mumps_flops {estimates[0]:.3e} mumps_factor_entries {entries:.4g} "
              f"mumps_mib_max {estimates[2]} mumps_mib_sum {estimates[3]} "
              f"load {load0:.2f},{os.getloadavg()[0]:.2f}", flush=True)


if __name__ == "__main__":
    main(sys.argv)
