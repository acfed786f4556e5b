"""The numbers a study keeps per point, by kind, checked against the scene
before anything runs.

Kinds (``[[metric]] kind = …``; every kind takes an optional ``name``, the
column's name):

- ``peak_displacement`` / ``peak_acceleration`` (simulate): the largest
  displacement from where the point starts, ``max_t |ρ(t) − ρ(0)|`` [m], or
  the largest acceleration ``max_t |ρ̈(t)|`` [m/s²], of a point — a scene
  ``[[point]]`` by ``point = NAME`` (relative to its ``relative_to`` body
  when it has one), or ``body``, ``position`` [m, body frame] and optional
  ``relative_to`` — in the inertial frame or the ``relative_to`` body's;
  ``direction = "x" | "y" | "z"``: that component's largest absolute value
  instead of the norm.
- ``peak_mount_force`` [N] / ``peak_mount_deflection`` [m] (simulate):
  ``max_t |f(t)|`` per mount (``mounts = [...]``, default all; one column
  each), norm over the mount's three axes or, with ``axis = 1 | 2 | 3``,
  that axis's largest absolute value.
- ``static_deflection`` [m] (static): each mount's deflection at the
  static equilibrium, the norm over its axes or, with ``axis``, that
  axis's signed value.
- ``max_static_deflection`` [m] (static): the largest of the mounts' static
  deflections (norm, or ``|axis|``).
- ``compare`` (compare): a figure of ``flexbed compare``'s table for one
  ``equipment`` body and ``case`` (rigid, flexible, damped):
  ``quantity = "peak" | "rms"`` [m], ``"static_z"`` [m], ``"frequency"`` [Hz].

The frequency-domain kinds (``natural_frequency``,
``effective_mass_fraction``, ``transmissibility``,
``peak_transmissibility``) are in :mod:`flexbed.study.frequency_metrics`.

New kinds join :data:`KINDS` (a class with ``analysis``, ``columns``,
``units``, ``values(outcomes)`` and a ``build(table, scene, where)``
constructor; ``columns`` and ``units`` from
:class:`~flexbed.study.metric_keys.OneColumn` or ``PerMount``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexbed.dynamics.sample_passes import peak_norms
from flexbed.errors import InputError
from flexbed.files.table_reader import short_repr
from flexbed.files.scene import SceneFile
from flexbed.study.frequency_metrics import FREQUENCY_KINDS
from flexbed.study.layout_metrics import LAYOUT_KINDS
from flexbed.study.metric_keys import OneColumn, PerMount, _options, resolve_point
from flexbed.study.outputs import PointRun
from flexbed.study.spec import MetricTable

__all__ = ["KINDS", "build_metric", "PeakMotion", "PeakMount", "StaticDeflection",
           "MaxStaticDeflection", "CompareFigure", "peak_norm"]

_DIRECTIONS = {"x": 0, "y": 1, "z": 2}
_CASES = ("rigid", "flexible", "damped")
_QUANTITIES = {"peak": "m", "rms": "m", "static_z": "m", "frequency": "Hz"}


def peak_norm(v: np.ndarray) -> np.ndarray:
    """``np.linalg.norm(v, axis=-1).max(axis=0)`` for v (k, ..., 3), the same
    numbers bit for bit (the squares summed in the same order, the root
    taken of the largest sum alone: the root is monotone and correctly
    rounded) in compiled code, one pass over the samples."""
    v = np.asarray(v, dtype=float)
    rows = v.reshape(v.shape[0], -1, 3) if v.ndim != 3 else v
    return peak_norms(rows).reshape(v.shape[1:-1])


def _mounts(scene: SceneFile, opts: dict, where: str) -> tuple:
    names = [m.name for m in scene.scene.mounts]
    chosen = opts.get("mounts", names)
    if isinstance(chosen, str) or not isinstance(chosen, list) or not chosen:
        raise InputError(f"{where}: mounts = {chosen!r} must be a list of mount names")
    for m in chosen:
        if m not in names:
            raise InputError(f"{where}: mount {m!r} is not a mount of the scene "
                             f"(mounts: {', '.join(names)})")
    return tuple(names.index(m) for m in chosen), tuple(chosen)


def _axis(opts: dict, where: str) -> int | None:
    axis = opts.get("axis")
    if axis is None:
        return None
    if axis not in (1, 2, 3) or isinstance(axis, bool):
        raise InputError(f"{where}: axis = {axis!r} must be 1, 2 or 3 (the mount's axes)")
    return axis


@dataclass(frozen=True)
class PeakMotion(OneColumn):
    """Peak displacement or acceleration of a point (see the module)."""

    kind: str
    column: str
    body: str
    position: tuple
    relative_to: str | None
    direction: int | None
    analysis = "simulate"

    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "PeakMotion":
        opts = _options(table, ("point", "body", "position", "relative_to", "direction"), where)
        body, pos, rel, label = resolve_point(scene, opts, where)
        direction = opts.get("direction")
        if direction is not None and direction not in _DIRECTIONS:
            raise InputError(f"{where}: direction = {direction!r} must be x, y or z")
        column = opts.get("name") or (f"{table.kind}.{label}" + (f"@{rel}" if rel else "")
                                      + (f".{direction}" if direction else ""))
        return cls(table.kind, column, body, pos, rel,
                   None if direction is None else _DIRECTIONS[direction])

    unit = property(lambda self: "m" if self.kind == "peak_displacement" else "m/s^2")

    def values(self, outcomes: dict) -> tuple:
        run = outcomes["simulate"]
        if self.kind == "peak_displacement":
            # a study point's run (PointRun) computes the positions alone
            x = run.point_position(self.body, self.position, relative_to=self.relative_to) \
                if isinstance(run, PointRun) else \
                run.point(self.body, self.position, relative_to=self.relative_to).position
            v = x - x[0]
        else:
            v = run.point(self.body, self.position, relative_to=self.relative_to).acceleration
        peak = np.abs(v[:, self.direction]).max() if self.direction is not None \
            else peak_norm(v)
        return (float(peak),)


#: ``sense`` of a peak mount metric: the largest |value|, or along an axis
#: the largest compression (−Δx, reported positive) or extension (+Δx)
SENSES = ("magnitude", "compression", "extension")
#: ``part``: the value itself, or its change from the static one (the run
#: starts at the equilibrium, so t = 0 is the static value)
PARTS = ("total", "dynamic")


@dataclass(frozen=True)
class PeakMount(PerMount):
    """Peak force or deflection of each mount over the run: its magnitude,
    or along an axis the largest compression or extension (deflection
    only: Δx < 0 is compression, as the results file's sign), in total or
    its dynamic part (less the static value)."""

    kind: str
    indices: tuple
    names: tuple
    axis: int | None
    label: str | None
    sense: str = "magnitude"
    part: str = "total"
    analysis = "simulate"

    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "PeakMount":
        opts = _options(table, ("mounts", "axis", "sense", "part"), where)
        idx, names = _mounts(scene, opts, where)
        if opts.get("name") and len(names) > 1:
            raise InputError(f"{where}: name applies to one mount (mounts = [...] with one name)")
        sense, part = opts.get("sense", "magnitude"), opts.get("part", "total")
        if sense not in SENSES:
            raise InputError(f"{where}: sense = {short_repr(sense)} must be one of "
                             f"{', '.join(SENSES)}")
        if part not in PARTS:
            raise InputError(f"{where}: part = {short_repr(part)} must be one of "
                             f"{', '.join(PARTS)}")
        axis = _axis(opts, where)
        if sense != "magnitude" and (axis is None or table.kind != "peak_mount_deflection"):
            raise InputError(f"{where}: sense = {sense!r} is the sign of a deflection along one "
                             f"axis: give kind = \"peak_mount_deflection\" and axis = 1, 2 or 3")
        return cls(table.kind, idx, names, axis, opts.get("name"), sense, part)

    unit = property(lambda self: "N" if self.kind == "peak_mount_force" else "m")

    @property
    def columns(self) -> tuple:
        if self.label:
            return (self.label,)
        tail = ("" if self.sense == "magnitude" else f".{self.sense}") + \
            ("" if self.part == "total" else ".dynamic")
        return tuple(c + tail for c in PerMount.columns.fget(self))

    def values(self, outcomes: dict) -> tuple:
        run = outcomes["simulate"]
        data = run.mount_force if self.kind == "peak_mount_force" else run.mount_deflection
        if self.indices != tuple(range(data.shape[1])):
            data = data[:, list(self.indices)]                          # (k, m, 3)
        if self.part == "dynamic":
            data = data - data[:1]
        if self.sense == "compression":
            peak = (-data[:, :, self.axis - 1]).max(axis=0)
        elif self.sense == "extension":
            peak = data[:, :, self.axis - 1].max(axis=0)
        else:
            peak = np.abs(data[:, :, self.axis - 1]).max(axis=0) if self.axis \
                else peak_norm(data)
        return tuple(float(x) for x in peak)


def static_deflections(outcomes: dict) -> np.ndarray:
    """(M, 3) [m]: every mount's deflection along its axes at the static
    equilibrium (the right-hand side's own evaluation, as the results
    file's ``mounts/deflection``)."""
    st = outcomes["static"]
    cached = outcomes.get("_static_dx")              # one evaluation for all of a point's metrics
    if cached is None or cached[0] is not st:
        eq = st.equilibrium                          # the statics' own evaluation at rest, if kept
        cached = (st, eq.mounts[0] if eq.mounts is not None
                  else st.system.observe(0.0, eq.y).dx)
        outcomes["_static_dx"] = cached
    return cached[1]


@dataclass(frozen=True)
class StaticDeflection(PerMount):
    """Each mount's static deflection."""

    kind: str
    indices: tuple
    names: tuple
    axis: int | None
    label: str | None
    analysis = "static"
    unit = "m"
    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "StaticDeflection":
        opts = _options(table, ("mounts", "axis"), where)
        idx, names = _mounts(scene, opts, where)
        if opts.get("name") and len(names) > 1:
            raise InputError(f"{where}: name applies to one mount (mounts = [...] with one name)")
        return cls(table.kind, idx, names, _axis(opts, where), opts.get("name"))

    def values(self, outcomes: dict) -> tuple:
        dx = static_deflections(outcomes)[list(self.indices)]
        v = dx[:, self.axis - 1] if self.axis else np.linalg.norm(dx, axis=1)
        return tuple(float(x) for x in v)


@dataclass(frozen=True)
class MaxStaticDeflection(OneColumn):
    """The largest static mount deflection."""

    kind: str
    column: str
    axis: int | None
    analysis = "static"
    unit = "m"

    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "MaxStaticDeflection":
        opts = _options(table, ("axis",), where)
        if not scene.scene.mounts:
            raise InputError(f"{where}: the scene has no mounts")
        axis = _axis(opts, where)
        return cls(table.kind, opts.get("name") or (table.kind + (f".axis{axis}" if axis else "")),
                   axis)

    def values(self, outcomes: dict) -> tuple:
        dx = static_deflections(outcomes)
        v = np.abs(dx[:, self.axis - 1]) if self.axis else np.linalg.norm(dx, axis=1)
        return (float(v.max()),)


@dataclass(frozen=True)
class CompareFigure(OneColumn):
    """A figure of the rigid / flexible / damped comparison."""

    kind: str
    column: str
    equipment: str
    case: str
    quantity: str
    analysis = "compare"

    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "CompareFigure":
        opts = _options(table, ("equipment", "case", "quantity"), where)
        names = [b.name for b in scene.scene.bodies]
        bed = scene.bed.body or (names[1] if len(names) > 1 else None)
        equipment = [n for n in names[1:] if n != bed]
        eq = opts.get("equipment")
        if eq not in equipment:
            raise InputError(f"{where}: equipment = {eq!r} must be one of "
                             f"{', '.join(equipment) or 'none'}")
        case = opts.get("case", "damped")
        if case not in _CASES:
            raise InputError(f"{where}: case = {case!r} must be one of {', '.join(_CASES)}")
        q = opts.get("quantity", "peak")
        if q not in _QUANTITIES:
            raise InputError(f"{where}: quantity = {q!r} must be one of "
                             f"{', '.join(_QUANTITIES)}")
        return cls(table.kind, opts.get("name") or f"compare.{case}.{eq}.{q}", eq, case, q)

    unit = property(lambda self: _QUANTITIES[self.quantity])

    def values(self, outcomes: dict) -> tuple:
        for row in outcomes["compare"].rows:
            if row["equipment"] == self.equipment and row["case"] == self.case:
                return (float(row[self.quantity]),)
        raise InputError(f"compare: no row for {self.equipment!r}, {self.case!r}")


#: metric kinds by name
KINDS = {"peak_displacement": PeakMotion, "peak_acceleration": PeakMotion,
         "peak_mount_force": PeakMount, "peak_mount_deflection": PeakMount,
         "static_deflection": StaticDeflection, "max_static_deflection": MaxStaticDeflection,
         "compare": CompareFigure}

KINDS.update(FREQUENCY_KINDS)       # natural_frequency, effective_mass_fraction, …
KINDS.update(LAYOUT_KINDS)          # decoupling, highest_frequency, rigid_frequencies


def build_metric(table: MetricTable, scene: SceneFile, study_name: str):
    """The metric of a ``[[metric]]`` table, checked against the scene."""
    where = f"{study_name}: metric {table.index} ({table.kind})"
    if table.kind not in KINDS:
        raise InputError(f"{study_name}: metric {table.index}: unknown kind {table.kind!r} "
                         f"(known: {', '.join(KINDS)})")
    return KINDS[table.kind].build(table, scene, where)
