"""Wall time of the muscle cylinder sweep (issue 26 item 2), ours against legacy FEniCS: ours is the
whole process `activemuscle run python/bench/muscle_sweep.toml` (Q2/Q1), FEniCS is
python/bench/fenics_muscle.py with Taylor–Hood P2/P1 on the same cells split in two triangles (the
same nodes, the same dof count), UMFPACK through PETSc on OpenBLAS (and, with --reference-blas,
on Debian's reference BLAS as installed), and with --dolfinx DOLFINx 0.5 as well:
python/bench/dolfinx_muscle.py, the same P2/P1 problem on DOLFINx, PETSc's MUMPS LU, on the same
OpenBLAS. Runs alternate code by code within each repeat so that a
shared machine's load shifts all alike; the table gives the median over the repeats (min–max of
the wall times) and the load (/proc/loadavg) before and after each mesh.

    cargo build --release                      # target/release/activemuscle
    apt-get install -y python3-dolfin [python3-dolfinx]
    apt-get download libopenblas0-serial && dpkg -x libopenblas0-serial_*.deb /tmp/ob
    OMP_NUM_THREADS=1 /usr/bin/python3 python/bench/muscle_sweep.py \\
        --openblas /tmp/ob/usr/lib/x86_64-linux-gnu/openblas-serial [--repeats 3] \\
        [--meshes 16x64,32x128] [--reference-blas] [--fenics-q2q1] [--one-thread] [--dolfinx]
        [--baseline OTHER/target/release/activemuscle]

The case (python/bench/muscle_sweep.toml; the equations in fenics_muscle.py's docstring): the
chapter's clamped cylinder R = 1, L = 4 mm, explicit law, frozen coupling with its exact tangent,
d = 0, the 20 stretches 0.70, 0.75, …, 1.60 and 1.17 (λ = 1, then upwards, then downwards from
λ = 1), Newton to 1e-10, uniform meshes. Before the table, the check that both codes solve the same
problem: FEniCS with Q2/Q1 on the quadrilaterals (3 × 3 Gauss, our discretisation) on --check-mesh
(default 8 × 32) must give our P at every stretch (the largest relative difference is printed),
and with --dolfinx DOLFINx's Q2/Q1 too (a second line).

Columns: process = wall time of the whole process: ours `activemuscle run` (mesh, symbolic
factorisation, the sweep, the 0D curve, CSV, figures and report.html), FEniCS `python3
fenics_muscle.py` (interpreter, DOLFIN import, JIT cache lookup, a warm-up sweep on 2 × 8, set-up,
the sweep), DOLFINx `python3 dolfinx_muscle.py` (the same with DOLFINx's import, FFCx/CFFI's
cache); sweep = ours the study's time in its summary (set-up, the sweep, the 0D curve), FEniCS and
DOLFINx the load path only (set-up and JIT warm-up excluded); Newton its = ours summed over
curves.csv (rejected steps included; the predictor solve of a step is no iteration: it reuses the
last factorisation), FEniCS and DOLFINx every assembly–LU–solve, the predictor iteration of each
load step and rejected steps included; per iteration = sweep / its; ratios: the row's median / ours'
(the first row) median;
P(1.17) of ours (Q2/Q1) and of FEniCS (P2/P1: another discretisation of the same problem, so
their difference is the discretisation's, not an error). Ours runs on rayon's default threads
(2 here), FEniCS in one process; --fenics-q2q1 adds FEniCS with ours' Q2/Q1 discretisation (the
like-for-like row where P2/P1 does not reach every stretch; with --dolfinx, DOLFINx Q2/Q1 as well);
--one-thread adds ours with RAYON_NUM_THREADS=1; --baseline BINARY adds another activemuscle
(an earlier commit's release build: ours before and after a change, in the same run, so that a
machine that runs slower or faster that day moves both); --dolfinx adds DOLFINx P2/P1 with MUMPS (one
process, OMP_NUM_THREADS=1, on the same OpenBLAS: MUMPS's dense fronts call libblas.so.3), its
rows named DOLFINx, alternated with the others in each repeat. An untimed run of fenics_muscle.py
(and of dolfinx_muscle.py) on 2 × 8 fills the FFC (FFCx) JIT cache first (a first compilation of
the P2/P1 forms takes ≈ 30 s of the process time for FFC, a few seconds for FFCx; with the cache
warm, a process's warm-up loads them).
"""

import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
OURS = os.path.join(ROOT, "target", "release", "activemuscle")
SCENE = os.path.join(HERE, "muscle_sweep.toml")
PYTHON = sys.executable if sys.executable.startswith("/usr/bin/") else "/usr/bin/python3"
FENICS = [PYTHON, os.path.join(HERE, "fenics_muscle.py")]
DOLFINX = [PYTHON, os.path.join(HERE, "dolfinx_muscle.py"), "--solver", "mumps"]
SUMMARY = re.compile(  # fenics_muscle.py's line, and dolfinx_muscle.py's (first word, solver)
    r"^(?:fenics|dolfinx) (\S+) (\d+)x(\d+) dofs (\d+) free (\d+) stretches (\d+)/(\d+) its (\d+) "
    r"predictors (\d+) sweep (\S+) iteration (\S+) setup (\S+) P\(1\.17\) (\S+)(?: solver \S+)?$",
    re.M,
)
ROW = re.compile(r"^lambda (\S+) P (\S+) newton_its (\d+)$", re.M)
FAILED = re.compile(r"^failed (\S+)$", re.M)
STRETCHES = [round(0.70 + 0.05 * i, 6) for i in range(19)] + [1.17]
STUDY_TIME = re.compile(r"^muscle sweep\s+cylinder\s+\d+\s+(\d+)/(\d+)\s+(\S+)\s*$", re.M)


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def scene_for(nr, nz, directory):
    """muscle_sweep.toml with its nr and nz lines set."""
    with open(SCENE) as f:
        text = f.read()
    text, n = re.subn(r"(?m)^nr = \d+$", f"nr = {nr}", text)
    text, m = re.subn(r"(?m)^nz = \d+$", f"nz = {nz}", text)
    if (n, m) != (1, 1):
        raise RuntimeError(f"{SCENE}: expected one `nr = ` and one `nz = ` line")
    path = os.path.join(directory, f"muscle_sweep_{nr}x{nz}.toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def ours(nr, nz, work, threads=None, binary=OURS):
    scene = scene_for(nr, nz, work)
    out = os.path.join(work, f"out_{nr}x{nz}")
    env = dict(os.environ)
    if threads:
        env["RAYON_NUM_THREADS"] = str(threads)
    t0 = time.perf_counter()
    run = subprocess.run([binary, "run", scene, "--out", out, "--quiet"],
                         capture_output=True, text=True, env=env, timeout=7200)
    wall = time.perf_counter() - t0
    if run.returncode not in (0, 3):  # 3: some stretch failed, the rest written
        raise RuntimeError(f"activemuscle run {scene} failed ({run.returncode}):\n{run.stderr[-3000:]}")
    with open(os.path.join(out, "curves.csv")) as f:
        rows = list(csv.DictReader(f))  # the scene has one study, one damage
    P = {round(float(r["lambda"]), 6): float(r["P"]) for r in rows}
    study = STUDY_TIME.search(run.stdout)
    return {
        "wall": wall,
        "study": float(study.group(3)) if study else float("nan"),
        "its": sum(int(r["newton_iterations"]) for r in rows),
        "dofs": int(rows[0]["dofs"]),
        "P": P,
        "failed": sorted(set(STRETCHES) - set(P)),
    }


def fenics(element, nr, nz, blas=None, command=FENICS):
    """One process of fenics_muscle.py (or, command=DOLFINX, of dolfinx_muscle.py)."""
    env = dict(os.environ, OMP_NUM_THREADS="1")
    if blas:
        env["LD_LIBRARY_PATH"] = blas
    script = os.path.basename(command[1])
    t0 = time.perf_counter()
    run = subprocess.run(command + ["--element", element, str(nr), str(nz)],
                         capture_output=True, text=True, env=env, timeout=7200)
    wall = time.perf_counter() - t0
    if run.returncode != 0:
        raise RuntimeError(f"{script} {element} {nr} {nz} failed:\n{run.stderr[-3000:]}")
    m = SUMMARY.search(run.stdout)
    if m is None:
        raise RuntimeError(f"{script}: no summary line in\n{run.stdout[-3000:]}")
    g = m.groups()
    return {
        "wall": wall,
        "dofs": int(g[3]),
        "free": int(g[4]),
        "its": int(g[7]),
        "predictors": int(g[8]),
        "sweep": float(g[9]),
        "setup": float(g[11]),
        "P": {round(float(a), 6): float(b) for a, b, _ in ROW.findall(run.stdout)},
        "failed": [float(x) for x in FAILED.findall(run.stdout)],
    }


def dolfinx(element, nr, nz, blas=None):
    return fenics(element, nr, nz, blas, DOLFINX)


def is_fenics(name):
    """A row of legacy FEniCS or of DOLFINx (the Python codes: their own sweep time, predictors)."""
    return name.startswith(("FEniCS", "DOLFINx"))


def relative(a, b):
    return abs(a - b) / abs(b) if b else float("inf")


def spread(values, digits=2):
    return f"{statistics.median(values):.{digits}f} ({min(values):.{digits}f}–{max(values):.{digits}f})"


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--meshes", default="16x64,32x128",
                        help="comma-separated nr x nz (default 16x64,32x128)")
    parser.add_argument("--openblas", metavar="DIR", required=True,
                        help="directory holding OpenBLAS's libblas.so.3 (LD_LIBRARY_PATH of FEniCS)")
    parser.add_argument("--reference-blas", action="store_true",
                        help="also FEniCS on the reference BLAS as installed")
    parser.add_argument("--fenics-q2q1", action="store_true",
                        help="also FEniCS Q2/Q1 on the quadrilaterals (ours' discretisation) on OpenBLAS")
    parser.add_argument("--one-thread", action="store_true",
                        help="also ours with one thread (RAYON_NUM_THREADS=1), as FEniCS")
    parser.add_argument("--dolfinx", action="store_true",
                        help="also DOLFINx 0.5 P2/P1 (dolfinx_muscle.py, MUMPS) on OpenBLAS; with "
                        "--fenics-q2q1 DOLFINx Q2/Q1 too")
    parser.add_argument("--baseline", metavar="BINARY",
                        help="also another activemuscle binary (e.g. an earlier commit's release "
                        "build), alternated with the others: ours before and after in the same run")
    parser.add_argument("--check-mesh", default="8x32",
                        help="mesh of the same-problem check, Q2/Q1 in both codes ('' to skip)")
    args = parser.parse_args(argv[1:])
    if not os.path.exists(OURS):
        sys.exit(f"{OURS} missing: cargo build --release")
    meshes = [tuple(int(x) for x in m.split("x")) for m in args.meshes.split(",")]
    work = tempfile.mkdtemp(prefix="muscle_sweep_")
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, commit {commit}, "
          f"{os.cpu_count()} cores, load {load()}")

    if args.check_mesh:
        nr, nz = (int(x) for x in args.check_mesh.split("x"))
        a, b = ours(nr, nz, work), fenics("Q2Q1", nr, nz, args.openblas)
        common = sorted(set(a["P"]) & set(b["P"]))
        worst = max((relative(b["P"][l], a["P"][l]), l) for l in common)
        print(f"same problem, Q2/Q1 {nr}x{nz} ({a['dofs']} free dofs): {len(common)} stretches "
              f"in both, largest relative difference of P {worst[0]:.1e} (at λ = {worst[1]:g}); "
              f"P(1.17) ours {a['P'].get(1.17, float('nan')):.12g}, "
              f"FEniCS {b['P'].get(1.17, float('nan')):.12g} kPa")
        if args.dolfinx:
            c = dolfinx("Q2Q1", nr, nz, args.openblas)
            common = sorted(set(a["P"]) & set(c["P"]))
            worst = max((relative(c["P"][l], a["P"][l]), l) for l in common)
            print(f"same problem, Q2/Q1 {nr}x{nz}, DOLFINx: {len(common)} stretches in both, largest "
                  f"relative difference of P {worst[0]:.1e} (at λ = {worst[1]:g}); P(1.17) DOLFINx "
                  f"{c['P'].get(1.17, float('nan')):.12g} kPa")

    fenics("P2P1", 2, 8, args.openblas)  # untimed: fills the FFC JIT cache for the P2/P1 forms
    if args.dolfinx:
        dolfinx("P2P1", 2, 8, args.openblas)  # untimed: the FFCx JIT cache of its P2/P1 forms

    codes = [("ours Q2/Q1", lambda nr, nz: ours(nr, nz, work))]
    if args.one_thread:
        codes.append(("ours Q2/Q1, 1 thread", lambda nr, nz: ours(nr, nz, work, 1)))
    if args.baseline:
        print(f"baseline: {args.baseline}")
        codes.append(("ours Q2/Q1, baseline",
                      lambda nr, nz: ours(nr, nz, work, binary=args.baseline)))
    fenics_codes = [("FEniCS P2/P1 + OpenBLAS", lambda nr, nz: fenics("P2P1", nr, nz, args.openblas))]
    if args.dolfinx:
        fenics_codes.append(("DOLFINx P2/P1 + MUMPS + OpenBLAS",
                             lambda nr, nz: dolfinx("P2P1", nr, nz, args.openblas)))
    if args.fenics_q2q1:
        fenics("Q2Q1", 2, 8, args.openblas)  # untimed: the JIT cache of the Q2/Q1 forms
        fenics_codes.append(("FEniCS Q2/Q1 + OpenBLAS",
                             lambda nr, nz: fenics("Q2Q1", nr, nz, args.openblas)))
        if args.dolfinx:
            dolfinx("Q2Q1", 2, 8, args.openblas)  # untimed: the FFCx JIT cache of the Q2/Q1 forms
            fenics_codes.append(("DOLFINx Q2/Q1 + MUMPS + OpenBLAS",
                                 lambda nr, nz: dolfinx("Q2Q1", nr, nz, args.openblas)))
    if args.reference_blas:
        fenics_codes.append(("FEniCS P2/P1, reference BLAS", lambda nr, nz: fenics("P2P1", nr, nz)))
    every = codes + fenics_codes

    print(f"\nmedian of {args.repeats} alternated runs (min–max), wall times in seconds")
    print("| cells | code | free dofs | Newton its | process [s] | sweep [s] | failed stretches "
          "| per iteration [ms] | this row / ours: process | sweep | per iteration "
          "| P(1.17) [kPa] | rel. diff. to ours | load before → after |")
    print("|---|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---|")
    for nr, nz in meshes:
        before = load()
        runs = {name: [] for name, _ in every}
        for _ in range(args.repeats):
            for name, code in every:
                runs[name].append(code(nr, nz))
        after = load()

        def summary(name):
            rs = runs[name]
            f = is_fenics(name)
            sweeps = [r["sweep"] if f else r["study"] for r in rs]
            return {
                "process": [r["wall"] for r in rs],
                "sweep": sweeps,
                "per_it": [t / r["its"] for t, r in zip(sweeps, rs)],
                "its": statistics.median(r["its"] for r in rs),
            }

        ref = summary(codes[0][0])
        ref_p = runs[codes[0][0]][0]["P"].get(1.17, float("nan"))
        for name, rs in runs.items():
            python = is_fenics(name)
            s = summary(name)
            its = f"{s['its']:.0f}" + (f" (of which {rs[0]['predictors']} predictors)" if python else "")
            free = rs[0]["free"] if python else rs[0]["dofs"]
            failed = ", ".join(f"{x:.2f}" for x in rs[0]["failed"]) or "none"
            p = rs[0]["P"].get(1.17, float("nan"))
            first = name == codes[0][0]
            ratio = {k: "–" if first else f"{statistics.median(s[k]) / statistics.median(ref[k]):.1f}×"
                     for k in ("process", "sweep", "per_it")}
            diff = f"{relative(p, ref_p):.1e}" if python else "–"
            print(f"| {nr} × {nz} | {name} | {free} | {its} | {spread(s['process'])} "
                  f"| {spread(s['sweep'])} | {failed} | {1e3 * statistics.median(s['per_it']):.1f} "
                  f"| {ratio['process']} | {ratio['sweep']} | {ratio['per_it']} | {p:.9f} | {diff} "
                  f"| {before} → {after} |", flush=True)


if __name__ == "__main__":
    main(sys.argv)
