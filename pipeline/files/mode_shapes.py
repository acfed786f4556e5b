"""The mounted system's mode shapes for ParaView: an XDMF file (the light
XML) over one HDF5 file (``<stem>.h5``) written through
:mod:`flexbed.files.store`.

``flexbed.mode_shapes`` 1.1 (every dataset has ``units`` and a
``description``):

- ``frequency`` (m,) [Hz], ``damping_ratio`` (m,) [1]: the modes;
- ``bodies/<i>/nodes`` (N, 3) [m]: body i's mesh at the equilibrium,
  inertial frame (the bed's plate mesh; a box of each other body's inertia);
  ``bodies/<i>/cells`` [1] in XDMF's layout for the group attributes
  ``topology`` ("Quadrilateral" (ne, 4), "Hexahedron" (ne, 8), and since
  1.1 "Triangle" (ne, 3) or "Mixed", :func:`flexbed.files.xdmf.xdmf_topology`)
  and ``cell_count`` (ne, since 1.1); ``name``;
- ``bodies/<i>/mode_<k>`` (N, 3) [1]: the node displacements in mode k
  (1-based, zero-padded), scaled to a largest node displacement of 1 over
  all bodies.

The XML holds one spatial collection of the bodies, each with one vector
field per mode ("mode_01 (3.94 Hz)" …): colour by a mode, "Warp By Vector"
with a scale factor of a few centimetres.
"""

from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from flexbed.files.destination import check_destination, write_text
from flexbed.files.store import Dataset, write_file
from flexbed.files.xdmf import data_item

__all__ = ["write_mode_shapes", "MODE_SHAPES_SCHEMA"]

MODE_SHAPES_SCHEMA = "flexbed.mode_shapes"
#: 1.1: a bed of triangles ("Triangle" or "Mixed" topology), ``cell_count``
VERSION = "1.1"


def write_mode_shapes(path: str | os.PathLike, meshes: list, frequency: np.ndarray,
                      damping_ratio: np.ndarray) -> Path:
    """Write ``path`` (XDMF) and its ``.h5`` beside it.

    Parameters
    ----------
    meshes : list of :class:`flexbed.analyses.mode_shapes.ShapeMesh`
    frequency, damping_ratio : (m,) arrays [Hz, 1]

    Returns
    -------
    Path
        The XDMF file.
    """
    path = check_destination(path)
    h5 = check_destination(path.with_suffix(".h5"))
    m = int(np.asarray(frequency).size)
    width = max(2, len(str(m)))
    ds = {"frequency": Dataset(np.asarray(frequency, float), "Hz", "natural frequency"),
          "damping_ratio": Dataset(np.asarray(damping_ratio, float), "1", "damping ratio")}
    attrs = {"": {"description": "the mounted system's mode shapes (open the .xdmf beside it)"}}
    for i, mesh in enumerate(meshes):
        g = f"bodies/{i}"
        ds[f"{g}/nodes"] = Dataset(mesh.nodes, "m", "nodes at the equilibrium, inertial frame")
        ds[f"{g}/cells"] = Dataset(mesh.cells, "1", "node indices of each cell")
        for k in range(m):
            ds[f"{g}/mode_{k + 1:0{width}d}"] = Dataset(
                np.ascontiguousarray(mesh.displacement[k]), "1",
                "node displacement in this mode, largest over all bodies 1")
        attrs[g] = {"name": mesh.name, "topology": mesh.topology,
                    "cell_count": int(mesh.cell_count)}
    write_file(h5, schema=MODE_SHAPES_SCHEMA, version=VERSION, datasets=ds, attrs=attrs)

    name = h5.name
    lines = ['<?xml version="1.0" encoding="utf-8"?>',
             '<Xdmf xmlns:xi="http://www.w3.org/2001/XInclude" Version="3.0">',
             "  <Domain>",
             f'    <Grid Name={quoteattr(path.stem)} GridType="Collection" '
             'CollectionType="Spatial">']
    for i, mesh in enumerate(meshes):
        g = f"bodies/{i}"
        n = mesh.nodes.shape[0]
        lines += [f'      <Grid Name={quoteattr(mesh.name)} GridType="Uniform">',
                  f'        <Topology TopologyType="{mesh.topology}" '
                  f'NumberOfElements="{mesh.cell_count}">',
                  f"          {data_item(name, f'{g}/cells', mesh.cells.shape, 'Int')}",
                  "        </Topology>",
                  '        <Geometry GeometryType="XYZ">',
                  f"          {data_item(name, f'{g}/nodes', mesh.nodes.shape, 'Float')}",
                  "        </Geometry>"]
        for k in range(m):
            label = f"mode_{k + 1:0{width}d} ({float(frequency[k]):.4g} Hz)"
            lines += [f'        <Attribute Name={quoteattr(label)} AttributeType="Vector" '
                      'Center="Node">',
                      "          "
                      + data_item(name, f"{g}/mode_{k + 1:0{width}d}", (n, 3), "Float"),
                      "        </Attribute>"]
        lines.append("      </Grid>")
    lines += ["    </Grid>", "  </Domain>", "</Xdmf>"]
    return write_text(path, "\n".join(lines) + "\n")
