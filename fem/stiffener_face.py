"""Which face a stiffener sits on: the plate's thickness along its line.

A flat, T or I stiffener is welded to the plate's lower (or upper) face,
so its centroid is t/2 + c from the mid-surface, t the *local* thickness:
a thickness zone under the stiffener moves it. The thickness must be one
along the whole line and on both sides of it (a line that crosses a
zone's edge, or runs along one, has no single face to sit on).
"""

from __future__ import annotations

import numpy as np

from .geometry import GeometryError, Zone, inside


def _crossings(a: np.ndarray, d: np.ndarray, poly: np.ndarray) -> list[float]:
    """Parameters s in (0, 1) where a + s d crosses an edge of the polygon."""
    out = []
    for p, q in zip(poly, np.roll(poly, -1, axis=0)):
        e = q - p
        den = d[0] * e[1] - d[1] * e[0]
        if abs(den) <= 1e-14 * np.linalg.norm(d) * np.linalg.norm(e):
            continue                                            # parallel
        r = p - a
        s = (r[0] * e[1] - r[1] * e[0]) / den
        u = (r[0] * d[1] - r[1] * d[0]) / den
        if 0.0 < s < 1.0 and -1e-12 <= u <= 1.0 + 1e-12:
            out.append(float(s))
    return out


def face_thickness(start, end, zones: tuple[Zone, ...], nominal: float,
                   element_size: float) -> float:
    """The plate's thickness under the stiffener from ``start`` to ``end``
    (drawing frame) [m].

    Parameters
    ----------
    start, end : (x, y)
        Its line [m].
    zones : tuple of Zone
        The bed's thickness zones (later ones win where they overlap), as
        the mesher sees them (circles as their polygons at ``element_size``).
    nominal : float
        The thickness outside zones [m].
    element_size : float
        The mesh's element side [m] (sets a circle's polygon).

    Raises
    ------
    GeometryError
        The thickness changes along the line or from one side to the other.
    """
    a, b = np.asarray(start, float), np.asarray(end, float)
    d = b - a
    L = float(np.hypot(*d))
    n = np.array([-d[1], d[0]]) / L
    polys = [(z.region.polygon(element_size), z.thickness) for z in zones]
    s = sorted({0.0, 1.0} | {c for poly, _ in polys for c in _crossings(a, d, poly)})
    mid = 0.5 * (np.array(s[:-1]) + np.array(s[1:]))
    eps = 1e-6 * L
    seen = set()
    for side in (1.0, -1.0):
        pts = a + mid[:, None] * d + side * eps * n
        t = np.full(len(pts), float(nominal))
        for poly, tz in polys:
            t[inside(poly, pts)] = tz
        seen |= set(t.tolist())
    if len(seen) > 1:
        shown = ", ".join(f"{v:g}" for v in sorted(seen))
        raise GeometryError("stiffener", f"from {list(start)} to {list(end)} m it lies on "
                                         f"plate of thickness {shown} m (it crosses or runs "
                                         f"along a zone's edge): split it where the thickness "
                                         f"changes, or give section = \"general\" with its "
                                         f"offset")
    return seen.pop()
