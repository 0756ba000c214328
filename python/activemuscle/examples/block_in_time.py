"""Activation in time from Python: a homogeneous block along the fibres, driven by the motor-unit
twitch superposition of Ehret, Böl & Itskov (2011), in free contraction (zero axial load), exactly
incompressible (the chapter's model) and nearly incompressible with U = (κ/2)(J − 1)², κ in kPa.

Each step solves the block quasi-statically: the stretch λ with P₁₁(λ) = 0 and, when compressible,
the two lateral stretches from zero lateral traction. As κ grows the history tends to the exact one,
|λ_κ − λ| and |J − 1| falling as 1/κ.

    python -m activemuscle.examples.block_in_time [KAPPA ...]      (default 1e4 1e6 [kPa])

Prints, per κ, the largest |λ_κ − λ_exact| and |J − 1| over the history, and a few steps.
"""

import sys

import numpy as np

from activemuscle import run_scene


def history(kappa=None, damage=0.0, t_end=0.4, step=0.01):
    """The free-contraction history: a dict of numpy columns (t [s], a, lambda, gamma, P [kPa],
    cauchy [kPa], J, ...), as history.csv; exactly incompressible when ``kappa`` is None."""
    scene = {
        "study": [
            {
                "kind": "activation-in-time",
                "name": "free",
                "time": {"from": 0.0, "to": t_end, "step": step},
                "schedule": [[0.0, 1.0], [0.5 * t_end, 0.0]],
                "stretch": "free",
                "damage": [damage],
                "motor_units": [
                    {"fraction": 0.6, "twitch_force": 0.36, "contraction_time": 0.09, "interstimulus": 0.04},
                    {"fraction": 0.4, "twitch_force": 0.36, "contraction_time": 0.04, "interstimulus": 0.015},
                ],
            }
        ]
    }
    if kappa is not None:
        scene["incompressibility"] = {"kind": "quadratic", "kappa": float(kappa)}
    results = run_scene(scene)
    study = results["free"]
    if len(study.failures["message"]):
        raise RuntimeError(f"kappa = {kappa}: {list(study.failures['message'])}")
    return {k: np.ma.getdata(v) for k, v in study.table.items()}


def main(argv):
    kappas = [float(k) for k in argv] or [1e4, 1e6]
    exact = history()
    print("t [s]   a       lambda (exact)", "".join(f"  lambda (k={k:.0e})  J (k={k:.0e})" for k in kappas))
    runs = [history(k) for k in kappas]
    for i in range(0, len(exact["t"]), 5):
        row = f"{exact['t'][i]:<7.3f} {exact['a'][i]:<7.4f} {exact['lambda'][i]:<15.6f}"
        row += "".join(f"  {r['lambda'][i]:<16.6f}  {r['J'][i]:<12.8f}" for r in runs)
        print(row)
    for k, r in zip(kappas, runs):
        gap = np.abs(r["lambda"] - exact["lambda"]).max()
        print(f"kappa = {k:.0e} kPa: max |lambda - lambda_exact| = {gap:.2e}, max |J - 1| = {np.abs(r['J'] - 1).max():.2e}")


if __name__ == "__main__":
    main(sys.argv[1:])
