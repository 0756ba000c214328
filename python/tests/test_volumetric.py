"""Volumetric: a scene's volumetric energy U(J) for codes that impose near incompressibility
themselves, against the forms' closed derivatives and the exact-incompressibility limit."""

import numpy as np
import pytest

import activemuscle as am

PRESSURES = np.array([-0.05, 0.0, 0.3, 7.0, 60.0])


def volumetric_stress(kind, kappa, mu, J):
    """U′(J) of each form written out (its linear term is zero with these energies)."""
    return {
        "quadratic": kappa * (J - 1),
        "logarithmic": kappa / 2 * (J - 1 / J),
        "4c-giantesio": -mu / 2 * J ** (-2 * kappa - 1),
    }[kind]


@pytest.mark.parametrize("kind, kappa, energy", [
    ("quadratic", 500.0, "giantesio-musesti"),
    ("logarithmic", 500.0, "giantesio-musesti"),
    ("4c-giantesio", 20.0, "4c-passive"),
])
def test_dilatation_inverts_the_volumetric_stress(kind, kappa, energy):
    material = am.Material(energy=energy)
    v = am.Volumetric(material, kind, kappa=kappa)
    p = PRESSURES[PRESSURES > 0] if kind == "4c-giantesio" else PRESSURES
    r = v.dilatation(p)
    J = r["volume_ratio"]
    np.testing.assert_allclose(volumetric_stress(kind, kappa, 0.1599, J), -p, rtol=1e-12, atol=1e-12)
    h = 1e-6
    slope = (volumetric_stress(kind, kappa, 0.1599, J + h) - volumetric_stress(kind, kappa, 0.1599, J - h)) / (2 * h)
    np.testing.assert_allclose(r["compliance"], 1 / slope, rtol=1e-7)
    np.testing.assert_allclose(v.derivatives(J)["first"], -p, rtol=1e-12, atol=1e-12)


def test_reference_pressure_balances_the_energy_at_rest():
    assert am.Volumetric(am.Material(), "quadratic", kappa=1e3).reference_pressure == 0.0
    # 4C's passive energy is not stress free at C = I: its S = (μ/2) I is what J^(−2κ) balances.
    v = am.Volumetric(am.Material(energy="4c-passive"), "4c-giantesio", kappa=20.0)
    assert v.reference_pressure == pytest.approx(0.1599 / 2, rel=1e-12)
    assert v.dilatation([v.reference_pressure])["volume_ratio"][0] == pytest.approx(1.0, abs=1e-14)


def test_near_incompressibility_tends_to_the_exact_curve_like_one_over_kappa():
    material = am.Material(law="explicit")
    stretches = [0.9, 1.1, 1.3]
    exact = material.uniaxial(stretches)["stress"]
    gap = {kappa: material.uniaxial(stretches, am.Volumetric(material, "quadratic", kappa=kappa))["stress"] - exact
           for kappa in (1e4, 1e5)}
    np.testing.assert_allclose(gap[1e4] / gap[1e5], 10.0, rtol=0.05)


def test_bad_volumetric_keys_are_refused():
    material = am.Material()
    with pytest.raises(ValueError, match="exact"):
        am.Volumetric(material, "exact")
    with pytest.raises(ValueError, match="kappa"):
        am.Volumetric(material, "quadratic")
    with pytest.raises(ValueError, match="kind"):
        am.Volumetric(material, "cubic", kappa=1.0)
    with pytest.raises(ArithmeticError, match="pressure 1"):
        am.Volumetric(material, "quadratic", kappa=10.0).dilatation([0.0, 20.0])
