"""What every metric kind shares: the keys, checked against the scene —
the options of a ``[[metric]]`` table (unknown keys refused, ``name``), a
body by name, a point (a scene ``[[point]]`` or a body and a position, with
``relative_to``) — and the columns and units a kind makes
(:class:`OneColumn`, :class:`PerMount`). Used by
:mod:`flexbed.study.metrics` and :mod:`flexbed.study.frequency_metrics`."""

from __future__ import annotations


from flexbed.errors import InputError
from flexbed.files.scene import SceneFile
from flexbed.files.table_reader import is_finite_number
from flexbed.study.spec import MetricTable

__all__ = ["resolve_point", "OneColumn", "PerMount"]


def _options(table: MetricTable, keys: tuple, where: str) -> dict:
    opts = dict(table.options)
    for key in opts:
        if key not in keys + ("name",):
            raise InputError(f"{where}: unknown key {key!r} for kind {table.kind!r} "
                             f"(known: {', '.join(keys + ('name',))})")
    name = opts.get("name")
    if name is not None and (not isinstance(name, str) or not name):
        raise InputError(f"{where}: name = {name!r} must be a non-empty string")
    return opts


def _body(scene: SceneFile, name, where: str, key: str) -> str:
    names = [b.name for b in scene.scene.bodies]
    if not isinstance(name, str) or name not in names:
        raise InputError(f"{where}: {key} = {name!r} is not a body of the scene "
                         f"(bodies: {', '.join(names)})")
    return name


def resolve_point(scene: SceneFile, opts: dict, where: str,
                  point_relative: bool = True) -> tuple:
    """A metric's point: a scene ``[[point]]`` by ``point = NAME`` or
    ``body`` + ``position`` [m, body frame], with an optional
    ``relative_to`` body (a scene point's own ``relative_to`` is the default
    when ``point_relative``). Returns (body, position, relative_to, label)."""
    if "point" in opts:
        for key in ("body", "position"):
            if key in opts:
                raise InputError(f"{where}: give point, or body and position, not both")
        pts = {p.name: p for p in scene.points}
        if not isinstance(opts["point"], str) or opts["point"] not in pts:
            raise InputError(f"{where}: point = {opts['point']!r} is not a [[point]] of the "
                             f"scene (points: {', '.join(pts) or 'none'})")
        p = pts[opts["point"]]
        body, pos, label = p.body, tuple(p.position), p.name
        rel = opts.get("relative_to", p.relative_to if point_relative else None)
    else:
        if "body" not in opts or "position" not in opts:
            raise InputError(f"{where}: give point = NAME, or body and position")
        body = _body(scene, opts["body"], where, "body")
        pos = opts["position"]
        if (not isinstance(pos, list) or len(pos) != 3
                or not all(is_finite_number(x) for x in pos)):
            raise InputError(f"{where}: position = {pos!r} must be 3 finite numbers [m]")
        pos, rel = tuple(float(x) for x in pos), opts.get("relative_to")
        label = f"{body} ({' '.join(f'{x:g}' for x in pos)})"
    if rel is not None:
        _body(scene, rel, where, "relative_to")
    return body, pos, rel, label


class OneColumn:
    """A kind that makes one column: ``columns`` is (``column``,), ``units``
    (``unit``,); the kind gives ``column`` (a field) and ``unit`` (a class
    attribute, or a property when it depends on the options)."""

    @property
    def columns(self) -> tuple:
        return (self.column,)

    @property
    def units(self) -> tuple:
        return (self.unit,)


class PerMount:
    """A kind that makes one column per mount of ``names``:
    ``<kind>.<mount>[.axisK]``, or ``label`` (the metric's ``name``, one
    mount only), each in ``unit``."""

    @property
    def columns(self) -> tuple:
        if self.label:
            return (self.label,)
        ax = f".axis{self.axis}" if self.axis else ""
        return tuple(f"{self.kind}.{m}{ax}" for m in self.names)

    @property
    def units(self) -> tuple:
        return (self.unit,) * len(self.names)
