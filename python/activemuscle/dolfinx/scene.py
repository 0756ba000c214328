"""The model of a scene file for the DOLFINx route: its `[material]`, `[activation]` and
`[incompressibility]` tables, resolved by the scene's own parser (`check_scene`: names, defaults
and messages are a scene file's)."""

from typing import List, Mapping, NamedTuple, Optional

try:
    import tomllib
except ImportError:  # Python < 3.11
    import tomli as tomllib

from .._native import Material, Volumetric
from ..scene import check_scene


class Model(NamedTuple):
    """A scene's model: the material, the volumetric energy (None: exact incompressibility),
    the fibre direction and the damage chosen."""

    material: Material
    volumetric: Optional[Volumetric]
    fibre: List[float]
    damage: float


def model_of_scene(scene, damage=None, law=None, coupling=None):
    """The Model of `scene` (a path, TOML text or a dict; a dict may leave out the studies). The damage is `damage`, else the
    first of `activation.damage`; `law` and `coupling`, when given, replace the scene's
    defaults (as a study's keys do)."""
    if isinstance(scene, Mapping) and "study" not in scene:  # a scene needs one to resolve
        scene = dict(scene, study=[{"kind": "uniaxial", "stretch": [1.0]}])
    resolved = tomllib.loads(check_scene(scene))
    keywords = {k: v for k, v in resolved["material"].items() if k != "fibre"}
    activation = dict(resolved.get("activation", {}))
    damages = activation.pop("damage", [0.0])
    keywords.update(activation)
    keywords["damage"] = damages[0] if damage is None else damage
    for key, value in (("law", law), ("coupling", coupling)):
        if value is not None:
            keywords[key] = value
    material = Material(**keywords)
    incompressibility = resolved.get("incompressibility", {})
    volumetric = None
    if incompressibility.get("kind", "exact") != "exact":
        volumetric = Volumetric(material, **incompressibility)
    return Model(material, volumetric, resolved["material"].get("fibre", [1.0, 0.0, 0.0]),
                 keywords["damage"])
