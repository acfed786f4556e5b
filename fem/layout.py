"""Where everything of the bed is, in the bed's own frame: the mesh, the
thickness of each cell and the fixed masses, placed so that the frame's
origin is the composite centre of mass (plate + fixed masses). Pure NumPy:
the scene reader uses it for the bed body's mass properties and to refuse
points off the bed and stiffeners that do not run along cell edges.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from .cells import locate
from .geometry import GeometryError
from .mass_properties import MassProperties, plate_mass_properties, shift_inertia
from .mesher import mesh_bed
from .quad_shapes import QuadShapes
from .stiffeners import line_mass_properties, line_nodes
from .spec import PlateSpec


@dataclass(frozen=True)
class BedLayout:
    """The bed in its frame (origin at the composite centre of mass).

    Attributes
    ----------
    nodes : ndarray (N, 2)
        x, y of the nodes [m].
    cells : ndarray (ne, 4)
        Quadrilaterals, and triangles as (a, b, c, c).
    thickness : ndarray (ne,) [m]
    centre : ndarray (3,)
        The composite centre of mass in the drawing frame [m].
    mid_z : float
        The mid-surface's z in the bed frame (−centre z) [m].
    mass_properties : MassProperties
        Composite mass, centre (drawing frame) and inertia about it.
    fixed : tuple of (FixedMass, ndarray (3,))
        Each fixed mass with (x, y) in the bed frame and z its height above
        the mid-surface [m].
    """

    nodes: np.ndarray
    cells: np.ndarray
    thickness: np.ndarray
    centre: np.ndarray
    mid_z: float
    mass_properties: MassProperties
    fixed: tuple

    def locate(self, x: float, y: float):
        """(cell, natural coordinates) of a point of the bed frame, or None."""
        return QuadShapes(self.nodes, self.cells, np.zeros((0, 1, 3)),
                          np.zeros((0, 1, 3))).locate(x, y)


def _check_lines(spec: PlateSpec) -> None:
    """Refuse a stiffener that leaves the bounding box of the bed's outline
    before the mesher draws grid lines through its ends (a far end would
    stretch the grid over all the space between)."""
    g = spec.geometry
    if not spec.stiffeners or g.mesh_file is not None:
        return
    outline = (np.array(g.outline) if g.outline is not None else
               np.array([[-spec.length_x / 2, -spec.length_y / 2],
                         [spec.length_x / 2, spec.length_y / 2]]))
    lo, hi = outline.min(axis=0), outline.max(axis=0)
    tol = 1e-9 * float(np.max(hi - lo))
    for st in spec.stiffeners:
        ends = np.array([st.start, st.end])
        if np.any(ends < lo - tol) or np.any(ends > hi + tol):
            raise GeometryError(f"stiffener {st.name!r}",
                                f"stiffener {st.name!r} from {list(st.start)} to "
                                f"{list(st.end)} m leaves the bed")


def _grid(spec: PlateSpec) -> tuple[np.ndarray, np.ndarray]:
    from .shell import grid_mesh
    return grid_mesh(spec)


@functools.lru_cache(maxsize=16)
def bed_layout(spec: PlateSpec) -> BedLayout:
    """The spec's :class:`BedLayout` (cached per spec); an auto bed's
    (``element_size = "auto"``) on its first mesh
    (:func:`flexbed.fem.auto_mesh.start_spec`)."""
    if spec.auto_mesh:
        from .auto_mesh import start_spec
        return bed_layout(start_spec(spec))
    lines = [(st.start, st.end) for st in spec.stiffeners]
    lines += [(p, p) for p in spec.mesh_points]           # nodes there
    if spec.geometry is None:
        nodes, cells = _grid(spec)
        t = np.full(cells.shape[0], spec.thickness)
    else:
        _check_lines(spec)
        nodes, cells, t = mesh_bed(spec.geometry, spec.length_x, spec.length_y,
                                   spec.thickness, spec.nx, spec.ny, lines=lines)
    for item in spec.masses:
        if locate(nodes, cells, item.position[0], item.position[1]) is None:
            raise GeometryError(f"fixed_mass {item.name!r}",
                                f"fixed_mass {item.name!r}: position = {list(item.position)} m "
                                f"is off the bed (outside its outline or in a cut-out)")
    plate = plate_mass_properties(nodes, cells, t, spec.density)
    m = plate.mass
    first = plate.mass * plate.centre
    pc = plate.centre
    J0 = plate.inertia + m * (pc @ pc * np.eye(3) - np.outer(pc, pc))    # about the origin
    for item in spec.masses:
        p = np.array(item.position)
        m += item.mass
        first = first + item.mass * p
        J0 = J0 + np.array(item.inertia) + item.mass * (p @ p * np.eye(3) - np.outer(p, p))
    for st in spec.stiffeners:
        ms, fs, Js = line_mass_properties(st, spec.density, np.zeros(3))
        m += ms
        first = first + fs
        J0 = J0 + Js
    c = first / m
    if spec.is_rectangle:
        c = np.zeros(3)                               # the grid is centred by construction
        mp = MassProperties(spec.mass, c, np.diag(spec.inertia))
    else:
        mp = MassProperties(float(m), c, shift_inertia(m, J0, c))
    fixed = tuple((item, np.array([item.position[0] - c[0], item.position[1] - c[1],
                                   item.position[2]])) for item in spec.masses)
    return BedLayout(nodes=nodes - c[:2], cells=cells, thickness=t, centre=c,
                     mid_z=float(-c[2]), mass_properties=mp, fixed=fixed)


def bed_mass_properties(spec: PlateSpec) -> MassProperties:
    """The bed's mass [kg], composite centre of mass in the drawing frame
    (3,) [m] and inertia about it (3, 3) [kg m²]: the solid rectangle's for
    the plain plate (as before), else integrated over the mesh plus the
    fixed masses (exactly what the shell's mass matrix holds)."""
    if spec.is_rectangle:
        return MassProperties(spec.mass, np.zeros(3), np.diag(spec.inertia))
    return bed_layout(spec).mass_properties


def check_stiffeners(spec: PlateSpec) -> None:
    """Refuse a stiffener that does not run along cell edges of the bed's
    mesh, before any assembly (the scene reader calls it).

    Raises
    ------
    GeometryError
        One line naming the stiffener and where (:func:`flexbed.fem.stiffeners.line_nodes`).
    """
    if not spec.stiffeners:
        return
    lay = bed_layout(spec)
    for st in spec.stiffeners:
        line_nodes(st, lay.nodes, lay.cells, lay.centre[:2])

def off_bed(spec: PlateSpec, points: np.ndarray) -> np.ndarray:
    """Which points (P, 2 or 3), drawing frame [m], are on no element of the
    bed (outside its outline or in a cut-out): bool (P,)."""
    pts = np.atleast_2d(np.asarray(points, dtype=float))[:, :2]
    if spec.geometry is None:
        a, b = spec.length_x / 2, spec.length_y / 2
        tol = 1e-9 * max(a, b)
        return (np.abs(pts[:, 0]) > a + tol) | (np.abs(pts[:, 1]) > b + tol)
    lay = bed_layout(spec)
    return np.array([lay.locate(x - lay.centre[0], y - lay.centre[1]) is None
                     for x, y in pts])


def elastic_mode_count(spec: PlateSpec) -> int | None:
    """The elastic modes the spec's FE model has (its degrees of freedom
    less its rigid-body modes), counted on its mesh before any assembly, so
    that a request for more is refused before the work starts.

    The Kirchhoff plate has 4 DOFs at each of its (nx + 1)(ny + 1) nodes and
    3 rigid-body modes (w-translation and two tilts: :data:`flexbed.fem.modes.RIGID_MODES`);
    the Mindlin shell 5 at each node of :func:`bed_layout`'s mesh, one more
    at each node of a hinged stiffener's line (its section rotation), and 6
    rigid-body modes.

    Returns
    -------
    int or None
        The count; None for an auto mesh (``element_size = "auto"``), which
        is chosen only while the modes are computed.
    """
    if spec.auto_mesh:
        return None
    if spec.theory != "mindlin":
        return 4 * (spec.nx + 1) * (spec.ny + 1) - 3
    from .shell import DOFS_PER_NODE, ShellModel
    lay = bed_layout(spec)
    dofs = DOFS_PER_NODE * lay.nodes.shape[0]
    for st in spec.stiffeners:
        if st.model == "hinged":
            dofs += line_nodes(st, lay.nodes, lay.cells, lay.centre[:2])[0].size
    return dofs - ShellModel.n_rigid
