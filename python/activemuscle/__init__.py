"""activemuscle: the mechanics of active skeletal muscle (Giantesio & Musesti) on numpy arrays.

``Material`` evaluates a batch of deformation gradients at once: F of shape (3, 3, ...) (felupe's
trailing axes) or (..., 3, 3), returning P = ∂Ŵ/∂F (without the pressure term), the exact tangent
A[i, j, k, l] = ∂P_ij/∂F_kl (not major-symmetric for the frozen coupling), γ, the fibre stretch,
Ŵ and dP/dγ::

    import numpy as np, activemuscle as am
    muscle = am.Material(law="explicit", coupling="frozen", damage=0.2)
    r = muscle.evaluate(F, fibre=[1, 0, 0])      # F: (3, 3, ...) or (..., 3, 3)
    r["stress"], r["tangent"], r["gamma"], r["dstress_dgamma"]

Keywords, names and defaults are a scene's (scenes/paper.toml): energy ("giantesio-musesti",
"ehret-bol-itskov", "neo-hookean", "4c-passive") with mu, alpha, beta, w0; law ("passive", "constant" with gamma,
"implicit", "explicit" with explicit={"a": .., "b": ..}, "energy" with below_minimum); coupling
("frozen" with frozen_tangent "exact" | "symmetric", "consistent"); damage; the active curve's
lambda_min, lambda_opt, k, p_opt; map ("chapter" | "volume-preserving"); representation ("exact" |
"tabulated", with table_stretches=[lo, hi]). Bad values raise ValueError with the core's message.

``run_scene`` runs a scene (a file, its TOML text or a dict) and returns each study's results as
columns of numpy arrays (``pandas.DataFrame(r["name"].table)``); ``check_scene`` returns the
resolved scene (``activemuscle.scene``).

``Volumetric(material, kind, kappa, mu)`` is a scene's ``[incompressibility]`` with a volumetric
energy U(J) (near incompressibility), for finite element codes that impose it themselves;
``material.uniaxial(stretches, volumetric)`` gives its homogeneous curve.

``activemuscle.felupe`` adapts a Material to felupe (``MuscleMaterial``, and ``Incompressible``
for the exact incompressibility of the chapter's mixed u–p formulation);
``activemuscle.dolfinx`` runs the material in DOLFINx under MPI (docs/distributed.md).
"""

from ._native import Material, Volumetric
from .scene import Results, Study, check_scene, run_scene

__all__ = ["Material", "Results", "Study", "Volumetric", "check_scene", "run_scene"]
