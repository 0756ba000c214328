"""Python's tables are the CSV files' tables: for a scene with a study of every kind, each file the
run writes (read back with the csv module and its datapackage.json) holds exactly the columns —
names, order, types — and the values of the Python tables of the studies that write to it, row
for row in scene order, an empty cell where Python masks a value or has None."""

import csv
import json
import math

import numpy as np
import pytest

import activemuscle as am

EVERY_KIND = """title = "every kind"

[[study]]
kind = "uniaxial"
name = "along"
stretch = [0.8, 1.0, 1.2]
compare = [{ energy = "ehret-bol-itskov" }]
constant_gamma = [0.1]
laws = ["implicit", "explicit"]
couplings = ["frozen"]
damage = [0.0, 0.5]

[[study]]
kind = "uniaxial"
name = "across"
direction = "across"
stretch = [1.1]
laws = ["implicit"]

[[study]]
kind = "cylinder"
name = "sliding cylinder"
nr = 1
nz = 2
bases = "sliding"
law = "implicit"
damage = [0.3]
stretch = [1.0, 1.1]

[study.points]
tip = [1.0, 4.0]
axis = [0.0, 4.0]

[[study]]
kind = "fit"
name = "damage"
fit = "damage"
true_damage = [0.3]
stretch = { from = 0.8, to = 1.2, step = 0.1 }
noise = 0.0

[[study]]
kind = "stability"
name = "stability"
stretch = [0.9, 1.1]
laws = ["implicit"]
couplings = ["frozen"]
damage = [0.2]
normals = 8

[[study]]
kind = "activation-in-time"
name = "twitch"
time = { from = 0.0, to = 0.1, step = 0.05 }
schedule = [[0.0, 1.0]]
stretch = 1.1

[[study]]
kind = "shear"
name = "shear"
shear = [0.0, 0.2]
fibre_angles = [0.0]
approaches = ["active-strain", "active-stress"]
damage = [0.0]

[[study]]
kind = "biaxial"
name = "biaxial"
path = "equibiaxial"
stretch = [1.0, 1.1]
approaches = ["active-stress"]
damage = [0.0]

[[study]]
kind = "tangent"
name = "tangent"
uniaxial_along = [1.1]
random_directions = 1
laws = ["explicit"]
couplings = ["frozen"]
h = { largest = 0.015625, smallest = 0.0009765625 }
fe = { nr = 1, nz = 2, elements = ["Q1/P0"], bases = ["sliding"], stretch = 1.05 }

[[study]]
kind = "tradeoff"
options = ["activation-law"]
stretch = [1.0, 1.1]
"""

# The numpy type of each type of datapackage.json.
DTYPES = {"number": "f", "integer": "i", "boolean": "b", "string": "O"}


def cell(value, kind):
    """A Python table's value as the text of a CSV cell (None and masked: empty)."""
    if value is None or value is np.ma.masked:
        return ""
    if kind == "boolean":
        return "true" if value else "false"
    return value


def parsed(text, kind):
    """A CSV cell's text as the value it stands for ("" for an empty cell)."""
    if text == "":
        return ""
    if kind == "number":
        return float(text)
    if kind == "integer":
        return int(text)
    return text


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("every") / "out"
    return am.run_scene(EVERY_KIND, out=out), out


def test_every_kind_writes_a_file_and_every_study_knows_its_file(run):
    r, out = run
    package = json.loads((out / "datapackage.json").read_text())
    described = [res["path"] for res in package["resources"]]
    assert sorted(described) == sorted(p.name for p in out.glob("*.csv"))
    assert set(described) == {
        "curves.csv", "fits.csv", "stability.csv", "history.csv", "shear.csv",
        "biaxial.csv", "tradeoff.csv", "points_sliding_cylinder.csv", "fit_points.csv",
        "tangent_summary.csv", "tangent.csv", "tangent_fe.csv", "tangent_newton.csv",
    }
    for s in r:
        assert not s.failures["message"].size, (s.name, s.failures)
        assert s.files["table"] in described, s.name
    assert r["sliding cylinder"].files["named_points"] == "points_sliding_cylinder.csv"


def test_python_tables_have_exactly_the_csv_columns_types_and_values(run):
    r, out = run
    package = json.loads((out / "datapackage.json").read_text())
    for resource in package["resources"]:
        path, fields = resource["path"], resource["schema"]["fields"]
        names = [f["name"] for f in fields]
        kinds = {f["name"]: f["type"] for f in fields}
        with open(out / path, newline="") as f:
            rows = list(csv.reader(f))
        assert rows[0] == names, path
        tables = [
            getattr(s, key)
            for s in r
            for key, file in s.files.items()
            if file == path
        ]
        assert tables, path
        at = 1
        for t in tables:
            assert list(t) == names, path
            n = len(t[names[0]])
            for name in names:
                column = t[name]
                assert column.dtype.kind == DTYPES[kinds[name]], (path, name, column.dtype)
                assert len(column) == n, (path, name)
            for i in range(n):
                written = rows[at + i]
                for j, name in enumerate(names):
                    mine = cell(t[name][i], kinds[name])
                    theirs = parsed(written[j], kinds[name])
                    assert mine == theirs, (path, at + i, name, mine, written[j])
            at += n
        assert at == len(rows), (path, at, len(rows))


def test_the_approach_is_named_where_a_law_is_and_active_stress_has_no_law(run):
    r, _ = run
    curves = r["along"].table
    active = curves["law"] == "implicit"
    assert set(curves["approach"][active]) == {"active-strain"}
    # The passive curves (the material's and the compared energy) have no approach.
    passive = curves["law"] == "passive"
    assert passive.sum() == 2 * 3 and all(a is None for a in curves["approach"][passive])
    shear = r["shear"].table
    stress = shear["approach"] == "active-stress"
    assert stress.any()
    assert all(x is None for x in shear["law"][stress])
    assert all(x is None for x in shear["coupling"][stress])
    for name in ("twitch", "stability"):
        t = r[name].table
        rows = np.array([x is not None for x in t["approach"]])
        assert set(t["approach"][rows]) == {"active-strain"}, name
    assert set(r["sliding cylinder"].named_points["approach"]) == {"active-strain"}


ACTIVE_STRESS = """title = "active stress"

[activation]
approach = "active-stress"

[[study]]
kind = "uniaxial"
name = "along"
stretch = [0.8, 1.0, 1.2]
damage = [0.0, 0.5]
"""


def test_an_active_stress_scene_names_its_approach_and_no_law():
    t = am.run_scene(ACTIVE_STRESS)["along"].table
    active = np.array([a is not None for a in t["approach"]])
    assert active.sum() == 2 * 3
    assert set(t["approach"][active]) == {"active-stress"}
    assert all(x is None for x in t["law"][active]) and all(x is None for x in t["coupling"][active])
    # Along the fibres active stress is the target itself: P = P_pas + (1 − d) P_act.
    p_pas, p_act = np.ma.getdata(t["P_pas"])[active], np.ma.getdata(t["P_act"])[active]
    np.testing.assert_allclose(t["P"][active], p_pas + p_act, rtol=1e-12, atol=1e-12)
