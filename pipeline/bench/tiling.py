"""Large scenes for the scaling benchmark: the built-in reference scene tiled
c × c times.

The unit is the built-in scene's bed (0.8 × 4.8 m) with its two pieces of
equipment on 4 mounts each and its 4 mounts to the base. :func:`tiled_text`
lays c × c copies of that unit side by side on one bed of 0.8c × 4.8c m
(same thickness and material, so c² times the unit's mass), every mount
point on the bed and on the base shifted with its unit, the equipment's
bodies copied with their positions shifted alike: N = 2c² pieces of
equipment, 4c² mounts to the base and 8c² mounts under the equipment.
Everything else (gravity, the base and its loads, the bed's model, the
solver settings) is the built-in scene's; the points of interest are
dropped. A unit's copies are named ``"<name> <ix>.<iy>"``; c = 1 is the
built-in scene itself, names unchanged.

:func:`tiled_scene` parses that text into a
:class:`~flexbed.files.scene.SceneFile`, as any scene file is read.
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

from flexbed.files.builtin import builtin_scene_text
from flexbed.files.scene import SceneFile, parse_scene
from flexbed.files.toml_text import dumps

__all__ = ["tiled_text", "tiled_scene", "equipment_count"]

#: the unit's size along x and y [m] (the built-in bed)
UNIT = (0.8, 4.8)


def equipment_count(c: int) -> int:
    """Pieces of equipment N = 2c² of the c × c tiling."""
    return 2 * c * c


def _shifted(v: list, dx: float, dy: float) -> list:
    return [float(v[0]) + dx, float(v[1]) + dy] + [float(x) for x in v[2:]]


def tiled_text(c: int, *, bed_model: str | None = None) -> str:
    """The TOML text of the built-in scene tiled ``c`` × ``c`` times.

    Parameters
    ----------
    c : int ≥ 1
        Copies along x and along y.
    bed_model : "rigid" or "flexible", optional
        ``[bed] model`` (default: the built-in scene's).

    Returns
    -------
    str
        A scene file (see the module docstring).
    """
    if not isinstance(c, int) or isinstance(c, bool) or c < 1:
        raise ValueError(f"tiled_text: c must be an integer ≥ 1, got {c!r}")
    data = tomllib.loads(builtin_scene_text())
    if bed_model is not None:
        data["bed"]["model"] = bed_model
    data.pop("point", None)
    if c == 1:
        return dumps(data)
    lx, ly = UNIT
    bodies = {b["name"]: b for b in data["body"]}
    base, bed = data["body"][0]["name"], data["body"][1]["name"]
    units = [(ix, iy, lx * (ix - 0.5 * (c - 1)), ly * (iy - 0.5 * (c - 1)))
             for ix in range(c) for iy in range(c)]
    new_bodies = data["body"][:2]
    for name, body in bodies.items():
        if name in (base, bed):
            continue
        for ix, iy, dx, dy in units:
            b = copy.deepcopy(body)
            b["name"] = f"{name} {ix}.{iy}"
            b["position"] = _shifted(body["position"], dx, dy)
            new_bodies.append(b)
    mounts = []
    for ix, iy, dx, dy in units:
        for m in data["mount"]:
            m = copy.deepcopy(m)
            m["name"] = f"{m['name']} {ix}.{iy}"
            for end in ("i", "j"):
                owner = m[f"body_{end}"]
                if owner in (base, bed):          # a point of the base or the bed: shifted
                    m[f"point_{end}"] = _shifted(m[f"point_{end}"], dx, dy)
                else:                              # the equipment's own copy, same local point
                    m[f"body_{end}"] = f"{owner} {ix}.{iy}"
            mounts.append(m)
    data["body"] = new_bodies
    data["mount"] = mounts
    data["bed"]["length_x"] = lx * c
    data["bed"]["length_y"] = ly * c
    data["scene"]["name"] = f"{data['scene']['name']}-tiled-{c}x{c}"
    data["scene"]["description"] = (f"the built-in scene tiled {c} x {c}: "
                                    f"{equipment_count(c)} pieces of equipment")
    return dumps(data)


def tiled_scene(c: int, *, bed_model: str | None = None) -> SceneFile:
    """:func:`tiled_text` read as a scene file (source ``lee1999-tiled-<c>x<c>.toml``)."""
    text = tiled_text(c, bed_model=bed_model)
    return parse_scene(text, Path(f"lee1999-tiled-{c}x{c}.toml"))
