"""Time per Newton iteration, ours (examples/fem_scaling.rs, Q2/Q1) against legacy FEniCS
(python/bench/fenics_cylinder.py, P2/P1 on the same cells split in two triangles: the same nodes,
the same dof count), runs alternated case by case so that a shared machine's load shifts both
alike; the median over the repeats, the load (/proc/loadavg) before and after each size.

    cargo build --release --example fem_scaling
    OMP_NUM_THREADS=1 /usr/bin/python3 python/bench/fe_per_iteration.py [--repeats 3] [--large]
        [--openblas DIR] [--one-thread]

Debian's python3-dolfin runs on the reference (netlib) BLAS unless an optimised BLAS is installed;
--openblas DIR adds FEniCS on OpenBLAS (DIR holds its libblas.so.3, e.g. after
`apt-get download libopenblas0-serial && dpkg -x libopenblas0-serial_*.deb /tmp/ob`:
DIR = /tmp/ob/usr/lib/x86_64-linux-gnu/openblas-serial), without touching the system's choice.

Sizes: 16 × 64 (9 360 free dofs) and 32 × 128 (37 152); --large adds 48 × 192 (83 376).
Before the table, a check that both solve the same problem: FEniCS with Q2/Q1 on the
quadrilaterals (our discretisation, 3 × 3 Gauss) at 16 × 64 must give our nominal stress.
Ratio = each code's median seconds per iteration / ours (ours: rayon's default threads for the
element loop, here 2; --one-thread adds ours on one thread, as FEniCS's one process).
"""

import argparse
import os
import re
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
OURS = os.path.join(ROOT, "target", "release", "examples", "fem_scaling")
FENICS = [sys.executable if sys.executable.startswith("/usr/bin/") else "/usr/bin/python3",
          os.path.join(HERE, "fenics_cylinder.py")]
LINE = re.compile(
    r"^(ours|fenics) (\S+) (\d+)x(\d+) dofs (\d+) (?:free (\d+) )?its (\d+) assembly (\S+) "
    r"factor (\S+) solve (\S+) iteration (\S+) P (\S+)$",
    re.M,
)
PHASES = ("assembly", "factor", "solve", "iteration")


def run(command, extra_env=None):
    env = dict(os.environ, OMP_NUM_THREADS="1", **(extra_env or {}))
    out = subprocess.run(command, capture_output=True, text=True, env=env, timeout=3600)
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{out.stderr[-3000:]}")
    m = LINE.search(out.stdout)
    if m is None:
        raise RuntimeError(f"{' '.join(command)}: no result line in\n{out.stdout[-3000:]}")
    g = m.groups()
    free = int(g[5]) if g[5] else int(g[4])
    return {"dofs": int(g[4]), "free": free, "its": int(g[6]), "P": float(g[11]),
            **{k: float(v) for k, v in zip(PHASES, g[7:11])}}


def ours(nr, nz, threads=None):
    return run([OURS, "Q2Q1", str(nr), str(nz)],
               {"RAYON_NUM_THREADS": str(threads)} if threads else None)


def fenics(element, nr, nz, blas=None):
    return run(FENICS + ["--element", element, str(nr), str(nz)],
               {"LD_LIBRARY_PATH": blas} if blas else None)


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--large", action="store_true", help="add 48 × 192 (83k dofs)")
    parser.add_argument("--one-thread", action="store_true",
                        help="also ours with one thread (RAYON_NUM_THREADS=1), as FEniCS")
    parser.add_argument("--openblas", metavar="DIR",
                        help="also FEniCS with the libblas.so.3 in DIR (LD_LIBRARY_PATH)")
    args = parser.parse_args(argv[1:])
    if not os.path.exists(OURS):
        sys.exit(f"{OURS} missing: cargo build --release --example fem_scaling")

    a, b = ours(16, 64), fenics("Q2Q1", 16, 64)
    print(f"same problem, Q2/Q1 16x64: ours P = {a['P']:.12g} kPa ({a['free']} free dofs), "
          f"FEniCS P = {b['P']:.12g} kPa ({b['free']} free dofs), "
          f"relative difference {abs(a['P'] - b['P']) / abs(b['P']):.1e}")

    codes = [("ours Q2/Q1", ours)]
    if args.one_thread:
        codes.append(("ours Q2/Q1, 1 thread", lambda nr, nz: ours(nr, nz, 1)))
    codes.append(("FEniCS P2/P1", lambda nr, nz: fenics("P2P1", nr, nz)))
    if args.openblas:
        codes.append(("FEniCS P2/P1 + OpenBLAS",
                      lambda nr, nz: fenics("P2P1", nr, nz, args.openblas)))
    sizes = [(16, 64), (32, 128)] + ([(48, 192)] if args.large else [])
    print(f"\nmedian of {args.repeats} alternated runs (min–max of the per-iteration time), "
          "seconds per Newton iteration; FEniCS: UMFPACK, one process")
    print("| cells | code | free dofs (total) | Newton its | assembly [s] | factorisation [s] "
          "| solve [s] | per iteration [s] | FEniCS / ours | P [kPa] | load before → after |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    for nr, nz in sizes:
        before = load()
        runs = {name: [] for name, _ in codes}
        for _ in range(args.repeats):
            for name, code in codes:
                runs[name].append(code(nr, nz))
        after = load()
        median = {name: {k: statistics.median(r[k] for r in rs) for k in PHASES + ("its",)}
                  for name, rs in runs.items()}
        reference = median[codes[0][0]]["iteration"]
        for name, rs in runs.items():
            m, times = median[name], [r["iteration"] for r in rs]
            print(f"| {nr} × {nz} | {name} | {rs[0]['free']} ({rs[0]['dofs']}) | {m['its']:.0f} "
                  f"| {m['assembly']:.4f} | {m['factor']:.4f} | {m['solve']:.4f} "
                  f"| {m['iteration']:.4f} ({min(times):.4f}–{max(times):.4f}) "
                  f"| {m['iteration'] / reference:.1f}× | {rs[0]['P']:.6f} | {before} → {after} |",
                  flush=True)


if __name__ == "__main__":
    main(sys.argv)
