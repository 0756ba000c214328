"""A muscle body on a tetrahedral DOLFINx mesh: the mixed u–p weak form of activemuscle's own
(axisymmetric) solver, in 3D.

Taylor–Hood P2/P1: continuous quadratic displacement u, continuous linear pressure p, test
functions (v, q). With P = ∂Ŵ/∂F from activemuscle at the quadrature points, J = det F and
cof F = J F⁻ᵀ = ∂J/∂F:

exact incompressibility (the chapter's; Π = ∫ [Ŵ(F) − p (J − 1)] dX):

    R(u, p; v, q) = ∫ (P − p cof F) : ∇v dX − ∫ q (J − 1) dX,

near incompressibility with a volumetric energy U(J) (a scene's `[incompressibility]`), the
perturbed Lagrangian Π = ∫ [Ŵ(F) − p (J − 1) − Φ(p)] dX, Φ the Legendre transform of U, whose
stationarity in p gives back ∫ [Ŵ + U(J)] dX (J̃(p) = (U′)⁻¹(−p), Φ′ = 1 − J̃, Φ″ = 1/U″(J̃)):

    R(u, p; v, q) = ∫ (P − p cof F) : ∇v dX − ∫ q (J − J̃(p)) dX.

The linearisation (dR in the direction (δu, δp)): A : ∇δu tested with ∇v, A = ∂P/∂F exact
from activemuscle, and UFL's derivative of the pressure terms −p cof F : ∇v − q J; near
incompressibility adds −∫ q δp / U″(J̃) dX. p is the hydrostatic pressure (as activemuscle's
solver reports it; felupe's and the legacy route's p is its negative).

Written against DOLFINx 0.5 (`fem.FunctionSpace(mesh, ufl.MixedElement(...))`; 0.7+ spells it
`fem.functionspace(mesh, basix.ufl.mixed_element([...]))`).
"""

import numpy as np
import ufl
from dolfinx import fem

from .quadrature import QuadratureMaterial


def taylor_hood(mesh):
    """The P2/P1 space of (u, p) on a tetrahedral mesh."""
    cell = mesh.ufl_cell()
    return fem.FunctionSpace(
        mesh, ufl.MixedElement([ufl.VectorElement("P", cell, 2), ufl.FiniteElement("P", cell, 1)])
    )


class MuscleBody:
    """The state w = (u, p), activemuscle's material at the quadrature points and the weak
    forms on `mesh`.

    material: an activemuscle.Material; fibre: a vector (3,) or a function of reference points
    X (3, n) → unit fibres (3, n); volumetric: an activemuscle.Volumetric for near
    incompressibility (None: exact, J = 1); degree: the quadrature degree (2: Basix's 4-point
    rule on a tetrahedron, exact for the P2 mass terms); parallel: the material on rayon's
    threads within each process.
    """

    def __init__(self, mesh, material, fibre=(1.0, 0.0, 0.0), volumetric=None, degree=2,
                 parallel=False):
        self.mesh, self.volumetric = mesh, volumetric
        self.W = taylor_hood(mesh)
        self.w = fem.Function(self.W)
        w, dw = self.w, ufl.TrialFunction(self.W)
        u, p = ufl.split(w)
        v, q = ufl.split(ufl.TestFunction(self.W))
        du, dp = ufl.split(dw)
        self.material = QuadratureMaterial(material, mesh, u, degree, fibre, pressure=p,
                                           volumetric=volumetric, parallel=parallel)
        m, dx = self.material, self.material.dx
        F = ufl.Identity(3) + ufl.grad(u)
        J = ufl.det(F)
        cof = J * ufl.inv(F).T
        volume_ratio = 1 if volumetric is None else m.volume_ratio()
        self.residual = (ufl.inner(m.stress() - p * cof, ufl.grad(v)) - q * (J - volume_ratio)) * dx
        constraint = (-p * ufl.inner(cof, ufl.grad(v)) - q * J) * dx
        self.jacobian = ufl.inner(m.tangent_action(ufl.grad(du)), ufl.grad(v)) * dx
        self.jacobian += ufl.derivative(constraint, w, dw)
        if volumetric is not None:
            self.jacobian -= q * m.compliance() * dp * dx
        self._energy_form = None
        self.reset()

    def reset(self):
        """The undeformed body at rest, u = 0 and p = p₀.

        Exact incompressibility: p₀ = P₂₂(I), the material's lateral stress at F = I with the
        fibre along e₁ (the same for any fibre: at F = I, P depends on m only through its
        frame), so that the lateral faces of a uniaxial state are traction free: for a uniform
        fibre field with clamped ends that is the solution at λ = 1, and it is the pressure
        with which an activated consistent model's tangent, A + p G:Gᵀ on isochoric G, is
        positive at rest where A alone is not (the energy law's).

        Near incompressibility: p₀ = −U′(1), at which J̃(p₀) = 1 = J(u = 0) (activemuscle's
        axisymmetric solver's start): from any other pressure the first step must make up the
        volume J − J̃(p₀) at once, which its Newton does not survive for active models."""
        if self.volumetric is not None:
            p0 = self.volumetric.reference_pressure
        else:
            rest = self.material.material.evaluate(np.eye(3)[None], [1.0, 0.0, 0.0], order="stress",
                                                    layout="leading")
            p0 = float(rest["stress"][0, 1, 1])
        self.w.x.array[:] = 0.0
        self.w.sub(1).interpolate(lambda x: np.full(x.shape[1], p0))
        self.w.x.scatter_forward()

    def stored_energy(self):
        """∫ Ŵ(F) dX at w over the whole body (every process), the material's energy without
        a volumetric energy's; raises the material's error where it cannot be evaluated."""
        if self._energy_form is None:
            self._energy_form = fem.form(self.material.energy() * self.material.dx)
        self.material.update(tangent=False)
        return self.mesh.comm.allreduce(fem.assemble_scalar(self._energy_form))

    @property
    def dofs(self):
        """Unknowns in all, over every process."""
        return self.W.dofmap.index_map.size_global * self.W.dofmap.index_map_bs
