"""The mounted system's mode shapes on meshes, for ParaView: the bed as its
plate mesh (the modes file's, or the plate's grid for a rigid bed; a
scene without a [bed] table has none), every other body (equipment) as
the box of its inertia, and per mode the
displacement of every node (rigid motion, and the bed's deformation
through its modes) from the point machinery (:mod:`flexbed.analyses.linear_points`).

Each mode's field is the real part of its shape turned so that the largest
node displacement is real, scaled to a largest node displacement of 1
(use ParaView's "Warp By Vector" with a scale factor of a few cm).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass

import numpy as np

from flexbed.analyses.linear_points import PointJacobians
from flexbed.analyses.modal import Mounted
from flexbed.analyses.points import Point
from flexbed.files.xdmf import xdmf_topology

__all__ = ["ShapeMesh", "mode_shape_meshes"]

_BOX = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                 [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float) / 2.0


@dataclass(frozen=True)
class ShapeMesh:
    """One body's mesh: ``name``; ``nodes`` (N, 3) at equilibrium, inertial
    [m]; ``cells`` in XDMF's layout of ``topology`` ("Quadrilateral"
    (ne, 4), "Triangle" (ne, 3), "Mixed" (flat) or "Hexahedron" (ne, 8),
    :func:`flexbed.files.xdmf.xdmf_topology`); ``displacement`` (m, N, 3)
    per mode [1]."""

    name: str
    nodes: np.ndarray
    cells: np.ndarray
    topology: str
    displacement: np.ndarray

    @property
    def cell_count(self) -> int:
        """Number of cells."""
        if self.topology != "Mixed":
            return int(self.cells.shape[0])
        count, k = 0, 0
        while k < self.cells.size:                  # type, then 3 or 4 corners
            k += 4 if self.cells[k] == 4 else 5
            count += 1
        return count


def _plate_grid(plate) -> tuple[np.ndarray, np.ndarray]:
    x = np.linspace(-plate.length_x / 2, plate.length_x / 2, plate.nx + 1)
    y = np.linspace(-plate.length_y / 2, plate.length_y / 2, plate.ny + 1)
    X, Y = np.meshgrid(x, y, indexing="ij")
    nodes = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    idx = np.arange(X.size).reshape(X.shape)
    cells = np.column_stack([idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(),
                             idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()])
    return nodes, cells


def _box(mass: float, J: np.ndarray) -> np.ndarray:
    """The 8 corners of the uniform box with this mass and inertia [m]."""
    jx, jy, jz = np.diag(J)
    sq = 6.0 / mass * np.array([jy + jz - jx, jx + jz - jy, jx + jy - jz])
    side = np.sqrt(np.maximum(sq, 0.0))
    side = np.maximum(side, 0.05 * side.max() if side.max() > 0 else 0.1)
    return _BOX * side


def mode_shape_meshes(sf, mt: Mounted) -> list[ShapeMesh]:
    """Every moving body's mesh and its displacement in every mode."""
    system, ms, md = mt.system, mt.ms, mt.modes
    pj = PointJacobians(sf, system, ms, mt.bed_modes)
    bodies = system.scene.bodies
    has_bed = mt.bed_modes is not None or "bed" in tomllib.loads(sf.text)
    bed = (sf.bed.body or bodies[1].name) if has_bed else None
    meshes = []
    for i in range(1, len(bodies)):
        name = bodies[i].name
        if name == bed:
            if mt.bed_modes is not None:
                local = np.asarray(mt.bed_modes.nodes, float)
                topo, cells = xdmf_topology(mt.bed_modes.cells)
            else:
                local, cells = _plate_grid(sf.bed.plate)
                topo = "Quadrilateral"
        else:
            local, cells = _box(float(system.mass[i]), system.J[i - 1]), np.arange(8)[None, :]
            topo = "Hexahedron"
        pts = [Point(f"node {k}", name, local[k]) for k in range(local.shape[0])]
        nodes = np.array([pj.position(p) for p in pts])
        J = np.array([pj.jacobian(p)[:, 3:] for p in pts])             # (N, 3, n)
        meshes.append((name, nodes, np.asarray(cells, dtype=np.int64), topo, J))
    disp = [np.einsum("Nin,mn->mNi", J, md.shapes) for *_, J in meshes]   # complex
    allmax = np.concatenate([np.abs(d).reshape(d.shape[0], -1) for d in disp], axis=1)
    k = np.argmax(allmax, axis=1)
    flat = np.concatenate([d.reshape(d.shape[0], -1) for d in disp], axis=1)
    ref = flat[np.arange(flat.shape[0]), k]
    scale = np.where(np.abs(ref) > 0.0, 1.0 / np.where(ref != 0, ref, 1.0), 0.0)
    return [ShapeMesh(name, nodes, cells, topo, (d * scale[:, None, None]).real)
            for (name, nodes, cells, topo, _), d in zip(meshes, disp)]
