"""activemuscle materials for felupe (https://github.com/adtzlr/felupe).

felupe calls a constitutive material ("umat") with x = [F, ..., statevars], F of shape
(3, 3, q, c) (quadrature points q, cells c: felupe's trailing axes); ``gradient(x)`` returns the
gradients and the new state variables, ``hessian(x)`` the upper-triangle blocks of the Hessian.

- :class:`MuscleMaterial`: x = [F, statevars] → [P, γ] and [A], A[i, j, k, l] = ∂P_ij/∂F_kl exact
  (not major-symmetric for the chapter's frozen coupling: felupe assembles the full A, so its
  Newton iterations converge quadratically). The state variable is γ (output only).
- :class:`Incompressible`: the chapter's exact incompressibility with a pressure field p, for
  fields (u, p) (e.g. :func:`taylor_hood`), Π(F, p) = Ŵ(F) + p (J − 1) in felupe's sign convention
  (p is minus the hydrostatic pressure of activemuscle's own solver):

      ∂Π/∂F = P + p J F⁻ᵀ,                ∂Π/∂p = J − 1,
      ∂²Π/∂F∂F = A + p J (F⁻ᵀ ⊗ F⁻ᵀ − F⁻ᵀ ⊙ᵢₗ F⁻ᵀ),   ∂²Π/∂F∂p = J F⁻ᵀ,   ∂²Π/∂p² = 0.
"""

import felupe as fem
import numpy as np
from felupe.math import cdya_il, det, dya, inv, transpose

from ._native import Material


class MuscleMaterial(fem.ConstitutiveMaterial):
    """Active muscle as a felupe material: ``gradient([F, statevars])`` → [P, γ],
    ``hessian([F, statevars])`` → [A].

    Parameters
    ----------
    material : activemuscle.Material, optional
        The material; or give its keyword choices (``law="explicit"``, ``damage=0.2``, ...).
    fibre : array_like
        Reference fibre direction: one vector (3,) or one per quadrature point, (3, q, c).
        In felupe's axisymmetric fields the axis is the first coordinate: (1, 0, 0).
    parallel : bool
        Evaluate large batches on all cores (rayon, GIL released).
    """

    def __init__(self, material=None, fibre=(1.0, 0.0, 0.0), parallel=True, **choices):
        if material is not None and choices:
            raise TypeError("give a Material or its keyword choices, not both")
        self.material = material if material is not None else Material(**choices)
        self.fibre = np.asarray(fibre, dtype=float)
        self.threads = parallel
        # felupe reads the state variables' shape from here (γ, one per point).
        self.x = [np.eye(3), np.zeros(1)]

    def _evaluate(self, F, order):
        return self.material.evaluate(
            F, self.fibre, order=order, layout="trailing", parallel=self.threads
        )

    def gradient(self, x, *args, out=None, **kwargs):
        r = self._evaluate(x[0], "stress")
        return [r["stress"], r["gamma"][None, ...]]

    def hessian(self, x, *args, out=None, **kwargs):
        return [self._evaluate(x[0], "tangent")["tangent"]]


class Incompressible(fem.ConstitutiveMaterial):
    """Exact incompressibility J = 1 by a pressure field: x = [F, p, statevars] (see the module
    docs for the equations). ``material`` is a :class:`MuscleMaterial` (or any felupe material
    whose state variables come last)."""

    def __init__(self, material):
        self.material = material
        self.x = [material.x[0], np.zeros(1), material.x[-1]]

    def gradient(self, x, *args, out=None, **kwargs):
        F, p, statevars = x[0], x[1], x[-1]
        P, statevars_new = self.material.gradient([F, statevars])
        J = det(F)
        return [P + p * J * transpose(inv(F, determinant=J)), J - 1.0, statevars_new]

    def hessian(self, x, *args, out=None, **kwargs):
        F, p, statevars = x[0], x[1], x[-1]
        (A,) = self.material.hessian([F, statevars])
        J = det(F)
        iFT = transpose(inv(F, determinant=J))
        return [A + p * J * (dya(iFT, iFT) - cdya_il(iFT, iFT)), J * iFT, None]


def taylor_hood(mesh_q1, axisymmetric=False):
    """Fields (u, p) of the Taylor–Hood pair Q2/Q1 on a quadrilateral mesh (continuous biquadratic
    displacement on the nine-node cells, continuous bilinear pressure on the corners, 3 × 3
    Gauss): the element of activemuscle's own axisymmetric solver. Returns (region, fields)."""
    mesh_q2 = mesh_q1.add_midpoints_edges().add_midpoints_faces()
    region = fem.RegionBiQuadraticQuad(mesh_q2)
    u = (fem.FieldAxisymmetric if axisymmetric else fem.Field)(region, dim=2)
    p = fem.FieldDual(region, mesh=mesh_q1)
    return region, fem.FieldContainer([u, p])
