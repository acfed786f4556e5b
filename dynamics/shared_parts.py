"""The parts of a compiled system that a study's variants share, made once.

A study compiles one :class:`~flexbed.dynamics.system.System` per point,
and its points differ in a few values (a mount's stiffness, the bed's
thickness): many parts of a System — the base's inputs compiled, the
kernel's tables built from them, the tables of what the scene lacks (no
flexible body, no Maxwell term) and its work arrays — come out the same
from point to point. Each part here is kept by the content of what it
is made from (:func:`content`: every float by its bits, every array by its
bytes), so a part is reused only where a fresh one would be equal bit for
bit; a part met with a new content is made as before. What is kept is read
only: a System never changes (its arrays are read-only), and Systems that
share a part share it as they share a compiled input's spline
(:func:`flexbed.dynamics.base_inputs.compiled_shape`).

:func:`base_inputs` gives the base's
:class:`~flexbed.dynamics.base_inputs.BaseInputs`, :func:`tables_of` the
kernel's tables made from a shared part (the compiled inputs) or from the
sizes alone (the work arrays, the tables of what a scene lacks).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .base_inputs import BaseInputs, content
from .bounded_cache import BoundedCache
from .scene import Scene

__all__ = ["base_inputs", "tables_of"]

#: BaseInputs by their items' content; the kernel's tables by the part and
#: what else they are made from
_INPUTS = BoundedCache(16)
_TABLES = BoundedCache(32)


def base_inputs(scene: Scene, gravity: np.ndarray) -> BaseInputs:
    """``BaseInputs.of(scene, gravity)``, its compiled inputs (``compiled``,
    ``drives``, ``loads``, ``body_loads``, ``breakpoints``) shared by scenes
    with equal inputs; its ``items``, ``r0`` and ``support`` the scene's
    own (a static support follows the total mass, which a study varies)."""
    base = scene.base
    items = tuple(base.drives) + tuple(base.loads) + tuple(scene.loads)
    try:
        key = (content(items), len(base.drives), len(base.loads))
        hash(key)
    except TypeError:                   # a field that cannot be hashed
        return BaseInputs.of(scene, gravity)
    made = _INPUTS.get(key, lambda: BaseInputs.of(scene, gravity))
    r0, support = BaseInputs.placement(scene, gravity)
    return dataclasses.replace(made, items=items, r0=r0, support=support)


def tables_of(part, key: tuple, make) -> dict:
    """``make()``, kernel tables made from a shared ``part`` (a LawBank, the
    compiled inputs' tuple, or None) and what ``key`` (hashable) names,
    made once per part and key; their arrays read-only."""
    def made():
        tables = make()
        for v in tables.values():
            v.flags.writeable = False
        return part, tables
    found, tables = _TABLES.get((id(part),) + key, made)
    if found is not part:               # not reached while the part is kept
        return make()
    return tables
