"""The batched material point against independent references: the single-point Rust API (the
batch machinery must not change a bit), the dual-number oracle over F's nine entries, central
differences of P, the chapter's closed form of the passive curve; and bad input."""

import numpy as np
import pytest

import activemuscle as am

LAWS = [
    dict(law="passive"),
    dict(law="constant", gamma=0.2),
    dict(law="implicit"),
    dict(law="explicit"),
    dict(law="energy"),
]
COUPLINGS = [
    dict(coupling="frozen"),
    dict(coupling="frozen", frozen_tangent="symmetric"),
    dict(coupling="consistent"),
]
MATERIALS = [dict(**l, **c, damage=0.1) for l in LAWS for c in COUPLINGS]


def sheared_stretches(n, seed=0):
    """n deformation gradients around a stretch of 0.8 … 1.3 along e₁ (the active range),
    (n, 3, 3)."""
    rng = np.random.default_rng(seed)
    lam = rng.uniform(0.8, 1.3, n)
    F = np.zeros((n, 3, 3))
    F[:, 0, 0] = lam
    F[:, 1, 1] = F[:, 2, 2] = lam**-0.5
    return F + rng.uniform(-0.05, 0.05, (n, 3, 3))


def fibres(n, seed=1):
    """n directions near e₁, not normalised (the material normalises them), (n, 3)."""
    rng = np.random.default_rng(seed)
    return np.array([2.0, 0.0, 0.0]) + rng.uniform(-0.3, 0.3, (n, 3))


def single(material, F, m, order="tangent"):
    return {k: np.asarray(v) for k, v in material.respond(F.tolist(), list(m), order=order).items()}


@pytest.mark.parametrize("choices", MATERIALS, ids=lambda c: "-".join(map(str, c.values())))
def test_batch_equals_the_single_point_rust_api_in_every_layout(choices):
    material = am.Material(**choices)
    n = 12
    F, m = sheared_stretches(n), fibres(n)
    expected = [single(material, F[p], m[p]) for p in range(n)]
    # (..., 3, 3) C-contiguous, points (3, 4); felupe's (3, 3, q, c) in C and Fortran order;
    # a strided view in two point axes (copied once).
    leading = F.reshape(3, 4, 3, 3)
    trailing = np.moveaxis(leading, (2, 3), (0, 1))
    cases = [
        ("leading", leading, m.reshape(3, 4, 3), lambda a, p: a[p // 4, p % 4]),
        ("trailing", np.ascontiguousarray(trailing), np.moveaxis(m.reshape(3, 4, 3), 2, 0),
         lambda a, p: a[..., p // 4, p % 4]),
        ("trailing", np.asfortranarray(trailing), np.asfortranarray(np.moveaxis(m.reshape(3, 4, 3), 2, 0)),
         lambda a, p: a[..., p // 4, p % 4]),
    ]
    strided = np.zeros((3, 3, 6, 8))
    strided[:, :, ::2, ::2] = trailing
    m_strided = np.zeros((3, 6, 8))
    m_strided[:, ::2, ::2] = np.moveaxis(m.reshape(3, 4, 3), 2, 0)
    cases.append(("trailing", strided[:, :, ::2, ::2], m_strided[:, ::2, ::2],
                  lambda a, p: a[..., p // 4, p % 4]))
    for layout, Fb, mb, at in cases:
        r = material.evaluate(Fb, mb, layout=layout)
        for p in range(n):
            e = expected[p]
            for key in ("gamma", "energy", "fibre_stretch"):
                assert r[key].shape == (3, 4)
                assert r[key][p // 4, p % 4] == e[key], key
            for key in ("stress", "dstress_dgamma"):
                np.testing.assert_allclose(at(r[key], p), e[key], rtol=1e-14, atol=0)
            A = at(r["tangent"], p)
            np.testing.assert_allclose(A, e["tangent"], rtol=1e-14, atol=1e-14 * np.abs(e["tangent"]).max())


def test_parallel_and_serial_batches_are_bitwise_equal():
    material = am.Material(law="explicit")
    F = sheared_stretches(5000)
    a = material.evaluate(F, [1, 0, 0], parallel=True)
    b = material.evaluate(F, [1, 0, 0], parallel=False)
    for key in a:
        assert np.array_equal(a[key], b[key]), key


@pytest.mark.parametrize("law", LAWS, ids=lambda c: c["law"])
def test_stress_tangent_and_rate_equal_the_nine_entry_oracle_at_the_laws_gamma(law):
    # At γ held (constant law) P and A are the oracle's; for every law dP/dγ at the law's γ is.
    material = am.Material(**law, coupling="frozen", frozen_tangent="symmetric")
    F, m = sheared_stretches(6, seed=3), fibres(6)
    r = material.evaluate(F, m)
    for p in range(6):
        unit = m[p] / np.linalg.norm(m[p])
        o = material.oracle(F[p].tolist(), r["gamma"][p], list(unit))
        np.testing.assert_allclose(r["dstress_dgamma"][p], o["dstress_dgamma"], rtol=1e-10,
                                   atol=1e-12 * np.abs(o["dstress_dgamma"]).max())
        np.testing.assert_allclose(r["stress"][p], o["stress"], rtol=1e-11,
                                   atol=1e-12 * np.abs(o["stress"]).max())
        # The symmetric frozen tangent is ∂²Ŵ/∂F² at γ held: the oracle's Hessian.
        np.testing.assert_allclose(r["tangent"][p], o["tangent"], rtol=1e-10,
                                   atol=1e-11 * np.abs(o["tangent"]).max())


def taylor_orders(material, F, m, dF):
    """Observed orders of |P(F + h dF) − P(F) − h A:dF| for h = 1e-1 … 1e-5."""
    base = material.evaluate(F, m)
    P0, A = base["stress"], base["tangent"]
    rem = []
    for h in 10.0 ** -np.arange(1, 6):
        P = material.evaluate(F + h * dF, m, order="stress")["stress"]
        rem.append(np.linalg.norm(P - P0 - h * np.einsum("...ijkl,...kl->...ij", A, dF)))
    return np.log10(np.array(rem[:-1]) / np.array(rem[1:]))


@pytest.mark.parametrize("choices", MATERIALS, ids=lambda c: "-".join(map(str, c.values())))
def test_tangent_is_the_derivative_of_the_stress_by_central_differences(choices):
    material = am.Material(**choices)
    F = sheared_stretches(1, seed=7)[0]
    m = np.array([1.0, 0.1, 0.0])
    dF = np.random.default_rng(8).uniform(-1, 1, (3, 3))
    exact = not (choices.get("frozen_tangent") == "symmetric" and choices["law"] not in ("passive", "constant"))
    # Central differences of P (step 1e-6, error ~1e-12 relative) against A:dF.
    h = 1e-6
    Pp = material.evaluate(F + h * dF, m, order="stress")["stress"]
    Pm = material.evaluate(F - h * dF, m, order="stress")["stress"]
    A = material.evaluate(F, m)["tangent"]
    fd, ad = (Pp - Pm) / (2 * h), np.einsum("ijkl,kl->ij", A, dF)
    error = np.linalg.norm(fd - ad) / np.linalg.norm(ad)
    if exact:
        assert error < 1e-7, error
        orders = taylor_orders(material, F, m, dF)
        assert np.all((orders[1:] > 1.9) & (orders[1:] < 2.1)), orders
    else:
        # The symmetric approximation drops the law's term: visibly not the derivative.
        assert error > 1e-4, error


def test_frozen_exact_tangent_is_not_major_symmetric_and_consistent_is():
    F = sheared_stretches(1, seed=11)[0]
    for choices, symmetric in (
        (dict(law="implicit", coupling="frozen"), False),
        (dict(law="implicit", coupling="consistent"), True),
        (dict(law="constant", gamma=0.2, coupling="frozen"), True),  # g′ = 0
    ):
        material = am.Material(**choices)
        A = material.evaluate(F, [1, 0, 0])["tangent"]
        asym = np.linalg.norm(A - A.transpose(2, 3, 0, 1)) / np.linalg.norm(A)
        assert material.symmetric_tangent == symmetric
        assert (asym < 1e-12) == symmetric, asym


def test_passive_uniaxial_curve_equals_the_chapters_closed_form():
    # eq. D:Ppas: P = μ/4 [e^{α(I_p − 1)} I_p′ + K_p′] along F = diag(λ, λ^-½, λ^-½).
    mu, alpha, w0 = 0.1599, 19.35, 0.7335
    lam = np.linspace(0.7, 1.5, 17)
    Ip = w0 / 3 * (lam**2 + 2 / lam) + (1 - w0) * lam**2
    dIp = w0 / 3 * (2 * lam - 2 / lam**2) + 2 * (1 - w0) * lam
    dKp = w0 / 3 * (2 - 2 / lam**3) - 2 * (1 - w0) / lam**3
    closed = mu / 4 * (np.exp(alpha * (Ip - 1)) * dIp + dKp)
    got = am.Material(law="passive").uniaxial(list(lam))["stress"]
    np.testing.assert_allclose(got, closed, rtol=1e-12, atol=1e-14)


def test_a_million_points_are_evaluated_and_agree_with_the_single_point_api():
    material = am.Material(law="explicit")
    n = 1_000_000
    F = np.broadcast_to(np.eye(3)[:, :, None], (3, 3, n)).copy()
    lam = np.linspace(0.8, 1.4, n)
    F[0, 0], F[1, 1], F[2, 2] = lam, lam**-0.5, lam**-0.5
    r = material.evaluate(F, [1.0, 0.0, 0.0], layout="trailing")
    assert r["tangent"].shape == (3, 3, 3, 3, n)
    for p in (0, 123_457, n - 1):
        e = single(material, F[:, :, p], [1.0, 0.0, 0.0])
        np.testing.assert_allclose(r["stress"][:, :, p], e["stress"], rtol=1e-14)
        np.testing.assert_allclose(r["tangent"][..., p], e["tangent"], rtol=1e-14, atol=1e-12)
    assert np.isfinite(r["tangent"]).all()


def test_defaults_are_the_chapters():
    assert repr(am.Material()) == (
        'Material(energy="giantesio-musesti", mu=0.1599, alpha=19.35, w0=0.7335, '
        'law="implicit", coupling="frozen", damage=0)'
    )
    # The chapter's checked value γ(1.17) ≈ 0.1489 of the implicit law (DESIGN.md).
    g = am.Material().uniaxial([1.17])["gamma"][0]
    assert abs(g - 0.14895) < 1e-5


BAD_INPUT = [
    (dict(F=np.zeros((3, 4, 5))), ValueError, "must be (3, 3, ...)"),
    (dict(F=np.zeros((3, 3, 3))), ValueError, "ambiguous"),
    (dict(F=np.eye(3), fibre=[1.0, 0.0]), ValueError, "fibre has shape [2]"),
    (dict(F=np.eye(3), fibre=[0.0, 0.0, 0.0]), ValueError, "fibre direction must be a finite, non-zero vector"),
    (dict(F=np.eye(3), fibre=[np.nan, 0.0, 0.0]), ValueError, "fibre direction"),
    (dict(F=np.eye(3), layout="sideways"), ValueError, 'layout = "sideways"'),
    (dict(F=np.eye(3), order="hessian"), ValueError, 'order = "hessian"'),
    (dict(F=np.diag([1.0, 1.0, -1.0])), ValueError, "det F = -1 (must be > 0)"),
    (dict(F=np.diag([1.0, np.nan, 1.0])), ValueError, "deformation gradient has det F = NaN"),
    (dict(F=np.zeros((3, 3))), ValueError, "det F = 0"),
    (dict(F=[["a", "b", "c"]] * 3), ValueError, "could not convert string to float"),
]


def test_a_fibre_direction_of_any_finite_scale_is_its_unit_vector():
    # Tiny and huge components: the same direction as the unit vector, neither underflow nor
    # overflow on the way to its norm.
    F = np.diag([1.1, 1.0 / np.sqrt(1.1), 1.0 / np.sqrt(1.1)])
    m = am.Material()
    for given, unit in [([1e-300, 0.0, 0.0], [1.0, 0.0, 0.0]),
                        ([1e300, 1e300, 0.0], [np.sqrt(0.5), np.sqrt(0.5), 0.0])]:
        a = m.evaluate(F, fibre=given)["stress"]
        b = m.evaluate(F, fibre=unit)["stress"]
        assert np.all(np.isfinite(a))
        assert np.allclose(a, b, rtol=1e-14, atol=0.0)


@pytest.mark.parametrize("case", BAD_INPUT, ids=lambda c: c[2])
def test_bad_input_raises_with_a_clear_message(case):
    kwargs, error, message = case
    F = kwargs.pop("F")
    with pytest.raises(error) as e:
        am.Material().evaluate(F, **kwargs)
    assert message in str(e.value)


def test_the_first_failing_point_is_named_in_parallel_batches_too():
    F = np.broadcast_to(np.eye(3), (40, 100, 3, 3)).copy()
    F[17, 42, 2, 2] = -1.0
    F[30, 1, 0, 0] = np.nan
    for parallel in (True, False):
        with pytest.raises(ValueError, match=r"point \[17, 42\] of F's point axes: deformation gradient has det F = -1"):
            am.Material(law="explicit").evaluate(F, parallel=parallel)


BAD_CHOICES = [
    (dict(energy="mooney"), 'energy = "mooney": unknown energy; the shipped ones are'),
    (dict(mu=-1.0), "mu = -1: must be finite and > 0"),
    (dict(w0=1.5), "w0 = 1.5: "),
    (dict(damage=2.0), "damage = 2: must lie in [0, 1]"),
    (dict(law="constant"), "needs gamma"),
    (dict(law="constant", gamma=1.0), "gamma = 1: activation gamma must lie in [0, 1)"),
    (dict(law="implicit", gamma=0.2), "gamma = 0.2: applies to law = \"constant\" only"),
    (dict(law="explicit", energy="ehret-bol-itskov"), "the explicit law (eq. (14)) is derived for the giantesio-musesti energy"),
    (dict(energy="neo-hookean"), "give mu [kPa]"),
    (dict(beta=1.0), "beta = 1: unknown field: the giantesio-musesti energy has no parameter beta"),
    (dict(coupling="loose"), 'coupling = "loose"'),
    (dict(frozen_tangent="bfgs"), 'frozen_tangent = "bfgs"'),
    (dict(below_minimum="never"), 'below_minimum = "never"'),
    (dict(law="explicit", explicit={"c": 1.0}), "explicit = { c = 1.0 }: unknown field `c`"),
    (dict(law="bogus"), 'law = "bogus": unknown variant'),
    (dict(lambda_min=1.5), "lambda_opt = 1.1704: must be > lambda_min"),
]


@pytest.mark.parametrize("case", BAD_CHOICES, ids=lambda c: c[1])
def test_bad_choices_raise_value_error_with_the_core_message(case):
    choices, message = case
    with pytest.raises(ValueError) as e:
        am.Material(**choices)
    assert message in str(e.value)


def test_non_finite_stress_is_an_error_not_a_nan():
    # Far beyond the representable stretch the exponential overflows: FloatingPointError.
    F = np.diag([30.0, 30.0**-0.5, 30.0**-0.5])
    with pytest.raises(FloatingPointError, match="non-finite"):
        am.Material(law="passive").evaluate(F)


def test_explicit_coefficients_are_read_the_chapters_by_default():
    # The chapter's a = 1.0133, b = 0.2050 given by hand are the default; another a changes γ.
    F = sheared_stretches(8)
    m = np.array([1.0, 0.0, 0.0])
    default = am.Material(law="explicit").evaluate(F, m)
    given = am.Material(law="explicit", explicit={"a": 1.0133, "b": 0.2050}).evaluate(F, m)
    other = am.Material(law="explicit", explicit={"a": 1.02}).evaluate(F, m)
    assert np.array_equal(default["gamma"], given["gamma"])
    assert not np.allclose(default["gamma"], other["gamma"])


def test_out_arrays_receive_the_same_values_as_fresh_ones():
    material = am.Material(law="explicit", damage=0.1)
    F = sheared_stretches(64).transpose(1, 2, 0)  # (3, 3, n), felupe's
    fresh = material.evaluate(F, fibres(64).T)
    out = {k: np.full_like(v, -1.0) for k, v in fresh.items()}
    out["tangent"] = np.asfortranarray(out["tangent"])  # any strides whose points flatten
    out["gamma"] = np.full(128, -1.0)[::2]
    r = material.evaluate(F, fibres(64).T, out=out)
    for k, v in fresh.items():
        assert r[k] is out[k] and np.array_equal(r[k], v), k
    # Only some outputs given: the others are fresh.
    r = material.evaluate(F, fibres(64).T, out={"stress": out["stress"]})
    assert r["stress"] is out["stress"] and np.array_equal(r["tangent"], fresh["tangent"])


def test_bad_out_arrays_raise_value_error():
    material = am.Material(law="explicit")
    F = sheared_stretches(5).transpose(1, 2, 0)
    read_only = np.empty((3, 3, 5))
    read_only.flags.writeable = False
    shared = np.empty(6)
    cases = [
        ({"stress": np.empty((3, 3, 4))}, r'out\["stress"\]: has shape \[3, 3, 4\]: must be \[3, 3, 5\]'),
        ({"stress": np.empty((3, 3, 5), np.float32)}, "must be a numpy array of float64"),
        ({"stress": F}, "share no memory with F"),
        ({"stress": read_only}, "not writeable"),
        ({"gamma": shared[:5], "energy": shared[1:]}, r'out\["energy"\]: cannot be written'),
        ({"tangent": np.empty((3, 3, 3, 3, 5))}, None),
        ({"stress": np.empty((3, 3, 5, 2))[..., 0].reshape(3, 3, 5)}, None),
        ({"bogus": np.empty(5)}, r'out\["bogus"\]: not an output'),
    ]
    for out, message in cases:
        if message is None:
            material.evaluate(F, out=out)  # accepted
            continue
        with pytest.raises(ValueError, match=message):
            material.evaluate(F, out=out)
    with pytest.raises(ValueError, match=r'out\["tangent"\]: not an output'):
        material.evaluate(F, order="stress", out={"tangent": np.empty((3, 3, 3, 3, 5))})
    # Points that do not flatten to one stride in F's order.
    G = np.zeros((3, 3, 4, 5)) + np.eye(3)[:, :, None, None]
    with pytest.raises(ValueError, match="point axes must flatten"):
        material.evaluate(G, out={"gamma": np.empty((5, 4)).T})


def test_tabulated_laws_give_the_exact_laws_within_the_tables_checked_tolerance():
    # Below λ_min (0.55), across the table and beyond it (1.7, where the exact solve answers).
    lam = np.linspace(0.55, 1.7, 117)
    for law, coupling in [("implicit", "frozen"), ("energy", "consistent")]:
        exact = am.Material(law=law, coupling=coupling, damage=0.3).uniaxial(lam)
        table = am.Material(law=law, coupling=coupling, damage=0.3, representation="tabulated").uniaxial(lam)
        assert np.all(np.abs(table["gamma"] - exact["gamma"]) <= 1e-12), law
        assert np.all(np.abs(table["stress"] - exact["stress"]) <= 1e-9 + 1e-13 * np.abs(exact["stress"])), law


def test_volume_preserving_map_gives_the_closed_form_of_a_neo_hookean_fibre():
    # F_a = (1 − γ) M + (1 − γ)^(−1/2) (I − M), W = μ/2 (tr C − 3), along the fibres:
    # Ŵ = μ/2 (λ²/c² + 2c/λ − 3), P = μ (λ/c² − c/λ²), c = 1 − γ (derived by hand).
    mu, gamma = 2.0, 0.2
    lam = np.linspace(0.7, 1.5, 9)
    c = 1.0 - gamma
    m = am.Material(energy="neo-hookean", mu=mu, law="constant", gamma=gamma, map="volume-preserving")
    # P crosses 0 at λ = c = 0.8: there only the rounding of μ-sized terms (≈ 1e-15 kPa) is left.
    np.testing.assert_allclose(m.uniaxial(lam)["stress"], mu * (lam / c**2 - c / lam**2), rtol=1e-12, atol=1e-13)
    chapter = am.Material(energy="neo-hookean", mu=mu, law="constant", gamma=gamma)
    assert not np.allclose(chapter.uniaxial(lam)["stress"], m.uniaxial(lam)["stress"])


@pytest.mark.parametrize("case", [
    (dict(map="isochoric"), 'map = "isochoric"'),
    (dict(representation="chebyshev"), 'representation = "chebyshev"'),
    (dict(table_stretches=[0.6, 1.5]), 'applies only with activation.representation = "tabulated"'),
    (dict(representation="tabulated", table_stretches=[1.5, 0.6]), "0 < λ_lo < λ_hi"),
], ids=lambda c: c[1])
def test_bad_map_or_representation_raises_with_the_scene_message(case):
    choices, message = case
    with pytest.raises(ValueError) as e:
        am.Material(**choices)
    assert message in str(e.value)


# Issue 23, item 6: the keywords come from the registries of energies and curves.
def test_curve_and_its_parameters_are_keywords_from_the_registry():
    # Ehret–Böl–Itskov's curve, as 4C writes it, along the fibres: P − P_pas = (1 − d) P_act.
    lmin, lopt, popt, d = 0.682, 1.192, 40.0, 0.2
    lam = np.array([0.8, 1.0, 1.2])
    e = np.exp((2 * lmin - lam - lopt) * (lam - lopt) / (2 * (lmin - lopt) ** 2))
    target = (1 - d) * popt * (lam - lmin) / (lopt - lmin) * e
    for choices in [dict(law="implicit", coupling="frozen"), dict(law="energy", coupling="consistent"),
                    dict(approach="active-stress")]:
        active = am.Material(curve="ehret-bol-itskov", lambda_min=lmin, lambda_opt=lopt, p_opt=popt,
                             damage=d, **choices)
        passive = am.Material(law="passive")
        got = np.asarray(active.uniaxial(list(lam))["stress"]) - np.asarray(passive.uniaxial(list(lam))["stress"])
        np.testing.assert_allclose(got, target, rtol=1e-10, err_msg=str(choices))


# An approach without a law (active stress) is never shown with one.
def test_active_stress_is_shown_by_its_approach_not_a_law():
    shown = repr(am.Material(approach="active-stress", damage=0.2))
    assert 'approach="active-stress"' in shown and "law=" not in shown, shown


def test_energy_parameters_of_any_shipped_energy_are_keywords():
    m = am.Material(energy="4c-passive", mu=5.0, alpha=15.0, beta=1.0, w0=0.8, law="passive")
    assert 'energy="4c-passive"' in repr(m) and "mu=5" in repr(m)


@pytest.mark.parametrize("case", [
    (dict(curve="ehret-bol-itskov", k=0.4), "the ehret-bol-itskov curve has no parameter k"),
    (dict(curve="sine"), "unknown active curve"),
    (dict(approach="sideways"), 'approach = "sideways"'),
    (dict(tau=1.0), "tau = (given): unknown keyword"),
    (dict(approach="structural", energy="neo-hookean", mu=1.0), "structural approach"),
    (dict(force_velocity={"min_rate": -17.0}), "missing field `ke`"),
    (dict(force_velocity={"min_rate": 17.0, "ke": 5, "kc": 5, "de": 0.5, "dc": 1}), "min_rate"),
    # A keyword that does not apply to the approach is refused as a scene refuses it.
    (dict(approach="active-stress", law="explicit"), 'law = "explicit": the explicit law does not apply to approach = "active-stress"'),
    (dict(approach="active-stress", coupling="consistent"), 'coupling = "consistent": coupling does not apply to approach = "active-stress"'),
    (dict(approach="active-stress", law="constant", gamma=0.2), "has none"),
    (dict(approach="structural", map="volume-preserving"), "map does not apply to approach = \"structural\""),
    (dict(approach="structural", law="explicit"), "fitted for active strain"),
], ids=lambda c: c[1])
def test_bad_registry_keywords_name_the_keyword(case):
    choices, message = case
    with pytest.raises(ValueError) as e:
        am.Material(**choices)
    assert message in str(e.value)
