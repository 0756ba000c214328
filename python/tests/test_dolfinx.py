"""The distributed route: activemuscle as a quadrature-point material in DOLFINx (Debian's
python3-dolfinx 0.5, run by Debian's /usr/bin/python3, under mpirun), against references that do
not share its code: the homogeneous 0D curve (sliding cylinder), activemuscle's own axisymmetric
solver (clamped cylinder), one process (two processes), the same energy written and
differentiated in UFL (fusiform muscle, fibres per quadrature point) and the stored energy (the
work of the consistent model's end force)."""

import os
import re
import shutil
import subprocess

import numpy as np
import pytest

import activemuscle as am

PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(am.__file__)))
CHECKS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "dolfinx_checks.py")
DEBIAN_PYTHON = "/usr/bin/python3"


def dolfinx_available():
    if not (os.path.exists(DEBIAN_PYTHON) and shutil.which("mpirun")):
        return False
    return subprocess.run([DEBIAN_PYTHON, "-c", "import dolfinx"], capture_output=True).returncode == 0


# CI installs python3-dolfinx and openmpi-bin (.ci/run): there a missing route is a failure.
pytestmark = pytest.mark.skipif(
    not dolfinx_available() and not os.environ.get("CI"),
    reason="needs Debian's python3-dolfinx and mpirun (apt-get install python3-dolfinx openmpi-bin)",
)


def run(command, processes=1):
    """stdout of `command` (arguments of Debian's python3) on `processes` MPI processes."""
    command = [DEBIAN_PYTHON] + command
    if processes > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-n", str(processes)] + command
    env = dict(os.environ, PYTHONPATH=PACKAGE_ROOT, OMP_NUM_THREADS="1")
    out = subprocess.run(command, env=env, capture_output=True, text=True, timeout=900)
    assert out.returncode == 0, out.stdout[-2000:] + out.stderr[-3000:]
    return out.stdout


def cylinder(*args, processes=1):
    """The columns of examples/dolfinx_cylinder's table: {name: array}."""
    out = run(["-m", "activemuscle.examples.dolfinx_cylinder", *args], processes)
    assert f"{processes} process(es)" in out
    header = next(line.split() for line in out.splitlines() if line.startswith("lambda "))
    rows = np.array([line.split() for line in out.splitlines() if re.match(r"^\d", line)], dtype=float)
    return dict(zip(header, rows.T))


MODELS = [
    (dict(law="explicit", coupling="frozen"), []),  # the whole cylinder: rigid motions pinned
    (dict(law="implicit", coupling="frozen", damage=0.5), ["--quarter"]),
    (dict(law="energy", coupling="consistent"), ["--quarter", "--half"]),
]


@pytest.mark.parametrize("choices, part", MODELS, ids=["explicit-frozen-whole", "implicit-frozen-d0.5-quarter",
                                                       "energy-consistent-eighth"])
def test_sliding_cylinder_reproduces_the_homogeneous_curve(choices, part):
    stretches = [0.8, 1.0, 1.3]
    args = ["--bases", "sliding", "--meshes", "2x4", "--stretches", ",".join(map(str, stretches))]
    args += [f"--{k}={v}" for k, v in choices.items()] + part
    got = cylinder(*args)
    expected = am.Material(**choices).uniaxial(stretches)["stress"]
    np.testing.assert_allclose(got["lambda"], stretches)
    np.testing.assert_allclose(got["P_2x4"], expected, rtol=1e-9)


def test_sliding_cylinder_near_incompressibility_reproduces_its_homogeneous_curve(tmp_path):
    scene = tmp_path / "scene.toml"
    scene.write_text('title = "near"\n[incompressibility]\nkind = "logarithmic"\nkappa = 500.0\n'
                     '[[study]]\nkind = "uniaxial"\nstretch = [1.0]\n')
    stretches = [0.8, 1.0, 1.3]
    got = cylinder("--scene", str(scene), "--law", "explicit", "--bases", "sliding", "--quarter",
                   "--meshes", "2x4", "--stretches", ",".join(map(str, stretches)))
    material = am.Material(law="explicit")
    near = material.uniaxial(stretches, am.Volumetric(material, "logarithmic", kappa=500.0))["stress"]
    np.testing.assert_allclose(got["P_2x4"], near, rtol=1e-9)
    # The volume the activated muscle loses there lowers its stress below the incompressible curve.
    assert np.all(near < material.uniaxial(stretches)["stress"])


def test_two_processes_give_the_numbers_of_one():
    args = ["--law", "explicit", "--meshes", "2x4", "--stretches", "0.9,1.2"]
    one, two = cylinder(*args), cylinder(*args, processes=2)
    np.testing.assert_allclose(two["P_2x4"], one["P_2x4"], rtol=1e-9)
    # Clamping stiffens the cylinder in tension and softens it in compression (as the chapter's Fig. 12).
    assert one["P_2x4"][1] > one["P_0d"][1] and one["P_2x4"][0] < one["P_0d"][0]


def axisymmetric(stretches, nr, nz, grading):
    """activemuscle's own axisymmetric Q2/Q1 solver on the clamped cylinder: P per stretch."""
    study = dict(kind="cylinder", name="axisymmetric", nr=nr, nz=nz, grading=grading, bases="clamped",
                 law="explicit", coupling="frozen", damage=[0.0], stretch=stretches)
    return am.run_scene({"title": "reference", "study": [study]})["axisymmetric"].table["P"]


def test_clamped_cylinder_approaches_the_axisymmetric_solution_as_its_mesh_is_refined():
    """Two 3D meshes, the second twice as fine: the finer is closer to the axisymmetric solution,
    and no further from it than from the coarser (P converges like h at the clamped rims, so the
    finer mesh's own error is about the change between the two)."""
    stretches = [1.17, 1.3]
    got = cylinder("--law", "explicit", "--quarter", "--half", "--meshes", "3x12,6x24",
                   "--stretches", ",".join(map(str, stretches)))
    reference = axisymmetric(stretches, 32, 128, 3.0)
    coarse, fine = got["P_3x12"], got["P_6x24"]
    assert np.all(abs(fine - reference) < abs(coarse - reference))
    assert np.all(abs(fine - reference) <= abs(coarse - fine))


def test_fusiform_route_equals_the_energy_differentiated_by_ufl():
    """Per-point fibres, active strain, P and the exact tangent through the quadrature spaces,
    on two processes: the force equals that of the energy written in UFL."""
    out = run([CHECKS, "ufl"], processes=2)
    rows = re.findall(r"^(\S+) activemuscle (\S+) ufl (\S+)$", out, re.M)
    assert [name for name, _, _ in rows] == ["giantesio-musesti", "neo-hookean"]
    for _, ours, theirs in rows:
        assert abs(float(ours) - float(theirs)) <= 1e-9 * abs(float(theirs))


def test_consistent_fusiform_is_hyperelastic_and_the_frozen_one_is_not():
    """The work of the end force equals the change of stored energy for the consistent coupling
    (to Simpson's rule's error, estimated by the rule on twice the step), not for the frozen."""
    out = run([CHECKS, "work"])
    rows = {m: tuple(map(float, v)) for m, *v in
            re.findall(r"^(\S+) work (\S+) work_2h (\S+) energy (\S+)$", out, re.M)}
    work, work_2h, energy = rows["energy-consistent"]
    assert abs(work - energy) <= abs(work - work_2h)
    work, _, energy = rows["explicit-frozen"]
    assert abs(work - energy) > 0.5 * abs(work)
