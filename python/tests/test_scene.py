"""Scenes from Python against independent references: the 0D closed form P = P_pas + (1 − d) P_act
of the implicit law (the chapter's eqs. for the passive curve and eq. (8)), the same scene as text
and as a dict, the scene's own messages, the command line's files."""

import csv
import json

import numpy as np
import pytest

import activemuscle as am

# The chapter's values (Tables 1, 2): the scene's defaults.
MU, ALPHA, W0 = 0.1599, 19.35, 0.7335
LAMBDA_MIN, LAMBDA_OPT, K, P_OPT = 0.6243, 1.1704, 0.4342, 73.52

STRETCHES = [0.8, 0.95, 1.1, 1.25, 1.4]
MU_NH = 2.0  # the neo-Hookean block of PLANAR [kPa]
DAMAGE = [0.0, 0.3]

TEXT = """title = "tiny"

[[study]]
kind = "uniaxial"
name = "along"
stretch = [0.8, 0.95, 1.1, 1.25, 1.4]
laws = ["implicit"]
couplings = ["frozen"]
damage = [0.0, 0.3]

[[study]]
kind = "cylinder"
name = "sliding cylinder"
nr = 1
nz = 2
grading = 1.0
bases = "sliding"
law = "implicit"
damage = [0.3]
stretch = [1.0, 1.1]
vtk = [1.1]
"""

DICT = {
    "title": "tiny",
    "study": [
        {
            "kind": "uniaxial",
            "name": "along",
            "stretch": np.array(STRETCHES),
            "laws": ["implicit"],
            "couplings": ["frozen"],
            "damage": DAMAGE,
        },
        {
            "kind": "cylinder",
            "name": "sliding cylinder",
            "nr": 1,
            "nz": 2,
            "grading": 1.0,
            "bases": "sliding",
            "law": "implicit",
            "damage": [0.3],
            "stretch": [1.0, 1.1],
            "vtk": [1.1],
        },
    ],
}


def passive_closed_form(lam):
    """eq. D:Ppas: P = μ/4 [e^{α(I_p − 1)} I_p′ + K_p′] along F = diag(λ, λ^-½, λ^-½)."""
    Ip = W0 / 3 * (lam**2 + 2 / lam) + (1 - W0) * lam**2
    dIp = W0 / 3 * (2 * lam - 2 / lam**2) + 2 * (1 - W0) * lam
    dKp = W0 / 3 * (2 - 2 / lam**3) - 2 * (1 - W0) / lam**3
    return MU / 4 * (np.exp(ALPHA * (Ip - 1)) * dIp + dKp)


def active_closed_form(lam):
    """eq. (8): P_act = P_opt exp(−k (λ² − λ_opt²)² / (λ − λ_min))."""
    return P_OPT * np.exp(-K * (lam**2 - LAMBDA_OPT**2) ** 2 / (lam - LAMBDA_MIN))


def test_uniaxial_study_reproduces_the_closed_form_of_the_implicit_law():
    r = am.run_scene(TEXT)
    t = r["along"].table
    lam = t["lambda"]
    passive = t["law"] == "passive"
    np.testing.assert_allclose(t["P"][passive], passive_closed_form(lam[passive]), rtol=1e-12, atol=1e-14)
    active = t["law"] == "implicit"
    d = np.ma.getdata(t["d"])[active]
    assert sorted(set(d)) == DAMAGE and not np.ma.getmaskarray(t["d"])[active].any()
    assert np.ma.getmaskarray(t["d"])[passive].all()
    expected = passive_closed_form(lam[active]) + (1 - d) * active_closed_form(lam[active])
    np.testing.assert_allclose(t["P"][active], expected, rtol=1e-10)
    np.testing.assert_allclose(np.ma.getdata(t["P_pas"])[active], passive_closed_form(lam[active]), rtol=1e-12, atol=1e-14)
    assert r["along"].points == r["along"].requested == len(lam) == 3 * len(STRETCHES)
    assert len(r["along"].failures["message"]) == 0


def test_the_explicit_law_beyond_its_fitted_stretches_is_flagged_row_by_row():
    # Its domain is 0.7 <= λ_f <= 1.5 (docs/explicit_law.md): 0.65 and 1.6 are computed and flagged.
    r = am.run_scene(
        '[[study]]\nkind = "uniaxial"\nname = "u"\nstretch = [0.65, 1.0, 1.6]\n'
        'laws = ["explicit"]\ncouplings = ["frozen"]\ndamage = [0.0]\n'
    )
    s = r["u"]
    explicit = s.table["law"] == "explicit"
    lam = s.table["lambda"][explicit]
    inside = np.ma.getdata(s.table["in_domain"])[explicit]
    assert list(inside) == [bool(0.7 <= x <= 1.5) for x in lam] and len(lam) == 3
    assert len(s.outside_domain["model"]) == 1
    assert "2 of 3 points outside the explicit law's domain" in s.outside_domain["message"][0]


def test_sliding_cylinder_equals_the_homogeneous_curve():
    t = am.run_scene(TEXT)["sliding cylinder"].table
    lam = t["lambda"]
    expected = passive_closed_form(lam) + (1 - t["d"]) * active_closed_form(lam)
    np.testing.assert_allclose(t["P"], expected, rtol=1e-10)
    assert (t["newton_iterations"] >= 1).all() and t["bases"].tolist() == ["sliding"] * 2


def test_every_table_is_columns_of_one_length_as_pandas_takes_them():
    for s in am.run_scene(TEXT):
        lengths = {name: np.shape(column) for name, column in s.table.items()}
        assert set(lengths.values()) == {(s.points,)}, lengths
        for column in s.table.values():
            assert isinstance(column, np.ndarray)
            if column.dtype.kind == "f":
                assert np.isfinite(np.ma.getdata(column)).all()


def test_a_dict_scene_equals_the_same_scene_as_text():
    assert am.check_scene(DICT) == am.check_scene(TEXT)
    a, b = am.run_scene(DICT), am.run_scene(TEXT)
    assert [s.name for s in a] == [s.name for s in b]
    for x, y in zip(a, b):
        assert x.table.keys() == y.table.keys()
        for name in x.table:
            u, v = x.table[name], y.table[name]
            assert np.array_equal(np.ma.getmaskarray(u), np.ma.getmaskarray(v)), name
            assert np.array_equal(np.ma.getdata(u), np.ma.getdata(v)), name


def test_check_scene_writes_out_every_default():
    resolved = am.check_scene(TEXT)
    assert "lambda_opt = 1.1704" in resolved and 'coupling = "frozen"' in resolved
    # The resolved scene is a scene: it resolves to itself.
    assert am.check_scene(resolved) == resolved


def test_an_invalid_scene_raises_value_error_with_its_line_or_key_path(tmp_path):
    bad = TEXT.replace("damage = [0.0, 0.3]", "damage = [0.0, 1.3]")
    line = bad.splitlines().index("damage = [0.0, 1.3]") + 1
    with pytest.raises(ValueError, match=rf"^<string>:{line}: study\[0\]\.damage\[1\] = 1\.3: damage d must lie in \[0, 1\]"):
        am.run_scene(bad)
    path = tmp_path / "bad.toml"
    path.write_text(bad)
    with pytest.raises(ValueError, match=rf"bad\.toml:{line}: study\[0\]\.damage\[1\] = 1\.3"):
        am.check_scene(path)
    d = {"study": [dict(DICT["study"][0], damage=[0.0, 1.3])]}
    with pytest.raises(ValueError, match=r"^<dict>: study\[0\]\.damage\[1\] = 1\.3: damage d must lie"):
        am.run_scene(d)
    with pytest.raises(ValueError, match=r"study\[0\]\.nr = None: a scene has no null"):
        am.run_scene({"study": [{"kind": "cylinder", "nr": None}]})
    with pytest.raises(ValueError, match="cannot read the scene file"):
        am.run_scene(str(tmp_path / "missing.toml"))


def test_a_failing_point_is_recorded_and_the_other_studies_go_on():
    # λ = 40 overflows the passive exponential: that stretch fails on every curve of the first
    # study, its other stretches and the second study are computed.
    scene = TEXT.replace("stretch = [0.8, 0.95, 1.1, 1.25, 1.4]", "stretch = [0.8, 1.1, 40.0]")
    r = am.run_scene(scene)
    along = r["along"]
    assert along.requested == 9 and along.points == 6
    assert len(along.failures["model"]) == 3
    assert all("lambda = 40" in m for m in along.failures["message"])
    assert sorted(set(along.table["lambda"])) == [0.8, 1.1]
    assert r["sliding cylinder"].points == 2 and len(r["sliding cylinder"].failures["model"]) == 0
    assert [f[0] for f in r.failures()] == ["along"] * 3


def test_out_writes_the_command_lines_files(tmp_path):
    out = tmp_path / "run"
    r = am.run_scene(TEXT, out=out)
    assert r.out == out
    with open(out / "curves.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == sum(s.points for s in r)
    assert (out / "report.html").is_file() and (out / "scene.toml").read_text() == TEXT
    vtk = r["sliding cylinder"].vtk
    # The field at the one stretch asked for, and the sweep's series (.pvd) that lists it.
    assert sorted(p.suffix for p in vtk) == [".pvd", ".vtu"]
    assert all(p.parent.parent == out / "vtk" and p.is_file() for p in vtk)
    # Without out, no VTK file is named (none is written).
    assert am.run_scene(TEXT)["sliding cylinder"].vtk == []


def test_out_writes_no_curves_csv_without_a_study_that_fills_it(tmp_path):
    out = tmp_path / "run"
    r = am.run_scene('[[study]]\nkind = "shear"\nname = "s"\nshear = [0.1, 0.2]\n', out=out)
    assert r["s"].files["table"] == "shear.csv"
    assert not (out / "curves.csv").exists()
    package = json.loads((out / "datapackage.json").read_text())
    assert [res["path"] for res in package["resources"]] == ["shear.csv"]
    assert sorted(p.name for p in out.glob("*.csv")) == ["shear.csv"]


FIT_AND_STABILITY = """
[[study]]
kind = "fit"
name = "damage"
fit = "damage"
true_damage = [0.1, 0.3]
stretch = { from = 0.75, to = 1.40, step = 0.05 }
noise = 0.0

[[study]]
kind = "stability"
name = "stability"
stretch = [0.8, 1.0, 1.2]
passive = true
laws = ["implicit"]
couplings = ["frozen"]
damage = [0.2]
normals = 20
"""


def test_fit_and_stability_tables():
    r = am.run_scene(FIT_AND_STABILITY)
    fit = r["damage"].table
    # Noise-free synthetic curves: the fit recovers the damage that made them.
    np.testing.assert_allclose(fit["value"], [0.1, 0.3], atol=1e-8)
    assert fit["converged"].all() and fit["parameter"].tolist() == ["d", "d"]
    s = r["stability"].table
    lam, d = s["lambda"], np.ma.getdata(s["d"])
    active = s["law"] == "implicit"

    def closed(lam, d, active):
        return passive_closed_form(lam) + np.where(active, 1 - d, 0.0) * active_closed_form(lam)

    np.testing.assert_allclose(s["P"], closed(lam, d, active), rtol=1e-10, atol=1e-14)
    h = 1e-6
    slope = (closed(lam + h, d, active) - closed(lam - h, d, active)) / (2 * h)
    np.testing.assert_allclose(s["dP_dlambda"], slope, rtol=1e-6, atol=1e-6)


def test_a_scene_and_a_material_with_the_same_keys_give_the_same_curve():
    # The same [material] and [activation] keys through both routes (Models::from_spec in both).
    keys = dict(mu=0.2, alpha=15.0, w0=0.7, lambda_opt=1.15, p_opt=60.0)
    scene = {
        "material": {k: keys[k] for k in ("mu", "alpha", "w0")},
        "activation": {k: keys[k] for k in ("lambda_opt", "p_opt")},
        "study": [dict(DICT["study"][0], damage=[0.3], couplings=["consistent"])],
    }
    t = am.run_scene(scene)["along"].table
    active = t["law"] == "implicit"
    material = am.Material(law="implicit", coupling="consistent", damage=0.3, **keys)
    got = material.uniaxial(list(t["lambda"][active]))
    np.testing.assert_array_equal(got["stress"], t["P"][active])
    np.testing.assert_array_equal(got["gamma"], t["gamma"][active])


def test_cauchy_stress_along_the_fibres_is_lambda_times_the_nominal_stress():
    # Incompressible uniaxial tension along e1: σ11 = J⁻¹ (P Fᵀ)11 = λ P (J = 1, lateral faces free).
    t = am.run_scene(TEXT)["along"].table
    np.testing.assert_allclose(t["cauchy"], t["lambda"] * t["P"], rtol=1e-12, atol=1e-15)


def test_named_points_of_a_sliding_cylinder_move_homogeneously():
    # Sliding bases: the homogeneous solution u_z = (λ − 1) z, u_r = (λ^(−1/2) − 1) r.
    text = TEXT + """
[study.points]
tip_axis = [0.0, 4.0]
tip_rim = [1.0, 4.0]
base_rim = [1.0, 0.0]
"""
    r = am.run_scene(text)["sliding cylinder"]
    p = r.named_points
    assert sorted(set(p["point"])) == ["base_rim", "tip_axis", "tip_rim"] and len(p["lambda"]) == 3 * 2
    np.testing.assert_allclose(p["u_z"], (p["lambda"] - 1) * p["z"], atol=1e-9)
    np.testing.assert_allclose(p["u_r"], (p["lambda"] ** -0.5 - 1) * p["r"], atol=1e-9)


def test_a_compressible_block_in_time_reports_its_volume_and_cauchy_stress():
    # Nearly incompressible (quadratic U, κ = 1e4 kPa): σ11 = P11 λ / J with J = λ λ2 λ3 ≠ 1,
    # and J → 1 as κ → ∞ (O(1/κ): a hundredfold κ brings J a hundredfold closer to 1).
    def history(kappa):
        scene = f"""
[incompressibility]
kind = "quadratic"
kappa = {kappa}

[[study]]
kind = "activation-in-time"
name = "h"
time = {{ from = 0.0, to = 0.2, step = 0.05 }}
schedule = [[0.0, 1.0]]
stretch = 1.1
"""
        return am.run_scene(scene)["h"].table

    t = history(1e4)
    np.testing.assert_allclose(t["cauchy"] * t["J"], t["P"] * t["lambda"], rtol=1e-12)
    departure = np.abs(t["J"] - 1).max()
    assert 1e-5 < departure < 1e-2
    assert np.abs(history(1e6)["J"] - 1).max() < 0.02 * departure


def test_the_block_in_time_example_tends_to_the_exact_history_as_one_over_kappa():
    from activemuscle.examples.block_in_time import history

    exact, soft, stiff = history(), history(1e4), history(1e6)
    np.testing.assert_allclose(exact["J"], 1.0, rtol=0, atol=4e-16)  # λ·(λ^(−½))², rounded
    for h in (exact, soft, stiff):
        assert np.abs(h["P"]).max() < 1e-9  # free contraction: zero axial load at every step
        assert h["lambda"][1:].max() < 0.75  # the stimulated block shortens towards λ_min
    gap = [np.abs(h["lambda"] - exact["lambda"]).max() for h in (soft, stiff)]
    volume = [np.abs(h["J"] - 1).max() for h in (soft, stiff)]
    # O(1/κ): a hundredfold κ, a hundredfold closer (within 20 %).
    assert 80 < gap[0] / gap[1] < 120 and 80 < volume[0] / volume[1] < 120, (gap, volume)


PLANAR = """title = "planar"

[material]
energy = "neo-hookean"
mu = 2.0

[[study]]
kind = "shear"
name = "shear"
shear = [0.0, 0.2, 0.5]
fibre_angles = [0.0, 30.0]
approaches = ["active-stress"]
damage = [0.0]

[[study]]
kind = "biaxial"
name = "equibiaxial"
path = "equibiaxial"
stretch = [1.0, 1.1, 1.2]
approaches = ["active-stress"]
damage = [0.0]
"""


def test_shear_and_biaxial_tables_of_a_neo_hookean_block_are_the_closed_forms():
    r = am.run_scene(PLANAR)
    s = r["shear"].table
    passive = s["law"] == "passive"
    k = s["shear"][passive]
    # σ = μ B − p I with σ₃₃ = 0: σ₁₂ = μk, σ₁₁ = μk², σ₂₂ = 0 for any fibre angle.
    np.testing.assert_allclose(s["sigma_12"][passive], MU_NH * k, atol=1e-12)
    np.testing.assert_allclose(s["sigma_11"][passive], MU_NH * k**2, atol=1e-12)
    np.testing.assert_allclose(s["sigma_22"][passive], 0.0, atol=1e-12)
    assert sorted(set(s["fibre_angle"].tolist())) == [0.0, 30.0]
    assert set(s["approach"][~passive].tolist()) == {"active-stress"}
    b = r["equibiaxial"].table
    p = b["law"] == "passive"
    lam = b["lambda_1"][p]
    # Equibiaxial, isotropic: P₁₁ = P₂₂ = μ (λ − λ⁻⁵) with λ₃ = λ⁻².
    np.testing.assert_allclose(b["lambda_3"][p], lam**-2, rtol=1e-14)
    np.testing.assert_allclose(b["P_11"][p], MU_NH * (lam - lam**-5), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(b["P_22"][p], b["P_11"][p], rtol=1e-12, atol=1e-12)
    # Active stress adds (1 − d) P_act(λ₁) to P₁₁ alone, with the chapter's curve (eq. (8)).
    a = ~p
    np.testing.assert_allclose(
        b["P_11"][a] - MU_NH * (b["lambda_1"][a] - b["lambda_1"][a] ** -5),
        active_closed_form(b["lambda_1"][a]),
        rtol=1e-10,
    )
    np.testing.assert_allclose(b["P_22"][a], b["P_22"][p], rtol=1e-12, atol=1e-12)


def test_a_thread_count_from_the_environment_above_four_per_core_is_bounded_with_a_warning():
    import os
    import re
    import subprocess
    import sys

    cores = os.cpu_count() or 1
    too_many = 4 * cores + 3  # a modest excess: a build without the bound must still start them
    code = (
        "import warnings\n"
        "with warnings.catch_warnings(record=True) as w:\n"
        "    warnings.simplefilter('always')\n"
        "    import activemuscle\n"
        "print('|'.join(str(x.message) for x in w if issubclass(x.category, RuntimeWarning)))\n"
    )
    env = dict(os.environ, RAYON_NUM_THREADS=str(too_many))
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120
    )
    assert out.returncode == 0, out.stderr
    assert f"RAYON_NUM_THREADS={too_many}" in out.stdout, out.stdout
    # The cores the module counts (its affinity and quota) are at most the machine's.
    counted = re.search(r"\((\d+) cores\): using (\d+) threads", out.stdout)
    assert counted, out.stdout
    assert 1 <= int(counted[1]) <= cores and int(counted[2]) == 4 * int(counted[1])
