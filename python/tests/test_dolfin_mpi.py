"""The distributed route: activemuscle as a quadrature-point material in legacy FEniCS (DOLFIN
2019, Debian's python3-dolfin, run by Debian's /usr/bin/python3) under MPI. The sliding block must
equal the homogeneous 0D curve; the clamped block on two processes must equal one process."""

import os
import re
import shutil
import subprocess

import numpy as np
import pytest

import activemuscle as am

PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(am.__file__)))
DEBIAN_PYTHON = "/usr/bin/python3"


def dolfin_available():
    if not (os.path.exists(DEBIAN_PYTHON) and shutil.which("mpirun")):
        return False
    return subprocess.run([DEBIAN_PYTHON, "-c", "import dolfin"], capture_output=True).returncode == 0


# CI installs python3-dolfin and openmpi-bin (.ci/run): there a missing route is a failure.
pytestmark = pytest.mark.skipif(
    not dolfin_available() and not os.environ.get("CI"),
    reason="needs Debian's python3-dolfin and mpirun (apt-get install python3-dolfin openmpi-bin)",
)


def run(bases, processes):
    command = [DEBIAN_PYTHON, "-m", "activemuscle.examples.dolfin_mpi", bases, "2"]
    if processes > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-n", str(processes)] + command
    env = dict(os.environ, PYTHONPATH=PACKAGE_ROOT, OMP_NUM_THREADS="1")
    out = subprocess.run(command, env=env, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    rows = re.findall(r"^(\d\.\d+) (\S+) (\S+)$", out.stdout, re.M)
    assert f"{processes} process(es)" in out.stdout
    return np.array(rows, dtype=float)


def test_sliding_block_reproduces_the_homogeneous_curve():
    rows = run("sliding", 1)
    lam, P, P0 = rows.T
    expected = am.Material(law="explicit").uniaxial(list(lam))["stress"]
    np.testing.assert_allclose(P0, expected, rtol=1e-12)
    np.testing.assert_allclose(P, expected, rtol=1e-9)


def test_clamped_block_on_two_processes_equals_one_process():
    one, two = run("clamped", 1), run("clamped", 2)
    np.testing.assert_allclose(two[:, 1], one[:, 1], rtol=1e-10)
    # Clamping stiffens the block: its nominal stress exceeds the homogeneous one.
    assert np.all(one[:, 1] > one[:, 2])
