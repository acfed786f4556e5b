"""A flexible body in the floating frame of reference, built from modal
invariants (plain arrays; no FE objects).

A material point at ū0 in the body frame (origin at the undeformed centre of
mass) is at R = r + A(p) (ū0 + Φ(ū0) a), with modal coordinates a (n,).
Velocity variables v = [ṙ (3, inertial), ω̄ (3, body frame), ȧ (n)], and
ṗ = ½ G(p)ᵀ ω̄ as for the rigid bodies. With ū = ū0 + Φa, Ṙ = L v,
L = [I, -A ũ, A Φ], the virtual power of the inertia forces gives

    M(p, a) v̇ = Q_v + Q_g + Q_e + Σ Q_F

with (~ the cross-product matrix; invariants as in :mod:`flexbed.fem.invariants`:
I2 first moment, I3 = ∫ρΦ, I4 = ∫ρũ0Φ, I5[k] = ∫ρΦ̃_kΦ, I6 = ∫ρΦᵀΦ,
I7 = J0, I8[k] = ∫ρũ0ᵀΦ̃_k, I9[k, l] = ∫ρΦ̃_kᵀΦ̃_l):

    S(a) = I2 + I3 a                       first moment
    J(a) = I7 + Σ a_k (I8_k + I8_kᵀ) + Σ a_k a_l I9_kl
    C(a) = I4 + Σ a_k I5[k]                ∫ρ ũ Φ
    M = [[m I,      -A S̃,   A I3],
         [S̃ Aᵀ,     J(a),   C(a)],
         [I3ᵀ Aᵀ,   C(a)ᵀ,  I6  ]]
    Q_v,r = -A (ω̃ω̃ S + 2 ω̃ I3 ȧ)
    Q_v,ω = -ω × (J ω) - 2 [Σ_k ȧ_k (I8_k + Σ_l a_l I9_kl)] ω
    Q_v,a[k] = ωᵀ [I8_kᵀ + Σ_l a_l I9_kl] ω + 2 Σ_l ωᵀ I5[k, :, l] ȧ_l
    Q_e = [0; 0; -K a - C ȧ]
    Q_g = [m g; S × (Aᵀ g); I3ᵀ Aᵀ g]
    Q_F = [F; ū_P × (Aᵀ F); Φ_Pᵀ Aᵀ F]      (force F at material point P)

The first-order set (``full = False``) keeps the terms linear in a in J and
drops the I5 and I9 terms: enough for small deformations, and cheaper.

:class:`FlexibleBody`'s invariants are those of the modes file, defined
once in :data:`flexbed.files.modes.INVARIANTS` (names, shapes, units),
which the pipeline maps onto this class and onto :mod:`flexbed.fem`'s;
a test checks both against it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import SceneError
from .kernel import flex_forces_body, flex_mass_body, flex_T

__all__ = ["FlexibleBody", "FlexibleEOM", "rayleigh_damping", "modal_damping", "cross"]


def _array(where: str, name: str, value, shape) -> np.ndarray:
    a = np.array(value, dtype=float)
    if a.shape != shape:
        raise SceneError(f"{where}: {name} has shape {a.shape}, expected {shape}")
    if not np.all(np.isfinite(a)):
        raise SceneError(f"{where}: {name} has non-finite entries")
    a.setflags(write=False)
    return a


def rayleigh_damping(modal_mass: np.ndarray, modal_stiffness: np.ndarray, alpha: float,
                     beta: float) -> np.ndarray:
    """c_aa = α M_aa + β K_aa (paper eq. 9) [kg/s per unit modal coordinate²]."""
    if alpha < 0 or beta < 0:
        raise SceneError(f"rayleigh: alpha = {alpha!r}, beta = {beta!r} must be >= 0")
    return alpha * np.asarray(modal_mass) + beta * np.asarray(modal_stiffness)


def modal_damping(omega: np.ndarray, ratio) -> np.ndarray:
    """c_aa = diag(2 ζ_k ω_k) for mass-normalised modes; ``ratio`` a scalar
    or one value per mode [–]."""
    omega = np.asarray(omega, dtype=float)
    zeta = np.broadcast_to(np.asarray(ratio, dtype=float), omega.shape)
    if np.any(zeta < 0):
        raise SceneError(f"damping_ratio = {np.asarray(ratio).tolist()!r} must be >= 0")
    return np.diag(2.0 * zeta * omega)


@dataclass(frozen=True, slots=True)
class FlexibleBody:
    """Floating-frame data of one flexible body.

    Parameters
    ----------
    mass : float
        [kg].
    first_moment : (3,)
        I2 [kg m] (zero with the origin at the centre of mass).
    inertia : (3, 3)
        I7 about the frame origin [kg m²].
    phi_integral : (3, n)
        I3 [kg^1/2].
    u_cross_phi : (3, n)
        I4 [kg^1/2 m].
    phi_cross_phi : (n, 3, n)
        I5 [–].
    modal_mass : (n, n)
        I6 [–].
    inertia_first_order : (n, 3, 3)
        I8 [kg^1/2 m].
    inertia_second_order : (n, n, 3, 3)
        I9 [–].
    modal_stiffness : (n, n)
        K_aa [s⁻²].
    modal_damping : (n, n)
        C_aa [s⁻¹].
    points : (P, 3)
        Material points the scene attaches to (mount ends, points of
        interest) in the body frame [m].
    point_shapes : (P, 3, n)
        Translation of each point per unit modal coordinate (for a point off
        the mid-surface: the node's translation plus its rotation × offset)
        [kg^-1/2].
    full : bool
        Keep every configuration-dependent term (True) or the first-order
        set only.
    basis : (N, n) or None
        What the modal coordinates are in terms of the N modes they were
        made from, a = basis @ a' (None: the first n modes themselves);
        carried for the outputs, not used by the equations.
    """

    mass: float
    first_moment: np.ndarray
    inertia: np.ndarray
    phi_integral: np.ndarray
    u_cross_phi: np.ndarray
    phi_cross_phi: np.ndarray
    modal_mass: np.ndarray
    inertia_first_order: np.ndarray
    inertia_second_order: np.ndarray
    modal_stiffness: np.ndarray
    modal_damping: np.ndarray
    points: np.ndarray
    point_shapes: np.ndarray
    full: bool = True
    basis: np.ndarray | None = None

    def __post_init__(self) -> None:
        where = "flexible body"
        n = np.shape(self.modal_mass)[0] if np.ndim(self.modal_mass) == 2 else -1
        if n < 0:
            raise SceneError(f"{where}: modal_mass must be (n, n)")
        if not (np.isfinite(self.mass) and self.mass > 0):
            raise SceneError(f"{where}: mass = {self.mass!r} must be > 0")
        object.__setattr__(self, "mass", float(self.mass))
        P = np.shape(self.points)[0] if np.ndim(self.points) == 2 else 0
        for name, shape in (("first_moment", (3,)), ("inertia", (3, 3)),
                            ("phi_integral", (3, n)), ("u_cross_phi", (3, n)),
                            ("phi_cross_phi", (n, 3, n)), ("modal_mass", (n, n)),
                            ("inertia_first_order", (n, 3, 3)),
                            ("inertia_second_order", (n, n, 3, 3)),
                            ("modal_stiffness", (n, n)), ("modal_damping", (n, n)),
                            ("points", (P, 3)), ("point_shapes", (P, 3, n))):
            object.__setattr__(self, name, _array(where, name, getattr(self, name), shape))
        if self.basis is not None:
            b = _array(where, "basis", self.basis, np.shape(self.basis))
            if b.ndim != 2 or b.shape[1] != n or b.shape[0] < n:
                raise SceneError(f"{where}: basis has shape {b.shape}, expected (N >= {n}, {n})")
            object.__setattr__(self, "basis", b)
        J = self.inertia
        if not np.allclose(J, J.T, rtol=0, atol=1e-12 * np.abs(J).max()) or \
                np.linalg.eigvalsh(J).min() <= 0:
            raise SceneError(f"{where}: inertia must be symmetric positive definite")
        if n and np.linalg.eigvalsh(0.5 * (self.modal_mass + self.modal_mass.T)).min() <= 0:
            raise SceneError(f"{where}: modal_mass must be positive definite")

    @property
    def n_modes(self) -> int:
        """Number of modal coordinates."""
        return int(self.modal_mass.shape[0])

    def point_index(self, point) -> int:
        """Index of a material point in :attr:`points` (exact match within 1e-9 m)."""
        d = np.abs(self.points - np.asarray(point, dtype=float)).max(axis=1) if len(
            self.points) else np.array([])
        hits = np.flatnonzero(d <= 1e-9)
        if hits.size == 0:
            raise SceneError(f"flexible body: no mode shapes for the point "
                             f"{tuple(float(v) for v in point)}")
        return int(hits[0])


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b along the last axis (both (..., 3)); plain arithmetic, several
    times faster than ``np.cross`` on the small arrays of the hot path."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def _writable(x: np.ndarray) -> np.ndarray:
    """A writable C-contiguous float64 copy of x."""
    return np.array(x, dtype=np.float64, order="C")


class FlexibleEOM:
    """The equations of motion of one :class:`FlexibleBody`.

    In the body frame, where the translational row is multiplied by Aᵀ and
    the translational acceleration is ``Aᵀ r̈``, the mass matrix

        M̄(a) = [[m I, -S̃, I3], [S̃, J(a), C(a)], [I3ᵀ, C(a)ᵀ, I6]]

    does not depend on A; the inertial forms of the module docstring are
    ``M = T M̄ Tᵀ``, ``Q = T Q̄`` with ``T = diag(A, I, I)``. M̄ and Q̄ come
    from the compiled functions of :mod:`flexbed.dynamics.kernel` (the right-hand
    side's own), so this class is the Python view of the same physics.

    Shapes: n modes; A (3, 3) rotation; w (3,) body angular velocity
    [rad/s]; a, ad (n,) modal coordinates and rates; g (3,) gravity [m/s²].
    """

    def __init__(self, body: FlexibleBody):
        self.body = body
        n = body.n_modes
        self.n = n
        self.m = body.mass
        # writable C-contiguous copies: the compiled functions then run on
        # the same array types as the right-hand side's views of its
        # storage, so one compiled specialisation serves both (a read-only
        # array is another type to numba, compiled again)
        self.I2 = _writable(body.first_moment)
        self.I3 = _writable(body.phi_integral)
        self.I4 = _writable(body.u_cross_phi)
        self.I7 = _writable(body.inertia)
        self.I6 = _writable(body.modal_mass)
        self.K = _writable(body.modal_stiffness)
        self.C = _writable(body.modal_damping)
        self.I8 = _writable(body.inertia_first_order)
        self.full = bool(body.full) and n > 0
        self.I5 = _writable(body.phi_cross_phi) if self.full else np.zeros_like(
            body.phi_cross_phi)
        self.I9 = _writable(body.inertia_second_order) if self.full else np.zeros_like(
            body.inertia_second_order)
        self._T = np.zeros((n, 3, 3))
        self._Mbar = np.zeros((6 + n, 6 + n))
        self._Qbar = np.zeros(6 + 2 * n)
        self._Q = np.zeros(6 + n)
        self._M = np.zeros((6 + n, 6 + n))

    # ------------------------------------------------------------ body frame
    def mass_matrix_body(self, a: np.ndarray) -> np.ndarray:
        """M̄(a) (6+n, 6+n) for [Aᵀ r̈, ω̄̇, ä] (a view, overwritten on the next call)."""
        a = np.ascontiguousarray(a, dtype=float)
        flex_T(self.I8, self.I9, self.n, a, self._T)
        flex_mass_body(self.m, self.I2, self.I3, self.I4, self.I5, self.I6, self.I7, self.I8,
                       self._T, self.n, a, self._Mbar)
        return self._Mbar

    def forces_body(self, w: np.ndarray, a: np.ndarray, ad: np.ndarray, gb: np.ndarray,
                    J: np.ndarray | None = None) -> np.ndarray:
        """[Q̄ (6+n), C ȧ (n)]: Q̄ = body-frame Q_v + Q_g + Q_e (translational row
        times Aᵀ) [N; N m; N m per unit a], then the damping forces; gb = Aᵀ g
        [m/s²] (a view, overwritten on the next call); ``J`` is accepted for
        compatibility and not needed."""
        M = self.mass_matrix_body(a)
        flex_forces_body(self.m, self.I2, self.I3, self.I5, self.K, self.C, self._T, self.n,
                         np.ascontiguousarray(w, dtype=float),
                         np.ascontiguousarray(a, dtype=float),
                         np.ascontiguousarray(ad, dtype=float),
                         np.ascontiguousarray(gb, dtype=float), M, self._Qbar)
        return self._Qbar

    # -------------------------------------------------------- inertial forms
    def inertia(self, a: np.ndarray) -> np.ndarray:
        """J(a) (3, 3) [kg m²]."""
        return self.mass_matrix_body(a)[3:6, 3:6].copy()

    def mass_matrix(self, A: np.ndarray, a: np.ndarray,
                    J: np.ndarray | None = None) -> np.ndarray:
        """M (6+n, 6+n) for velocities [ṙ, ω̄, ȧ] (a view, overwritten on the
        next call); ``J`` is accepted for compatibility and not needed."""
        M = self._M
        M[...] = self.mass_matrix_body(a)
        M[:3] = A @ M[:3]
        M[:, :3] = M[:, :3] @ A.T
        return M

    def forces(self, A: np.ndarray, w: np.ndarray, a: np.ndarray, ad: np.ndarray,
               g: np.ndarray, J: np.ndarray | None = None) -> np.ndarray:
        """Q_v + Q_g + Q_e (6+n,): quadratic velocity, gravity, elastic and
        damping forces [N; N m; N m per unit a] (a view, overwritten on the
        next call); ``J`` = :meth:`inertia` (a) when the caller has it."""
        if J is None:
            J = self.inertia(a)
        Q = self._Q
        Q[:] = self.forces_body(w, a, ad, A.T @ g, J)[:6 + self.n]
        Q[:3] = A @ Q[:3]
        return Q

    def kinetic_energy(self, A, w, a, rd, ad) -> float:
        """½ vᵀ M v [J]."""
        v = np.concatenate([rd, w, ad])
        return 0.5 * float(v @ self.mass_matrix(A, a) @ v)

    def strain_energy(self, a: np.ndarray) -> float:
        """½ aᵀ K a [J]."""
        return 0.5 * float(a @ self.K @ a)
