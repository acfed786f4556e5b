"""The bed as it is built: an outline, cut-outs and thickness zones, or a
mesh from the user's own mesher — as frozen data with a hash.

Coordinates are the *drawing frame* the user writes them in [m]. The
mesher (:mod:`flexbed.fem.mesher`) turns a :class:`BedGeometry` into
bilinear quadrilaterals; the model then moves its origin to the bed's
centre of mass (:mod:`flexbed.fem.mass_properties`).

A circle is meshed as the regular polygon of :func:`Region.polygon`
(k ≥ 24 vertices, at most about ``element_size`` apart) whose area is
exactly πr² (its vertices sit at r √(2π / (k sin(2π/k))), 0.4 % outside the
circle at k = 24); the second moments of area differ from the disc's by
O(1/k²) (0.3 % at k = 24).
Thickness zones are symmetric about the mid-surface.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

SHAPES = ("rectangle", "circle", "polygon")
#: the largest coordinate magnitude of a bed [m]: past a thousand kilometres
#: a number is a unit slip, and the bed's ρ t L⁴ stays far inside double
#: precision
MAX_COORDINATE = 1e6
#: the smallest extent of a polygon or region, and the smallest element
#: size [m]: below a micrometre a feature is a typing slip, and the mesher's
#: rounding (1e-12 m) stays far below it
MIN_EXTENT = 1e-6


class GeometryError(ValueError):
    """A geometry input out of its range; ``entry`` names the key."""

    def __init__(self, entry: str, message: str):
        super().__init__(message)
        self.entry = entry


def _points(entry: str, value) -> tuple[tuple[float, float], ...]:
    """A simple polygon's points, checked
    (:func:`flexbed.fem.mesh_checks.check_polygon`)."""
    from .mesh_checks import check_polygon
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise GeometryError(entry, f"{entry} = {_short(value)} must be a list of [x, y] "
                                   f"points") from None
    if arr.ndim != 2 or arr.shape[1] != 2 or arr.shape[0] < 3:
        raise GeometryError(entry, f"{entry} = {_short(value)} must be at least 3 [x, y] "
                                   f"points")
    check_polygon(entry, arr)
    return tuple((float(x), float(y)) for x, y in arr)


def _short(value) -> str:
    """repr of a value, cut to 120 characters."""
    text = repr(value)
    return text if len(text) <= 120 else text[:100] + " ... " + text[-15:]


def _extent_check(entry: str, value: float) -> None:
    if not MIN_EXTENT <= value <= MAX_COORDINATE:
        raise GeometryError(entry, f"{entry} = {value!r} m must lie within {MIN_EXTENT:g} to "
                                   f"{MAX_COORDINATE:g} m (coordinates in metres)")


def file_digest(path: str | Path) -> str:
    """SHA-256 of a file's bytes (hex), read in pieces of 1 MiB (a mesh file
    of gigabytes is hashed without holding it)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def signed_area(poly: np.ndarray) -> float:
    """Shoelace area of a polygon (k, 2), positive when counter-clockwise [m²]."""
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def inside(poly: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Even–odd test: which points (P, 2) lie strictly inside the polygon (k, 2)."""
    x, y = pts[:, 0][:, None], pts[:, 1][:, None]
    x0, y0 = poly[:, 0][None, :], poly[:, 1][None, :]
    x1, y1 = np.roll(poly[:, 0], -1)[None, :], np.roll(poly[:, 1], -1)[None, :]
    crosses = (y0 > y) != (y1 > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
    return np.sum(crosses & (x < xc), axis=1) % 2 == 1


@dataclass(frozen=True, slots=True)
class Region:
    """A rectangle (centre, size), a circle (centre, radius) or a polygon
    (points), in the drawing frame [m]."""

    shape: str
    centre: tuple[float, float] = (0.0, 0.0)
    size: tuple[float, float] | None = None
    radius: float | None = None
    points: tuple[tuple[float, float], ...] | None = None

    def __post_init__(self) -> None:
        if self.shape not in SHAPES:
            raise GeometryError("shape", f"shape = {self.shape!r} must be one of "
                                         + ", ".join(f'"{s}"' for s in SHAPES))
        c = np.array(self.centre, dtype=float)
        if c.shape != (2,) or not np.all(np.isfinite(c)):
            raise GeometryError("centre", f"centre = {self.centre!r} must be [x, y]")
        object.__setattr__(self, "centre", (float(c[0]), float(c[1])))
        if np.abs(c).max() > MAX_COORDINATE:
            raise GeometryError("centre", f"centre = {self.centre!r} m is beyond "
                                          f"{MAX_COORDINATE:g} m (coordinates in metres)")
        if self.shape == "rectangle":
            s = np.array(self.size if self.size is not None else [], dtype=float)
            if s.shape != (2,) or not np.all(np.isfinite(s) & (s > 0)):
                raise GeometryError("size", f"size = {self.size!r} must be [a, b] > 0 for a "
                                            f"rectangle")
            object.__setattr__(self, "size", (float(s[0]), float(s[1])))
            for v in self.size:
                _extent_check("size", v)
        elif self.shape == "circle":
            r = self.radius
            if isinstance(r, bool) or not isinstance(r, (int, float)) or not (
                    math.isfinite(r) and r > 0):
                raise GeometryError("radius", f"radius = {r!r} must be a number > 0 for a "
                                              f"circle")
            object.__setattr__(self, "radius", float(r))
            _extent_check("radius", self.radius)
        else:
            object.__setattr__(self, "points", _points("points", self.points))

    def polygon(self, element_size: float) -> np.ndarray:
        """Counter-clockwise vertices (k, 2) [m]."""
        cx, cy = self.centre
        if self.shape == "rectangle":
            a, b = self.size[0] / 2, self.size[1] / 2
            return np.array([[cx - a, cy - b], [cx + a, cy - b], [cx + a, cy + b],
                             [cx - a, cy + b]])
        if self.shape == "circle":
            k = max(24, int(math.ceil(2 * math.pi * self.radius / element_size)))
            ang = 2 * math.pi * np.arange(k) / k
            # vertices just outside the circle, so the k-gon's area is πr²
            R = self.radius * math.sqrt(2 * math.pi / (k * math.sin(2 * math.pi / k)))
            return np.column_stack([cx + R * np.cos(ang), cy + R * np.sin(ang)])
        poly = np.array(self.points)
        return poly if signed_area(poly) > 0 else poly[::-1].copy()

    def describe(self) -> str:
        """One line naming the region."""
        if self.shape == "rectangle":
            return f"rectangle {self.size[0]:g} x {self.size[1]:g} m at {self.centre}"
        if self.shape == "circle":
            return f"circle r = {self.radius:g} m at {self.centre}"
        return f"polygon of {len(self.points)} points"


@dataclass(frozen=True, slots=True)
class Zone:
    """A region of another thickness [m] (symmetric about the mid-surface)."""

    region: Region
    thickness: float

    def __post_init__(self) -> None:
        t = self.thickness
        if isinstance(t, bool) or not isinstance(t, (int, float)) or not (
                math.isfinite(t) and t > 0):
            raise GeometryError("thickness", f"thickness = {t!r} must be a number > 0 [m]")
        object.__setattr__(self, "thickness", float(t))


@dataclass(frozen=True, slots=True)
class BedGeometry:
    """What the bed looks like in plan.

    Parameters
    ----------
    outline : tuple of (x, y) or None
        The outer boundary, a polygon [m] (None: the length_x × length_y
        rectangle centred on the origin).
    cutouts : tuple of Region
        Holes through the plate.
    zones : tuple of Zone
        Regions of another thickness; where zones overlap the later one
        counts.
    element_size : float or None
        Target element side [m] (None: the plate's nx × ny grid spacing).
    mesh_file : str or None
        A mesh read with meshio instead of the outline (quads and
        triangles, z ignored); with its SHA-256 in ``mesh_digest``.
    mesh_digest : str or None
    """

    outline: tuple[tuple[float, float], ...] | None = None
    cutouts: tuple[Region, ...] = ()
    zones: tuple[Zone, ...] = ()
    element_size: float | None = None
    mesh_file: str | None = None
    mesh_digest: str | None = None

    def __post_init__(self) -> None:
        if self.outline is not None:
            object.__setattr__(self, "outline", _points("outline", self.outline))
        h = self.element_size
        if h is not None and (isinstance(h, bool) or not isinstance(h, (int, float))
                              or not (math.isfinite(h) and h > 0)):
            raise GeometryError("element_size", f"element_size = {h!r} must be a number > 0 "
                                                f"[m]")
        if h is not None:
            object.__setattr__(self, "element_size", float(h))
            _extent_check("element_size", self.element_size)
        if self.mesh_file is not None and (self.outline is not None or self.cutouts):
            raise GeometryError("mesh_file", "give either mesh_file or outline/cutout, "
                                             "not both")
        if self.mesh_file is not None and self.mesh_digest is None:
            path = Path(self.mesh_file)
            if path.exists() and not path.is_file():      # a FIFO would block the read
                kind = "a folder" if path.is_dir() else "a FIFO, device or socket"
                raise GeometryError("mesh_file", f"mesh_file = {self.mesh_file!r} is {kind}, "
                                                 f"not a mesh file")
            try:
                digest = file_digest(self.mesh_file)
            except OSError as exc:
                raise GeometryError("mesh_file", f"mesh_file = {self.mesh_file!r}: cannot read "
                                                 f"it ({exc.strerror or exc})") from None
            object.__setattr__(self, "mesh_digest", digest)
        object.__setattr__(self, "cutouts", tuple(self.cutouts))
        object.__setattr__(self, "zones", tuple(self.zones))

    @property
    def is_plain(self) -> bool:
        """True when nothing but the rectangle and its grid is asked for."""
        return (self.outline is None and not self.cutouts and not self.zones
                and self.element_size is None and self.mesh_file is None
                and self.mesh_digest is None)
