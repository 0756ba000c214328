"""ns per material point: activemuscle from Python (P, A and dP/dγ, felupe's (3, 3, n) layout and
(n, 3, 3); fresh outputs, and (3, 3, n) into reused `out=` arrays), the same points in a plain Rust loop (python/examples/per_point.rs, same run), and
felupe's own NeoHooke (P and A by numpy) for scale. Not a test: timings only.

    maturin develop --release -m python/Cargo.toml   # the fat-LTO build the numbers need
    python python/bench/bench.py [N ...] [--law explicit] [--rounds 3]

Alternates the routes round by round (a noisy machine shifts all of them alike).
"""

import argparse
import os
import re
import subprocess
import time

import numpy as np

import activemuscle as am

HERE = os.path.dirname(os.path.abspath(__file__))


def points(n):
    """The bench's F, (3, 3, n): a stretch λ ∈ [0.8, 1.4] along e₁, isochoric (as per_point.rs)."""
    lam = 0.8 + 0.6 * np.arange(n) / max(n - 1, 1)
    F = np.zeros((3, 3, n))
    F[0, 0], F[1, 1], F[2, 2] = lam, lam**-0.5, lam**-0.5
    return F


def best(f, repeat=3):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return min(times)


def rust(n, law):
    out = subprocess.run(
        ["cargo", "run", "--quiet", "--release", "--manifest-path",
         os.path.join(HERE, "..", "Cargo.toml"), "--example", "per_point", "--", str(n), law],
        check=True, capture_output=True, text=True,
    ).stdout
    values = {}
    for key, v in re.findall(r"(rust_\w+_ns) ([\d.]+)", out):
        values[key] = min(values.get(key, float("inf")), float(v))
    return values


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("n", nargs="*", type=int, default=[100_000, 1_000_000])
    ap.add_argument("--law", default="explicit")
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args()
    material = am.Material(law=args.law, coupling="frozen")
    try:
        import felupe as fem

        neo = fem.NeoHooke(mu=1.0)
    except ImportError:
        neo = None
    print(f"# law = {args.law}, frozen coupling; load: {os.getloadavg()[0]:.2f}; ns per point (best of rounds)")
    print("n route ns_per_point ratio_to_rust")
    for n in args.n:
        F = points(n)
        Fl = np.ascontiguousarray(np.moveaxis(F, 2, 0))
        res = {}

        def keep(key, value):
            res[key] = min(res.get(key, float("inf")), value)

        for _ in range(args.rounds):
            for key, value in rust(n, args.law).items():
                keep(key, value)
            keep("python_trailing_parallel", best(lambda: material.evaluate(F, layout="trailing")) / n * 1e9)
            keep("python_trailing_serial", best(lambda: material.evaluate(F, layout="trailing", parallel=False)) / n * 1e9)
            out = {k: np.empty_like(v) for k, v in material.evaluate(F[..., :1], layout="trailing").items()}
            out = {k: np.empty(v.shape[:-1] + (n,)) for k, v in out.items()}  # reused, warm after the first call
            keep("python_trailing_out_parallel", best(lambda: material.evaluate(F, layout="trailing", out=out)) / n * 1e9)
            keep("python_trailing_out_serial", best(lambda: material.evaluate(F, layout="trailing", parallel=False, out=out)) / n * 1e9)
            keep("python_leading_parallel", best(lambda: material.evaluate(Fl, layout="leading")) / n * 1e9)
            keep("python_leading_serial", best(lambda: material.evaluate(Fl, layout="leading", parallel=False)) / n * 1e9)
            if neo is not None:
                x = [F[..., None], np.zeros((0, n, 1))]  # felupe wants (3, 3, q, c)
                keep("felupe_neohooke_P_and_A", best(lambda: (neo.gradient(x), neo.hessian(x))) / n * 1e9)
        for key in sorted(res):
            ref = res["rust_parallel_ns"] if "parallel" in key else res["rust_serial_ns"]
            ratio = "" if key.startswith(("rust", "felupe")) else f"{res[key] / ref:.2f}"
            print(f"{n} {key} {res[key]:.1f} {ratio}")


if __name__ == "__main__":
    main()
