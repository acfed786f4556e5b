"""The scene file's loads on bodies: ``[[load]]`` (a force or a moment at a
body point, any time shape of ``[[base.force]]``, or ``shape =
"harmonic"``: an order of a running speed) and ``[[unbalance]]`` (a
rotating unbalance m·e at a running speed, or over a run-up), read into
:class:`flexbed.dynamics.body_loads.BodyLoad` entries.

Points are in the body's frame [m]; on the bed, in the bed's drawing frame
(as mounts' points are), moved here to its centre-of-mass frame and refused
off the bed.
"""

from __future__ import annotations

import math

import numpy as np

from flexbed.dynamics.body_loads import FRAMES, QUANTITIES, BodyLoad, harmonic, unbalance
from flexbed.dynamics.errors import SceneError
from flexbed.dynamics.scene import DIRECTIONS

from flexbed.files.drives import ALL_SHAPE_KEYS

__all__ = ["read_loads", "LOAD_KEYS", "UNBALANCE_KEYS", "HARMONIC_KEYS"]

_PLACE_KEYS = ("name", "body", "point", "frame", "quantity")
HARMONIC_KEYS = ("speed", "order", "amplitude", "phase_deg", "start", "duration")
LOAD_KEYS = _PLACE_KEYS + tuple(k for k in ALL_SHAPE_KEYS if k != "units") + ("speed", "order")
UNBALANCE_KEYS = ("name", "body", "point", "axis", "mass_radius", "speed", "runup", "phase_deg",
                  "start", "duration")


def read_loads(reader, data: dict, names: list, bed_name: str | None, centre, off_bed) -> tuple:
    """The ``[[load]]`` and ``[[unbalance]]`` entries of a parsed scene file.

    Parameters
    ----------
    reader : ShapeReader
        The scene file's reader (its ``fail`` raises the one-line error).
    data : dict
        The parsed TOML.
    names : list of str
        The bodies' names, the base first.
    bed_name : str or None
        The bed's body, whose points are in its drawing frame.
    centre : callable
        ``centre()``: the bed's centre of mass in its drawing frame (3,) [m]
        (asked only for a load on the bed).
    off_bed : callable or None
        ``off_bed(point) -> bool`` for a bed that refuses points off it.

    Returns
    -------
    tuple of BodyLoad
    """
    out = []
    used = set()
    for i, t in enumerate(reader.tables("load", data.get("load", []))):
        where = _where("load", i, t)
        reader.keys(where, t, LOAD_KEYS, ("body", "direction", "shape"))
        name, body, point = _place(reader, where, t, names, used, f"load {i + 1}")
        frame = reader.string(where, "frame", t.get("frame", "inertial"), FRAMES)
        quantity = reader.string(where, "quantity", t.get("quantity", "force"), QUANTITIES)
        direction = DIRECTIONS.index(reader.string(where, "direction", t["direction"],
                                                   DIRECTIONS))
        point = _on_bed(reader, where, body, point, bed_name, centre, off_bed)
        try:
            if t["shape"] == "harmonic":
                out.append(_harmonic(reader, where, t, name, body, point, direction, frame,
                                     quantity))
                continue
            for key in ("speed", "order"):
                if key in t:
                    reader.fail(where, f"key '{key}' applies to shape = 'harmonic' only")
            shape_table = {k: v for k, v in t.items() if k not in _PLACE_KEYS}
            terms = reader.terms(where, shape_table, "force")
            out += [BodyLoad(body, point, direction, s, frame, quantity, name) for s in terms]
        except SceneError as exc:
            reader.fail(where, str(exc))
    for i, t in enumerate(reader.tables("unbalance", data.get("unbalance", []))):
        where = _where("unbalance", i, t)
        reader.keys(where, t, UNBALANCE_KEYS, ("body", "axis", "mass_radius", "speed"))
        name, body, point = _place(reader, where, t, names, used, f"unbalance {i + 1}")
        point = _on_bed(reader, where, body, point, bed_name, centre, off_bed)
        axis = DIRECTIONS.index(reader.string(where, "axis", t["axis"], DIRECTIONS))
        me = reader.number(where, "mass_radius", t["mass_radius"], positive=True)
        speed = t["speed"]
        runup = None
        if isinstance(speed, list):
            speeds = reader.numbers(where, "speed", speed, 2, non_negative=True)
            if "runup" not in t:
                reader.fail(where, f"speed = {speed!r}: two speeds (a run-up) need 'runup', "
                                   f"its time [s]")
            runup = reader.number(where, "runup", t["runup"], positive=True)
            if "duration" in t:
                reader.fail(where, "duration does not apply to a run-up (the machine runs on "
                                   "at the top speed)")
            speed = speeds
        else:
            if "runup" in t:
                reader.fail(where, f"runup = {t['runup']!r} needs two speeds, "
                                   f"speed = [from, to] [Hz]")
            speed = reader.number(where, "speed", speed)
            if not speed > 0.0:
                reader.fail(where, f"speed = {speed!r} Hz must be > 0 (a running speed)")
        phase = math.radians(reader.number(where, "phase_deg", t.get("phase_deg", 0.0)))
        start = reader.number(where, "start", t.get("start", 0.0), non_negative=True)
        duration = (reader.number(where, "duration", t["duration"], positive=True)
                    if "duration" in t else math.inf)
        try:
            out += list(unbalance(name, body, point, axis, me, speed, phase, start, duration,
                                  runup))
        except SceneError as exc:
            reader.fail(where, str(exc))
    return tuple(out)


def _where(kind: str, i: int, t) -> str:
    if isinstance(t, dict) and isinstance(t.get("name"), str):
        return f"{kind} {t['name']!r}"
    return f"{kind} {i + 1}"


def _place(reader, where: str, t: dict, names: list, used: set, default: str):
    """(name, body, point) of an entry, the body checked: a body of the
    scene, not the base."""
    name = reader.string(where, "name", t["name"]) if "name" in t else default
    if name in used:
        reader.fail(where, "name is used twice")
    used.add(name)
    body = reader.string(where, "body", t["body"])
    if body not in names:
        reader.fail(where, f"body = {body!r} is not a body (bodies: {', '.join(names)})")
    if body == names[0]:
        reader.fail(where, f"body = {body!r} is the base: loads on a (free) base are "
                           f"[[base.force]] entries")
    point = np.array(reader.numbers(where, "point", t.get("point", [0.0, 0.0, 0.0]), 3))
    return name, body, point


def _on_bed(reader, where, body, point, bed_name, centre, off_bed):
    """A bed point from the drawing frame to the bed's frame (checked on it)."""
    if body != bed_name:
        return point
    if off_bed is not None and off_bed(point):
        reader.fail(where, f"point = {point.tolist()} m is off the bed (outside its outline "
                           f"or in a cut-out)")
    return point - np.asarray(centre(), dtype=float)


def _harmonic(reader, where, t, name, body, point, direction, frame, quantity) -> BodyLoad:
    allowed = set(_PLACE_KEYS) | {"direction", "shape"} | set(HARMONIC_KEYS)
    for key in t:
        if key not in allowed:
            reader.fail(where, f"key '{key}' does not apply to shape = 'harmonic' "
                               f"(known: {', '.join(sorted(allowed))})")
    for key in ("speed", "order", "amplitude"):
        if key not in t:
            reader.fail(where, f"'{key}' is required for shape = 'harmonic'")
    speed = reader.number(where, "speed", t["speed"])
    if not speed > 0.0:
        reader.fail(where, f"speed = {speed!r} Hz must be > 0 (a running speed)")
    order = reader.number(where, "order", t["order"], positive=True)
    amplitude = reader.number(where, "amplitude", t["amplitude"])
    phase = math.radians(reader.number(where, "phase_deg", t.get("phase_deg", 0.0)))
    start = reader.number(where, "start", t.get("start", 0.0), non_negative=True)
    duration = (reader.number(where, "duration", t["duration"], positive=True)
                if "duration" in t else math.inf)
    return harmonic(name, body, point, direction, amplitude, speed, order, phase, start,
                    duration, frame, quantity)
