"""Free–free modes of the plate: shift-invert eigen-solution, rigid-body
modes told apart by what they are, mass-normalised elastic modes with a
deterministic sign, and a label saying what each elastic mode looks like.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg as la
import scipy.sparse.linalg as sla

from .banded import BandedCholesky
from .plate import PlateModel

RIGID_MODES = 3           # a bending-only plate has w-translation and two tilts
# (a model says how many it has: ``model.n_rigid``, 6 for the Mindlin shell)
RIGID_FRACTION = 0.5      # share of a vector's M-norm in the rigid subspace
DEGENERATE_RTOL = 1e-8    # frequencies this close form one eigenspace
_DENSE_LIMIT = 400        # DOFs below which a dense solve is used


class ModesError(ValueError):
    """Modes that cannot be delivered as asked (count, cut-off)."""


@dataclass(frozen=True)
class ModeSet:
    """Elastic free–free modes of a plate.

    Attributes
    ----------
    omega : ndarray (n,)
        Circular frequencies [rad/s], ascending.
    vectors : ndarray (ndof, n)
        DOF vectors, mass-normalised (ΦᵀMΦ = I), rigid-free (RᵀMΦ = 0)
        [kg^-1/2 per unit DOF].
    rigid_omega : ndarray (3,) or (6,)
        Frequencies the solver returned for the vectors identified as rigid
        motions [rad/s] (zero up to the solver's accuracy).
    labels : tuple of str
        "bending about x", "bending about y", "torsion", "in-plane" (Mindlin:
        most of the strain energy in the membrane) or "mixed".
    symmetry : tuple of str
        Two letters per mode: symmetric (S) or antisymmetric (A) under
        x → -x, then under y → -y ("-" for neither).
    energy_fractions : ndarray (n, 3)
        Share of the bending energy in w_xx², w_yy² and the twist w_xy²
        (Mindlin: in βx,x², βy,y² and the rest).
    split_degenerate : bool
        True when the last mode kept and the first one left out share a
        frequency (the cut splits an eigenspace).
    omega_next : float
        Circular frequency of the first elastic mode left out [rad/s]
        (inf when every mode is kept): the set holds every mode below it.
    """

    omega: np.ndarray
    vectors: np.ndarray
    rigid_omega: np.ndarray
    labels: tuple[str, ...]
    symmetry: tuple[str, ...]
    energy_fractions: np.ndarray
    split_degenerate: bool
    omega_next: float

    @property
    def frequency(self) -> np.ndarray:
        """Frequencies [Hz], (n,)."""
        return self.omega / (2.0 * math.pi)


def _eigen(model, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Lowest ``k`` eigenpairs of K φ = λ M φ (λ = ω²)."""
    n = model.K.shape[0]
    if n <= _DENSE_LIMIT or k >= n - 1:
        vals, vecs = la.eigh(model.K.toarray(), model.M.toarray())
        return vals[:k], vecs[:, :k]
    spec = model.spec
    # Shift below zero, at a fraction of a beam estimate of the first elastic
    # eigenvalue: K - σM is then positive definite (free–free K is singular)
    # and well conditioned.
    if isinstance(model, PlateModel):
        length = max(spec.length_x, spec.length_y)
    else:                                      # any outline: its bounding box
        length = float(np.max(np.ptp(model.nodes, axis=0)))
    omega1 = (4.73 / length) ** 2 * math.sqrt(spec.rigidity / (spec.density * spec.thickness))
    sigma = -0.1 * omega1 ** 2
    try:
        factor = BandedCholesky(model.K - sigma * model.M, order=model.band_order())
    except np.linalg.LinAlgError:
        raise ModesError("the stiffness is not positive semi-definite (a mesh with inverted "
                         "or degenerate elements, or a part not joined to the rest)") from None
    op = sla.LinearOperator(model.K.shape, matvec=factor.solve, dtype=float)
    start = np.random.default_rng(0).standard_normal(n)   # deterministic, generic
    vals, vecs = sla.eigsh(model.K, k=k, M=model.M, sigma=sigma, which="LM", OPinv=op, v0=start)
    order = np.argsort(vals)
    return vals[order], vecs[:, order]


def _fix_sign(w: np.ndarray) -> float:
    """+1 or -1 so that the largest nodal deflection (first node among
    near-ties) is positive."""
    mag = np.abs(w)
    first = int(np.flatnonzero(mag >= (1.0 - 1e-6) * mag.max())[0])
    return 1.0 if w[first] >= 0 else -1.0


def _mirror_maps(nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Index maps of the nodes mirrored in x and in y (tensor grids)."""
    key = {(round(x, 9), round(y, 9)): i for i, (x, y) in enumerate(nodes)}
    mx = np.array([key.get((round(-x, 9), round(y, 9)), i) for i, (x, y) in enumerate(nodes)])
    my = np.array([key.get((round(x, 9), round(-y, 9)), i) for i, (x, y) in enumerate(nodes)])
    return mx, my


def _symmetry_letter(w: np.ndarray, mirrored: np.ndarray) -> str:
    scale = np.linalg.norm(w)
    if np.linalg.norm(w - mirrored) <= 1e-6 * scale:
        return "S"
    if np.linalg.norm(w + mirrored) <= 1e-6 * scale:
        return "A"
    return "-"


def _describe(model, vectors: np.ndarray):
    if isinstance(model, PlateModel):
        mats = (model.K_xx, model.K_yy, model.K_twist)
    else:
        mats = model.energy_parts()
    parts = np.column_stack([np.einsum("ij,ij->j", vectors, m @ vectors) for m in mats])
    fractions = parts[:, :3] / parts[:, :3].sum(axis=1, keepdims=True)
    names = ("bending about y", "bending about x", "torsion")
    labels = [names[int(np.argmax(f))] if f.max() >= 0.6 else "mixed" for f in fractions]
    if parts.shape[1] > 3:                       # membrane energy: an in-plane mode
        membrane = parts[:, 3] / parts.sum(axis=1)
        labels = ["in-plane" if m >= 0.6 else lab for m, lab in zip(membrane, labels)]
    if isinstance(model, PlateModel):
        mx, my = _mirror_maps(model.nodes)
        w = vectors[model.node_dofs[0]]
        fields = (w, w[mx], w[my])
    else:
        fields = model.symmetry_fields(vectors)
    f, fx, fy = fields
    symmetry = tuple(_symmetry_letter(f[:, j], fx[:, j]) + _symmetry_letter(f[:, j], fy[:, j])
                     for j in range(vectors.shape[1]))
    return tuple(labels), symmetry, fractions


def free_free_modes(model: PlateModel, n_modes: int | None = None,
                    fmax: float | None = None) -> ModeSet:
    """Elastic free–free modes: the lowest ``n_modes``, or all below ``fmax``.

    Parameters
    ----------
    model : PlateModel
        Assembled plate.
    n_modes : int, optional
        Number of elastic modes to keep (≥ 1).
    fmax : float, optional
        Keep every elastic mode with frequency below this [Hz] (at least one).

    Returns
    -------
    ModeSet

    Raises
    ------
    ModesError
        Neither or both of ``n_modes``/``fmax``; zero modes; more modes than
        the mesh has; no mode below ``fmax``; rigid modes not found.
    """
    if (n_modes is None) == (fmax is None):
        raise ModesError("give either a number of modes or a cut-off frequency")
    ndof = model.K.shape[0]
    n_rigid = getattr(model, "n_rigid", RIGID_MODES)
    available = ndof - n_rigid
    if n_modes is not None:
        if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) or n_modes < 1:
            raise ModesError(f"modes = {n_modes!r}: at least one elastic mode is needed")
        if n_modes > available:
            raise ModesError(f"modes = {n_modes}: the {model.spec.nx} x {model.spec.ny} plate "
                             f"has only {available} elastic modes")
        k = min(ndof, n_rigid + n_modes + 4)
    else:
        if not (fmax > 0):
            raise ModesError(f"fmax = {fmax!r} must be > 0 Hz")
        k = min(ndof, n_rigid + 12)
    omega_cut = None if fmax is None else 2.0 * math.pi * fmax
    while True:
        vals, vecs = _eigen(model, k)
        if omega_cut is None or k >= ndof or vals[-1] > omega_cut ** 2:
            break
        k = min(ndof, 2 * k)

    M = model.M
    R = model.rigid_vectors()
    gram = R.T @ (M @ R)
    coeff = la.solve(gram, R.T @ (M @ vecs), assume_a="pos")          # (3, k)
    norms = np.einsum("ij,ij->j", vecs, M @ vecs)
    fraction = np.einsum("ij,ij->j", coeff, gram @ coeff) / norms
    rigid = fraction > RIGID_FRACTION
    if rigid.sum() != n_rigid:
        raise ModesError(f"expected {n_rigid} rigid-body modes, found {int(rigid.sum())} "
                         f"(fractions {np.round(fraction[:n_rigid + 2], 6).tolist()})")
    rigid_omega = np.sqrt(np.abs(vals[rigid]))
    # Elastic vectors: remove any rigid component, then a Rayleigh–Ritz step
    # on their span makes them M-orthonormal and K-orthogonal to round-off.
    phi = vecs[:, ~rigid] - R @ coeff[:, ~rigid]
    Kr = phi.T @ (model.K @ phi)
    Mr = phi.T @ (M @ phi)
    lam, y = la.eigh(0.5 * (Kr + Kr.T), 0.5 * (Mr + Mr.T))
    phi = phi @ y
    lam = np.maximum(lam, 0.0)
    omega_all = np.sqrt(lam)

    if n_modes is not None:
        keep = n_modes
    else:
        keep = int(np.sum(omega_all < omega_cut))
        if keep == 0:
            raise ModesError(f"fmax = {fmax} Hz: no elastic mode below it "
                             f"(the first is at {omega_all[0] / (2 * math.pi):.4g} Hz)")
    split = (keep < omega_all.size
             and abs(omega_all[keep] - omega_all[keep - 1]) <= DEGENERATE_RTOL * omega_all[keep])
    phi = phi[:, :keep]
    w = phi[model.node_dofs[0]] if isinstance(model, PlateModel) else model.sign_field(phi)
    signs = np.array([_fix_sign(w[:, j]) for j in range(keep)])
    phi = phi * signs
    labels, symmetry, fractions = _describe(model, phi)
    return ModeSet(omega=omega_all[:keep].copy(), vectors=phi, rigid_omega=rigid_omega,
                   labels=labels, symmetry=symmetry, energy_fractions=fractions,
                   split_degenerate=bool(split),
                   omega_next=float(omega_all[keep]) if keep < omega_all.size else math.inf)
