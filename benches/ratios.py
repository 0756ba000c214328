#!/usr/bin/env python3
"""Ratios of the constitutive benchmarks, each taken within one run, over repeated runs.

    python3 benches/ratios.py [RUNS] [FILTER]

Runs `cargo bench --bench constitutive -- FILTER` RUNS times (default 3, filter
"^(tangent|muscle|law)/"), reads the medians criterion writes to
target/criterion/<group>/<id>/new/estimates.json after each run, and prints per run the load
average (`/proc/loadavg` before and after) and each ratio below, then the median, smallest and
largest ratio over the runs. A ratio is formed from two medians of the same run, so a slow phase
of a shared machine inflates both sides. BENCH_BIN=target/release/deps/constitutive-<hash> runs
an already built executable instead of cargo.
"""

import json
import os
import pathlib
import statistics
import subprocess
import sys

RATIOS = [
    ("P + dP/dF + dP/dgamma, fast AD / closed form, axisym", "tangent/fast_ad_axi", "tangent/closed_form_axi"),
    ("P + dP/dF + dP/dgamma, fast AD / closed form, 3D", "tangent/fast_ad_3d", "tangent/closed_form_3d"),
    ("respond, implicit tabulated / explicit (frozen)", "muscle/implicit_tabulated_frozen_exact_axi", "muscle/explicit_frozen_exact_axi"),
    ("respond, implicit exact / explicit (frozen)", "muscle/implicit_frozen_exact_axi", "muscle/explicit_frozen_exact_axi"),
    ("respond, energy tabulated (consistent) / explicit (frozen)", "muscle/energy_tabulated_consistent_axi", "muscle/explicit_frozen_exact_axi"),
    ("respond, energy exact (consistent) / explicit (frozen)", "muscle/energy_consistent_axi", "muscle/explicit_frozen_exact_axi"),
    ("respond, explicit / closed-form tangent, axisym", "muscle/explicit_frozen_exact_axi", "tangent/closed_form_axi"),
    ("law, implicit tabulated / explicit", "law/implicit-tabulated", "law/explicit"),
    ("law, implicit exact / tabulated", "law/implicit", "law/implicit-tabulated"),
    ("law, energy exact / tabulated", "law/energy", "law/energy-tabulated"),
]


def load():
    return pathlib.Path("/proc/loadavg").read_text().split()[0]


def medians(root):
    out = {}
    for f in root.glob("*/*/new/estimates.json"):
        out[f"{f.parts[-4]}/{f.parts[-3]}"] = json.loads(f.read_text())["median"]["point_estimate"]
    return out


def main():
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    pattern = sys.argv[2] if len(sys.argv) > 2 else "^(tangent|muscle|law)/"
    root = pathlib.Path(__file__).resolve().parent.parent / "target" / "criterion"
    per_run = []
    for run in range(runs):
        before = load()
        command = ["cargo", "bench", "--bench", "constitutive", "--", pattern]
        if "BENCH_BIN" in os.environ:  # an already built bench executable
            command = [os.environ["BENCH_BIN"], "--bench", pattern]
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
        after = load()
        m = medians(root)
        ratios = {name: m[a] / m[b] for name, a, b in RATIOS if a in m and b in m}
        per_run.append(ratios)
        print(f"run {run + 1}: load {before} -> {after}")
        for name, a, b in RATIOS:
            if name in ratios:
                print(f"  {name}: {m[a]:.1f} / {m[b]:.1f} ns = {ratios[name]:.3f}")
    print(f"over {runs} runs (median [min, max]):")
    for name, _, _ in RATIOS:
        values = [r[name] for r in per_run if name in r]
        if values:
            print(f"  {name}: {statistics.median(values):.3f} [{min(values):.3f}, {max(values):.3f}]")


if __name__ == "__main__":
    main()
