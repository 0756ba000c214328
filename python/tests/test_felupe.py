"""felupe + activemuscle against references that do not share felupe's code: the homogeneous 0D
curve (sliding cylinder, 3D block on symmetry planes), activemuscle's own axisymmetric solver
(clamped cylinder), and felupe's own neo-Hookean material (fusiform muscle)."""

import felupe as fem
import numpy as np
import pytest

import activemuscle as am
from activemuscle.examples.felupe_cylinder import cylinder
from activemuscle.examples.felupe_fusiform import fusiform, generatrix_fibres, spindle
from activemuscle.felupe import Incompressible, MuscleMaterial

MODELS = [
    dict(law="passive"),
    dict(law="explicit", coupling="frozen"),
    dict(law="implicit", coupling="frozen", damage=0.5),
    dict(law="energy", coupling="consistent"),
]


@pytest.mark.parametrize("choices", MODELS, ids=lambda c: "-".join(map(str, c.values())))
def test_sliding_cylinder_reproduces_the_homogeneous_curve(choices):
    material = am.Material(**choices)
    stretches = [0.8, 1.0, 1.17, 1.3]
    r = cylinder(material, stretches, bases="sliding", nr=2, nz=4)
    zero_d = material.uniaxial(stretches)["stress"]
    np.testing.assert_allclose(r["stress"], zero_d, rtol=1e-9)


# activemuscle's own solver on the same uniform 6 × 24 Taylor–Hood mesh (R = 1, L = 4), clamped
# bases, explicit law, frozen coupling, d = 0:
#   DAMAGE=0 cargo run --release --example cylinder_sweep -- 6 24 explicit
CLAMPED_6X24 = {0.80: 12.812760, 1.17: 76.642120, 1.30: 83.532800}


def test_clamped_cylinder_equals_activemuscles_own_solver():
    material = am.Material(law="explicit", coupling="frozen")
    stretches = sorted(CLAMPED_6X24)
    r = cylinder(material, stretches, bases="clamped", nr=6, nz=24)
    expected = np.array([CLAMPED_6X24[s] for s in stretches])
    # The reference is printed to six decimals.
    np.testing.assert_allclose(r["stress"], expected, rtol=0, atol=1.5e-6)


def block_on_symmetry_planes(umat, stretches, n=3):
    """A unit cube of Q1/P0 hexahedra on the planes x = 0, y = 0, z = 0 (normal displacement 0),
    stretched along x: homogeneous uniaxial tension. Nominal stress at each stretch."""
    mesh = fem.Cube(n=n)
    field = fem.FieldsMixed(fem.RegionHexahedron(mesh), n=2)
    solid = fem.SolidBody(Incompressible(umat), field)
    b = {
        "x0": fem.Boundary(field[0], fx=0.0, skip=(0, 1, 1)),
        "y0": fem.Boundary(field[0], fy=0.0, skip=(1, 0, 1)),
        "z0": fem.Boundary(field[0], fz=0.0, skip=(1, 1, 0)),
        "move": fem.Boundary(field[0], fx=1.0, skip=(0, 1, 1)),
    }
    out = []
    for lam in stretches:
        b["move"].value = lam - 1.0
        dof0, dof1 = fem.dof.partition(field, b)
        res = fem.newtonraphson(
            items=[solid], x0=field, dof1=dof1, dof0=dof0,
            ext0=fem.dof.apply(field, b, dof0), tol=1e-11, verbose=0,
        )
        assert res.success
        out.append(fem.tools.force(field, res.fun, b["move"])[0])
    return np.array(out)


@pytest.mark.parametrize("choices", MODELS[1:], ids=lambda c: "-".join(map(str, c.values())))
def test_3d_block_on_symmetry_planes_reproduces_the_homogeneous_curve(choices):
    material = am.Material(**choices)
    stretches = [1.05, 1.1, 1.17]
    got = block_on_symmetry_planes(MuscleMaterial(material), stretches)
    np.testing.assert_allclose(got, material.uniaxial(stretches)["stress"], rtol=1e-9)


class ClosedFormNeoHooke(fem.ConstitutiveMaterial):
    """W = μ/2 (tr C − 3) written out: P = μ F, A_iJkL = μ δ_ik δ_JL."""

    def __init__(self, mu):
        self.mu = mu
        self.x = [np.eye(3), np.zeros(0)]

    def gradient(self, x, *args, out=None, **kwargs):
        return [self.mu * x[0], x[-1]]

    def hessian(self, x, *args, out=None, **kwargs):
        F = x[0]
        eye = np.eye(3)
        A = self.mu * np.einsum("ik,jl->ijkl", eye, eye)
        return [np.broadcast_to(A.reshape(3, 3, 3, 3, *([1] * (F.ndim - 2))), (3, 3, 3, 3, *F.shape[2:]))]


def test_fusiform_neo_hookean_equals_the_closed_form_material():
    # Not felupe's NeoHooke: that one is isochoric, μ/2 (J^(-2/3) tr C − 3), equal to ours only
    # where J = 1, and Q1/P0 enforces J = 1 in each cell's mean only (forces differ by 4 %).
    ours = fusiform(MuscleMaterial(energy="neo-hookean", mu=1.0, law="passive"), 1.2, nx=6, nr=2)
    closed = fusiform(ClosedFormNeoHooke(mu=1.0), 1.2, nx=6, nr=2)
    assert ours["force"] == pytest.approx(closed["force"], rel=1e-10)
    assert ours["force"] > 0.1


def test_fusiform_active_muscle_runs_with_fibres_per_quadrature_point():
    region = fem.RegionHexahedron(spindle(6, 2))
    fibres = generatrix_fibres(region)
    assert fibres.shape == (3, 8, region.mesh.ncells)
    np.testing.assert_allclose(np.linalg.norm(fibres, axis=0), 1.0, rtol=1e-14)
    active = fusiform(MuscleMaterial(law="explicit", fibre=fibres), 1.1, nx=6, nr=2)
    damaged = fusiform(MuscleMaterial(law="explicit", damage=0.5, fibre=fibres), 1.1, nx=6, nr=2)
    passive = fusiform(MuscleMaterial(law="passive", fibre=fibres), 1.1, nx=6, nr=2)
    # Loss of activation lowers the force, towards the passive muscle's.
    assert active["force"] > damaged["force"] > passive["force"] > 0.0


def test_umat_interface_shapes():
    umat = MuscleMaterial(law="explicit")
    F = np.broadcast_to(np.eye(3)[:, :, None, None], (3, 3, 4, 7)).copy()
    F[0, 0] = 1.1
    P, gamma = umat.gradient([F, np.zeros((1, 4, 7))])
    (A,) = umat.hessian([F, np.zeros((1, 4, 7))])
    assert P.shape == (3, 3, 4, 7) and gamma.shape == (1, 4, 7) and A.shape == (3, 3, 3, 3, 4, 7)
    assert np.all((gamma > 0) & (gamma < 1))


def test_the_fusiform_example_runs_every_model_it_lists(capsys):
    """The documented command (`python -m activemuscle.examples.felupe_fusiform 1.1`) on a small
    mesh: every model converges and is printed, and the exit status is 0 (it used to crash on the
    energy-consistent model, which felupe's Newton without line search cannot run here)."""
    from activemuscle.examples.felupe_fusiform import main

    assert main(["felupe_fusiform", "1.1", "6", "2"]) == 0
    rows = [l.split() for l in capsys.readouterr().out.splitlines() if not l.startswith("#")]
    assert [r[0] for r in rows[1:]] == [
        "passive", "explicit-frozen", "explicit-frozen-d0.5", "energy-frozen"
    ]
    assert all(float(r[1]) > 0.0 for r in rows[1:])
