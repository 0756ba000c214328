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
        [--meshes 16x64,32x128,64x256,128x512] [--repeats 1] [--ours-only | --dolfinx-only] \\
        [--truncate 128x512:1.05,1.1] [--record runs.jsonl]
    /usr/bin/python3 python/bench/cost_curve.py --table runs.jsonl [more.jsonl …]

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
against log n over the meshes run (n: free dofs); per sweep, over the full sweeps only.

--truncate NRxNZ:L1,L2,… solves only those stretches on that mesh (both codes, `--stretches`):
a truncated sweep, where the whole one would take too long, for the time per iteration and the
peak memory; its row is marked "truncated" and its sweep time is not a sweep's.

--record FILE appends each run to FILE as it ends (one JSON object a line: a long run that is
stopped keeps what it measured); --table FILE… prints the table and the exponents of the runs
recorded, from one invocation or several (e.g. the largest mesh run alone, later).
"""

import argparse
import json
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


def stretch_option(stretches):
    return ["--stretches", ",".join(f"{l:g}" for l in stretches)] if stretches else []


def ours(nr, nz, stretches, binary=OURS):
    stdout, wall, peak = timed([binary, str(nr), str(nz), "muscle"] + stretch_option(stretches))
    m = COST.search(stdout)
    if m is None:
        raise RuntimeError(f"fem_memory: no cost line in\n{stdout[-3000:]}")
    g = m.groups()
    return {"dofs": int(float(g[2])), "estimate_counts": float(g[3]), "estimate": float(g[4]),
            "sweep": float(g[5]), "its": int(g[6]), "iteration": float(g[7]) / 1e3,
            "peak": peak, "reached": f"{g[9]}/{g[10]}", "wall": wall}


def dolfinx(nr, nz, stretches, blas):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    if blas:
        env["LD_LIBRARY_PATH"] = blas
    stdout, wall, peak = timed(DOLFINX + [str(nr), str(nz)] + stretch_option(stretches), env)
    m = SUMMARY.search(stdout)
    if m is None:
        raise RuntimeError(f"dolfinx_muscle.py: no summary line in\n{stdout[-3000:]}")
    g = m.groups()
    return {"dofs": int(g[3]), "sweep": float(g[8]), "its": int(g[6]),
            "iteration": float(g[9]), "peak": peak, "reached": f"{g[4]}/{g[5]}", "wall": wall}


def slope(xs, ys):
    """Least-squares slope of log y against log x (nan below two points)."""
    if len(xs) < 2:
        return float("nan")
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = statistics.mean(lx), statistics.mean(ly)
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


def truncation(text):
    """`128x512:1.05,1.1` → ((128, 512), [1.05, 1.1])."""
    try:
        mesh, stretches = text.split(":")
        nr, nz = (int(x) for x in mesh.split("x"))
        return (nr, nz), [float(l) for l in stretches.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not NRxNZ:L1,L2,…")


def measure(args, meshes, record):
    """Runs the codes alternated mesh by mesh; each run, with the load, to record(run)."""
    truncated = dict(args.truncate)
    codes = ([] if args.dolfinx_only else [("ours", lambda nr, nz, ls: ours(nr, nz, ls, args.binary))]) \
        + ([] if args.ours_only else [("DOLFINx", lambda nr, nz, ls: dolfinx(nr, nz, ls, args.openblas))])
    if not args.ours_only:
        dolfinx(2, 8, None, args.openblas)  # untimed: the FFCx JIT cache of the Q2/Q1 forms
    for nr, nz in meshes:
        for _ in range(args.repeats):
            for name, code in codes:
                before = load()
                stretches = truncated.get((nr, nz))
                run = code(nr, nz, stretches)
                run.update(code=name, mesh=[nr, nz], full=stretches is None, stretches=stretches,
                           load=f"{before} → {load()}")
                print(f"# {nr}x{nz} {name}: {run}", flush=True)
                record(run)


def table(runs):
    """The markdown table (medians per code and mesh) and the fitted exponents."""
    groups = {}
    for r in runs:
        series = tuple(r.get("stretches") or ())  # () = the whole sweep
        groups.setdefault((r["code"], tuple(r["mesh"]), series), []).append(r)
    rows = []
    def order(group):  # by mesh, ours first, a full sweep before a truncated one
        (code, mesh, series), _ = group
        return mesh, code != "ours", series

    for _, rs in sorted(groups.items(), key=order):
        row = dict(rs[0], repeats=len(rs), load=", ".join(r["load"] for r in rs),
                   series=tuple(rs[0].get("stretches") or ()))
        for key in ("sweep", "iteration", "peak", "wall"):
            row[key] = statistics.median(r[key] for r in rs)
        rows.append(row)
    print("\nmedians over the runs per code and mesh")
    print("| cells | code | free dofs | Newton its | stretches | sweep [s] | per iteration [ms] "
          "| peak [MiB] | estimate from the counts [MiB] | estimate after the analysis [MiB] "
          "| runs | load before → after |")
    print("|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---|")
    for r in rows:
        counts = f"{r['estimate_counts']:.0f} ({r['estimate_counts'] / r['peak']:.2f}×)" \
            if "estimate" in r else "–"
        exact = f"{r['estimate']:.0f} ({r['estimate'] / r['peak']:.2f}×)" if "estimate" in r else "–"
        reached = r["reached"] + ("" if r["full"] else
                                  " truncated: " + ", ".join(f"{l:g}" for l in r["series"]))
        print(f"| {r['mesh'][0]} × {r['mesh'][1]} | {r['code']} | {r['dofs']} | {r['its']} | {reached} "
              f"| {r['sweep']:.2f} | {1e3 * r['iteration']:.1f} | {r['peak']:.0f} | {counts} "
              f"| {exact} | {r['repeats']} | {r['load']} |")
    print("\nfitted exponent p of time ∝ n^p (n: free dofs), least squares over the meshes of one "
          "code and one list of stretches")
    for code, series in sorted({(r["code"], r["series"]) for r in rows}, key=lambda k: (k[0] != "ours", k[1])):
        rs = [r for r in rows if r["code"] == code and r["series"] == series]
        n = [r["dofs"] for r in rs]
        what = "the whole sweep" if not series else "truncated to " + ", ".join(f"{l:g}" for l in series)
        print(f"- {code}, {what}, {len(rs)} meshes: per iteration p = "
              f"{slope(n, [r['iteration'] for r in rs]):.2f}, per sweep p = "
              f"{slope(n, [r['sweep'] for r in rs]):.2f}, peak memory p = "
              f"{slope(n, [r['peak'] for r in rs]):.2f}")
    pairs = [(o, d) for o in rows for d in rows if o["code"] == "ours" and d["code"] == "DOLFINx"
             and o["mesh"] == d["mesh"] and o["series"] == d["series"]]
    for o, d in pairs:
        what = "whole sweep" if not o["series"] else "truncated"
        print(f"- DOLFINx / ours, {o['mesh'][0]} × {o['mesh'][1]} ({what}): per sweep "
              f"{d['sweep'] / o['sweep']:.1f}×, per Newton iteration {d['iteration'] / o['iteration']:.1f}×")


def main(argv):
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--meshes", default="16x64,32x128,64x256,128x512",
                        help="NRxNZ cells, comma-separated (default: %(default)s)")
    parser.add_argument("--repeats", type=int, default=1,
                        help="runs per code and mesh, alternated; the table gives medians")
    parser.add_argument("--openblas", metavar="DIR",
                        help="directory holding OpenBLAS's libblas.so.3 (LD_LIBRARY_PATH of DOLFINx)")
    only = parser.add_mutually_exclusive_group()
    only.add_argument("--ours-only", action="store_true", help="skip DOLFINx")
    only.add_argument("--dolfinx-only", action="store_true", help="skip ours")
    parser.add_argument("--truncate", type=truncation, action="append", default=[],
                        metavar="NRxNZ:L1,L2,...",
                        help="on that mesh, only these stretches (a truncated sweep); repeatable")
    parser.add_argument("--binary", default=OURS, help="our fem_memory example (default: %(default)s)")
    parser.add_argument("--record", metavar="FILE",
                        help="append each run to FILE (one JSON object a line) as it ends")
    parser.add_argument("--table", metavar="FILE", nargs="+",
                        help="run nothing: the table of the runs recorded in FILE(s)")
    args = parser.parse_args(argv[1:])
    if args.table:
        runs = []
        for name in args.table:
            with open(name) as f:
                runs += [json.loads(line) for line in f if line.strip()]
        table(runs)
        return
    if not args.dolfinx_only and not os.path.exists(args.binary):
        sys.exit(f"{args.binary} missing: cargo build --release --example fem_memory")
    meshes = [tuple(int(x) for x in m.split("x")) for m in args.meshes.split(",")]
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, commit {commit}, "
          f"{os.cpu_count()} cores, load {load()}", flush=True)
    runs = []

    def record(run):
        runs.append(run)
        if args.record:
            with open(args.record, "a") as f:
                f.write(json.dumps(run, ensure_ascii=False) + "\n")

    measure(args, meshes, record)
    table(runs)


if __name__ == "__main__":
    main(sys.argv)
