"""Stresses in the bed: linear operators from a DOF vector to the plate's
stresses at element centres, and the plane-stress measures built on them.

Recovery point: the **centre of each element** (cell data; nothing is
extrapolated to nodes). For the bilinear shell (MITC4) the centre is the
one-point Gauss point where membrane strain and curvature are most
accurate (and the incompatible membrane modes 1 − ξ², 1 − η² have zero
gradient there, so the condensed modes need not be recovered); a triangle's
strain and curvature are constant over it (its own, not the edge-smoothed
ones); a Kirchhoff (BFS) element is evaluated at its centre.

At height z above the mid-surface the in-plane strain is ε0 + z κ
(membrane strain ε0, curvature κ = ∇β, engineering shear), so with
Q = E / (1 − ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1 − ν)/2]]

    σ(z) = Q ε0 + z Q κ,      top face z = +t/2, bottom z = −t/2.

The operators return the membrane stress σm = Q ε0 and the bending
stress at the top face σb = (t/2) Q κ; the bottom face's bending stress is
−σb. Components are (σxx, σyy, τxy) in the bed frame [Pa].

Stiffeners' stresses (:func:`stiffener_stress_operators`) are recovered
from the shell DOFs the stiffener is joined to, with its own kinematics
(centroid at the offset, moving as U = (u + e θy, v − e θx, w); a hinged
stiffener's section with its own rotation ψ, DOFs after the nodes'); it is
a small function of its own so that a different stiffener model changes
one place.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .cells import is_triangle
from .mitc3 import gradients, strain_operators
from .mitc4 import shape

__all__ = ["BedStressOperators", "StiffenerStress", "shell_stress_operators",
           "plate_stress_operators", "stiffener_stress_operators", "von_mises", "principal",
           "face_stresses"]


@dataclass(frozen=True)
class StiffenerStress:
    """Stress operators of one stiffener, one row per beam element (at its
    mid-point).

    Attributes
    ----------
    name : str
    centres : ndarray (k, 2)
        Mid-points of the beam elements in the bed frame [m].
    axial : sparse (k, ndof)
        Axial stress at the section's centroid E ε_c [Pa per unit DOF].
    gradient : sparse (k, ndof)
        Bending stress per metre above the centroid, −E w'' (a hinged
        stiffener's: −E ψ', its own curvature) [Pa/m per unit DOF]: the
        stress at a fibre d above the centroid is axial + d · gradient.
    fibres : ndarray (2,)
        The extreme fibres' heights above the centroid [m] (upper, lower).
    """

    name: str
    centres: np.ndarray
    axial: sp.csr_matrix
    gradient: sp.csr_matrix
    fibres: np.ndarray


@dataclass(frozen=True)
class BedStressOperators:
    """Linear maps from a DOF vector to the bed's stresses.

    Attributes
    ----------
    centres : ndarray (ne, 2)
        Element centres in the bed frame [m].
    membrane : sparse (3 ne, ndof)
        σm at each centre, rows (e, component) [Pa per unit DOF].
    bending : sparse (3 ne, ndof)
        Bending stress at the top face, σb [Pa per unit DOF].
    stiffeners : tuple of StiffenerStress
    """

    centres: np.ndarray
    membrane: sp.csr_matrix
    bending: sp.csr_matrix
    stiffeners: tuple = ()

    def of(self, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Membrane and top-face bending stresses (n, ne, 3) of DOF vectors
        phi (ndof, n) [Pa per unit of phi]."""
        ne = self.centres.shape[0]
        n = phi.shape[1]
        m = (self.membrane @ phi).T.reshape(n, ne, 3)
        b = (self.bending @ phi).T.reshape(n, ne, 3)
        return m, b


def _material(young: float, poisson: float) -> np.ndarray:
    nu = poisson
    return young / (1.0 - nu * nu) * np.array([[1.0, nu, 0.0], [nu, 1.0, 0.0],
                                               [0.0, 0.0, 0.5 * (1.0 - nu)]])


def _scatter(blocks: np.ndarray, dofs: np.ndarray, rows: np.ndarray, ndof: int,
             nrows: int) -> sp.csr_matrix:
    """(k, 3, d) blocks on DOFs (k, d) for elements ``rows`` (k,) into a
    (3 nrows, ndof) matrix."""
    k, c, d = blocks.shape
    r = (3 * rows[:, None, None] + np.arange(c)[None, :, None]).repeat(d, axis=2)
    cc = np.broadcast_to(dofs[:, None, :], (k, c, d))
    return sp.coo_matrix((blocks.ravel(), (r.ravel(), cc.ravel())),
                         shape=(3 * nrows, ndof)).tocsr()


def shell_stress_operators(model) -> BedStressOperators:
    """Stress operators of a :class:`flexbed.fem.shell.ShellModel`, its
    stiffeners included.

    Parameters
    ----------
    model : ShellModel

    Returns
    -------
    BedStressOperators
    """
    spec, nodes, cells, t = model.spec, model.nodes, model.cells, model.thickness
    ne, ndof = cells.shape[0], model.K.shape[0]
    Q = _material(spec.young, spec.poisson)
    tri = is_triangle(cells)
    centres = np.empty((ne, 2))
    mem, ben = [], []
    quads = np.flatnonzero(~tri)
    if quads.size:
        xy = nodes[cells[quads]]
        _, dN = shape(0.0, 0.0)
        J = np.einsum("ai,eaj->eij", dN, xy)
        dNx = np.einsum("eij,aj->eai", np.linalg.inv(J), dN)          # (nq, 4, 2)
        U, V, TX, TY = (np.arange(4) * 5 + k for k in (0, 1, 3, 4))
        Bm = np.zeros((quads.size, 3, 20))
        Bm[:, 0, U] = dNx[:, :, 0]
        Bm[:, 1, V] = dNx[:, :, 1]
        Bm[:, 2, U] = dNx[:, :, 1]
        Bm[:, 2, V] = dNx[:, :, 0]
        Bb = np.zeros((quads.size, 3, 20))                             # β = (θy, −θx)
        Bb[:, 0, TY] = dNx[:, :, 0]
        Bb[:, 1, TX] = -dNx[:, :, 1]
        Bb[:, 2, TY] = dNx[:, :, 1]
        Bb[:, 2, TX] = -dNx[:, :, 0]
        dofs = (5 * cells[quads][:, :, None] + np.arange(5)).reshape(quads.size, 20)
        mem.append(_scatter(Q @ Bm, dofs, quads, ndof, ne))
        ben.append(_scatter((0.5 * t[quads])[:, None, None] * (Q @ Bb), dofs, quads, ndof, ne))
        centres[quads] = xy.mean(axis=1)
    tris = np.flatnonzero(tri)
    if tris.size:
        corners = cells[tris, :3]
        xy = nodes[corners]
        _, dNx = gradients(xy)
        Bm, Bb = strain_operators(dNx)
        dofs = (5 * corners[:, :, None] + np.arange(5)).reshape(tris.size, 15)
        mem.append(_scatter(Q @ Bm, dofs, tris, ndof, ne))
        ben.append(_scatter((0.5 * t[tris])[:, None, None] * (Q @ Bb), dofs, tris, ndof, ne))
        centres[tris] = xy.mean(axis=1)
    stiff, first = [], 5 * nodes.shape[0]          # the hinged ones' own DOFs follow the nodes'
    for st in spec.stiffeners:
        stiff.append(stiffener_stress_operators(st, model, first))
        if st.model == "hinged":
            first += stiff[-1].centres.shape[0] + 1
    stiff = tuple(stiff)
    return BedStressOperators(centres=centres, membrane=sum(mem[1:], mem[0]).tocsr(),
                              bending=sum(ben[1:], ben[0]).tocsr(), stiffeners=stiff)


def plate_stress_operators(model) -> BedStressOperators:
    """Stress operators of a Kirchhoff :class:`flexbed.fem.plate.PlateModel`
    (bending only: the membrane operator is zero). With u = −z ∂w/∂x the
    curvature is κ = −(w_xx, w_yy, 2 w_xy)."""
    from skfem import Basis

    spec = model.spec
    mesh, elem = model.mesh, model.basis.elem
    # one quadrature point at each cell's centre (reference square [0, 1]²)
    centre = Basis(mesh, elem, quadrature=(np.array([[0.5], [0.5]]), np.array([1.0])))
    ne, ndof = mesh.t.shape[1], model.K.shape[0]
    nb = len(centre.basis)
    curv = np.zeros((ne, 3, nb))
    for j in range(nb):
        H = centre.basis[j][0].hess[..., 0]                              # (2, 2, ne)
        curv[:, 0, j] = -H[0, 0]
        curv[:, 1, j] = -H[1, 1]
        curv[:, 2, j] = -2.0 * H[0, 1]
    Q = _material(spec.young, spec.poisson)
    dofs = centre.element_dofs.T                                         # (ne, nb)
    rows = np.arange(ne)
    bending = _scatter(0.5 * spec.thickness * (Q @ curv), dofs, rows, ndof, ne)
    centres = mesh.p[:, mesh.t].mean(axis=1).T
    return BedStressOperators(centres=centres, membrane=sp.csr_matrix((3 * ne, ndof)),
                              bending=bending)


def stiffener_fibres(st) -> np.ndarray:
    """Heights above a stiffener's centroid of its extreme fibres (2,) or
    (0,) [m]: (c, −c), c the centroid's height above the section's base
    (the end joined to the plate). Exact for the symmetric flat bar and I;
    for a T (flange at the free end, so its centroid lies nearer the flange
    than the base) the base fibre is exact and the flange's fibre, nearer
    than c, is over-estimated: a safe bound. A general section records no
    depth: none (the centroid's axial stress only). Adapt here when the
    stiffener model records its depth.
    """
    c = float(st.section.centroid)
    return np.array([c, -c]) if c > 0 else np.zeros(0)


def stiffener_stress_operators(st, model, first: int = 0) -> StiffenerStress:
    """Axial and bending stress operators of one stiffener on the shell.

    Kinematics (as the beam is joined, :mod:`flexbed.fem.stiffeners`): a
    fibre at height z above the mid-surface moves along the axis s by
    u_s + z β_s (β = (θy, −θx): β_s = s_x θy − s_y θx = −φ), so its strain
    is u_s' + z β_s'. Over a beam element between nodes A, B at distance L
    the centroid's strain is ε_c = (u_s,B − u_s,A)/L + e (β_s,B − β_s,A)/L
    and β_s' = (β_s,B − β_s,A)/L, which is also the cubic Hermite
    deflection's −w'' at the element's mid-point. A ``"hinged"`` stiffener
    has a section rotation ψ of its own (nodal DOFs ``first`` …, in order
    along its line): its fibre d above the centroid, a = d + c above the
    face z_f = e − c (c the centroid's height above the face, negative
    below it), moves by u_s − z_f φ − a ψ, so ε_c = u_s' + (e − c)
    β_s' − c ψ' and the gradient is −ψ' (its own curvature, not the
    plate's). The in-plane (lateral) bending and torsion stresses are not
    recovered.

    Parameters
    ----------
    st : Stiffener
    model : ShellModel
    first : int
        The first of a hinged stiffener's own DOFs.

    Returns
    -------
    StiffenerStress
    """
    from .stiffeners import line_nodes
    order, along = line_nodes(st, model.nodes, model.cells, model.origin)
    s3, _ = st.axes()
    E, ndof = model.spec.young, model.K.shape[0]
    a, b = order[:-1], order[1:]
    k, L = a.size, along[b] - along[a]

    hinged = st.model == "hinged"
    c = math.copysign(st.section.centroid, st.offset)     # the centroid above the face

    def operator(w_u: float, w_beta: float, w_psi: float = 0.0) -> sp.csr_matrix:
        """E (w_u Δu_s + w_beta Δβ_s + w_psi Δψ) / L per element."""
        per = np.array([w_u * s3[0], w_u * s3[1], -w_beta * s3[1], w_beta * s3[0]]
                       + ([w_psi] if hinged else []))
        cols, vals = [], []
        for node, own, sign in ((a, first + np.arange(k), -1.0), (b, first + 1 + np.arange(k),
                                                                  1.0)):
            at = [5 * node[:, None] + np.array([0, 1, 3, 4])]
            cols.append(np.concatenate(at + ([own[:, None]] if hinged else []), axis=1))
            vals.append(sign * E * per[None, :] / L[:, None])
        return sp.coo_matrix((np.concatenate(vals, axis=1).ravel(),
                              (np.repeat(np.arange(k), 2 * per.size),
                               np.concatenate(cols, axis=1).ravel())),
                             shape=(k, ndof)).tocsr()

    centres = 0.5 * (model.nodes[a] + model.nodes[b])
    if hinged:
        return StiffenerStress(name=st.name, centres=centres,
                               axial=operator(1.0, st.offset - c, -c),
                               gradient=operator(0.0, 0.0, -1.0), fibres=stiffener_fibres(st))
    return StiffenerStress(name=st.name, centres=centres,
                           axial=operator(1.0, st.offset), gradient=operator(0.0, 1.0),
                           fibres=stiffener_fibres(st))


def face_stresses(membrane: np.ndarray, bending: np.ndarray) -> np.ndarray:
    """Stress components at the top and bottom faces (..., 2, 3) [Pa] from
    σm and the top face's σb (..., 3)."""
    return np.stack([membrane + bending, membrane - bending], axis=-2)


def von_mises(sigma: np.ndarray) -> np.ndarray:
    """Plane-stress von Mises stress (...) of components (..., 3) =
    (σxx, σyy, τxy) [Pa]: √(σxx² − σxx σyy + σyy² + 3 τxy²)."""
    sx, sy, txy = sigma[..., 0], sigma[..., 1], sigma[..., 2]
    return np.sqrt(np.maximum(sx * sx - sx * sy + sy * sy + 3.0 * txy * txy, 0.0))


def principal(sigma: np.ndarray) -> np.ndarray:
    """In-plane principal stresses (..., 2), largest first, of components
    (..., 3) [Pa]."""
    sx, sy, txy = sigma[..., 0], sigma[..., 1], sigma[..., 2]
    mid = 0.5 * (sx + sy)
    r = np.hypot(0.5 * (sx - sy), txy)
    return np.stack([mid + r, mid - r], axis=-1)
