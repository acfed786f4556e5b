"""A 3D-solid reference model of a bed: scikit-fem hexahedra, linear
elasticity, consistent mass, free–free modes by shift-invert.

Used only to *check* the shell (:mod:`flexbed.fem.shell`) and its
stiffeners: the reference bed as a solid block, optionally with a
rectangular cut-out through it and flat-bar stiffeners welded under it
along its whole length (y). Plate and webs are one conforming mesh: a
tensor grid whose lines pass through every face of the plate, the hole and
the webs, with the cells outside the solid removed.

Elements: triquadratic 27-node hexahedra (``ElementHex2``) with 3 × 3 × 3
Gauss points (exact for both matrices on these rectangular boxes),
quadratic through the thickness. ``level`` n halves every cell side of the
base grid n times in the plate's plane and down the webs; ``nz`` elements
go through the plate's thickness (one already represents bending and the
Poisson thickness change, yet a thick plate's torsion needs more: see
docs/solid-reference.md); one element goes across a web's thickness (its
displacement across 20 mm is at most quadratic).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from skfem import Basis, BilinearForm, ElementHex2, MeshHex, asm

from .spec import PlateSpec

#: the reference bed, whose values the solid's defaults are
_REFERENCE = PlateSpec()


@dataclass(frozen=True)
class Web:
    """A flat bar under the plate along its whole length: centre line at
    x = ``x`` [m], ``width`` (along x) and ``height`` (down from the plate's
    lower face) [m]."""

    x: float
    width: float
    height: float


@dataclass(frozen=True)
class SolidBed:
    """A rectangular plate centred on the origin, mid-surface z = 0.

    Parameters
    ----------
    length_x, length_y, thickness : float
        Plate sides and thickness [m] (defaults: the reference bed).
    young, poisson, density : float
        Steel [Pa, -, kg/m³].
    hole : (x0, x1, y0, y1) or None
        A rectangular cut-out through the plate [m].
    webs : tuple of Web
        Flat bars under the plate (not through the hole: the hole must not
        cross a web).
    h0 : float
        Target cell side of the base grid (level 0) [m].
    """

    length_x: float = _REFERENCE.length_x
    length_y: float = _REFERENCE.length_y
    thickness: float = _REFERENCE.thickness
    young: float = _REFERENCE.young
    poisson: float = _REFERENCE.poisson
    density: float = _REFERENCE.density
    hole: tuple[float, float, float, float] | None = None
    webs: tuple[Web, ...] = ()
    h0: float = 0.2

    def __post_init__(self) -> None:
        if self.hole is not None:
            x0, x1, y0, y1 = self.hole
            if not (-self.length_x / 2 <= x0 < x1 <= self.length_x / 2
                    and -self.length_y / 2 <= y0 < y1 <= self.length_y / 2):
                raise ValueError(f"hole = {self.hole!r} must lie on the plate")
            for web in self.webs:
                if web.x + web.width / 2 > x0 and web.x - web.width / 2 < x1:
                    raise ValueError(f"hole = {self.hole!r} must not cross the web at "
                                     f"x = {web.x!r} m")


def _lines(breaks: list[float], counts: list[int]) -> np.ndarray:
    """Grid lines splitting each interval between sorted breaks in counts[i] parts."""
    parts = [np.linspace(a, b, n + 1)[:-1] for a, b, n in zip(breaks[:-1], breaks[1:], counts)]
    return np.append(np.concatenate(parts), breaks[-1])


def _breaks(edges: set[float], fixed: set[tuple[float, float]], h0: float, level: int
            ) -> np.ndarray:
    """Lines through every edge; intervals listed in ``fixed`` keep one cell."""
    b = sorted(edges)
    counts = [1 if (lo, hi) in fixed else max(1, round((hi - lo) / h0)) * 2 ** level
              for lo, hi in zip(b[:-1], b[1:])]
    return _lines(b, counts)


def solid_mesh(bed: SolidBed, level: int = 0, nz: int = 1) -> MeshHex:
    """The conforming hexahedral mesh of plate, hole and webs.

    Parameters
    ----------
    bed : SolidBed
    level : int
        Refinement level (cell sides h0 / 2**level in the plate's plane and
        down the webs).
    nz : int
        Elements through the plate's thickness.
    """
    a, b, t = bed.length_x / 2, bed.length_y / 2, bed.thickness / 2
    ex, fixed = {-a, a}, set()
    for web in bed.webs:
        lo, hi = web.x - web.width / 2, web.x + web.width / 2
        ex |= {lo, hi}
        fixed.add((lo, hi))
    ey = {-b, b}
    if bed.hole is not None:
        ex |= {bed.hole[0], bed.hole[1]}
        ey |= {bed.hole[2], bed.hole[3]}
    x = _breaks(ex, fixed, bed.h0, level)
    y = _breaks(ey, set(), bed.h0, level)
    z = np.linspace(-t, t, nz + 1)
    depth = max((web.height for web in bed.webs), default=0.0)
    if depth > 0:
        zb = sorted({-t - web.height for web in bed.webs} | {-t})
        below = _lines(zb, [max(1, round((hi - lo) / bed.h0)) * 2 ** level
                            for lo, hi in zip(zb[:-1], zb[1:])])
        z = np.concatenate([below[:-1], z])
    mesh = MeshHex.init_tensor(x, y, z)
    c = mesh.p[:, mesh.t].mean(axis=1)
    keep = c[2] > -t
    for web in bed.webs:
        keep |= (np.abs(c[0] - web.x) < web.width / 2) & (c[2] > -t - web.height)
    if bed.hole is not None:
        x0, x1, y0, y1 = bed.hole
        keep &= ~((c[0] > x0) & (c[0] < x1) & (c[1] > y0) & (c[1] < y1) & (c[2] > -t))
    return mesh.remove_elements(np.flatnonzero(~keep))


@dataclass(frozen=True)
class SolidModes:
    """Free–free modes of a solid bed.

    Attributes
    ----------
    frequency : ndarray (n,)
        Elastic natural frequencies [Hz], ascending (the six rigid modes
        dropped).
    vectors : ndarray (3N, n)
        Mass-normalised mode shapes; DOF 3 i + c is component c (x, y, z) at
        node i.
    nodes : ndarray (N, 3)
        The nodes of the ElementHex2 basis (vertices, edge and face
        mid-points, centres) [m].
    """

    frequency: np.ndarray
    vectors: np.ndarray
    nodes: np.ndarray

    @property
    def dofs(self) -> int:
        return self.vectors.shape[0]

    def midsurface(self, points: np.ndarray) -> np.ndarray:
        """Mode translations (u, v, w) at points (P, 2) of the mid-surface
        z = 0 that are nodes of the mesh: (n, P, 3). Raises KeyError for a
        point that is not a node."""
        scale = 1e6
        on = np.flatnonzero(np.abs(self.nodes[:, 2]) < 1e-9)
        key = {(round(self.nodes[i, 0] * scale), round(self.nodes[i, 1] * scale)): i for i in on}
        rows = np.array([key[(round(p[0] * scale), round(p[1] * scale))] for p in points])
        v = self.vectors.reshape(-1, 3, self.vectors.shape[1])[rows]     # (P, 3, n)
        return np.transpose(v, (2, 0, 1))


def gradient_products(G: np.ndarray, dx: np.ndarray) -> np.ndarray:
    """A[e, a, b, i, j] = ∫ ∂a φi ∂b φj over each element (ne, 3, 3, k, k),
    from the basis gradients G (k, 3, ne, nq) and quadrature weights dx
    (ne, nq)."""
    return np.einsum("iaeq,jbeq,eq->eabij", G, G, dx, optimize=True)


def assemble(mesh: MeshHex, young: float, poisson: float, density: float,
             chunk: int = 256) -> tuple[sp.csr_matrix, sp.csr_matrix, Basis]:
    """Stiffness and consistent mass of isotropic linear elasticity on
    ElementHex2, DOF 3 i + c.

    The scalar basis (scikit-fem: element, mapping, 3 × 3 × 3 Gauss points)
    gives ∫ ∂a φi ∂b φj; the element blocks are
    K[(i, c), (j, d)] = λ A_cd + μ (δ_cd Σ_a A_aa + A_dc), the same as
    scikit-fem's vector ``linear_elasticity`` form (tested) without its
    per-pair kernel calls.
    """
    basis = Basis(mesh, ElementHex2(), intorder=4)
    mu = young / (2 * (1 + poisson))
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    k = len(basis.basis)
    dofs = basis.element_dofs.T                                        # (ne, k)
    vdofs = (3 * dofs[:, :, None] + np.arange(3)).reshape(len(dofs), 3 * k)
    n = 3 * basis.N
    K = sp.csr_matrix((n, n))
    eye = np.eye(3)
    G = np.array([phi[0].grad for phi in basis.basis])                  # (k, 3, ne, nq)
    for lo in range(0, len(dofs), chunk):
        A = gradient_products(G[:, :, lo:lo + chunk], basis.dx[lo:lo + chunk])
        lap = np.trace(A, axis1=1, axis2=2)                            # (e, k, k)
        blocks = (lam * A + mu * np.swapaxes(A, 1, 2)
                  + mu * eye[None, :, :, None, None] * lap[:, None, None])   # (e, c, d, i, j)
        blocks = np.transpose(blocks, (0, 3, 1, 4, 2)).reshape(-1, 3 * k, 3 * k)
        d = vdofs[lo:lo + chunk]
        rows = np.repeat(d, 3 * k, axis=1).ravel()
        cols = np.tile(d, (1, 3 * k)).ravel()
        K = K + sp.coo_matrix((blocks.ravel(), (rows, cols)), shape=(n, n)).tocsr()
    Ms = asm(_mass, basis)
    M = density * sp.kron(Ms, sp.identity(3), format="csr")
    return K, M, basis


@BilinearForm
def _mass(u, v, w):
    return u * v


def solid_modes(bed: SolidBed, level: int = 0, nz: int = 1, n_modes: int = 8
                ) -> SolidModes:
    """The first ``n_modes`` elastic modes of the solid bed.

    Shift-invert Lanczos (SciPy ``eigsh``, SuperLU factor of K + σ²M —
    minimum-degree ordering — with a shift below zero, so the six rigid
    modes are found too and dropped).

    Raises
    ------
    RuntimeError
        The six lowest eigenvalues are not rigid-body ones.
    """
    K, M, basis = assemble(solid_mesh(bed, level, nz), bed.young, bed.poisson, bed.density)
    shift = (2 * math.pi * 5.0) ** 2
    # minimum degree on AᵀA + A: a quarter of COLAMD's fill on these meshes
    lu = sla.splu((K + shift * M).tocsc(), permc_spec="MMD_AT_PLUS_A",
                  options=dict(SymmetricMode=True))
    inv = sla.LinearOperator(K.shape, matvec=lu.solve, dtype=float)
    vals, vecs = sla.eigsh(K, k=n_modes + 6, M=M, sigma=-shift, which="LM", OPinv=inv)
    order = np.argsort(vals)
    vals, vecs = vals[order], vecs[:, order]
    if np.max(np.abs(vals[:6])) > 1e-6 * vals[6]:
        raise RuntimeError(f"the six lowest eigenvalues {vals[:6]} are not rigid-body modes")
    f = np.sqrt(vals[6:]) / (2 * math.pi)
    return SolidModes(f, vecs[:, 6:], basis.doflocs.T.copy())
