"""The bed's motion for ParaView: an XDMF time series (``<stem>.xdmf``, the
light XML) over one HDF5 file (``<stem>.h5``, the heavy data), both written
here, the HDF5 through :mod:`flexbed.files.store` so that it describes
itself as every flexbed file does.

``flexbed.bed_motion`` 1.1 (every dataset has ``units`` and a
``description``):

- ``mesh/nodes`` (N, 3) [m]: the nodes at t = 0, inertial frame;
- ``mesh/cells`` [1]: the cells in XDMF's layout for the group attribute
  ``mesh/topology``: ``"Quadrilateral"`` (ne, 4) node indices (every file
  of 1.0, and every mesh of quads), ``"Triangle"`` (ne, 3), or ``"Mixed"``
  (one flat array: per cell its XDMF type, 4 = triangle or
  5 = quadrilateral, then its node indices);
- ``time`` (k,) [s]: the frames' times;
- ``frames/<i>/displacement`` (N, 3) [m]: node positions minus their
  t = 0 positions (rigid motion and deformation), frame i (zero-padded);
- ``frames/<i>/deflection`` (N,) [m]: elastic deflection along the bed's
  normal; each ``frames/<i>`` group has the attribute ``time`` [s].

The XML follows the layout meshio writes (one mesh grid, included by every
step of a temporal collection), which ParaView's XDMF readers open; use
"Warp By Vector" on ``displacement`` and play.
"""

from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

import numpy as np

from flexbed.files.destination import check_destination, write_text
from flexbed.files.store import Dataset, write_file

__all__ = ["write_bed_motion", "temporal_xdmf", "BED_MOTION_SCHEMA"]

BED_MOTION_SCHEMA = "flexbed.bed_motion"
#: 1.1: triangles ("Triangle" or "Mixed" topology, group attribute
#: ``mesh/topology``); a mesh of quads is written as in 1.0
VERSION = "1.1"

#: XDMF's cell type numbers in a "Mixed" topology
_XDMF_TRIANGLE, _XDMF_QUADRILATERAL = 4, 5


def xdmf_topology(cells: np.ndarray) -> tuple[str, np.ndarray]:
    """XDMF topology type and cell array of a shell mesh (ne, 4) whose
    triangles are stored (a, b, c, c): ``("Quadrilateral", (ne, 4))``,
    ``("Triangle", (ne, 3))`` or ``("Mixed", flat)``, flat = per cell
    its type (4 triangle, 5 quadrilateral) then its corners."""
    cells = np.asarray(cells, dtype=np.int64)
    tri = cells[:, 3] == cells[:, 2]
    if not tri.any():
        return "Quadrilateral", cells
    if tri.all():
        return "Triangle", np.ascontiguousarray(cells[:, :3])
    parts = [np.concatenate([[_XDMF_TRIANGLE], c[:3]]) if t
             else np.concatenate([[_XDMF_QUADRILATERAL], c]) for c, t in zip(cells, tri)]
    return "Mixed", np.concatenate(parts).astype(np.int64)


def data_item(h5name: str, dataset: str, shape: tuple, kind: str) -> str:
    """An XDMF ``DataItem`` pointing at ``h5name:/dataset`` of ``shape``
    (``kind``: "Int" or "Float", 8 bytes)."""
    dims = " ".join(str(int(d)) for d in shape)
    return (f'<DataItem DataType="{kind}" Dimensions="{dims}" Format="HDF" Precision="8">'
            f"{escape(h5name)}:/{dataset}</DataItem>")


def series_files(path, nodes, cells, times) -> tuple:
    """What a time series' XDMF and its HDF5 share, checked before anything is
    written: (path, h5 path, nodes (N, 3) float, number of cells, topology,
    cells as XDMF numbers them, times (k,) float, width of the frame names)."""
    path = check_destination(path)
    h5 = check_destination(Path(path).with_suffix(".h5"))
    nodes = np.asarray(nodes, dtype=float)
    n_cells = np.asarray(cells).shape[0]
    topology, cells = xdmf_topology(cells)
    times = np.asarray(times, dtype=float)
    width = max(4, len(str(max(times.size - 1, 0))))
    return path, h5, nodes, n_cells, topology, cells, times, width


def temporal_xdmf(h5name: str, stem: str, topology: str, n_cells: int, cells_shape: tuple,
                  nodes_shape: tuple, times: np.ndarray, width: int,
                  attributes: list[tuple[str, str, str, tuple]]) -> str:
    """The XDMF text of a time series in an HDF5 file: the mesh once
    (``mesh/cells``, ``mesh/nodes``), then one grid per frame
    ``frames/NNNN`` holding ``attributes``.

    Parameters
    ----------
    attributes : list of (name, type, centre, shape)
        Each frame's datasets: ``type`` "Scalar" or "Vector", ``centre``
        "Node" or "Cell", ``shape`` the dataset's.
    """
    mesh = ("xpointer(//Grid[@Name=&quot;mesh&quot;]/*[self::Topology or "
            "self::Geometry])")
    lines = ['<?xml version="1.0" encoding="utf-8"?>',
             '<Xdmf xmlns:xi="http://www.w3.org/2001/XInclude" Version="3.0">',
             "  <Domain>",
             '    <Grid Name="mesh" GridType="Uniform">',
             f'      <Topology TopologyType="{topology}" NumberOfElements="{n_cells}">',
             f"        {data_item(h5name, 'mesh/cells', cells_shape, 'Int')}",
             "      </Topology>",
             '      <Geometry GeometryType="XYZ">',
             f"        {data_item(h5name, 'mesh/nodes', nodes_shape, 'Float')}",
             "      </Geometry>",
             "    </Grid>",
             f'    <Grid Name={quoteattr(stem)} GridType="Collection" '
             'CollectionType="Temporal">']
    for i, t in enumerate(times):
        g = f"frames/{i:0{width}d}"
        lines += ['      <Grid GridType="Uniform">',
                  f'        <xi:include xpointer="{mesh}"/>',
                  f'        <Time Value="{float(t)!r}"/>']
        for name, kind, centre, shape in attributes:
            lines += [f'        <Attribute Name="{name}" AttributeType="{kind}" '
                      f'Center="{centre}">',
                      f"          {data_item(h5name, f'{g}/{name}', shape, 'Float')}",
                      "        </Attribute>"]
        lines += ["      </Grid>"]
    lines += ["    </Grid>", "  </Domain>", "</Xdmf>"]
    return "\n".join(lines) + "\n"


def write_bed_motion(path: str | os.PathLike, nodes: np.ndarray, cells: np.ndarray,
                     times: np.ndarray, displacement: np.ndarray,
                     deflection: np.ndarray) -> Path:
    """Write the bed's motion as ``path`` (XDMF) and its ``.h5`` beside it.

    Parameters
    ----------
    path : path-like
        The ``.xdmf`` file; the HDF5 file is ``path`` with suffix ``.h5``.
    nodes : ndarray (N, 3)
        Node positions at t = 0, inertial frame [m].
    cells : ndarray (ne, 4)
        Quadrilaterals (node indices, counter-clockwise); triangles as
        (a, b, c, c).
    times : ndarray (k,)
        Frame times [s].
    displacement : ndarray (k, N, 3)
        Node positions minus their t = 0 positions, inertial frame [m].
    deflection : ndarray (k, N)
        Elastic deflection along the bed's normal [m].

    Returns
    -------
    Path
        The XDMF file.
    """
    path, h5, nodes, n_cells, topology, cells, times, width = series_files(path, nodes, cells,
                                                                          times)
    k, n = times.size, nodes.shape[0]
    ds = {
        "mesh/nodes": Dataset(nodes, "m", "node positions at t = 0, inertial frame"),
        "mesh/cells": Dataset(cells, "1", f"the cells, XDMF {topology} topology"),
        "time": Dataset(times, "s", "time of each frame"),
    }
    attrs = {"": {"description": "the bed's motion: displacement and elastic deflection of "
                                 "every node per frame (open the .xdmf beside it)"},
             "mesh": {"topology": topology}}
    for i in range(k):
        g = f"frames/{i:0{width}d}"
        ds[f"{g}/displacement"] = Dataset(
            np.ascontiguousarray(displacement[i], dtype=float), "m",
            "node position minus its t = 0 position (rigid motion and deformation), "
            "inertial frame")
        ds[f"{g}/deflection"] = Dataset(np.ascontiguousarray(deflection[i], dtype=float), "m",
                                        "elastic deflection along the bed's normal")
        attrs[g] = {"time": float(times[i])}
    write_file(h5, schema=BED_MOTION_SCHEMA, version=VERSION, datasets=ds, attrs=attrs)

    text = temporal_xdmf(h5.name, path.stem, topology, n_cells, cells.shape, nodes.shape,
                         times, width, [("displacement", "Vector", "Node", (n, 3)),
                                        ("deflection", "Scalar", "Node", (n,))])
    return write_text(path, text)
