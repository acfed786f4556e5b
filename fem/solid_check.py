"""The shell against the 3D solid (:mod:`flexbed.fem.solid`): the two
checked beds, their modes sampled on the mid-surface, and modes matched by
shape (MAC), not by index.

* ``"stiffened"``: the reference bed (0.8 × 4.8 × 0.1 m steel) with two
  flat bars 100 × 20 mm under it along its length at x = ±0.2 m (they
  raise the vertical bending modes by 22–24 %);
* ``"cutout"``: the reference bed with a 0.2 × 0.8 m rectangular hole at
  (0.1, 1.0) m (x from 0 to 0.2, y from 0.6 to 1.4).

Shapes are compared through the translations (u, v, w) of the mid-surface
at a grid of points that are nodes of every solid mesh (x every 0.2 m, y
every 0.2 m, the hole's inside left out) — the web's own motion is not
sampled, so a local web mode matches no plate mode.
"""

from __future__ import annotations

import numpy as np

from .geometry import BedGeometry, Region
from .solid import SolidBed, SolidModes, Web
from .spec import PlateSpec
from .stiffeners import Stiffener, section_of

#: flat bars under the stiffened bed: centre x [m], width [m], height [m]
BARS = ((-0.2, 0.02, 0.1), (0.2, 0.02, 0.1))
#: the cut-out bed's hole: x0, x1, y0, y1 [m]
HOLE = (0.0, 0.2, 0.6, 1.4)
CASES = ("stiffened", "cutout")


def solid_bed(case: str) -> SolidBed:
    """The solid model of a case."""
    if case == "stiffened":
        return SolidBed(webs=tuple(Web(x, w, h) for x, w, h in BARS))
    if case == "cutout":
        return SolidBed(hole=HOLE)
    if case == "plain":
        return SolidBed()
    raise ValueError(f"case = {case!r} must be one of {CASES + ('plain',)}")


def shell_spec(case: str, element_size: float = 0.05) -> PlateSpec:
    """The Mindlin shell of a case: the bars as flat-bar stiffeners on the
    plate's lower face (offset −(t/2 + h/2)), the hole as a cut-out."""
    if case == "stiffened":
        n = round(0.8 / element_size)
        sts = tuple(Stiffener(f"bar{i}", (x, -2.4), (x, 2.4), section_of("flat", height=h, width=w),
                              -(0.05 + h / 2)) for i, (x, w, h) in enumerate(BARS))
        return PlateSpec(theory="mindlin", nx=n, ny=6 * n, stiffeners=sts)
    if case == "cutout":
        x0, x1, y0, y1 = HOLE
        hole = Region("rectangle", (0.5 * (x0 + x1), 0.5 * (y0 + y1)), size=(x1 - x0, y1 - y0))
        return PlateSpec(theory="mindlin",
                         geometry=BedGeometry(cutouts=(hole,), element_size=element_size))
    if case == "plain":
        n = round(0.8 / element_size)
        return PlateSpec(theory="mindlin", nx=n, ny=6 * n)
    raise ValueError(f"case = {case!r} must be one of {CASES + ('plain',)}")


def sample_points(case: str) -> np.ndarray:
    """Mid-surface points (P, 2) [m], drawing frame: x every 0.2 m, y every
    0.2 m, the points strictly inside the hole left out."""
    X, Y = np.meshgrid(np.linspace(-0.4, 0.4, 5), np.linspace(-2.4, 2.4, 25))
    p = np.column_stack([X.ravel(), Y.ravel()])
    if case == "cutout":
        x0, x1, y0, y1 = HOLE
        tol = 1e-9
        p = p[~((p[:, 0] > x0 + tol) & (p[:, 0] < x1 - tol)
                & (p[:, 1] > y0 + tol) & (p[:, 1] < y1 - tol))]
    return p


def solid_shapes(modes: SolidModes, points: np.ndarray) -> np.ndarray:
    """Solid mode translations at mid-surface points, flattened (n, 3P)."""
    return modes.midsurface(points).reshape(len(modes.frequency), -1)


def shell_shapes(bed, points: np.ndarray) -> np.ndarray:
    """Shell mode translations at mid-surface points (drawing frame) of a
    :class:`~flexbed.fem.bed.BedModes`, flattened (n, 3P)."""
    from .quad_shapes import QuadShapes
    mid_z = float(bed.nodes[0, 2])
    q = QuadShapes(bed.nodes[:, :2], bed.cells, bed.translation, bed.rotation, mid_z)
    pts = np.column_stack([points - bed.origin, np.full(len(points), mid_z)])
    return q.at(pts)[0].reshape(bed.translation.shape[0], -1)


def mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion of every pair of rows, (na, nb) in [0, 1]."""
    num = (a @ b.T) ** 2
    return num / np.outer(np.sum(a * a, axis=1), np.sum(b * b, axis=1))


def match(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each row of ``a`` the row of ``b`` most like it: (index (na,), MAC (na,))."""
    m = mac(a, b)
    j = np.argmax(m, axis=1)
    return j, m[np.arange(len(j)), j]
