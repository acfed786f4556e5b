"""Physical sanity of a scene that is valid but probably not meant: warned
about in one line each (:class:`~flexbed.errors.FlexbedWarning`), not
refused. (What no body can have, such as an inertia that breaks the
triangle inequality, is refused where bodies are checked,
:mod:`flexbed.dynamics.scene`.)"""

from __future__ import annotations

import math
import warnings

import numpy as np

from flexbed.dynamics.scene import Scene
from flexbed.errors import FlexbedWarning
from flexbed.files.bed_section import BedSection

__all__ = ["FAR_POINT", "body_sizes", "warn_far_points"]

#: a mount point further than this many times its body's size from the
#: body's centre of mass is warned about (not refused)
FAR_POINT = 10.0


def body_sizes(scene: Scene, bed_body: str | None, bed: BedSection) -> dict[str, float]:
    """Size [m] of every body but the base: the bed's plate, half its
    diagonal; another body, the half-diagonal of the uniform box with its
    mass and inertia, sqrt(1.5 trace(J) / m) (a box a x b x c has trace(J)
    = m (a² + b² + c²) / 6). Not the base's: its orientation is locked, so
    its inertia says nothing of its size."""
    sizes = {}
    for b in scene.bodies[1:]:
        if b.name == bed_body:
            p = bed.plate
            sizes[b.name] = 0.5 * math.sqrt(p.length_x ** 2 + p.length_y ** 2 + p.thickness ** 2)
        else:
            sizes[b.name] = math.sqrt(1.5 * float(np.trace(b.inertia)) / b.mass)
    return sizes


def warn_far_points(label: str, scene: Scene, bed_body: str | None, bed: BedSection) -> None:
    """A FlexbedWarning for each mount point (and load point) more than :data:`FAR_POINT`
    times its body's size (:func:`body_sizes`) from the body's centre of
    mass; ``label`` is the scene file's name as messages show it."""
    sizes = body_sizes(scene, bed_body, bed)
    for m in scene.mounts:
        for key, body, point in (("point_i", m.body_i, m.point_i),
                                 ("point_j", m.body_j, m.point_j)):
            if body not in sizes:
                continue
            d = math.hypot(*point.tolist())
            if d > FAR_POINT * sizes[body]:
                warnings.warn(FlexbedWarning(
                    f"{label}: mount {m.name!r}: {key} = {np.asarray(point).tolist()} is "
                    f"{d:.3g} m from the centre of body {body!r}, more than {FAR_POINT:g} x "
                    f"its size ({sizes[body]:.3g} m): a point in the wrong frame or unit?"),
                    stacklevel=3)
    for ld in scene.loads:
        d = float(np.linalg.norm(ld.point))
        if ld.body in sizes and d > FAR_POINT * sizes[ld.body]:
            warnings.warn(FlexbedWarning(
                f"{label}: load {ld.name!r}: point = {ld.point.tolist()} is {d:.3g} m from the "
                f"centre of body {ld.body!r}, more than {FAR_POINT:g} x its size "
                f"({sizes[ld.body]:.3g} m): a point in the wrong frame or unit?"), stacklevel=3)
