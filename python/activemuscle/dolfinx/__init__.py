"""activemuscle in DOLFINx, under MPI: the route for geometries the axisymmetric solver cannot
mesh and for meshes larger than one machine (docs/distributed.md).

activemuscle's nominal stress and exact tangent enter the weak form at the quadrature points of
a tetrahedral mesh (each process fills them for its own cells from the batched
`Material.evaluate`); Taylor–Hood P2/P1 with exact incompressibility, or near
incompressibility with a scene's volumetric energy (`Volumetric`); Newton with a line search,
MUMPS's parallel LU. Any model a `Material` takes (energy, approach, law, coupling, damage), a
fibre field per quadrature point::

    import activemuscle as am
    from activemuscle.dolfinx import MuscleBody, Newton, ends, end_area, meshes, sweep
    mesh = meshes.cylinder(rings=4, nx=16)                   # R = 1, L = 4, axis x
    body = MuscleBody(mesh, am.Material(law="explicit"))     # fibres along x
    newton = Newton(body, *ends(body, length=4.0, bases="clamped"))
    area = end_area(mesh, 4.0)
    sweep(newton, [0.9, 1.17], 4.0, lambda lam, force, its: print(lam, force / area))

Run under `mpirun -n N /usr/bin/python3 ...` (Debian's python3-dolfinx 0.5.2, written against
that version; the notes in each module say what later versions renamed).
"""

from . import meshes
from .body import MuscleBody, taylor_hood
from .ends import end_area, ends
from .newton import Newton, sweep
from .quadrature import QuadratureMaterial
from .scene import model_of_scene

__all__ = ["MuscleBody", "Newton", "QuadratureMaterial", "end_area", "ends", "meshes",
           "model_of_scene", "sweep", "taylor_hood"]
