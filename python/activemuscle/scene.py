"""Scenes from Python: run a scene file, a scene's TOML text or a dict, and get each study's
results as columns of numpy arrays that ``pandas.DataFrame(...)`` takes directly::

    import activemuscle as am, pandas as pd
    r = am.run_scene("scenes/paper.toml")                # or TOML text, or a dict
    curves = pd.DataFrame(r["uniaxial"].table)           # one row per point
    r["uniaxial"].failures                               # what could not be computed, and why

The scene is validated and resolved by the scene's own parser (names, defaults and messages are
a scene file's; a dict's errors name the key path, ``study[1].damage``). ``out`` writes the
outputs the command line writes (the CSV files of the studies the scene has — curves.csv only
with a uniaxial or cylinder study —, datapackage.json, figures, report.html, VTK files) into
that directory; without it nothing is written.
"""

from __future__ import annotations

import json
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Union

from . import _native

Source = Union[str, "os.PathLike[str]", Mapping[str, Any]]


@dataclass
class Study:
    """One study's outcome. ``table``: the study's rows of its CSV file (``files["table"]``:
    curves.csv for uniaxial and cylinder studies, fits.csv, stability.csv, history.csv,
    shear.csv, biaxial.csv, tradeoff.csv), with exactly the file's columns, names, types and
    values: one numpy array per column (float64 numbers, int64 counts, bool flags, object arrays
    of names), values that do not apply to a row masked (``numpy.ma``, missing in pandas); every
    column's unit and meaning is in the run's ``datapackage.json``. ``named_points`` (cylinder
    studies with ``[study.points]``): the rows of ``points_<study>.csv``, likewise; ``fit_points``
    (fit studies): the rows of ``fit_points.csv`` (each datum with the fitted model and the
    residual, then the fitted curve). A tangent
    study's ``table`` is tangent_summary.csv; ``remainders``, ``fe_remainders`` and ``newton``
    are tangent.csv, tangent_fe.csv and tangent_newton.csv (the last two with its ``fe`` level).
    ``failures``: columns ``model`` and ``message``. ``outside_domain``: the models evaluated
    outside their law's domain (the explicit law's, docs/explicit_law.md), columns ``model`` and
    ``message``; their rows are computed all the same, ``in_domain`` false. ``vtk``: the VTK
    files written (under ``out``; none without it): a ``.vtu`` per stretch asked for and a
    ``.pvd`` series per sweep. ``findings``: what a trade-off study found."""

    name: str
    kind: str
    table: Dict[str, Any]
    failures: Dict[str, Any]
    models: int
    points: int
    requested: int
    elapsed: float
    details: List[str] = field(default_factory=list)
    vtk: List[Path] = field(default_factory=list)
    findings: List[str] = field(default_factory=list)
    named_points: Dict[str, Any] = field(default_factory=dict)
    fit_points: Dict[str, Any] = field(default_factory=dict)
    remainders: Dict[str, Any] = field(default_factory=dict)
    fe_remainders: Dict[str, Any] = field(default_factory=dict)
    newton: Dict[str, Any] = field(default_factory=dict)
    files: Dict[str, str] = field(default_factory=dict)
    outside_domain: Dict[str, Any] = field(default_factory=dict)


@dataclass
class Results:
    """Every study of a run, in the scene's order; ``results[name]`` or ``results[i]``."""

    title: str
    file: str
    out: Optional[Path]
    studies: List[Study]

    def __getitem__(self, key: Union[str, int]) -> Study:
        if isinstance(key, int):
            return self.studies[key]
        for s in self.studies:
            if s.name == key:
                return s
        names = ", ".join(repr(s.name) for s in self.studies)
        raise KeyError(f"no study named {key!r}; the studies are {names}")

    def __len__(self) -> int:
        return len(self.studies)

    def __iter__(self):
        return iter(self.studies)

    def failures(self) -> List[tuple]:
        """Every failure as (study, model, message)."""
        return [
            (s.name, m, msg)
            for s in self.studies
            for m, msg in zip(s.failures["model"], s.failures["message"])
        ]


_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: Any, path: str) -> str:
    if not isinstance(k, str):
        raise ValueError(f"{path}: keys must be strings, not {k!r}")
    return k if _BARE_KEY.match(k) else json.dumps(k, ensure_ascii=False)


def _value(v: Any, path: str) -> str:
    """The TOML of one value, inline (tables as inline tables)."""
    if hasattr(v, "tolist") and not isinstance(v, (str, bytes)):
        v = v.tolist()  # numpy scalars and arrays
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        # JSON's string escapes are TOML's basic-string escapes.
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, Mapping):
        items = ", ".join(
            f"{_key(k, path)} = {_value(x, f'{path}.{k}' if path else str(k))}"
            for k, x in v.items()
        )
        return "{ " + items + " }" if items else "{}"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x, f"{path}[{i}]") for i, x in enumerate(v)) + "]"
    if v is None:
        raise ValueError(f"{path} = None: a scene has no null; leave the key out for its default")
    raise ValueError(f"{path} = {v!r}: not a scene value (number, string, bool, list or dict)")


def to_toml(scene: Mapping[str, Any]) -> str:
    """A scene dict as TOML text, one top-level key a line (tables inline)."""
    if not isinstance(scene, Mapping):
        raise ValueError(f"a scene dict must be a mapping, not {type(scene).__name__}")
    return "".join(f"{_key(k, '')} = {_value(v, str(k))}\n" for k, v in scene.items())


def _source(scene: Source) -> dict:
    """The keyword arguments of the native functions for `scene`: a dict (converted to TOML), a
    path to an existing file, or else TOML text."""
    if isinstance(scene, Mapping):
        return dict(text=to_toml(scene), from_dict=True)
    if isinstance(scene, os.PathLike):
        return dict(path=os.fspath(scene))
    if isinstance(scene, str):
        if "\n" not in scene and "=" not in scene:
            return dict(path=scene)  # a missing file is reported by the scene loader
        return dict(text=scene)
    raise ValueError(
        f"a scene is a path, TOML text or a dict, not {type(scene).__name__}"
    )


def check_scene(scene: Source) -> str:
    """The resolved scene as TOML, every default written out (what ``activemuscle check``
    prints); raises ValueError with the scene's message (file:line: key = value: rule)."""
    return _native.check_scene(**_source(scene))


def run_scene(scene: Source, out: Optional[Union[str, "os.PathLike[str]"]] = None) -> Results:
    """Runs every study of `scene` (a path — a ``str`` without a newline or ``=``, or a
    ``PathLike`` —, TOML text or a dict) and returns its results; with
    `out`, also writes the command line's outputs there. Raises ValueError for an invalid scene
    (the scene's message), FloatingPointError for a non-finite result, RuntimeError when a study
    cannot run at all; a point, curve or fit that fails is recorded in its study's ``failures``
    and the run goes on."""
    kwargs = _source(scene)
    if out is not None:
        kwargs["out"] = os.fspath(out)
    r = _native.run_scene(**kwargs)
    return Results(
        title=r["title"],
        file=r["file"],
        out=r["out"],
        studies=[Study(**s) for s in r["studies"]],
    )
