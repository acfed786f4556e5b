"""The meshes ``element_size = "auto"`` chooses from: the bed at one element
size h, with nodes where the bed needs them.

:func:`mesh_spec` turns an auto :class:`~flexbed.fem.spec.PlateSpec` (its
``mesh_tolerance`` set) into the plain spec of one mesh: the outline,
cut-outs and zones meshed at ``element_size = h`` by
:func:`flexbed.fem.mesher.mesh_bed`, whose grid lines (or, for slanted and
curved edges, whose constraint points) pass through

* the stiffeners, end to end (as for any element_size mesh);
* the fixed masses' and the mount points' (x, y) (``mesh_points``);
* on a rectilinear bed, lines h/2 and h/4 inside every free edge (the
  outline's and the cut-outs'): the shear-deformable plate's twisting
  moment has a boundary layer about a thickness wide along a free edge,
  which a uniform grid resolves only at h ≲ t. Graded there, the torsion
  modes of the reference bed converge at the rate of the smooth modes (h²,
  observed 1.9–2.0 from h = 0.2 to 0.05 m, against 0.6–1.4 on a uniform
  grid) and the 0.1 m grid's first torsion mode is 0.2 % high instead of
  1.2 %. The grading scales with h, so the meshes at h and 2h are alike
  (Richardson's condition, :mod:`flexbed.fem.accuracy`).

Pure NumPy (no assembly): the scene reader uses :func:`start_spec` for an
auto bed's mass properties, which do not depend on h for outlines made of
straight edges (the meshed area is the exact area).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .geometry import BedGeometry, signed_area
from .spec import PlateSpec

#: elements across the bed's shorter side on the first mesh tried
START_CELLS = 4
#: free-edge grading: extra lines at these fractions of h inside the edge
GRADING = (0.5, 0.25)


def outline_polygon(spec: PlateSpec) -> np.ndarray:
    """The outline (k, 2), counter-clockwise, drawing frame [m]."""
    g = spec.geometry
    if g is None or g.outline is None:
        a, b = spec.length_x / 2, spec.length_y / 2
        return np.array([[-a, -b], [a, -b], [a, b], [-a, b]])
    poly = np.array(g.outline, dtype=float)
    return poly if signed_area(poly) > 0 else poly[::-1].copy()


def start_size(spec: PlateSpec) -> float:
    """The first element size tried: the bounding box's shorter side over
    :data:`START_CELLS` [m]."""
    return float(np.min(np.ptp(outline_polygon(spec), axis=0))) / START_CELLS


def _axis_parallel(poly: np.ndarray) -> bool:
    d = np.roll(poly, -1, axis=0) - poly
    tol = 1e-12 * np.abs(d).max()
    return bool(np.all((np.abs(d[:, 0]) <= tol) | (np.abs(d[:, 1]) <= tol)))


def _edge_points(poly: np.ndarray, h: float, material_left: bool) -> list:
    """Points at GRADING × h from each edge of a counter-clockwise polygon,
    on the material side, each at an edge end's other coordinate (already a
    grid line)."""
    out = []
    for p, q in zip(poly, np.roll(poly, -1, axis=0)):
        d = q - p
        normal = np.array([-d[1], d[0]]) / np.hypot(*d)        # left of p → q
        if not material_left:
            normal = -normal
        for f in GRADING:
            r = p + f * h * normal
            out.append((float(r[0]), float(r[1])))
    return out


def grading_points(spec: PlateSpec, h: float) -> tuple:
    """The free-edge grading points of a rectilinear bed at element size h
    (empty when an edge is slanted or curved: those meshes are not graded)."""
    outline = outline_polygon(spec)
    holes = [c.polygon(h) for c in spec.geometry.cutouts] if spec.geometry is not None else []
    if not all(_axis_parallel(p) for p in [outline] + holes):
        return ()
    pts = _edge_points(outline, h, True)
    for hole in holes:
        pts += _edge_points(hole, h, False)
    return tuple(pts)


def mesh_spec(spec: PlateSpec, h: float) -> PlateSpec:
    """The plain spec of an auto bed's mesh at element size ``h`` [m]: its
    geometry with ``element_size = h``, nodes at the fixed masses, the
    ``mesh_points`` and the free-edge grading (see the module's text)."""
    if not spec.auto_mesh:
        raise ValueError("mesh_spec needs a spec with mesh_tolerance (element_size = \"auto\")")
    g = spec.geometry or BedGeometry()
    geometry = replace(g, element_size=float(h))
    points = (spec.mesh_points + tuple((m.position[0], m.position[1]) for m in spec.masses)
              + grading_points(spec, h))
    return replace(spec, mesh_tolerance=None, geometry=geometry, mesh_points=points)


def start_spec(spec: PlateSpec) -> PlateSpec:
    """The auto bed's mesh at :func:`start_size` (its layout stands for the
    bed before the mesh is chosen: mass properties, points on the bed,
    stiffeners along mesh lines)."""
    return mesh_spec(spec, start_size(spec))


def max_cells_size(spec: PlateSpec, dofs: int) -> float:
    """The element size [m] below which the bed's mesh would have more than
    ``dofs`` degrees of freedom (5 per node, about one node per h² of area)."""
    area = abs(signed_area(outline_polygon(spec)))
    return math.sqrt(5.0 * area / dofs)
