"""A bed's mesh read from a file with meshio, checked as a mesh.

Reading is quiet and fails in one :class:`~flexbed.fem.geometry.GeometryError`
naming the file: meshio prints its own messages and ends the process
(``sys.exit``) on a file it cannot read; both are caught here. Before the
file is read, the point count its header declares (VTU, legacy VTK, Gmsh
2, Gmsh 4 in ASCII) is checked against the solver's limit, so a mesh too large is
refused at once; after it, the count of the nodes the cells use.

The mesh is its linear ``quad`` and ``triangle`` cells (other cell types —
lines, vertices, volumes, quadratic cells — are ignored, and a file with
none of the two is refused), z ignored. Nodes no cell uses are dropped;
clockwise cells are turned counter-clockwise; every other fault of
:func:`flexbed.fem.mesh_checks.check_cells` is refused.
"""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import numpy as np

from .cells import as_cells
from .geometry import GeometryError
from .mesh_checks import check_cells, check_coordinates, check_size

#: how much of a file's start is searched for its declared point count [bytes]
HEAD_BYTES = 1 << 16


def declared_points(path: Path) -> int | None:
    """The number of points a mesh file's header declares, or None when
    its format is not one of VTU, legacy VTK and Gmsh (2, or 4 in ASCII),
    or the count is not within the file's first ``HEAD_BYTES``."""
    suffix = path.suffix.lower()
    if suffix not in (".vtu", ".vtk", ".msh"):
        return None
    try:
        with open(path, "rb") as f:
            head = f.read(HEAD_BYTES).decode("latin-1")
    except OSError:
        return None
    if suffix == ".vtu":
        counts = re.findall(r'NumberOfPoints\s*=\s*"\s*(\d+)\s*"', head)
        return sum(int(n) for n in counts) if counts else None
    if suffix == ".vtk":
        m = re.search(r"^\s*POINTS\s+(\d+)", head, re.MULTILINE)
        return int(m.group(1)) if m else None
    fmt = re.search(r"\$MeshFormat\r?\n(\d+)(?:\.\d+)?[ \t]+(\d)", head)
    nodes = re.search(r"\$Nodes\r?\n(\d+)(?:[ \t]+(\d+))?[ \t\d]*\r?\n", head)
    if not (fmt and nodes) or (fmt.group(1) == "4" and fmt.group(2) != "0"):
        return None                 # Gmsh 4's binary counts are not text
    if fmt.group(1) == "4":
        return int(nodes.group(2)) if nodes.group(2) is not None else None
    return int(nodes.group(1))


def _read_quietly(path: Path, label: str):
    """meshio.read with its printing silenced and its failures (exceptions
    and sys.exit) turned into one GeometryError."""
    import meshio
    said = io.StringIO()
    try:
        with contextlib.redirect_stdout(said), contextlib.redirect_stderr(said):
            return meshio.read(path)
    except SystemExit:
        reason = None
    except Exception as exc:                    # meshio raises many kinds
        reason = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    if reason is None:
        lines = [ln.strip() for ln in said.getvalue().splitlines()
                 if ln.strip() and not ln.strip().startswith(("Error:", "Couldn't"))]
        formats = meshio.extension_to_filetypes.get(path.suffix.lower(), ["its format"])
        reason = f"not a valid {' or '.join(formats)} file"
        if lines:
            reason += f": {lines[0]}"
    reason = reason.replace(str(path), path.name)
    if len(reason) > 160:
        reason = reason[:150] + " ..."
    raise GeometryError("mesh_file", f"{label}: cannot read it ({reason})")


def _cell_blocks(mesh, label: str, n_points: int) -> tuple[np.ndarray, np.ndarray]:
    quads = [np.asarray(b.data) for b in mesh.cells if b.type == "quad"]
    tris = [np.asarray(b.data) for b in mesh.cells if b.type == "triangle"]
    if not quads and not tris:
        found = ", ".join(sorted({b.type for b in mesh.cells})) or "no cells"
        raise GeometryError("mesh_file", f"{label} has no quad or triangle cells (it has "
                                         f"{found}); the bed is a shell of linear quads "
                                         f"and triangles")
    quads = np.vstack(quads).astype(np.int64) if quads else np.zeros((0, 4), np.int64)
    tris = np.vstack(tris).astype(np.int64) if tris else np.zeros((0, 3), np.int64)
    for kind, block in (("quad", quads), ("triangle", tris)):
        bad = np.any((block < 0) | (block >= n_points), axis=1)
        if bad.any():
            c = int(np.flatnonzero(bad)[0])
            raise GeometryError("mesh_file", f"{label}: {kind} {c} refers to nodes "
                                             f"{block[c].tolist()}; the file has {n_points} "
                                             f"points")
    return quads, tris


def read_mesh_file(path: str | Path, *, per_node: int, limit: int
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Nodes (N, 2) [m] and counter-clockwise cells (ne, 4) of a mesh file:
    its quads, then its triangles stored (a, b, c, c)
    (:mod:`flexbed.fem.cells`).

    Parameters
    ----------
    path : str or Path
    per_node, limit : int
        Degrees of freedom per node and the most the mesh may have.

    Raises
    ------
    GeometryError
        One line starting ``mesh_file = '<path>'``: unreadable, too large,
        without quads or triangles, or not a sound mesh.
    """
    path = Path(path)
    label = f"mesh_file = {str(path)!r}"
    declared = declared_points(path)
    if declared is not None:
        check_size("mesh_file", f"{label} declares {declared:,} points:", declared, per_node,
                   limit)
    mesh = _read_quietly(path, label)
    points = np.asarray(mesh.points)
    if points.ndim != 2 or points.shape[1] < 2 or not np.issubdtype(points.dtype, np.number):
        raise GeometryError("mesh_file", f"{label}: its points are not x, y(, z) numbers "
                                         f"(shape {points.shape})")
    quads, tris = _cell_blocks(mesh, label, points.shape[0])
    cells = as_cells(quads, tris)
    used, inverse = np.unique(cells.ravel(), return_inverse=True)
    check_size("mesh_file", f"{label} has {used.size:,} nodes in its cells:", used.size,
               per_node, limit)
    nodes = points[used, :2].astype(float)
    check_coordinates(label, nodes, "node", used)          # numbered as in the file
    cells = inverse.reshape(cells.shape)
    return nodes, check_cells(label, nodes, cells, quads.shape[0])
