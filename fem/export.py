"""Mode shapes for ParaView: one VTU file (meshio), one point-data field
per mode: the mode's nodal translation (a 3-vector per node, mass
normalised, kg^-1/2), so "Warp By Vector" shows the shape; a field
``rotationNN`` per mode carries the nodal rotations. (The bed's motion over
a run is written by :mod:`flexbed.files.xdmf`.)
"""

from __future__ import annotations

from pathlib import Path

import meshio
import numpy as np

from .cells import is_triangle


def mode_field_name(index: int, frequency: float) -> str:
    """Field name of mode ``index`` (0-based), e.g. ``mode01_23.17Hz``."""
    return f"mode{index + 1:02d}_{frequency:.2f}Hz"


def write_modes_vtu(path: str | Path, nodes: np.ndarray, cells: np.ndarray,
                    translation: np.ndarray, rotation: np.ndarray,
                    frequency: np.ndarray) -> Path:
    """Write the mode shapes as a VTU file.

    Parameters
    ----------
    path : path-like
        Output file (``.vtu``); its folder is created.
    nodes : ndarray (N, 3)
        Node coordinates [m].
    cells : ndarray (ne, 4)
        Quadrilaterals (node indices, counter-clockwise); triangles as
        (a, b, c, c), written as VTK triangles.
    translation, rotation : ndarray (n, N, 3)
        Nodal translations and rotations per mode.
    frequency : ndarray (n,)
        Frequencies [Hz].

    Returns
    -------
    Path
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    data = {}
    for k, f in enumerate(frequency):
        data[mode_field_name(k, float(f))] = np.ascontiguousarray(translation[k])
        data[f"rotation{k + 1:02d}"] = np.ascontiguousarray(rotation[k])
    cells = np.asarray(cells, dtype=np.int64)
    tri = is_triangle(cells)
    blocks = [(kind, c) for kind, c in (("quad", cells[~tri]), ("triangle", cells[tri, :3]))
              if c.shape[0]]
    mesh = meshio.Mesh(points=np.asarray(nodes, dtype=float), cells=blocks, point_data=data)
    tmp = path.with_name(f".{path.name}.tmp")
    meshio.write(tmp, mesh, file_format="vtu")
    tmp.replace(path)
    return path
