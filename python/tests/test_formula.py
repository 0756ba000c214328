"""An energy written as a formula, from Python, against independent references: the
neo-Hookean formula against its closed form μ(λ − λ⁻²); the chapter's energy written as a
formula against the compiled one (stress, tangent, dP/dγ of every law and coupling, to
rounding); a scene given as a dict that fits a formula energy to its own curve; and the scene's
messages for a bad formula."""

import math

import numpy as np
import pytest

import activemuscle as am

POSITIVE = [0.0, math.inf]
CHAPTER = dict(
    W="Ip = w0/3*tr_c + (1 - w0)*c_m; Kp = w0/3*tr_c_inv + (1 - w0)*c_inv_m;"
    " mu/4*(expm1(alpha*(Ip - 1))/alpha + Kp - 1)",
    parameters={
        "mu": {"value": 0.1599, "unit": "kPa", "range": POSITIVE},
        "alpha": {"value": 19.35, "range": POSITIVE},
        "w0": {"value": 0.7335, "range": [0.0, 1.0]},
    },
)


def test_the_neo_hookean_formula_has_its_closed_form_along_the_fibres():
    mu = 0.37
    m = am.Material(
        energy="formula",
        W="mu/2*(I1 - 3)",
        parameters={"mu": {"value": mu, "range": POSITIVE}},
        law="passive",
    )
    lam = np.linspace(0.7, 1.6, 10)
    got = m.uniaxial(list(lam))["stress"]
    assert np.allclose(got, mu * (lam - lam**-2), rtol=1e-13, atol=1e-14)


@pytest.mark.parametrize("law", ["implicit", "energy"])
@pytest.mark.parametrize("coupling", ["frozen", "consistent"])
def test_the_chapters_energy_as_a_formula_responds_as_the_compiled_one(law, coupling):
    rng = np.random.default_rng(44)
    F = np.eye(3) + rng.uniform(-0.15, 0.15, (20, 3, 3))
    F[:, 0, 0] += 0.1
    compiled = am.Material(law=law, coupling=coupling, damage=0.2).evaluate(F, fibre=[1, 0, 0])
    written = am.Material(energy="formula", **CHAPTER, law=law, coupling=coupling, damage=0.2)
    written = written.evaluate(F, fibre=[1, 0, 0])
    for key in ["stress", "tangent", "dstress_dgamma", "gamma"]:
        a, b = np.asarray(written[key]), np.asarray(compiled[key])
        assert np.max(np.abs(a - b)) <= 1e-11 * max(1.0, np.max(np.abs(b))), key


def test_a_scene_dict_fits_a_formula_energy_to_its_own_curve():
    truth = {"c10": 0.12, "k1": 0.4, "k2": 6.0}

    def parameters(values):
        return {name: {"value": v, "unit": "kPa", "range": POSITIVE} for name, v in values.items()}

    W = "c10*(I1 - 3) + k1/(2*k2)*expm1(k2*(I4 - 1)^2)"
    scene = {
        "material": {
            "energy": "formula",
            "W": W,
            "parameters": parameters({"c10": 0.3, "k1": 1.0, "k2": 3.0}),
        },
        "study": [
            {
                "kind": "fit",
                "name": "own curve",
                "fit": "passive",
                "stretch": list(np.linspace(1.02, 1.35, 25)),
                "reference": {"energy": "formula", "W": W, "parameters": parameters(truth)},
            }
        ],
    }
    study = am.run_scene(scene)["own curve"]
    table = study.table
    for name, value in truth.items():
        row = list(table["parameter"]).index(name)
        assert table["converged"][row]
        assert abs(table["value"][row] - value) < 1e-7 * value
    # fit_points.csv's rows: the 25 data with their residuals (the model reproduces its own
    # curve), then the fitted curve.
    points = study.fit_points
    data = np.asarray(points["row"]) == "data"
    assert data.sum() == 25
    assert np.max(np.abs(np.asarray(points["residual"])[data])) < 1e-6


def test_a_bad_formula_is_refused_with_the_key_and_a_suggestion():
    with pytest.raises(ValueError, match=r"W = I_1: unknown name `I_1`.*did you mean `I1`"):
        am.Material(energy="formula", W="mu/2*(I_1 - 3)", parameters={"mu": 1.0})
    neo_hookean = dict(energy="formula", W="mu/2*(I1 - 3)")
    out_of_range = r"parameters.mu.value = -1: must lie in the range \(0, inf\)"
    with pytest.raises(ValueError, match=out_of_range):
        am.Material(**neo_hookean, parameters={"mu": {"value": -1, "range": POSITIVE}})
    with pytest.raises(ValueError, match=r"a division by `k`"):
        W = "mu*(I1 - 3) + expm1(k*(I4 - 1)^2)/k"
        am.Material(energy="formula", W=W, parameters={"mu": 1.0, "k": 2.0})
    with pytest.raises(ValueError, match=r"parameters.mu.colour = \(given\): unknown key"):
        am.Material(**neo_hookean, parameters={"mu": {"value": 1, "colour": "red"}})
