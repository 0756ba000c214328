"""The boundary conditions of a body stretched between its ends x = 0 and x = L, and the end's
area.

The end x = L is moved along x by (λ − 1) L; the lateral surface is traction free.

- "clamped": u = 0 on x = 0, u_y = u_z = 0 on x = L (the chapter's prescribed displacement of
  the bases; the fusiform muscle glued to its tendons);
- "sliding": u_x = 0 on x = 0 and u_x moved on x = L, u_y, u_z free there; the rigid motions
  left are removed at two vertices of x = 0 (u_y = u_z = 0 on the axis, u_z = 0 where the
  y-axis meets the rim), which the homogeneous uniaxial solution satisfies: a prism in sliding
  tension is in that homogeneous state, and the FE solution must equal the 0D curve.

With `symmetry` the body is the part y, z ≥ 0 of a body symmetric about the planes y = 0 and
z = 0 (a quarter cylinder): u_y = 0 on y = 0 and u_z = 0 on z = 0, and no vertex is pinned.
With `half` the far end x = L is the mid-plane of a body twice as long, symmetric about it: it
is moved along x and free to slide (the whole body's ends then move apart by 2 (λ − 1) L).

Dofs are found topologically (those of the facets, or vertices, whose every vertex lies on the
plane or point): `dolfinx.mesh.locate_entities(_boundary)` and `fem.locate_dofs_topological`,
DOLFINx 0.5 (kept in later versions).
"""

import numpy as np
import ufl
from dolfinx import fem, mesh as dmesh

BASES = ("clamped", "sliding")


def _on_plane(length):
    return lambda x: np.isclose(x[0], length)


def ends(body, length, bases="clamped", radius=1.0, symmetry=False, half=False):
    """(fixed, moved) for body.Newton: lists of (subspace of body.W, dofs). `radius`: the
    radius of the end x = 0 (sliding only: where its rim meets the y-axis); `symmetry`: the
    planes y = 0 and z = 0 are symmetry planes; `half`: x = length is a symmetry plane."""
    if bases not in BASES:
        raise ValueError(f"bases = {bases!r}: must be one of {BASES}")
    mesh, W = body.mesh, body.W
    fdim = mesh.topology.dim - 1
    near, far = (dmesh.locate_entities_boundary(mesh, fdim, _on_plane(x)) for x in (0.0, length))
    u = [W.sub(0).sub(c) for c in range(3)]

    def on(c, dim, entities):
        return u[c], fem.locate_dofs_topological(u[c], dim, entities)

    moved = [on(0, fdim, far)]
    planes = []
    if symmetry:
        planes = [on(c, fdim, dmesh.locate_entities_boundary(mesh, fdim, lambda x, c=c: np.isclose(x[c], 0.0)))
                  for c in (1, 2)]
    if bases == "clamped":
        far_held = [] if half else [on(c, fdim, far) for c in (1, 2)]
        return [on(c, fdim, near) for c in range(3)] + far_held + planes, moved
    if symmetry:
        return [on(0, fdim, near)] + planes, moved

    def vertex(y):
        return dmesh.locate_entities(
            mesh, 0, lambda x: np.isclose(x[0], 0.0) & np.isclose(x[1], y) & np.isclose(x[2], 0.0))

    axis, rim = vertex(0.0), vertex(radius)
    return [on(0, fdim, near), on(1, 0, axis), on(2, 0, axis), on(2, 0, rim)], moved


def end_area(mesh, length):
    """The area of the end x = length, ∫ 1 dA over its facets (the polygon the mesh has, on every
    process)."""
    fdim = mesh.topology.dim - 1
    facets = dmesh.locate_entities_boundary(mesh, fdim, _on_plane(length))
    tags = dmesh.meshtags(mesh, fdim, np.sort(facets).astype(np.int32), np.ones(len(facets), dtype=np.int32))
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
    local = fem.assemble_scalar(fem.form(1.0 * ds(1)))
    return mesh.comm.allreduce(local)
