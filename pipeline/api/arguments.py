"""The API's arguments checked at the boundary: one line naming the
function, the argument and the value, as a scene file's entries are.

A library call with a wrong argument must fail as the command line does —
:class:`flexbed.errors.InputError` with one line such as
``flexbed.simulate: t_end = '1.0' must be a number`` — never with a
``TypeError`` from deep inside, and never be accepted silently (a string
where a number belongs, a misspelt choice). :class:`Arguments` is the
scene reader's :class:`~flexbed.files.table_reader.TableReader` with the
function's name in place of the file's, so both say the same thing about
the same value.

Points have one form in every function:
``(name, body, position)`` or ``(name, body, position, relative_to)``,
``position`` three numbers [m] in the body's frame (a
:class:`~flexbed.analyses.points.Point` is taken too).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

import numpy as np

from flexbed.analyses.points import Point
from flexbed.files.modes import ModesData
from flexbed.files.scene import SceneFile
from flexbed.files.table_reader import TableReader, is_number, short_repr

__all__ = ["Arguments"]

#: the tuple form of a point, as messages show it
POINT_FORM = "(name, body, [x, y, z]) or (name, body, [x, y, z], relative_to), metres"


class Arguments(TableReader):
    """Checks of one call's arguments; messages start ``flexbed.<function>:``.

    Parameters
    ----------
    function : str
        The function's name as users call it (``"simulate"``,
        ``"Results.point"``).
    """

    def __init__(self, function: str):
        super().__init__(f"flexbed.{function}", Path.cwd())

    def bad(self, key: str, value: Any, expected: str):
        """Refuse ``key = value``: it must be ``expected``."""
        self.fail("", f"{key} = {short_repr(value)} must be {expected}")

    # objects -----------------------------------------------------------
    def scene(self, value: Any, key: str = "scene") -> SceneFile:
        if isinstance(value, SceneFile):
            return value
        if isinstance(value, (str, Path)):
            self.bad(key, value, f"a scene: read the file with flexbed.load_scene({str(value)!r})")
        self.bad(key, value, "a scene from flexbed.load_scene or flexbed.vary")

    def modes(self, value: Any, key: str = "modes") -> ModesData | None:
        if value is None or isinstance(value, ModesData):
            return value
        if isinstance(value, (str, Path)):
            self.bad(key, value, f"modes from flexbed.modes(scene, file={str(value)!r})")
        self.bad(key, value, "the bed's modes from flexbed.modes(scene), or None")

    def path(self, value: Any, key: str, *, optional: bool = True) -> Path | None:
        if value is None and optional:
            return None
        if isinstance(value, (str, Path)) and str(value):
            return Path(value)
        self.bad(key, value, "a file name (str or pathlib.Path)")

    def callback(self, value: Any, key: str):
        if value is None or callable(value):
            return value
        self.bad(key, value, "a function (callable) or None")

    # values ------------------------------------------------------------
    def flag(self, value: Any, key: str, *, optional: bool = False) -> bool | None:
        if value is None and optional:
            return None
        if isinstance(value, (bool, np.bool_)):
            return bool(value)
        self.bad(key, value, "True or False")

    def choice(self, value: Any, key: str, choices: Sequence[str]) -> str | None:
        if value is None:
            return None
        return self.string("", key, value, tuple(choices))

    def real(self, value: Any, key: str, *, positive: bool = False,
             optional: bool = True) -> float | None:
        if value is None and optional:
            return None
        if isinstance(value, np.generic) and np.ndim(value) == 0:
            value = value.item()
        return self.number("", key, value, positive=positive)

    def integer(self, value: Any, key: str, *, minimum: int, maximum: int,
                optional: bool = False) -> int | None:
        if value is None and optional:
            return None
        if isinstance(value, np.integer):
            value = int(value)
        if isinstance(value, bool) or not isinstance(value, int):
            self.bad(key, value, "an integer")
        if not minimum <= value <= maximum:
            self.bad(key, value, f"from {minimum} to {maximum:,}")
        return value

    def band(self, value: Any, key: str = "band") -> tuple[float, float] | None:
        if value is None:
            return None
        if isinstance(value, (str, bytes)) or not _sequence(value) or len(value) != 2:
            self.bad(key, value, "(f_min, f_max) in Hz, two numbers")
        lo = self.real(value[0], f"{key}[0]", positive=True, optional=False)
        hi = self.real(value[1], f"{key}[1]", positive=True, optional=False)
        if not lo < hi:
            self.bad(key, value, "(f_min, f_max) with f_min < f_max")
        return lo, hi

    def position(self, value: Any, key: str) -> np.ndarray:
        """Three finite numbers [m] → (3,) array."""
        if isinstance(value, (str, bytes)) or not _sequence(value) or len(value) != 3 \
                or not all(is_number(v) or isinstance(v, np.number) for v in value):
            self.bad(key, value, "three numbers [x, y, z] in metres")
        xyz = np.array([float(v) for v in value])
        if not np.all(np.isfinite(xyz)):
            self.bad(key, value, "three finite numbers [x, y, z] in metres")
        return xyz

    def name(self, value: Any, key: str) -> str:
        return self.string("", key, value)

    def point(self, value: Any, key: str) -> tuple[Point, str | None]:
        """A point in the one tuple form (or a Point) → (Point, relative_to)."""
        if isinstance(value, Point):
            return value, value.relative_to
        if isinstance(value, (str, bytes)) or not _sequence(value) or len(value) not in (3, 4):
            self.bad(key, value, POINT_FORM)
        name = self.name(value[0], f"{key} name")
        body = self.name(value[1], f"{key} body")
        xyz = self.position(value[2], f"{key} position")
        rel = self.name(value[3], f"{key} relative_to") if len(value) == 4 and value[3] \
            is not None else None
        return Point(name, body, xyz, rel), rel

    def points(self, value: Any, key: str) -> list[tuple[Point, str | None]] | None:
        """One point or a list of them, each as :meth:`point`."""
        if value is None:
            return None
        if isinstance(value, Point) or (_sequence(value) and len(value) in (3, 4)
                                         and isinstance(value[0], str)
                                         and not isinstance(value[1], (Point, tuple, list))):
            return [self.point(value, key)]
        if isinstance(value, (str, bytes)) or not _sequence(value) or not len(value):
            self.bad(key, value, f"a point {POINT_FORM}, or a list of them")
        return [self.point(p, f"{key}[{i}]") for i, p in enumerate(value)]


def _sequence(value: Any) -> bool:
    return isinstance(value, (list, tuple, np.ndarray))
