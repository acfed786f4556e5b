"""The bed's stresses for ParaView: an XDMF time series (``<stem>.xdmf``)
over one HDF5 file (``<stem>.h5``, :mod:`flexbed.files.store`), cell data
on the undeformed mesh (the stresses are recovered at element centres).

``flexbed.bed_stress`` 1.0 (every dataset has ``units``):

- ``mesh/nodes`` (N, 3) [m], ``mesh/cells`` [1]: the bed's mesh in its
  frame, cells in XDMF's layout (group attribute ``mesh/topology``, as
  :mod:`flexbed.files.xdmf`);
- ``time`` (k,) [s];
- ``frames/<i>/von_mises_top``, ``von_mises_bottom`` (ne,) [Pa]: von Mises
  stress at the top and bottom faces, frame i;
- ``frames/<i>/principal_max`` (ne,) [Pa]: the largest principal stress
  over both faces;
- ``peak/von_mises`` (ne,) [Pa]: each element's peak over the run.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from flexbed.files.destination import write_text
from flexbed.files.store import Dataset, write_file
from flexbed.files.xdmf import series_files, temporal_xdmf

__all__ = ["write_stress_series", "STRESS_SCHEMA"]

STRESS_SCHEMA = "flexbed.bed_stress"
VERSION = "1.0"
_FIELDS = (("von_mises_top", "von Mises stress at the top face"),
           ("von_mises_bottom", "von Mises stress at the bottom face"),
           ("principal_max", "largest principal stress over both faces"))


def write_stress_series(path: str | os.PathLike, nodes: np.ndarray, cells: np.ndarray,
                        times: np.ndarray, fields: dict, peak: np.ndarray) -> Path:
    """Write the stress time series as ``path`` (XDMF) and its ``.h5``.

    Parameters
    ----------
    path : path-like
        The ``.xdmf`` file; the HDF5 is ``path`` with suffix ``.h5``.
    nodes : ndarray (N, 3) [m]
    cells : ndarray (ne, 4)
        Quadrilaterals; triangles as (a, b, c, c).
    times : ndarray (k,) [s]
    fields : dict
        ``von_mises_top``, ``von_mises_bottom``, ``principal_max``: (k, ne) [Pa].
    peak : ndarray (ne,)
        Each element's peak von Mises stress [Pa].

    Returns
    -------
    Path
        The XDMF file.
    """
    path, h5, nodes, ne, topology, cells, times, width = series_files(path, nodes, cells, times)
    k = times.size
    ds = {"mesh/nodes": Dataset(nodes, "m", "node positions in the bed frame"),
          "mesh/cells": Dataset(cells, "1", f"the cells, XDMF {topology} topology"),
          "time": Dataset(times, "s", "time of each frame"),
          "peak/von_mises": Dataset(np.asarray(peak, dtype=float), "Pa",
                                    "each element's peak von Mises stress over the run")}
    attrs = {"": {"description": "the bed's stresses at element centres per frame (open the "
                                 ".xdmf beside it)"}, "mesh": {"topology": topology}}
    for i in range(k):
        g = f"frames/{i:0{width}d}"
        for name, text in _FIELDS:
            ds[f"{g}/{name}"] = Dataset(np.ascontiguousarray(fields[name][i], dtype=float),
                                        "Pa", text)
        attrs[g] = {"time": float(times[i])}
    write_file(h5, schema=STRESS_SCHEMA, version=VERSION, datasets=ds, attrs=attrs)

    text = temporal_xdmf(h5.name, path.stem, topology, ne, cells.shape, nodes.shape, times,
                         width, [(fname, "Scalar", "Cell", (ne,)) for fname, _ in _FIELDS])
    return write_text(path, text)
