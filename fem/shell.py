"""Reissner–Mindlin flat shell assembled on a mesh of quadrilaterals
(MITC4 bending and shear, plane-stress membrane with incompatible modes)
and triangles (MITC3 shear with edge-smoothed membrane and bending,
:mod:`flexbed.fem.triangle_shell`), mixed freely.

Five degrees of freedom per node, u, v, w, θx, θy (see
:mod:`flexbed.fem.mitc4`); the bed frame's z is the mid-surface normal.
Unlike the Kirchhoff plate the model has in-plane motion and so all six
rigid-body motions, and its mass matrix carries every translation: the
bed's mass, centre of mass and inertia come from it.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import scipy.sparse as sp

from .fixed_masses import attachment
from .geometry import GeometryError
from .mitc4 import element_drilling, element_matrices
from .spec import PlateSpec, PlateSpecError
from .stiffeners import stiffener_matrices
from .cells import is_triangle
from .triangle_shell import triangle_blocks

DOFS_PER_NODE = 5
DOF_NAMES = ("u", "v", "w", "theta_x", "theta_y")


def grid_mesh(spec: PlateSpec) -> tuple[np.ndarray, np.ndarray]:
    """Nodes (N, 2) [m] and counter-clockwise quads (ne, 4) of the
    rectangular nx × ny grid centred on the origin (node index = i + j (nx+1))."""
    a, b = spec.length_x, spec.length_y
    x = np.linspace(-a / 2, a / 2, spec.nx + 1)
    y = np.linspace(-b / 2, b / 2, spec.ny + 1)
    X, Y = np.meshgrid(x, y)
    nodes = np.column_stack([X.ravel(), Y.ravel()])
    i, j = np.meshgrid(np.arange(spec.nx), np.arange(spec.ny))
    n0 = (i + j * (spec.nx + 1)).ravel()
    cells = np.column_stack([n0, n0 + 1, n0 + spec.nx + 2, n0 + spec.nx + 1])
    return nodes, cells


def _assemble_parts(parts: list, n: int, per_node: int) -> sp.csr_matrix:
    """Sum element blocks into an (n, n) CSR matrix.

    parts: list of (blocks (ne, k, k), node stencils (ne, k / per_node)),
    each node carrying ``per_node`` consecutive DOFs."""
    data, rows, cols = [], [], []
    for blk, where in parts:
        dofs = (per_node * where[:, :, None] + np.arange(per_node)).reshape(where.shape[0], -1)
        k = dofs.shape[1]
        rows.append(np.repeat(dofs, k, axis=1).ravel())
        cols.append(np.tile(dofs, (1, k)).ravel())
        data.append(blk.ravel())
    return sp.coo_matrix((np.concatenate(data), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(n, n)).tocsr()


def _drilling(parts: list, N: int) -> sp.csr_matrix:
    """Nodal in-plane rotation (N, 5N): each element's value (operators
    (ne, 2c) on its c corners' (u, v)) averaged over the elements at a node."""
    count = np.zeros(N)
    for _, corners in parts:
        count += np.bincount(corners.ravel(), minlength=N)
    data, rows, cols = [], [], []
    for op, corners in parts:
        ne, c = corners.shape
        uv = (DOFS_PER_NODE * corners[:, :, None] + np.arange(2)).reshape(ne, 2 * c)
        rows.append(np.broadcast_to(corners[:, :, None], (ne, c, 2 * c)).ravel())
        data.append((op[:, None, :] / count[corners][:, :, None]).ravel())
        cols.append(np.broadcast_to(uv[:, None, :], (ne, c, 2 * c)).ravel())
    return sp.coo_matrix((np.concatenate(data), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(N, DOFS_PER_NODE * N)).tocsr()


@dataclass(frozen=True)
class ShellModel:
    """Assembled Mindlin shell. Matrices are (ndof, ndof) CSR, ndof = 5 N + m:
    the five DOFs of each node (node i: 5 i … 5 i + 4), then m DOFs of the
    stiffeners' own (``model = "hinged"``: the web's section rotation at
    each node of its line, :mod:`flexbed.fem.stiffeners`).

    Attributes
    ----------
    spec : PlateSpec
    nodes : ndarray (N, 2)
        Node coordinates [m].
    cells : ndarray (ne, 4)
        Quadrilaterals, counter-clockwise; triangles as (a, b, c, c)
        (:mod:`flexbed.fem.cells`).
    K, M : sparse (ndof, ndof)
        Stiffness and consistent mass.
    M0 : sparse (N, N)
        Scalar nodal mass ∫ρt N_i N_j dA [kg]: the mass of each
        translation component.
    M2 : sparse (N, N)
        ∫ρt³/12 N_i N_j dA [kg m²]: the rotary inertia of each rotation.
    K_xx, K_yy, K_twist, K_membrane, K_shear : sparse (ndof, ndof)
        Parts of K (bending βx,x², βy,y², the rest of the bending, the
        membrane, the transverse shear) that tell mode shapes apart.
    drilling : sparse (N, ndof)
        Nodal in-plane rotation ½(∂v/∂x − ∂u/∂y): element-centre values
        averaged over the elements around each node.
    thickness : ndarray (ne,)
        Thickness of each element [m].
    origin : ndarray (2,)
        Where the model's origin, the bed's centre of mass, is in the
        drawing frame the geometry was given in [m] (zero for the plain
        rectangle).
    mid_z : float
        Height of the mid-surface in the bed frame [m]: minus the centre of
        mass's height when fixed masses lift it.
    fixed : tuple
        Fixed masses as (FixedMass, centre in the bed frame's x, y and its
        height above the mid-surface (3,), DOFs (20,), T (3, 20), R (3, 20))
        (:mod:`flexbed.fem.fixed_masses`); their mass is in ``M``.
    extra_nodes : ndarray (m,) of int
        The node each DOF past 5 N sits at (the banded ordering puts it
        after that node's five).
    extra_rigid : sparse (m, 5 N) or None
        The extra DOFs' values in a rigid motion given by the nodes' DOFs
        (the web's section turns with the plate's normal).
    """

    spec: PlateSpec
    nodes: np.ndarray
    cells: np.ndarray
    K: sp.csr_matrix
    M: sp.csr_matrix
    M0: sp.csr_matrix
    M2: sp.csr_matrix
    K_xx: sp.csr_matrix
    K_yy: sp.csr_matrix
    K_twist: sp.csr_matrix
    K_membrane: sp.csr_matrix
    K_shear: sp.csr_matrix
    drilling: sp.csr_matrix
    thickness: np.ndarray
    origin: np.ndarray
    mid_z: float = 0.0
    fixed: tuple = ()
    extra_nodes: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    extra_rigid: sp.csr_matrix | None = None

    n_rigid = 6

    @property
    def node_dofs(self) -> np.ndarray:
        """Global DOF index (5, N): rows u, v, w, θx, θy."""
        N = self.nodes.shape[0]
        return np.arange(DOFS_PER_NODE * N).reshape(N, DOFS_PER_NODE).T

    def dof_vector(self, u=0.0, v=0.0, w=0.0, tx=0.0, ty=0.0) -> np.ndarray:
        """DOF vector (ndof,) from nodal values (the extra DOFs as in a
        rigid motion: ``extra_rigid`` of the nodal part)."""
        N = self.nodes.shape[0]
        out = np.empty((N, DOFS_PER_NODE))
        for k, values in enumerate((u, v, w, tx, ty)):
            out[:, k] = np.broadcast_to(values, (N,))
        if self.extra_rigid is None:
            return out.ravel()
        return np.concatenate([out.ravel(), self.extra_rigid @ out.ravel()])

    def rigid_vectors(self) -> np.ndarray:
        """DOF vectors (ndof, 6): translations along x, y, z, rotations about
        x, y, z (about the origin)."""
        x, y = self.nodes.T
        return np.column_stack([self.dof_vector(u=1.0), self.dof_vector(v=1.0),
                                self.dof_vector(w=1.0), self.dof_vector(w=y, tx=1.0),
                                self.dof_vector(w=-x, ty=1.0), self.dof_vector(u=-y, v=x)])

    def band_order(self) -> np.ndarray:
        """DOF ordering (ndof,) node row by node row along the shorter side."""
        x, y = self.nodes.T
        span_x, span_y = np.ptp(x), np.ptp(y)
        fast, slow = (x, y) if span_x <= span_y else (y, x)
        node_order = np.lexsort((fast, slow))
        if not self.extra_nodes.size:
            return self.node_dofs[:, node_order].T.ravel()
        N = self.nodes.shape[0]
        rank = np.empty(N, dtype=np.int64)
        rank[node_order] = np.arange(N)
        m = self.extra_nodes.size
        owner = np.concatenate([np.repeat(np.arange(N), DOFS_PER_NODE), self.extra_nodes])
        return np.lexsort((np.arange(DOFS_PER_NODE * N + m), rank[owner]))

    def translations(self, phi: np.ndarray) -> np.ndarray:
        """Nodal translations (n, N, 3) of DOF vectors phi (ndof, n)."""
        d = self.node_dofs
        return np.stack([phi[d[0]].T, phi[d[1]].T, phi[d[2]].T], axis=-1)

    def rotations(self, phi: np.ndarray) -> np.ndarray:
        """Nodal rotations (n, N, 3): θx, θy and the in-plane rotation."""
        d = self.node_dofs
        return np.stack([phi[d[3]].T, phi[d[4]].T, (self.drilling @ phi).T], axis=-1)

    def sign_field(self, phi: np.ndarray) -> np.ndarray:
        """The values (3N, n) whose largest decides a mode's sign."""
        d = self.node_dofs
        return np.concatenate([phi[d[2]], phi[d[0]], phi[d[1]]])

    def energy_parts(self) -> tuple:
        """Bending parts (βx,x², βy,y², rest) then membrane and shear."""
        return (self.K_xx, self.K_yy, self.K_twist, self.K_membrane, self.K_shear)

    def mirror_maps(self) -> tuple[np.ndarray, np.ndarray]:
        """Index maps of the nodes mirrored in x and in y (a node without a
        mirror image maps to itself)."""
        scale = max(np.ptp(self.nodes[:, 0]), np.ptp(self.nodes[:, 1]))
        # coordinates to 1e-9 of the bed's size as one integer key each
        # (|x| <= scale: the keys fit in int64), matched by sorting
        q = np.round(self.nodes / scale * 1e9).astype(np.int64) + 1_000_000_000
        key = q[:, 0] * 2_000_000_001 + q[:, 1]
        order = np.argsort(key)
        ordered = key[order]
        own = np.arange(self.nodes.shape[0])

        def find(k: np.ndarray) -> np.ndarray:
            pos = np.minimum(np.searchsorted(ordered, k), k.size - 1)
            return np.where(ordered[pos] == k, order[pos], own)

        mirrored_x = (2_000_000_000 - q[:, 0]) * 2_000_000_001 + q[:, 1]
        mirrored_y = q[:, 0] * 2_000_000_001 + (2_000_000_000 - q[:, 1])
        return find(mirrored_x), find(mirrored_y)

    def symmetry_fields(self, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Translations (3N, n), and the same mirrored in x and in y: a field
        symmetric under x → -x has u(-x) = -u(x), v and w even."""
        mx, my = self.mirror_maps()
        d = self.node_dofs
        u, v, w = phi[d[0]], phi[d[1]], phi[d[2]]
        # a mesh that is not its own mirror image: no symmetry to test ("-")
        nan = np.full((3 * self.nodes.shape[0], phi.shape[1]), np.nan)
        sx = np.concatenate([-u[mx], v[mx], w[mx]]) if self._mirrored(mx, 0) else nan
        sy = np.concatenate([u[my], -v[my], w[my]]) if self._mirrored(my, 1) else nan
        return np.concatenate([u, v, w]), sx, sy

    def _mirrored(self, m: np.ndarray, axis: int) -> bool:
        """True when map m sends every node to its mirror image in ``axis``."""
        p, q = self.nodes, self.nodes[m]
        scale = float(np.max(np.ptp(p, axis=0)))
        other = 1 - axis
        return bool(np.all(np.abs(q[:, axis] + p[:, axis]) <= 1e-9 * scale)
                    and np.all(np.abs(q[:, other] - p[:, other]) <= 1e-9 * scale))


def assemble_mesh(spec: PlateSpec, nodes: np.ndarray, cells: np.ndarray,
                  thickness: np.ndarray | None = None,
                  origin: np.ndarray | None = None) -> ShellModel:
    """Assemble the shell on a given mesh of quadrilaterals and triangles.

    Parameters
    ----------
    spec : PlateSpec
        Material (and the thickness when ``thickness`` is None).
    nodes : ndarray (N, 2)
        Node coordinates [m].
    cells : ndarray (ne, 4)
        Counter-clockwise quadrilaterals, and triangles as (a, b, c, c).
    thickness : ndarray (ne,), optional
        Thickness of each element [m].
    origin : ndarray (2,), optional
        Recorded as :attr:`ShellModel.origin`.

    Returns
    -------
    ShellModel
    """
    nodes = np.asarray(nodes, dtype=float)
    cells = np.asarray(cells, dtype=np.int64)
    ne, N = cells.shape[0], nodes.shape[0]
    t = np.full(ne, spec.thickness) if thickness is None else np.asarray(thickness, float)
    tri = is_triangle(cells)
    quads, tris = cells[~tri], cells[tri, :3]
    ndof = DOFS_PER_NODE * N
    names = ("membrane", "shear", "bend_xx", "bend_yy", "bend_rest")
    blocks = {k: [] for k in names + ("mass0", "mass2")}
    drill = []                                      # (operator (k, 2c), corners (k, c))
    if quads.shape[0]:
        xy = nodes[quads]
        e = element_matrices(xy, t[~tri], spec.young, spec.poisson, spec.density)
        for k in names:
            blocks[k].append((e[k], quads))
        blocks["mass0"].append((e["mass0"], quads))
        blocks["mass2"].append((e["mass2"], quads))
        drill.append((element_drilling(xy), quads))
    if tris.shape[0]:
        e = triangle_blocks(nodes, tris, t[tri], spec.young, spec.poisson, spec.density)
        for k in names:
            blocks[k].append(e[k])
        blocks["mass0"].append((e["mass0"], tris))
        blocks["mass2"].append((e["mass2"], tris))
        drill.append((e["drilling"], tris))
    parts = {k: _assemble_parts(blocks[k], ndof, DOFS_PER_NODE) for k in names}
    K = parts["membrane"] + parts["shear"] + parts["bend_xx"] + parts["bend_yy"] \
        + parts["bend_rest"]
    M0 = _assemble_parts(blocks["mass0"], N, 1)
    M2 = _assemble_parts(blocks["mass2"], N, 1)
    M = sp.csr_matrix((ndof, ndof))
    for k, blk in enumerate([M0, M0, M0, M2, M2]):
        sel = sp.csr_matrix((np.ones(N), (DOFS_PER_NODE * np.arange(N) + k, np.arange(N))),
                            shape=(ndof, N))
        M = M + sel @ blk @ sel.T
    drilling = _drilling(drill, N)
    K = (0.5 * (K + K.T)).tocsr()
    return ShellModel(spec=spec, nodes=nodes, cells=cells, K=K, M=M.tocsr(), M0=M0, M2=M2,
                      K_xx=parts["bend_xx"], K_yy=parts["bend_yy"], K_twist=parts["bend_rest"],
                      K_membrane=parts["membrane"], K_shear=parts["shear"], drilling=drilling,
                      thickness=t, origin=np.zeros(2) if origin is None else np.asarray(origin))


def assemble_shell(spec: PlateSpec) -> ShellModel:
    """The shell on the spec's mesh, origin at the bed's centre of mass
    (:func:`flexbed.fem.layout.bed_layout`), fixed masses included."""
    from .layout import bed_layout
    lay = bed_layout(spec)
    model = assemble_mesh(spec, lay.nodes, lay.cells, lay.thickness, origin=lay.centre[:2])
    if not lay.fixed and not spec.stiffeners:
        return model
    mass_blocks, stiff_blocks, attached = [], [], []
    for item, where in lay.fixed:
        cell, s_nat = lay.locate(where[0], where[1])
        dofs, T, R = attachment(lay.nodes, lay.cells, cell, s_nat, item.position[2])
        mass_blocks.append((dofs, item.mass * T.T @ T + R.T @ np.array(item.inertia) @ R))
        attached.append((item, where, dofs, T, R))
    n = model.M.shape[0]
    extra_nodes, extra_rigid = [], []
    for st in spec.stiffeners:
        try:
            K, M, slices, own = stiffener_matrices(st, lay.nodes, lay.cells, model.drilling,
                                                   lay.centre[:2], spec.young, spec.poisson,
                                                   spec.density, first=n)
        except GeometryError as exc:
            raise PlateSpecError("stiffener", str(exc)) from None
        stiff_blocks += K
        mass_blocks += M
        attached += slices
        if own is not None:
            extra_nodes.append(own[0])
            extra_rigid.append(own[1])
            n += own[0].size
    if n > model.M.shape[0]:
        model = replace(model, extra_nodes=np.concatenate(extra_nodes),
                        extra_rigid=sp.vstack(extra_rigid).tocsr(),
                        **{k: _grown(getattr(model, k), n) for k in (
                            "K", "M", "K_xx", "K_yy", "K_twist", "K_membrane", "K_shear",
                            "drilling")})
    K = (model.K + _sum_blocks(stiff_blocks, n)).tocsr() if stiff_blocks else model.K
    return replace(model, K=K, M=(model.M + _sum_blocks(mass_blocks, n)).tocsr(),
                   mid_z=lay.mid_z, fixed=tuple(attached))


def _grown(A: sp.spmatrix, n: int) -> sp.csr_matrix:
    """A with its columns (and its rows, when square) padded with zeros to n."""
    A = A.tocoo()
    rows = n if A.shape[0] == A.shape[1] else A.shape[0]
    return sp.coo_matrix((A.data, (A.row, A.col)), shape=(rows, n)).tocsr()


def _sum_blocks(blocks: list, n: int) -> sp.csr_matrix:
    """Σ of dense blocks (dofs (k,), (k, k)) into an (n, n) matrix."""
    data = np.concatenate([b.ravel() for _, b in blocks])
    rows = np.concatenate([np.repeat(d, d.size) for d, _ in blocks])
    cols = np.concatenate([np.tile(d, d.size) for d, _ in blocks])
    return sp.coo_matrix((data, (rows, cols)), shape=(n, n)).tocsr()
