"""The cost curve of the muscle sweep (issue 48 item 2): time per Newton iteration, per sweep and
peak memory against the number of unknowns, ours and DOLFINx's, on the side-by-side run's case
(python/bench/muscle_sweep.py: the chapter's clamped cylinder R = 1, L = 4 mm, explicit law,
frozen coupling with its exact tangent, d = 0, the 20 stretches 0.70, 0.75, …, 1.60 and 1.17,
Newton to 1e-10, uniform Q2/Q1 meshes), with the fitted exponent p of time ∝ n^p and ours'
memory estimate (the one that refuses a mesh, src/fem/memory.rs) against the measured peak.

    cargo build --release --example fem_memory
    apt-get download libopenblas0-serial && dpkg -x libopenblas0-serial_*.deb /tmp/ob
    OMP_NUM_THREADS=1 /usr/bin/python3 python/bench/cost_curve.py \\
        --openblas /tmp/ob/usr/lib/x86_64-linux-gnu/openblas-serial \\
        [--meshes 16x64,32x128,64x256,128x512] [--repeats 1] [--ours-only]

Ours: target/release/examples/fem_memory NR NZ muscle (the library's solver on the sweep alone,
rayon's default threads: 2 here), which prints the memory estimate from the counts (before the
symbolic factorisation, what refuses a mesh before anything is allocated) and after it (the
exact dofs, nonzeros and factor size), the sweep's wall time, its Newton iterations (curves.csv's:
the load steps' iterations summed over the stretches) and the peak resident memory (VmHWM).
DOLFINx: python/bench/dolfinx_muscle.py --element Q2Q1 (Taylor–Hood on the same quadrilaterals,
MUMPS LU on OpenBLAS, one process), its sweep time (the load path, set-up and JIT excluded) and
iterations (every assembly–LU–solve, predictors included). Peak memory of both: the process's
maximum resident set (`/usr/bin/time -f %M`). Runs alternate ours and DOLFINx mesh by mesh; the
table gives medians over the repeats. The exponent p is the least-squares slope of log time
against log n over the meshes run (n: free dofs).
"""

import argparse
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
OURS = os.path.join(ROOT, "target", "release", "examples", "fem_memory")
PYTHON = sys.executable if sys.executable.startswith("/usr/bin/") else "/usr/bin/python3"
DOLFINX = [PYTHON, os.path.join(HERE, "dolfinx_muscle.py"), "--solver", "mumps", "--element", "Q2Q1"]
COST = re.compile(
    r"^cost (\d+)x(\d+) dofs (\S+) estimate_counts (\S+) estimate (\S+) sweep (\S+) its (\d+) "
    r"iteration (\S+) peak (\S+) stretches (\d+)/(\d+)$",
    re.M,
)
SUMMARY = re.compile(
    r"^dolfinx \S+ (\d+)x(\d+) dofs (\d+) free (\d+) stretches (\d+)/(\d+) its (\d+) "
    r"predictors (\d+) sweep (\S+) iteration (\S+) setup (\S+) P\(1\.17\) (\S+)(?: solver \S+)?$",
    re.M,
)


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def timed(command, env=None):
    """Runs `command` under /usr/bin/time: (stdout, wall seconds, peak resident MiB)."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as out:
        t0 = time.perf_counter()
        run = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", out.name] + command,
                             capture_output=True, text=True, env=env, timeout=6 * 3600)
        wall = time.perf_counter() - t0
        if run.returncode != 0:
            raise RuntimeError(f"{' '.join(command)} failed ({run.returncode}):\n{run.stderr[-3000:]}")
        kib = float(out.read().split()[-1])
    return run.stdout, wall, kib / 1024.0


def ours(nr, nz, binary=OURS):
    stdout, wall, peak = timed([binary, str(nr), str(nz), "muscle"])
    m = COST.search(stdout)
    if m is None:
        raise RuntimeError(f"fem_memory: no cost line in\n{stdout[-3000:]}")
    g = m.groups()
    return {"dofs": int(float(g[2])), "estimate_counts": float(g[3]), "estimate": float(g[4]),
            "sweep": float(g[5]), "its": int(g[6]), "iteration": float(g[7]) / 1e3,
            "peak": peak, "reached": f"{g[9]}/{g[10]}", "wall": wall}


def dolfinx(nr, nz, blas):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    if blas:
        env["LD_LIBRARY_PATH"] = blas
    stdout, wall, peak = timed(DOLFINX + [str(nr), str(nz)], env)
    m = SUMMARY.search(stdout)
    if m is None:
        raise RuntimeError(f"dolfinx_muscle.py: no summary line in\n{stdout[-3000:]}")
    g = m.groups()
    return {"dofs": int(g[3]), "sweep": float(g[8]), "its": int(g[6]),
            "iteration": float(g[9]), "peak": peak, "reached": f"{g[4]}/{g[5]}", "wall": wall}


def slope(xs, ys):
    """Least-squares slope of log y against log x."""
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = statistics.mean(lx), statistics.mean(ly)
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--meshes", default="16x64,32x128,64x256,128x512")
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--openblas", metavar="DIR",
                        help="directory holding OpenBLAS's libblas.so.3 (LD_LIBRARY_PATH of DOLFINx)")
    parser.add_argument("--ours-only", action="store_true", help="skip DOLFINx")
    parser.add_argument("--binary", default=OURS, help="our fem_memory example (default: %(default)s)")
    args = parser.parse_args(argv[1:])
    if not os.path.exists(args.binary):
        sys.exit(f"{args.binary} missing: cargo build --release --example fem_memory")
    meshes = [tuple(int(x) for x in m.split("x")) for m in args.meshes.split(",")]
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, commit {commit}, "
          f"{os.cpu_count()} cores, load {load()}", flush=True)
    if not args.ours_only:
        dolfinx(2, 8, args.openblas)  # untimed: the FFCx JIT cache of the Q2/Q1 forms
    codes = [("ours", lambda nr, nz: ours(nr, nz, args.binary))] + ([] if args.ours_only else
                                [("DOLFINx", lambda nr, nz: dolfinx(nr, nz, args.openblas))])
    rows = {name: [] for name, _ in codes}
    for nr, nz in meshes:
        before = load()
        runs = {name: [] for name, _ in codes}
        for _ in range(args.repeats):
            for name, code in codes:
                runs[name].append(code(nr, nz))
                print(f"# {nr}x{nz} {name}: {runs[name][-1]}", flush=True)
        after = load()
        for name, _ in codes:
            rs = runs[name]
            row = dict(rs[0])
            for key in ("sweep", "iteration", "peak", "wall"):
                row[key] = statistics.median(r[key] for r in rs)
            row.update(mesh=f"{nr} × {nz}", load=f"{before} → {after}")
            rows[name].append(row)

    print(f"\nmedian of {args.repeats} run(s) per code and mesh, alternated")
    print("| cells | code | free dofs | Newton its | stretches | sweep [s] | per iteration [ms] "
          "| peak [MiB] | estimate from the counts [MiB] | estimate after the analysis [MiB] "
          "| load before → after |")
    print("|---|---|---:|---:|---|---:|---:|---:|---:|---:|---|")
    for i in range(len(meshes)):
        for name, _ in codes:
            r = rows[name][i]
            counts = f"{r['estimate_counts']:.0f} ({r['estimate_counts'] / r['peak']:.2f}×)" \
                if "estimate" in r else "–"
            exact = f"{r['estimate']:.0f} ({r['estimate'] / r['peak']:.2f}×)" if "estimate" in r else "–"
            print(f"| {r['mesh']} | {name} | {r['dofs']} | {r['its']} | {r['reached']} "
                  f"| {r['sweep']:.2f} | {1e3 * r['iteration']:.1f} | {r['peak']:.0f} | {counts} "
                  f"| {exact} | {r['load']} |")
    if len(meshes) >= 2:
        print("\nfitted exponent p of time ∝ n^p (n: free dofs), least squares over the meshes")
        for name, _ in codes:
            rs = rows[name]
            n = [r["dofs"] for r in rs]
            print(f"- {name}: per iteration p = {slope(n, [r['iteration'] for r in rs]):.2f}, "
                  f"per sweep p = {slope(n, [r['sweep'] for r in rs]):.2f}, "
                  f"peak memory p = {slope(n, [r['peak'] for r in rs]):.2f}")
        if len(codes) == 2:
            print("- DOLFINx / ours, per sweep: " + ", ".join(
                f"{d['mesh']} {d['sweep'] / o['sweep']:.1f}×"
                for o, d in zip(rows["ours"], rows["DOLFINx"])))


if __name__ == "__main__":
    main(sys.argv)
