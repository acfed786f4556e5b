"""Modes of the mounted system: frequencies, damping, shapes, energy tables,
effective masses.

Undamped modes solve ``K φ = ω² M φ``
(:class:`~flexbed.dynamics.frequency.mounted.MountedSystem`).
The mounts of eq. 1–6 push along axes fixed in body i, which makes K
unsymmetric when they carry a preload (their axes turn with the body, the
force does not add the torque of that turn), so the general eigenproblem is
solved with its left vectors ψ as well (``ψᴴ K = ω² ψᴴ M``).

With damping (mount dampers, Rayleigh or modal bed damping) the modes are
the complex ones of the first-order form ``[[0, I], [−M⁻¹K, −M⁻¹C]]``:
each underdamped pair ``λ = −ζ ωₙ ± i ωₙ √(1 − ζ²)`` gives ``ωₙ = |λ|``,
``ζ = −Re λ / |λ|`` and the complex shape φ (the position half of its
eigenvector). Overdamped motions (a flexible bed's high modes under
stiffness-proportional damping) give real roots λ < 0 instead, which are
no modes: they are listed apart as decay rates −λ.

Tables, per mode (shape φ, complex or real):

- kinetic energy share of coordinate j, time-averaged:
  ``e_j = Re(φ̄_j (M φ)_j) / Re(φᴴ M φ)`` — they sum to 1; for a block
  diagonal M (rigid bodies about their centres of mass) each is ≥ 0;
- strain energy share of each mount axis, ``½ k_t |D φ|²``, and of the
  flexible bodies' elastic deformation, ``½ Re(φᴴ K_el φ)``, over their sum
  (k_t the mount's tangent stiffness at rest);
- modal effective mass for a base translation along X, Y, Z (undamped
  modes): ``m_k,d = (ψ_kᴴ M ι_d)(ι_dᵀ M φ_k) / (ψ_kᴴ M φ_k)``; by the
  biorthogonality of φ and ψ, ``Σ_k m_k,d = ι_dᵀ M ι_d``, the moving mass
  (everything but the base), exactly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
from scipy.sparse.linalg import ArpackNoConvergence, LinearOperator, eigs, splu

from . import star_modes
from .shares import bilinear, kinetic, shares, sparse_of, strain
from .mounted import DENSE_LIMIT, MountedSystem

__all__ = ["Modes", "solve_modes"]


@dataclass(frozen=True)
class Modes:
    """The mounted system's modes, ordered by natural frequency.

    Attributes (m modes, n coordinates, M mounts)
    ----------
    frequency : (m,) array
        Natural frequency ωₙ/2π [Hz] (undamped: √(eig)/2π).
    damping_ratio : (m,) array
        ζ [1] (0 when undamped).
    damped_frequency : (m,) array
        ωₙ√(1 − ζ²)/2π [Hz].
    shapes : (m, n) complex array
        φ, scaled so that its largest |component| is 1 + 0i.
    undamped_frequency : (n,) array
        √(eig(K, M))/2π [Hz], ascending (NaN for a negative eigenvalue).
    undamped_shapes : (n, n) array
        Undamped φ_k (rows), unit modal mass ``|ψ_kᴴ M φ_k| = 1`` with ψ
        scaled alike.
    energy : (m, n) array
        Kinetic energy share [1] of each coordinate per mode.
    strain_mounts : (m, M, 3) array
        Strain energy share [1] of each mount axis per mode.
    strain_elastic : (m,) array
        Share [1] of the flexible bodies' own deformation.
    effective_mass : (n, 3) array
        Modal effective mass [kg] of the undamped modes for base
        translation along X, Y, Z.
    moving_mass : float
        Σ of the effective masses along each axis [kg].
    overdamped_rates : (r,) array
        Decay rates −λ [1/s] of the real roots (overdamped motions), ascending.
    """

    frequency: np.ndarray
    damping_ratio: np.ndarray
    damped_frequency: np.ndarray
    shapes: np.ndarray
    undamped_frequency: np.ndarray
    undamped_shapes: np.ndarray
    energy: np.ndarray
    strain_mounts: np.ndarray
    strain_elastic: np.ndarray
    effective_mass: np.ndarray
    moving_mass: float
    overdamped_rates: np.ndarray

    @property
    def cumulative_mass_fraction(self) -> np.ndarray:
        """(n, 3) cumulative effective mass over the moving mass [1]."""
        return np.cumsum(self.effective_mass, axis=0) / self.moving_mass


def _pivot(phi: np.ndarray) -> np.ndarray:
    """Each row's component of largest modulus (m,)."""
    return phi[np.arange(phi.shape[0]), np.argmax(np.abs(phi), axis=1)]


def _unit_phase(phi: np.ndarray) -> np.ndarray:
    """Rows scaled so that their largest |component| is 1 + 0i."""
    return phi / _pivot(phi)[:, None]


def _standard_eig(ms: MountedSystem):
    """(λ, left, right) of K φ = λ M φ for a large system as
    ``scipy.linalg.eig(K, M, left=True, right=True)`` gives them, from the
    standard problem M⁻¹K (QR, about a third of the generalized QZ's work)
    and its inverse eigenvector matrix: the rows wₖᵀ of V⁻¹ are M⁻¹K's left
    vectors, so ψₖ = conj(M⁻ᵀ wₖ) satisfies ψₖᴴ K = λₖ ψₖᴴ M, and the left
    and right vectors are biorthogonal by construction, even within the
    clusters of equal frequencies that identical pieces of equipment make."""
    lam, vr = np.linalg.eig(np.linalg.solve(ms.M, ms.K))
    w = np.linalg.inv(vr)                                         # rows: left vectors of M⁻¹K
    vl = np.linalg.solve(ms.M.T, w.T).conj()
    return lam, vl, vr


def _undamped(ms: MountedSystem, plan=None, tables: bool = False):
    """(f (n,), φ (n, n), ψ (n, n), raw): the undamped modes, ascending, and
    with ``tables`` their raw energy tables from the structured solution
    (:meth:`~flexbed.dynamics.frequency.star_modes.Structured.energies`), or None."""
    large = ms.n > DENSE_LIMIT
    got = star_modes.undamped(ms, plan) if plan is not None else None
    if got is not None:
        lam, vl, vr, mu, structured = got
    elif large:
        lam, vl, vr = _standard_eig(ms)
    else:
        lam, vl, vr = scipy.linalg.eig(ms.K, ms.M, left=True, right=True)
    order = np.argsort(lam.real)
    lam, phi, psi = lam[order], vr[:, order].T, vl[:, order].T     # rows, fresh copies
    p, q = _pivot(phi), _pivot(psi)
    phi /= p[:, None]                             # (n, n), real up to round-off
    psi /= q[:, None]
    real = np.abs(phi.imag).max() <= 1e-9 * max(np.abs(phi).max(), 1.0)
    if real:
        phi, psi = phi.real, psi.real
    if got is not None:          # ψᴴ M φ of the structured vectors, given, over the pivots
        mu = mu[order] / (q.conj() * p)
        mu = mu.real if real else mu
    else:
        mu = bilinear(psi, sparse_of(ms, "M") if large else ms.M, phi, large)     # ψᴴ M φ
    s = np.sqrt(np.abs(mu))
    phi = phi / s[:, None]
    psi = psi / (mu / s)[:, None].conj()          # now ψ_kᴴ M φ_k = 1
    w2 = lam.real
    f = np.where(w2 >= 0.0, np.sqrt(np.abs(w2)), np.nan) / (2.0 * np.pi)
    raw = structured.energies(ms, order) if tables and got is not None else None
    return f, phi, psi, raw


def _damped(ms: MountedSystem, plan=None):
    """:func:`_damped_from`'s modes and their raw energy tables from the
    structured solution, or None."""
    n = ms.n
    got = star_modes.damped(ms, plan) if plan is not None else None
    if got is not None:
        *modes, picked = _damped_from(got[0], got[1], n)
        return (*modes, got[2].energies(ms, picked))
    Minv = np.linalg.solve(ms.M, np.hstack([ms.K, ms.C]))
    S = np.zeros((2 * n, 2 * n))
    S[:n, n:] = np.eye(n)
    S[n:, :n] = -Minv[:, :n]
    S[n:, n:] = -Minv[:, n:]
    lam, V = np.linalg.eig(S)
    return (*_damped_from(lam, V[:n], n)[:5], None)


def _damped_from(lam: np.ndarray, V: np.ndarray, n: int):
    """Modes from the first-order eigenvalues λ (r,) and the position halves
    of their vectors V (n, r): (ωₙ, ζ, ω_d, shapes, overdamped rates, the
    columns of V the modes are, in their order)."""
    scale = np.abs(lam).max() if lam.size else 1.0
    osc = lam.imag > 1e-12 * scale
    real = np.abs(lam.imag) <= 1e-12 * scale
    rates = np.sort(-lam[real].real)
    picked = np.flatnonzero(osc)
    lam = lam[osc]
    wn = np.abs(lam)
    # a decay rate at the eigensolver's round-off (|Re λ| ≤ 1e-12 max|λ|, the
    # bound that tells oscillating from real eigenvalues above) is no damping:
    # such a mode is undamped (ζ = 0), not damped or growing by ±1e-16
    zeta = np.where(np.abs(lam.real) <= 1e-12 * scale, 0.0, -lam.real / wn)
    order = np.argsort(wn, kind="stable")
    picked = picked[order]
    shapes = V[:, picked].T                       # rows, a fresh copy: scaled in place
    shapes /= _pivot(shapes)[:, None]
    return wn[order], zeta[order], lam.imag[order], shapes, rates, picked


def _krylov_size(n: int, count: int) -> int:
    """Arnoldi's basis for ``count`` eigenvalues of an n × n problem: 30
    vectors more than asked (SciPy's default, 2·count + 1, found 2 of the 4
    copies of an exactly 4-fold frequency of four identical pieces of
    equipment; a Krylov space holds one vector of an exactly repeated
    eigenvalue's space, the others come from round-off, which more vectors
    give time to grow)."""
    return min(n - 1, max(2 * count + 1, count + 30))


def _lowest_undamped(ms: MountedSystem, count: int):
    """The ``count`` lowest undamped modes by shift-invert Arnoldi at 0
    (right vectors from (K, M), left ones from (Kᵀ, Mᵀ)), biorthogonalised
    over the set (ψ ← T⁻ᴴ ψ with T = Ψᴴ M Φ, so that ψ_kᴴ M φ_l = δ_kl even
    within a cluster of equal frequencies) and scaled as :func:`_undamped`
    scales them."""
    Ms, Ks, _ = ms.sparse
    v0 = np.cos(np.arange(ms.n) + 0.5)
    ncv = _krylov_size(ms.n, count)
    lam, vr = eigs(Ks.tocsc(), k=count, M=Ms.tocsc(), sigma=0.0, which="LM", v0=v0, ncv=ncv)
    lam_l, vl = eigs(Ks.T.tocsc(), k=count, M=Ms.T.tocsc(), sigma=0.0, which="LM", v0=v0,
                     ncv=ncv)
    order, order_l = np.argsort(lam.real, kind="stable"), np.argsort(lam_l.real, kind="stable")
    lam, vr, vl = lam[order], vr[:, order], vl[:, order_l]
    phi = _unit_phase(vr.T)
    psi = _unit_phase(vl.T)
    if np.abs(phi.imag).max() <= 1e-9 * max(np.abs(phi).max(), 1.0) and \
            np.abs(psi.imag).max() <= 1e-9 * max(np.abs(psi).max(), 1.0):
        phi, psi = phi.real, psi.real
    Mphi = (Ms @ phi.T).T
    mu = np.einsum("ki,ki->k", psi.conj(), Mphi)                  # ψᴴ M φ, as _undamped
    s = np.sqrt(np.abs(mu))
    phi = phi / s[:, None]
    T = psi.conj() @ (Mphi / s[:, None]).T                        # (k, k) ψᴴ M φ
    psi = np.linalg.solve(T.conj().T, psi)                        # now ψ_kᴴ M φ_l = δ_kl
    w2 = lam.real
    f = np.where(w2 >= 0.0, np.sqrt(np.abs(w2)), np.nan) / (2.0 * np.pi)
    return f, phi, psi


def _lowest_damped(ms: MountedSystem, count: int):
    """:func:`_damped` for the 2·count eigenvalues of the first-order form
    nearest 0, by Arnoldi on its inverse ``[[−K⁻¹C, −K⁻¹M], [I, 0]]``
    (applied with one sparse factorisation of K)."""
    Ms, Ks, Cs = ms.sparse
    n = ms.n
    lu = splu(Ks.tocsc())

    def matvec(z):
        x, v = z[:n], z[n:]
        return np.concatenate([-lu.solve(np.asarray(Cs @ x + Ms @ v)), x])

    op = LinearOperator((2 * n, 2 * n), matvec=matvec, dtype=float)
    k = min(2 * count, 2 * n - 2)
    mu, V = eigs(op, k=k, which="LM", v0=np.cos(np.arange(2 * n) + 0.5),
                 ncv=_krylov_size(2 * n, k))
    lam = 1.0 / mu
    return (*_damped_from(lam, V[:n], n)[:5], None)


def solve_modes(ms: MountedSystem, count: int | None = None) -> Modes:
    """Frequencies, damping ratios, shapes and tables of the mounted system.

    count : int, optional
        Only the ``count`` lowest modes, by shift-invert Arnoldi on the
        sparse matrices (``MountedSystem.sparse``; :func:`_lowest_undamped`,
        :func:`_lowest_damped`); the effective masses are then those of the
        modes found (their sum the share of the moving mass they carry,
        ``cumulative_mass_fraction``). Default: every mode. Above
        :data:`~flexbed.dynamics.frequency.mounted.DENSE_LIMIT` coordinates,
        when the bodies split into leaves and a hub
        (:func:`~flexbed.dynamics.frequency.star_modes.plan_of`: pieces of
        equipment on one bed), by the structured eigen-solution of
        :mod:`~flexbed.dynamics.frequency.star` (identical pieces of
        equipment's modes with the bed at rest found exactly, a dense solve
        of the rest, the energy tables of the modes with the bed at rest from
        their structure: 774 coordinates in ~0.2 s), else by dense
        eigen-solutions (O(n³), seconds at that size). With ``count`` and
        such a structure, that solution cut to ``count`` (exact where
        identical pieces repeat a frequency exactly). Arnoldi converges
        slowly where ``count`` cuts a cluster of nearly equal frequencies;
        if it does not converge, the full solution is cut to ``count``.
    """
    plan = star_modes.plan_of(ms) if ms.n > DENSE_LIMIT else None
    # pieces of equipment on a bed: every mode by the structured solution (exact
    # where identical pieces repeat a frequency exactly, which Arnoldi is not), then cut
    lowest = (count is not None and ms.sparse is not None and count < ms.n - 1
              and plan is None)
    if lowest:
        try:
            f0, phi0, psi0 = _lowest_undamped(ms, count)
            damped = _lowest_damped(ms, count) if ms.damped else None
        except ArpackNoConvergence:
            lowest = False
    raw = None
    if not lowest:
        f0, phi0, psi0, raw = _undamped(ms, plan, tables=not ms.damped)
        damped = _damped(ms, plan) if ms.damped else None
        if count is not None:
            f0, phi0, psi0 = f0[:count], phi0[:count], psi0[:count]
            raw = None if raw is None else tuple(t[:count] for t in raw)
    if damped is not None:
        wn, zeta, wd, shapes, rates, raw = damped
        if count is not None:
            keep = np.argsort(wn, kind="stable")[:count]
            wn, zeta, wd, shapes = wn[keep], zeta[keep], wd[keep], shapes[keep]
            raw = None if raw is None else tuple(t[keep] for t in raw)
        freq, fd = wn / (2.0 * np.pi), wd / (2.0 * np.pi)
    else:
        freq, zeta, fd, shapes = f0, np.zeros_like(f0), f0, _unit_phase(phi0 + 0j)
        rates = np.zeros(0)
    Mi = ms.M @ ms.iota                                           # (n, 3)
    eff = ((psi0.conj() @ Mi) * (phi0 @ Mi)).real                 # (n, 3)
    if raw is None:
        raw = (kinetic(ms, shapes), *strain(ms, shapes))
    energy, mounts, elastic = shares(*raw)
    return Modes(frequency=freq, damping_ratio=zeta, damped_frequency=fd, shapes=shapes,
                 undamped_frequency=f0, undamped_shapes=np.asarray(phi0),
                 energy=energy, strain_mounts=mounts,
                 strain_elastic=elastic, effective_mass=eff, moving_mass=ms.moving_mass,
                 overdamped_rates=rates)
