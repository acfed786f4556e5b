"""The base's drives and loads as functions of time, on the Python side.

:class:`BaseInputs` holds every input of a scene's base compiled once (a
curve's spline and its integrals built here and reused for the kernel's
tables, :mod:`flexbed.dynamics.kernel_tables`) and answers what the
integrators and the outputs ask of them: the base's prescribed motion and
the external load at a time, the breakpoints, the longest step the inputs
allow. The compiled right-hand side evaluates the same inputs from its own
tables (:mod:`flexbed.dynamics.kernel.inputs`).

One-sided limits: every evaluation takes the end of the segment being
integrated, ``seg_end`` [s]; at t ≥ seg_end an input gives its limit from
the left (from inside the segment), elsewhere it is right-continuous.
``seg_end = inf`` (the default) means right-continuous everywhere (statics,
outputs).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .bounded_cache import BoundedCache
from .scene import Scene

__all__ = ["BaseInputs", "compiled_shape", "content"]

#: shapes compiled already, by content (:func:`compiled_shape`); a few kept
_COMPILED = BoundedCache(16)


def content(obj):
    """A hashable key equal for equal shapes: a dataclass by its type and
    fields, an array by its dtype, shape and bytes, a float by its bits
    (−0.0 is not 0.0), any other value by its type and itself."""
    if isinstance(obj, float):
        return (float, obj.hex())
    if isinstance(obj, np.ndarray):
        return (obj.dtype.str, obj.shape, obj.tobytes())
    if isinstance(obj, (tuple, list)):
        return tuple(content(v) for v in obj)
    names = _FIELD_NAMES.get(type(obj))
    if names is None and dataclasses.is_dataclass(obj):
        names = _FIELD_NAMES[type(obj)] = tuple(f.name for f in dataclasses.fields(obj))
    if names is not None:
        return (type(obj),) + tuple(content(getattr(obj, name)) for name in names)
    return (type(obj), obj)


#: the fields' names of the dataclasses met by :func:`content`, by type
_FIELD_NAMES: dict = {}


def compiled_shape(shape):
    """``shape.compile()`` (a :class:`~flexbed.dynamics.time_functions.TimeFunction`,
    read only), computed once for equal shapes: the variants of a study
    share their inputs, and a sampled curve's spline costs about a
    millisecond to build."""
    try:
        key = content(shape)
        hash(key)
    except TypeError:                   # a field that cannot be hashed
        return shape.compile()
    return _COMPILED.get(key, shape.compile)


@dataclass(frozen=True, slots=True)
class BaseInputs:
    """The inputs of a scene's base, compiled.

    Attributes
    ----------
    r0 : (3,) array [m]
        The base's position in the scene (read-only).
    support : (3,) array [N]
        Constant external force on a free base (read-only): the scene's
        ``support``, or ``−(total mass) g`` for ``"static"``.
    items : tuple
        The scene's drives, then its loads on the base, then its loads on
        other bodies (:class:`flexbed.dynamics.scene.Drive`,
        :class:`~flexbed.dynamics.scene.Load`,
        :class:`~flexbed.dynamics.body_loads.BodyLoad`).
    roles : tuple of int
        0 for a drive, 1 for a load on the base, 2 for a load on a body,
        per item.
    compiled : tuple of TimeFunction
        Their compiled shapes, in the same order.
    drives, loads : tuple of 3 tuples of TimeFunction
        The compiled drives (accelerations [m/s²]) and loads [N] per
        direction X, Y, Z, in scene order.
    body_loads : tuple of TimeFunction
        The compiled loads on bodies [N or N m], in scene order.
    breakpoints : tuple of float
        Times [s] > 0 where an input (or a derivative) jumps, sorted.
    """

    r0: np.ndarray
    support: np.ndarray
    items: tuple
    roles: tuple
    compiled: tuple
    drives: tuple
    loads: tuple
    breakpoints: tuple
    body_loads: tuple = ()

    @classmethod
    def of(cls, scene: Scene, gravity: np.ndarray) -> BaseInputs:
        """Compile the inputs of ``scene``'s base; ``gravity`` (3,) [m/s²]
        gives a ``"static"`` support."""
        base = scene.base
        items = tuple(base.drives) + tuple(base.loads) + tuple(scene.loads)
        compiled = tuple(compiled_shape(d.shape) for d in items)
        body_loads = compiled[len(base.drives) + len(base.loads):]
        drives = [[], [], []]
        loads = [[], [], []]
        bps = set()
        for d, f in zip(base.drives, compiled):
            drives[d.direction].append(f)
            bps.update(f.breakpoints)
        for d, f in zip(base.loads, compiled[len(base.drives):]):
            loads[d.direction].append(f)
            bps.update(f.breakpoints)
        for f in body_loads:
            bps.update(f.breakpoints)
        r0, support = cls.placement(scene, gravity)
        return cls(r0=r0, support=support, items=items,
                   roles=(0,) * len(base.drives) + (1,) * len(base.loads)
                   + (2,) * len(scene.loads), compiled=compiled,
                   drives=tuple(tuple(f) for f in drives), loads=tuple(tuple(f) for f in loads),
                   breakpoints=tuple(sorted(b for b in bps if b > 0.0)),
                   body_loads=tuple(body_loads))

    @staticmethod
    def placement(scene: Scene, gravity: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The base's position r0 (3,) [m] in ``scene`` and its support (3,)
        [N] (``"static"``: −(total mass) ``gravity``), both read-only."""
        base = scene.base
        if isinstance(base.support, str):
            support = (-scene.total_mass * gravity if base.support == "static"
                       else np.zeros(3))
        else:
            support = np.array(base.support, dtype=float)
        r0 = np.array(scene.bodies[0].position, dtype=float)
        r0.flags.writeable = False
        support = np.array(support, dtype=float)
        support.flags.writeable = False
        return r0, support

    def motion_at(self, t: float, seg_end: float = math.inf):
        """The base's prescribed position [m], velocity [m/s] and acceleration
        [m/s²] at time t [s], each (3,), from the drives (a free base's motion
        comes from the state)."""
        at = None if math.isinf(seg_end) else seg_end
        r = self.r0.copy()
        v = np.zeros(3)
        a = np.zeros(3)
        for k in range(3):
            for f in self.drives[k]:
                r[k] += f.second(t, at)
                v[k] += f.first(t, at)
                a[k] += f.value(t, at)
        return r, v, a

    def load_at(self, t: float, seg_end: float = math.inf) -> np.ndarray:
        """External force on the base [N] (3,) at time t [s]: loads + support."""
        at = None if math.isinf(seg_end) else seg_end
        F = self.support.copy()
        for k in range(3):
            for f in self.loads[k]:
                F[k] += f.value(t, at)
        return F

    def max_step(self, t_a: float, t_b: float) -> float:
        """Longest adaptive step [s] allowed on [t_a, t_b] by the inputs active
        there (inf: none)."""
        out = np.inf
        for f in tuple(f for k in range(3) for f in self.drives[k] + self.loads[k]) \
                + self.body_loads:
            lo, hi = f.support
            if lo < t_b and hi > t_a:
                out = min(out, f.max_step)
        return float(out)

    def compiled_input(self, shape):
        """The compiled form (value and exact integrals) of one of the base's
        input shapes, as built with these inputs (another shape: compiled
        now)."""
        for item, f in zip(self.items, self.compiled):
            if item.shape is shape:
                return f
        return shape.compile()
