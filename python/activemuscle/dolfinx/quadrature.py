"""activemuscle's material at the quadrature points of a DOLFINx mesh.

The nominal stress P = ∂Ŵ/∂F and the exact tangent A = ∂P/∂F (A[i, j, k, l] = ∂P_ij/∂F_kl, not
major-symmetric for the chapter's frozen coupling) live in quadrature spaces: one value per
quadrature point, no interpolation, no continuity. Each process evaluates F = I + ∇u at the
quadrature points of the cells it owns (a compiled `dolfinx.fem.Expression`), hands the batch to
`Material.evaluate` and writes P and A into those spaces for its own cells: a material point
needs only its own F, so this step communicates nothing. The weak forms then read P as a 3 × 3
matrix and A through its action A : G on a matrix G.

Near incompressibility (a scene's `[incompressibility]` with a volumetric energy U(J)) adds two
scalar fields at the same points, the volume ratio J̃(p) = (U′)⁻¹(−p) and the compliance
1/U″(J̃) at the interpolated pressure p (`Volumetric.dilatation`): the perturbed Lagrangian of
activemuscle's own solver (see activemuscle.dolfinx.body).

Written against DOLFINx 0.5 / FFCx 0.5 / UFL 2022.2: quadrature elements as
`ufl.VectorElement("Quadrature", cell, degree, dim=d, quad_scheme="default")` (0.5's Basix
wrapper takes no rank-4 tensor element, so P and A are flat: 9 and 81 entries, row-major), the
points of Basix's default rule of that degree, which FFCx uses for both the element and the
measure `dx(metadata={"quadrature_degree": degree})`. In DOLFINx 0.7+ the element is
`basix.ufl.quadrature_element(cell, value_shape=(d,), degree=degree)`; the rest (Expression,
Function.x.array, the dofmap) is unchanged.
"""

import basix
import numpy as np
import ufl
from dolfinx import fem

# The Python exceptions of Material.evaluate and Volumetric.dilatation for a point they cannot
# evaluate (det F ≤ 0, an overflow, no root): a trial state the solver must reject.
MATERIAL_ERRORS = (ValueError, ArithmeticError)


def quadrature_points(mesh, degree):
    """The reference points of Basix's default rule of `degree` on the mesh's cell."""
    cell = basix.cell.string_to_type(mesh.topology.cell_name())
    return basix.make_quadrature(cell, degree)[0]


def quadrature_space(mesh, degree, size):
    """A space of `size` values per quadrature point (the rule of `degree`)."""
    element = ufl.VectorElement("Quadrature", mesh.ufl_cell(), degree, dim=size, quad_scheme="default")
    return fem.FunctionSpace(mesh, element)


def as_matrix(flat):
    """The 3 × 3 matrix of a 9-entry field (row-major)."""
    return ufl.as_matrix([[flat[3 * i + j] for j in range(3)] for i in range(3)])


def tangent_action(flat, G):
    """A : G, (A : G)_ij = A_ijkl G_kl, of an 81-entry field A (row-major in ij, then kl)."""
    return ufl.as_matrix(
        [[sum(flat[27 * i + 9 * j + 3 * k + l] * G[k, l] for k in range(3) for l in range(3))
          for j in range(3)] for i in range(3)]
    )


class PointValues:
    """Values at the quadrature points of the owned cells of one quadrature space: `view`
    (owned points, size) in the point order of `Expression.eval`, and `store` into the Function.
    Where the space numbers its dofs cell by cell, point by point (as DOLFINx does for quadrature
    spaces without ghost cells), `view` is the Function's own memory and `store` does nothing."""

    def __init__(self, space, cells, points_per_cell):
        self.function = fem.Function(space)
        size = space.dofmap.index_map_bs
        dofs = space.dofmap.list.array.reshape(-1, points_per_cell)[cells].ravel()
        array = self.function.x.array.reshape(-1, size)
        if np.array_equal(dofs, np.arange(dofs.size)):
            self.view, self._dofs = array[: dofs.size], None
        else:
            self.view, self._dofs = np.empty((dofs.size, size)), dofs
        self._array = array

    def store(self):
        if self._dofs is not None:
            self._array[self._dofs] = self.view


class QuadratureMaterial:
    """P, A, Ŵ (and, near incompressibility, J̃ and 1/U″) at the quadrature points of the
    owned cells, from a `Material` (and a `Volumetric`).

    u: the displacement (a Function or a component of one, e.g. `ufl.split(w)[0]`) on `mesh`;
    fibre: one vector (3,), or a function of the reference points X (3, n) returning unit
    fibres (3, n), evaluated once at the quadrature points; pressure, volumetric: the pressure
    (UFL) and a `Volumetric` for the nearly incompressible forms; parallel: let the material
    use rayon's threads (off: under MPI each process has its core).
    """

    def __init__(self, material, mesh, u, degree, fibre=(1.0, 0.0, 0.0), pressure=None,
                 volumetric=None, parallel=False):
        self.material, self.volumetric, self.parallel = material, volumetric, parallel
        self.dx = ufl.dx(domain=mesh, metadata={"quadrature_degree": degree})
        points = quadrature_points(mesh, degree)
        npts = len(points)
        self.cells = np.arange(mesh.topology.index_map(mesh.topology.dim).size_local, dtype=np.int32)
        self.count = self.cells.size * npts

        def field(size):
            return PointValues(quadrature_space(mesh, degree, size), self.cells, npts)

        self._stress, self._tangent, self._energy = field(9), field(81), field(1)
        self._F = fem.Expression(ufl.Identity(3) + ufl.grad(u), points)
        self._F_values = np.empty((self.cells.size, npts * 9))
        if callable(fibre):
            X = fem.Expression(ufl.SpatialCoordinate(mesh), points).eval(self.cells)
            self.fibre = np.ascontiguousarray(np.asarray(fibre(X.reshape(-1, 3).T)).T)
        else:
            self.fibre = np.asarray(fibre, dtype=float)
        if volumetric is not None:
            self._volume_ratio, self._compliance = field(1), field(1)
            self._p = fem.Expression(pressure, points)
            self._p_values = np.empty((self.cells.size, npts))

    def stress(self):
        """P as a UFL 3 × 3 matrix."""
        return as_matrix(self._stress.function)

    def tangent_action(self, G):
        """A : G as a UFL 3 × 3 matrix."""
        return tangent_action(self._tangent.function, G)

    def energy(self):
        """Ŵ at the points (UFL): the stored energy density of the last update."""
        return self._energy.function[0]

    def volume_ratio(self):
        """J̃(p) at the points (UFL), near incompressibility only."""
        return self._volume_ratio.function[0]

    def compliance(self):
        """1/U″(J̃(p)) at the points (UFL), near incompressibility only."""
        return self._compliance.function[0]

    def deformation_gradients(self):
        """F at the owned points, (n, 3, 3)."""
        self._F.eval(self.cells, self._F_values)
        return self._F_values.reshape(-1, 3, 3)

    def update(self, tangent=True):
        """Evaluates the material at the current displacement (P and Ŵ, and A when `tangent`) and the
        volumetric fields at the current pressure. Raises MATERIAL_ERRORS for a point the
        material cannot evaluate (the message names it)."""
        out = {"stress": self._stress.view.reshape(-1, 3, 3), "energy": self._energy.view.reshape(-1)}
        if tangent:
            out["tangent"] = self._tangent.view.reshape(-1, 3, 3, 3, 3)
        self.material.evaluate(self.deformation_gradients(), self.fibre,
                               order="tangent" if tangent else "stress", layout="leading",
                               parallel=self.parallel, out=out)
        self._stress.store()
        self._energy.store()
        if tangent:
            self._tangent.store()
        if self.volumetric is not None:
            self._p.eval(self.cells, self._p_values)
            r = self.volumetric.dilatation(self._p_values.ravel())
            self._volume_ratio.view[:, 0] = r["volume_ratio"]
            self._compliance.view[:, 0] = r["compliance"]
            self._volume_ratio.store()
            self._compliance.store()
