"""Checks of activemuscle.dolfinx on the fusiform spindle that need DOLFINx in the process (run
by tests/test_dolfinx.py with Debian's python3, under mpirun or not):

`ufl`: the spindle solved twice, once by activemuscle.dolfinx (P and A from activemuscle at
the quadrature points, per-point generatrix fibres), once with the energy written in UFL and
differentiated by UFL (P = ∂Ŵ/∂F by `ufl.diff`, the Jacobian by `ufl.derivative`), the fibres a
UFL expression of the reference coordinates; the same mesh, element, quadrature, conditions and
Newton, so the two forces must agree to the solver's tolerance. The energies: the chapter's
passive energy (eq. (1), Table 1) and the neo-Hookean μ/2 (tr C − 3), each with active strain at
a held activation γ (F_a = I − γ M, Ŵ = (1 − γ) W(F_a⁻ᵀ C F_a⁻¹)). Prints
`<energy> activemuscle <force> ufl <force>`.

`work`: the spindle stretched from λ = 1 to 1.1 in eight equal steps; the work of the end force,
∫ f dδ by Simpson's rule over the nine states (and over every other state: the rule's error is
a fifteenth of their difference), against the change of the stored energy ∫ Ŵ dX. Equal (to
the rule's error) for a hyperelastic model, the consistent coupling; not for the frozen one,
whose P is no gradient. Prints `<model> work <W> work_2h <W with steps 2h> energy <ΔE>`.

    mpirun -n 2 /usr/bin/python3 tests/dolfinx_checks.py ufl|work
"""

import sys

import numpy as np
import ufl
from mpi4py import MPI

import activemuscle as am
from activemuscle.dolfinx import MuscleBody, Newton, ends, meshes, sweep

LENGTH, BELLY, TENDON = 4.0, 1.0, 0.4
MU, ALPHA, W0 = 0.1599, 19.35, 0.7335


def generatrix(X):
    """The generatrix fibre of meshes.generatrix_fibres as a UFL expression of X."""
    s = np.pi / LENGTH
    r = TENDON + (BELLY - TENDON) * ufl.sin(s * X[0])
    dr = (BELLY - TENDON) * s * ufl.cos(s * X[0])
    m = ufl.as_vector([1.0, X[1] * dr / r, X[2] * dr / r])
    return m / ufl.sqrt(ufl.dot(m, m))


def active_strain(passive, gamma):
    """Ŵ(F) = (1 − γ) W(C_e), C_e = F_e^T F_e, F_e = F F_a⁻¹, F_a = I − γ M (γ held)."""
    def energy(F, m):
        M = ufl.outer(m, m)
        Fe = F * (ufl.Identity(3) + gamma / (1 - gamma) * M)  # F (I − γM)⁻¹
        return (1 - gamma) * passive(Fe.T * Fe, M)
    return energy


def chapter(C, M):
    """The chapter's eq. (1): μ/4 [(e^{α(I_p − 1)} − 1)/α + K_p − 1]."""
    Ci = ufl.inv(C)
    i_p = W0 / 3 * ufl.tr(C) + (1 - W0) * ufl.inner(C, M)
    k_p = W0 / 3 * ufl.tr(Ci) + (1 - W0) * ufl.inner(Ci, M)
    return MU / 4 * ((ufl.exp(ALPHA * (i_p - 1)) - 1) / ALPHA + k_p - 1)


def neo_hooke(C, M):
    """μ/2 (tr C − 3)."""
    return MU / 2 * (ufl.tr(C) - 3)


class UflMaterial:
    """Stands in for QuadratureMaterial: P from UFL; update() does nothing (`material` gives
    MuscleBody.reset its pressure at rest)."""

    def __init__(self, body, energy):
        self.material = body.material.material
        u = ufl.split(body.w)[0]
        F = ufl.variable(ufl.Identity(3) + ufl.grad(u))
        self.P = ufl.diff(energy(F, generatrix(ufl.SpatialCoordinate(body.mesh))), F)

    def update(self, tangent=True):
        pass


def ufl_body(mesh, material, energy):
    """A MuscleBody whose stress is UFL's and whose Jacobian is UFL's derivative of the
    residual (the quadrature fields stay unused)."""
    body = MuscleBody(mesh, material, meshes_fibres)
    reference = UflMaterial(body, energy)
    dx = body.material.dx
    v, q = ufl.split(ufl.TestFunction(body.W))
    u, p = ufl.split(body.w)
    F = ufl.Identity(3) + ufl.grad(u)
    J = ufl.det(F)
    body.residual = (ufl.inner(reference.P - p * J * ufl.inv(F).T, ufl.grad(v)) - q * (J - 1)) * dx
    body.jacobian = ufl.derivative(body.residual, body.w, ufl.TrialFunction(body.W))
    body.material = reference
    return body


def meshes_fibres(X):
    return meshes.generatrix_fibres(X, LENGTH, BELLY, TENDON)


def force(body, stretch):
    newton = Newton(body, *ends(body, LENGTH, "clamped"))
    out = {}
    sweep(newton, [stretch], LENGTH, lambda lam, f, _: out.update({lam: f}))
    if stretch not in out:
        raise RuntimeError(f"stretch {stretch} not reached: {newton.error}")
    return out[stretch]


def ufl_check(mesh, gamma=0.1, stretch=1.1):
    for name, material, energy in [
        ("giantesio-musesti", am.Material(law="constant", gamma=gamma), active_strain(chapter, gamma)),
        ("neo-hookean", am.Material(energy="neo-hookean", mu=MU, law="constant", gamma=gamma),
         active_strain(neo_hooke, gamma)),
    ]:
        ours = force(MuscleBody(mesh, material, meshes_fibres), stretch)
        theirs = force(ufl_body(mesh, material, energy), stretch)
        say(f"{name} activemuscle {ours:.15g} ufl {theirs:.15g}")


def simpson(f, h):
    """∫ over equal steps h of the values f (an even number of steps)."""
    return h / 3 * (f[0] + f[-1] + 4 * f[1:-1:2].sum() + 2 * f[2:-1:2].sum())


def work_check(mesh, steps=8, stretch=1.1):
    path = [1.0 + (stretch - 1.0) * k / steps for k in range(steps + 1)]
    for name, choices in [("energy-consistent", dict(law="energy", coupling="consistent")),
                          ("explicit-frozen", dict(law="explicit", coupling="frozen"))]:
        body = MuscleBody(mesh, am.Material(**choices), meshes_fibres)
        newton = Newton(body, *ends(body, LENGTH, "clamped"))
        states = {}
        sweep(newton, path, LENGTH, lambda lam, f, _: states.update({lam: (f, body.stored_energy())}))
        if len(states) != len(path):
            raise RuntimeError(f"{name}: not every stretch reached ({newton.error})")
        f = np.array([states[lam][0] for lam in path])
        h = (stretch - 1.0) * LENGTH / steps  # the end's displacement per step
        say(f"{name} work {simpson(f, h):.12g} work_2h {simpson(f[::2], 2 * h):.12g} "
            f"energy {states[path[-1]][1] - states[path[0]][1]:.12g}")


def say(line):
    if MPI.COMM_WORLD.rank == 0:
        print(line, flush=True)


def main(argv):
    mesh = meshes.spindle(2, 6, LENGTH, BELLY, TENDON)
    {"ufl": ufl_check, "work": work_check}[argv[1]](mesh)


if __name__ == "__main__":
    main(sys.argv)
