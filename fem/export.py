"""Files for ParaView.

- Mode shapes: one VTU file, one point-data field per mode: the mode's
  nodal translation (a 3-vector per node, mass normalised, kg^-1/2), so
  "Warp By Vector" shows the shape; a field ``rotationNN`` per mode carries
  the nodal rotations.
- The bed's motion: an XDMF time series on the undeformed mesh (in its
  initial place) with the nodes' displacement (rigid motion + deformation)
  and the elastic deflection per time step.
"""

from __future__ import annotations

import contextlib
from pathlib import Path

import meshio
import numpy as np


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
        Quadrilaterals (node indices, counter-clockwise).
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
    mesh = meshio.Mesh(points=np.asarray(nodes, dtype=float),
                       cells=[("quad", np.asarray(cells, dtype=np.int64))], point_data=data)
    tmp = path.with_name(f".{path.name}.tmp")
    meshio.write(tmp, mesh, file_format="vtu")
    tmp.replace(path)
    return path


def write_motion_series(path: str | Path, nodes: np.ndarray, cells: np.ndarray,
                        times: np.ndarray, displacement: np.ndarray,
                        deflection: np.ndarray) -> Path:
    """Write the bed's motion as an XDMF time series (with its HDF5 heavy data).

    Parameters
    ----------
    path : path-like
        ``.xdmf`` file; meshio writes ``<stem>.h5`` next to it.
    nodes : ndarray (N, 3)
        Node positions at t = 0, inertial frame [m].
    cells : ndarray (ne, 4)
        Quadrilaterals.
    times : ndarray (k,)
        [s].
    displacement : ndarray (k, N, 3)
        Node positions minus their t = 0 positions, inertial frame [m]
        (use "Warp By Vector" to see the motion).
    deflection : ndarray (k, N)
        Elastic deflection along the bed's normal [m].
    """
    path = Path(path).resolve()
    path.parent.mkdir(parents=True, exist_ok=True)
    # meshio puts the heavy-data file in the working folder: write from the
    # destination's folder so that both files land together.
    with contextlib.chdir(path.parent), meshio.xdmf.TimeSeriesWriter(path.name) as writer:
        writer.write_points_cells(np.asarray(nodes, dtype=float),
                                  [("quad", np.asarray(cells, dtype=np.int64))])
        for k, t in enumerate(times):
            writer.write_data(float(t), point_data={
                "displacement": np.ascontiguousarray(displacement[k]),
                "deflection": np.ascontiguousarray(deflection[k])})
    return path
