"""The scene file's limits: what a run is qualified against (issue 23).

- per ``[[mount]]``: ``bump_stop`` (a snubber per direction: gaps,
  contact stiffness and damping, :class:`~flexbed.dynamics.laws.BumpStop`,
  which the dynamics reads from the scene's mounts);
  ``stroke_compression`` and ``stroke_extension`` (3
  floats > 0 [m], one per mount direction: the travel allowed for
  Δx_k < 0 and Δx_k > 0, Δx as the results file gives it), ``rated_load``
  (the data sheet's static load [N], against the static force's
  resultant) and ``max_force`` (its largest dynamic force [N], against the
  force's resultant over the run);
- per ``[[body]]``: ``fragility = {peak = 40, units = "g"}``, the largest
  absolute acceleration the equipment may see (optionally at ``point``,
  body frame [m]; default its centre of mass);
- on the flexible bed's ``[[body]]``: ``allowable_stress`` [Pa], the
  largest von Mises stress its material may carry, one number for the
  plate and its stiffeners or a table ``{plate = …, stiffeners = …}``
  when they differ (judged against the stresses by modal superposition,
  :mod:`flexbed.analyses.bed_stress`);
- ``[[clearance]]`` tables: a point on one body and a point, a plane or a
  box on another body (or the base), with the smallest distance allowed
  [m].

:func:`read_limits` reads them from the parsed TOML for the scene reader
(:mod:`flexbed.files.scene`), which lets these keys through its own
tables; :func:`check_static_strokes` refuses a stroke smaller than the
static deflection once the equilibrium is known. Everything is frozen
data of plain tuples; the checks of a run against it are
:mod:`flexbed.analyses.verdict`'s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from flexbed.dynamics.laws import BumpStop
from flexbed.dynamics.pulses import STANDARD_GRAVITY
from flexbed.errors import InputError
from flexbed.files.drives import UNITS
from flexbed.files.table_reader import short_repr

__all__ = ["Limits", "MountLimits", "Fragility", "Clearance", "Allowable", "read_limits",
           "check_static_strokes", "MOUNT_LIMIT_KEYS", "JUDGED_ONLY_KEYS", "BODY_LIMIT_KEYS",
           "CLEARANCE_KEYS", "UNITS", "STANDARD_GRAVITY"]

# STANDARD_GRAVITY: g0 = 9.80665 m/s² (ISO 80000-3), the "g" of fragility
# levels and shock specifications; UNITS: an acceleration's ``units`` and its
# factor to m/s² — the drives' own (one vocabulary for both)

MOUNT_LIMIT_KEYS = ("stroke_compression", "stroke_extension", "rated_load", "max_force",
                    "bump_stop")
#: the mount keys a run is only judged against (outside the equilibrium's
#: hash); ``bump_stop`` changes the forces, so it is not one of them
JUDGED_ONLY_KEYS = MOUNT_LIMIT_KEYS[:4]
_STOP_KEYS = ("direction", "gap_compression", "gap_extension", "stiffness", "damping")
BODY_LIMIT_KEYS = ("fragility", "allowable_stress")
_ALLOWABLE_KEYS = ("plate", "stiffeners")
_FRAGILITY_KEYS = ("peak", "units", "point")
CLEARANCE_KEYS = ("name", "body", "point", "other", "other_point", "plane", "box", "minimum")
_SHAPES = ("other_point", "plane", "box")


@dataclass(frozen=True, slots=True)
class MountLimits:
    """One mount's data-sheet limits; None where the scene gives none.

    compression, extension : 3 floats [m] per mount direction (the travel
    allowed for Δx < 0 and Δx > 0); rated_load, max_force : float [N];
    stops : 3 :class:`~flexbed.dynamics.laws.BumpStop` or None, the
    mount's bump stops per direction (also on the scene's Mount, where
    the dynamics reads them).
    """

    mount: str
    compression: tuple | None = None
    extension: tuple | None = None
    rated_load: float | None = None
    max_force: float | None = None
    stops: tuple = (None, None, None)


@dataclass(frozen=True, slots=True)
class Fragility:
    """A body's fragility: its largest allowed absolute acceleration.

    given : float, the peak as the scene gives it, in ``units`` ("g" or
    "m/s2"); point : 3 floats [m] in the body's frame (the bed's: its
    drawing frame, as for ``[[point]]``), or None for the centre of mass.
    """

    body: str
    given: float
    units: str = "m/s2"
    point: tuple | None = None

    @property
    def peak(self) -> float:
        """The peak [m/s²]."""
        return self.given * UNITS[self.units]


@dataclass(frozen=True, slots=True)
class Clearance:
    """A ``[[clearance]]``: ``point`` on ``body`` kept ``minimum`` [m] from a
    shape on ``other``.

    kind : "point" (``geometry`` = (position,)), "plane" ((a point on it,
    its unit normal: the side it points to is free), "box" ((min corner,
    max corner), axis-aligned: the obstacle); all in ``other``'s frame [m]
    (the bed's drawing frame for the bed).
    """

    name: str
    body: str
    point: tuple
    other: str
    kind: str
    geometry: tuple
    minimum: float


@dataclass(frozen=True, slots=True)
class Allowable:
    """The bed's allowable stresses [Pa]: plate and stiffeners (equal when
    the scene gives one number)."""

    body: str
    plate: float
    stiffeners: float


@dataclass(frozen=True, slots=True)
class Limits:
    """Every limit of a scene: mounts (MountLimits, only those with a
    limit), fragility (Fragility per body that has one), clearances, the
    bed's allowable stress (Allowable or None)."""

    mounts: tuple = ()
    fragility: tuple = ()
    clearances: tuple = ()
    allowable: Allowable | None = None

    def mount(self, name: str) -> MountLimits:
        """The limits of mount ``name`` (all None when it has none)."""
        for m in self.mounts:
            if m.mount == name:
                return m
        return MountLimits(name)

    def body(self, name: str) -> Fragility | None:
        """The fragility of body ``name``, or None."""
        for f in self.fragility:
            if f.body == name:
                return f
        return None

    @property
    def empty(self) -> bool:
        return not (self.mounts or self.fragility or self.clearances
                    or self.allowable is not None)


def read_limits(reader, data: dict, names: list[str], bed_name: str | None = None,
                off_bed: Callable[[list], bool] | None = None) -> Limits:
    """The limits of a parsed scene.

    Parameters
    ----------
    reader : flexbed.files.table_reader.TableReader
        The scene's reader (its messages name the file).
    data : dict
        The parsed TOML (its ``body`` and ``mount`` tables already checked
        by the scene reader, which lets the limit keys through).
    names : list of str
        The bodies' names, base first.
    bed_name : str, optional
        The bed's body; ``off_bed(point)`` says whether a point in its
        drawing frame lies off the plate (checked where the bed needs it).
    """
    mounts = []
    for t in data.get("mount", []):
        where = f"mount {t['name']!r}"
        got = {}
        for key in MOUNT_LIMIT_KEYS[:2]:
            if key in t:
                got[key] = tuple(reader.numbers(where, key, t[key], 3, positive=True))
        for key in MOUNT_LIMIT_KEYS[2:4]:
            if key in t:
                got[key] = reader.number(where, key, t[key], positive=True)
        if "bump_stop" in t:
            got["bump_stop"] = _stops(reader, where, t["bump_stop"])
        if got:
            mounts.append(MountLimits(t["name"], got.get("stroke_compression"),
                                      got.get("stroke_extension"), got.get("rated_load"),
                                      got.get("max_force"),
                                      got.get("bump_stop", (None, None, None))))
    fragility = []
    for i, t in enumerate(data.get("body", [])):
        if "fragility" in t:
            fragility.append(_fragility(reader, f"body {t['name']!r}", t["fragility"],
                                        t["name"], i, bed_name, off_bed))
    allowable = None
    for t in data.get("body", []):
        if "allowable_stress" in t:
            allowable = _allowable(reader, t, bed_name, data.get("bed", {}))
    clearances = []
    for i, t in enumerate(reader.tables("clearance", data.get("clearance", []))):
        c = _clearance(reader, i, t, names, bed_name, off_bed)
        if any(c.name == o.name for o in clearances):
            reader.fail(f"clearance {c.name!r}", "name is used twice")
        clearances.append(c)
    return Limits(tuple(mounts), tuple(fragility), tuple(clearances), allowable)


def _allowable(reader, t: dict, bed_name, bed: dict) -> Allowable:
    """``allowable_stress`` on a body: the flexible bed's only, > 0 [Pa]."""
    where, key, value = f"body {t['name']!r}", "allowable_stress", t["allowable_stress"]
    if t["name"] != bed_name:
        reader.fail(where, f"{key}: only the bed's body carries stresses ([bed] body)")
    if bed.get("model", "rigid") != "flexible":
        reader.fail(where, f"{key} needs [bed] model = \"flexible\" (a rigid bed has no "
                           f"stresses)")
    if isinstance(value, dict):
        reader.keys(f"{where}: {key}", value, _ALLOWABLE_KEYS, ("plate",))
        plate = reader.number(where, f"{key}.plate", value["plate"], positive=True)
        stiff = reader.number(where, f"{key}.stiffeners", value.get("stiffeners", plate),
                              positive=True)
        return Allowable(t["name"], plate, stiff)
    v = reader.number(where, key, value, positive=True)
    return Allowable(t["name"], v, v)


def _stops(reader, where, value) -> tuple:
    """``bump_stop``: one table (or an array of them, one per direction)
    → 3 BumpStop or None."""
    tables = [value] if isinstance(value, dict) else value
    if not isinstance(tables, list) or not tables or \
            not all(isinstance(v, dict) for v in tables):
        reader.fail(where, f"bump_stop = {short_repr(value)} must be a table {{direction = …, "
                           f"gap_compression = …, stiffness = …}} or a list of them")
    stops = [None, None, None]
    for i, t in enumerate(tables):
        key = "bump_stop" if len(tables) == 1 else f"bump_stop[{i}]"
        reader.keys(f"{where}: {key}", t, _STOP_KEYS, ("direction", "stiffness"))
        d = t["direction"]
        if isinstance(d, bool) or d not in (1, 2, 3):
            reader.fail(where, f"{key}.direction = {short_repr(d)} must be 1, 2 or 3")
        if stops[d - 1] is not None:
            reader.fail(where, f"{key}: direction {d} has a bump stop already")
        if "gap_compression" not in t and "gap_extension" not in t:
            reader.fail(where, f"{key}: give gap_compression or gap_extension (or both)")
        args = {k: reader.number(where, f"{key}.{k}", t[k], positive=True)
                for k in ("gap_compression", "gap_extension", "stiffness") if k in t}
        args["damping"] = reader.number(where, f"{key}.damping", t.get("damping", 0.0),
                                        non_negative=True)
        stops[d - 1] = BumpStop(**args)
    return tuple(stops)


def _fragility(reader, where, value, body, index, bed_name, off_bed) -> Fragility:
    key = "fragility"
    if not isinstance(value, dict):
        reader.fail(where, f"{key} = {short_repr(value)} must be a table "
                           f"{{peak = …, units = \"g\"}}")
    reader.keys(f"{where}: {key}", value, _FRAGILITY_KEYS, ("peak",))
    if index == 0:
        reader.fail(where, f"{key}: the base carries no equipment (its motion is given); put "
                           f"the fragility on the body the mounts carry")
    units = reader.string(where, f"{key}.units", value.get("units", "m/s2"), tuple(UNITS))
    peak = reader.number(where, f"{key}.peak", value["peak"], positive=True)
    point = None
    if "point" in value:
        point = tuple(reader.numbers(where, f"{key}.point", value["point"], 3))
        _on_bed(reader, where, f"{key}.point", point, body, bed_name, off_bed)
    return Fragility(body, peak, units, point)


def _clearance(reader, i, t, names, bed_name, off_bed) -> Clearance:
    where = f"clearance {t['name']!r}" if isinstance(t.get("name"), str) else \
        f"clearance {i + 1}"
    reader.keys(where, t, CLEARANCE_KEYS, ("name", "body", "point", "other", "minimum"))
    name = reader.string(where, "name", t["name"])
    body = reader.string(where, "body", t["body"])
    other = reader.string(where, "other", t["other"])
    for key, b in (("body", body), ("other", other)):
        if b not in names:
            reader.fail(where, f"{key} = {b!r} is not a body (bodies: {', '.join(names)})")
    if other == body:
        reader.fail(where, f"other = {other!r} is the body itself: a clearance is between "
                           f"two bodies (or a body and the base)")
    point = tuple(reader.numbers(where, "point", t["point"], 3))
    _on_bed(reader, where, "point", point, body, bed_name, off_bed)
    given = [k for k in _SHAPES if k in t]
    if len(given) != 1:
        reader.fail(where, f"give exactly one of {', '.join(_SHAPES)} (the shape on "
                           f"{other!r}); got {', '.join(given) or 'none'}")
    minimum = reader.number(where, "minimum", t["minimum"], non_negative=True)
    kind = given[0]
    if kind == "other_point":
        xyz = tuple(reader.numbers(where, "other_point", t[kind], 3))
        _on_bed(reader, where, "other_point", xyz, other, bed_name, off_bed)
        return Clearance(name, body, point, other, "point", (xyz,), minimum)
    if kind == "plane":
        table = reader.keys(f"{where}: plane", t[kind], ("point", "normal"), ("point", "normal"))
        origin = tuple(reader.numbers(where, "plane.point", table["point"], 3))
        normal = np.array(reader.numbers(where, "plane.normal", table["normal"], 3))
        size = float(np.linalg.norm(normal))
        if not size > 0 or not math.isfinite(size):
            reader.fail(where, f"plane.normal = {normal.tolist()} must be a non-zero vector")
        return Clearance(name, body, point, other, "plane",
                         (origin, tuple((normal / size).tolist())), minimum)
    table = reader.keys(f"{where}: box", t[kind], ("min", "max"), ("min", "max"))
    lo = reader.numbers(where, "box.min", table["min"], 3)
    hi = reader.numbers(where, "box.max", table["max"], 3)
    for k in range(3):
        if not lo[k] < hi[k]:
            reader.fail(where, f"box.min[{k}] = {lo[k]!r} must be < box.max[{k}] = {hi[k]!r}")
    return Clearance(name, body, point, other, "box", (tuple(lo), tuple(hi)), minimum)


def _on_bed(reader, where, key, point, body, bed_name, off_bed) -> None:
    if off_bed is not None and body == bed_name and off_bed(list(point)):
        reader.fail(where, f"{key} = {list(point)} m is off the bed (outside its outline or "
                           f"in a cut-out)")


def check_static_strokes(label: str, limits: Limits, mount_names, dx: np.ndarray) -> None:
    """Refuse a stroke limit the static equilibrium already uses up.

    Parameters
    ----------
    label : str
        The scene file's name, as messages show it.
    limits : Limits
    mount_names : sequence of str
    dx : ndarray (M, 3)
        The mounts' static deflections [m].

    Raises
    ------
    InputError
        One line naming the file, the mount, the key and the value.
    """
    for m, name in enumerate(mount_names):
        lim = limits.mount(name)
        for key, stroke, sign, word in (("stroke_compression", lim.compression, -1.0,
                                         "compression"),
                                        ("stroke_extension", lim.extension, 1.0, "extension")):
            if stroke is None:
                continue
            for k in range(3):
                used = sign * float(dx[m, k])
                if used > stroke[k]:
                    raise InputError(f"{label}: mount {name!r}: {key}[{k}] = {stroke[k]:g} m is "
                                     f"smaller than the static deflection in direction {k + 1}, "
                                     f"{used:.6g} m of {word}: the mount is past its stroke "
                                     f"at rest")
