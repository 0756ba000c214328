"""Tetrahedral meshes of the muscle shapes: the chapter's cylinder and the fusiform spindle.

Both are a disc triangulation extruded along the axis x (the fibre direction; a scene's default
fibre is (1, 0, 0)): rings of radius k R/n (k = 1 … n) with 6k nodes each around a centre node,
the 6 n² near-equilateral triangles between neighbouring rings (a quarter disc, y, z ≥ 0, for
a model on two symmetry planes: 4k nodes a ring, n² triangles in the quadrant), and n_x layers in x, uniform or
refined towards both ends like activemuscle's axisymmetric mesh (middle/end layer height
`grading`). Each prism is split into three tetrahedra by the order of its vertices' global
numbers (for bottom vertices a < b < c: (a, b, c, a′), (b, c, a′, b′), (c, a′, b′, c′)), so the
quadrilateral face between two prisms gets the same diagonal from both sides.

The spindle scales the disc at x by r(x)/R, r(x) = r_t + (r_b − r_t) sin(π x / L) (the shape of
examples/felupe_fusiform.py). The mesh is built on rank 0 and distributed by DOLFINx's
partitioner; ghost_mode none: each process owns the cells it assembles and no others.

Written against DOLFINx 0.5 (`dolfinx.mesh.create_mesh` with a UFL domain; in 0.7+ the domain
is `basix.ufl.element("Lagrange", "tetrahedron", 1, shape=(3,))`).
"""

import math

import numpy as np
import ufl
from dolfinx import mesh as dmesh
from mpi4py import MPI


def axial_breaks(length, nx, grading=1.0):
    """Layer boundaries on [0, length]: uniform for grading 1, otherwise heights growing
    geometrically from both ends to the middle, middle/end height = grading (activemuscle's
    axisymmetric `Mesh::structured`, in its z)."""
    if nx < 1 or not (math.isfinite(grading) and grading >= 1.0):
        raise ValueError(f"nx = {nx}, grading = {grading}: need nx ≥ 1 and a finite grading ≥ 1")
    half = (nx + 1) // 2
    q = grading ** (1.0 / (half - 1)) if half > 1 else 1.0
    heights = np.array([q ** min(i, nx - 1 - i) for i in range(nx)])
    breaks = np.concatenate([[0.0], np.cumsum(heights)]) * (length / heights.sum())
    breaks[-1] = length
    return breaks


def _zip_rings(inner, outer):
    """Triangles between two closed rings of node numbers, each ordered by angle from 0: advance
    on the ring whose next node comes first in angle."""
    ni, no = len(inner), len(outer)
    triangles, i, o = [], 0, 0
    while i < ni or o < no:
        next_outer = (o + 1) / no
        next_inner = (i + 1) / ni
        if o < no and (i == ni or next_outer <= next_inner + 1e-12):
            triangles.append((inner[i % ni], outer[o], outer[(o + 1) % no]))
            o += 1
        else:
            triangles.append((inner[i], outer[o % no], inner[(i + 1) % ni]))
            i += 1
    return triangles


def disc(rings, radius=1.0, quarter=False):
    """A disc of `rings` rings: points (N, 2) and triangles (6 rings², 3); with `quarter`, the
    quadrant y, z ≥ 0 of the disc of 4k-node rings (rings² triangles)."""
    if rings < 1:
        raise ValueError(f"rings = {rings}: need at least one ring")
    sectors = 4 if quarter else 6
    points, triangles, previous = [(0.0, 0.0)], [], [0]
    for k in range(1, rings + 1):
        angles = 2 * np.pi * np.arange(sectors * k) / (sectors * k)
        start = len(points)
        points += [(radius * k / rings * math.cos(a), radius * k / rings * math.sin(a)) for a in angles]
        ring = list(range(start, start + sectors * k))
        if k == 1:
            triangles += [(0, ring[j], ring[(j + 1) % sectors]) for j in range(sectors)]
        else:
            triangles += _zip_rings(previous, ring)
        previous = ring
    points, triangles = np.array(points), np.array(triangles, dtype=np.int64)
    if not quarter:
        return points, triangles
    centroids = points[triangles].mean(axis=1)
    triangles = triangles[(centroids[:, 0] > 0) & (centroids[:, 1] > 0)]
    used, triangles = np.unique(triangles, return_inverse=True)
    return points[used], triangles.reshape(-1, 3)


def extrude(points, triangles, breaks):
    """Vertices (N (n_x + 1), 3) and tetrahedra of the prisms of a triangulation over the layers
    `breaks` along x (vertex of disc point d in layer j: j N + d)."""
    n = len(points)
    x = np.column_stack([np.repeat(breaks, n), np.tile(points, (len(breaks), 1))])
    t = np.sort(triangles, axis=1)  # a < b < c: the split rule of the module docs
    a, b, c = t.T
    cells = []
    for j in range(len(breaks) - 1):
        lo, hi = j * n, (j + 1) * n
        cells += [
            np.column_stack([a + lo, b + lo, c + lo, a + hi]),
            np.column_stack([b + lo, c + lo, a + hi, b + hi]),
            np.column_stack([c + lo, a + hi, b + hi, c + hi]),
        ]
    return x, np.concatenate(cells)


def distribute(comm, x, cells):
    """The DOLFINx mesh of (x, cells) given on rank 0, partitioned over `comm`, no ghost cells."""
    domain = ufl.Mesh(ufl.VectorElement("Lagrange", ufl.tetrahedron, 1))
    if comm.rank != 0:
        x, cells = np.empty((0, 3)), np.empty((0, 4), dtype=np.int64)
    return dmesh.create_mesh(comm, cells, x, domain, ghost_mode=dmesh.GhostMode.none)


def cylinder(rings, nx, radius=1.0, length=4.0, grading=1.0, quarter=False, half=False,
             comm=MPI.COMM_WORLD):
    """The cylinder 0 ≤ x ≤ length, y² + z² ≤ radius² (the chapter's R = 1, L = 4); with
    `quarter`, its part y, z ≥ 0; with `half`, its part x ≤ length/2 (the first nx/2 layers:
    nx must be even)."""
    if half and nx % 2:
        raise ValueError(f"nx = {nx}: a half cylinder takes the first half of an even number of layers")
    breaks = axial_breaks(length, nx, grading)
    points, triangles = disc(rings, radius, quarter)
    return distribute(comm, *extrude(points, triangles, breaks[: nx // 2 + 1] if half else breaks))


def spindle_radius(x, length=4.0, belly=1.0, tendon=0.4):
    """r(x) = tendon + (belly − tendon) sin(π x / L) and its derivative r′(x)."""
    s = np.pi / length
    return tendon + (belly - tendon) * np.sin(s * x), (belly - tendon) * s * np.cos(s * x)


def spindle(rings, nx, length=4.0, belly=1.0, tendon=0.4, grading=1.0, comm=MPI.COMM_WORLD):
    """The fusiform spindle of examples/felupe_fusiform.py: the unit-disc cylinder with its
    cross-section at x scaled to the radius r(x)."""
    points, triangles = disc(rings, 1.0)
    x, cells = extrude(points, triangles, axial_breaks(length, nx, grading))
    x[:, 1:] *= spindle_radius(x[:, 0], length, belly, tendon)[0][:, None]
    return distribute(comm, x, cells)


def generatrix_fibres(X, length=4.0, belly=1.0, tendon=0.4):
    """Unit fibres (3, n) along the spindle's generatrices at reference points X (3, n):
    the curves (x, a r(x), b r(x)) have tangent m ∝ (1, y r′/r, z r′/r)."""
    r, dr = spindle_radius(X[0], length, belly, tendon)
    m = np.stack([np.ones_like(X[0]), X[1] * dr / r, X[2] * dr / r])
    return m / np.linalg.norm(m, axis=0)
