"""Material.taylor_test: the Taylor test of the tangent at one state, as numpy arrays."""

import numpy as np
import pytest

from activemuscle import Material

F = [[1.15, 0.05, -0.02], [0.03, 0.94, 0.04], [-0.01, 0.02, 0.93]]
DF = [[0.3, -0.2, 0.1], [0.25, -0.35, 0.15], [-0.1, 0.2, 0.4]]


def slope(r, key):
    """The least-squares slope of log r(h) against log h over the remainders above the floor,
    taken here from the arrays (independent of the medians the core reports)."""
    h, values = r["h"], r[key]
    valid = ~np.ma.getmaskarray(values) & (np.ma.filled(values, 0.0) > r["floor"])
    return np.polyfit(np.log(h[valid]), np.log(np.ma.filled(values, 1.0)[valid]), 1)[0]


def test_a_smooth_state_has_orders_one_and_two():
    r = Material(law="implicit", coupling="frozen").taylor_test(F, DF)
    assert r["flag"] is None, r["reason"]
    assert abs(r["order_0"] - 1) < 0.05 and abs(r["order_1"] - 2) < 0.1
    assert abs(slope(r, "r0") - 1) < 0.05 and abs(slope(r, "r1") - 2) < 0.1
    assert r["fd_error"] < 1e-6
    # The frozen coupling's exact tangent is not symmetric, and says why.
    assert r["asymmetry"] > 1e-3 and "frozen" in r["asymmetry_reason"]
    assert "symmetric frozen" in r["approximations"]
    assert isinstance(r["r1"], np.ma.MaskedArray) and r["r1"].shape == r["h"].shape


def test_a_state_across_lambda_min_is_flagged_with_that_cause():
    lam = 0.682 + 0.001  # Ehret–Böl–Itskov's curve: λ_min = 0.682, where its slope jumps
    f = np.diag([lam, lam**-0.5, lam**-0.5])
    df = -np.diag([1.0, 0.0, 0.0])
    r = Material(approach="active-stress", curve="ehret-bol-itskov").taylor_test(f, df)
    assert r["flag"] == "lambda-min-kink", r["reason"]


def test_bad_input_is_an_error_naming_it():
    with pytest.raises(ValueError, match="dF"):
        Material().taylor_test(F, np.zeros((3, 3)))
    with pytest.raises(ValueError, match="h"):
        Material().taylor_test(F, DF, h=[2.0, 0.5, 0.25])
    with pytest.raises(ValueError):
        Material().taylor_test(np.diag([1.0, 1.0, -1.0]), DF)
    # A non-finite entry of F: a floating-point error naming F, never NaN remainders.
    with pytest.raises(FloatingPointError, match="entry of F"):
        Material().taylor_test(np.diag([1.0, np.nan, 1.0]), DF)
