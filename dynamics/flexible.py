"""A flexible body in the floating frame of reference, built from modal
invariants (plain arrays; no FE objects).

A material point at ū0 in the body frame (origin at the undeformed centre of
mass) is at R = r + A(p) (ū0 + Φ(ū0) a), with modal coordinates a (n,).
Velocity variables v = [ṙ (3, inertial), ω̄ (3, body frame), ȧ (n)], and
ṗ = ½ G(p)ᵀ ω̄ as for the rigid bodies. With ū = ū0 + Φa, Ṙ = L v,
L = [I, -A ũ, A Φ], the virtual power of the inertia forces gives

    M(p, a) v̇ = Q_v + Q_g + Q_e + Σ Q_F

with (~ the cross-product matrix; invariants as in :mod:`fem.invariants`:
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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import SceneError

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


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


class FlexibleEOM:
    """The equations of motion of one :class:`FlexibleBody`, compiled once.

    The right-hand side works in the body frame, where the translational
    row is multiplied by Aᵀ and the translational acceleration is
    ``Aᵀ r̈``: there the mass matrix

        M̄(a) = [[m I, -S̃, I3], [S̃, J(a), C(a)], [I3ᵀ, C(a)ᵀ, I6]]

    does not depend on A, and M̄ and the body-frame forces Q̄ are linear
    maps, compiled here, of a few products of (1, a), ȧ, ω̄ and Aᵀg; the
    inertial forms of the module docstring are ``M = T M̄ Tᵀ``,
    ``Q = T Q̄`` with ``T = diag(A, I, I)``.

    Every call does arithmetic only. Shapes: n modes; A (3, 3) rotation;
    w (3,) body angular velocity [rad/s]; a, ad (n,) modal coordinates and
    rates; g (3,) gravity [m/s²].
    """

    def __init__(self, body: FlexibleBody):
        self.body = body
        n = body.n_modes
        self.n = n
        self.m = body.mass
        self.I2 = body.first_moment
        self.I3 = body.phi_integral
        self.I4 = body.u_cross_phi
        self.I7 = body.inertia
        self.I6 = body.modal_mass
        self.K = body.modal_stiffness
        self.C = body.modal_damping
        I8 = body.inertia_first_order
        self.I8 = I8
        self.full = bool(body.full) and n > 0
        self.I5 = body.phi_cross_phi if self.full else np.zeros_like(body.phi_cross_phi)
        self.I9 = body.inertia_second_order if self.full else np.zeros_like(
            body.inertia_second_order)
        self._compile_mass()
        self._compile_forces()

    # -------------------------------------------------------------- compiled
    def _compile_mass(self) -> None:
        """M̄ = M̄0 + (its entries that vary) = [1, a, a⊗a] @ map."""
        n = self.n
        N = 6 + n
        eps = _levi_civita()
        # S(a) = Σ_q u_q Su[q], u = (1, a); J(a) likewise with a ⊗ a; C(a) = Σ u_q Cu[q]
        Su = np.concatenate([self.I2[None], self.I3.T])                        # (n+1, 3)
        Cu = np.concatenate([self.I4[None], self.I5])                           # (n+1, 3, n)
        Ju = np.concatenate([self.I7[None], self.I8 + np.transpose(self.I8, (0, 2, 1))])
        Jaa = self.I9                                                           # (n, n, 3, 3)
        # -S̃ = Σ_d S_d (-ε_{c d e})... S̃[c, e] = Σ_d ε_{c d e} S_d
        tilde = np.einsum("qd,cde->qce", Su, eps)                               # (n+1, 3, 3)
        full = np.zeros((n + 1 + n * n, N, N))
        full[:n + 1, :3, 3:6] = -tilde
        full[:n + 1, 3:6, :3] = tilde
        full[:n + 1, 3:6, 3:6] = Ju
        full[n + 1:, 3:6, 3:6] = Jaa.reshape(n * n, 3, 3)
        full[:n + 1, 3:6, 6:] = Cu
        full[:n + 1, 6:, 3:6] = np.transpose(Cu, (0, 2, 1))
        const = np.zeros((N, N))
        const[:3, :3] = self.m * np.eye(3)
        if n:
            const[:3, 6:] = self.I3
            const[6:, :3] = self.I3.T
            const[6:, 6:] = self.I6
        var = np.flatnonzero(np.any(full.reshape(n + 1 + n * n, N * N) != 0.0, axis=0))
        self._M_var = var                                   # entries of M̄ that vary
        self._M_map = np.ascontiguousarray(full.reshape(-1, N * N)[:, var])
        self._Mbar = const.copy()
        self._Mbar_flat = self._Mbar.reshape(-1)
        self._M_const = const
        self._ua = np.zeros(n + 1 + n * n)                  # [1, a, a ⊗ a]
        self._ua[0] = 1.0
        self._ua_a = self._ua[1:n + 1]
        self._ua_aa = self._ua[n + 1:].reshape(n, n)

    def _compile_forces(self) -> None:
        """Q̄ and Cȧ = feat @ map, feat = [u, ȧ, ω⊗ω⊗u, ω⊗ȧ⊗u, Aᵀg⊗u],
        u = (1, a); ω × Jω comes apart (J is quadratic in a)."""
        n = self.n
        N = 6 + n
        u = n + 1
        eps = _levi_civita()
        I3, I5, I8, I9 = self.I3, self.I5, self.I8, self.I9
        Su = np.concatenate([self.I2[None], I3.T])                              # (u, 3)
        # outputs: Q̄ (N) then C ȧ (n)
        Fu = np.zeros((u, N + n))
        Fad = np.zeros((n, N + n))
        Fww = np.zeros((3, 3, u, N + n))
        Fwad = np.zeros((3, n, u, N + n))
        Fg = np.zeros((3, u, N + n))
        d = np.eye(3)
        # Q̄_r = -ω × (ω × S) - 2 ω × (I3 ȧ) + m Aᵀg
        Fww[:, :, :, :3] = -(np.einsum("ci,qj->ijqc", d, Su) - np.einsum("qc,ij->ijqc", Su, d))
        Fwad[:, :, 0, :3] = -2.0 * np.einsum("cil,lk->ikc", eps, I3)
        Fg[:, 0, :3] = self.m * d
        # Q̄_ω = -2 [Σ_k ȧ_k (I8_k + Σ_l a_l I9_kl)] ω + S × Aᵀg   (- ω × Jω apart)
        Fwad[:, :, 0, 3:6] = -2.0 * np.einsum("kcj->jkc", I8)
        Fwad[:, :, 1:, 3:6] = -2.0 * np.einsum("klcj->jklc", I9)
        Fg[:, :, 3:6] = np.einsum("cde,qd->eqc", eps, Su)
        if n:
            # Q̄_a[k] = ωᵀ (I8_k + Σ_l a_l I9_kl) ω + 2 ωᵀ I5[k] ȧ + I3ᵀ Aᵀg - K a - C ȧ
            Fww[:, :, 0, 6:N] = np.einsum("kij->ijk", I8)
            Fww[:, :, 1:, 6:N] = np.einsum("klij->ijlk", I9)
            Fwad[:, :, 0, 6:N] = 2.0 * np.einsum("kil->ilk", I5)
            Fg[:, 0, 6:N] = I3
            Fu[1:, 6:N] = -self.K.T
            Fad[:, 6:N] = -self.C.T
            Fad[:, N:] = self.C.T
        self._Q_map = np.ascontiguousarray(np.concatenate(
            [Fu, Fad, Fww.reshape(-1, N + n), Fwad.reshape(-1, N + n), Fg.reshape(-1, N + n)]))
        f = np.zeros(u + n + 9 * u + 3 * n * u + 3 * u)
        self._feat = f
        self._f_u = f[:u]
        self._f_u[0] = 1.0
        self._f_a = f[1:u]
        self._f_ad = f[u:u + n]
        o = u + n
        self._f_ww = f[o:o + 9 * u].reshape(9, u)
        o += 9 * u
        self._f_wad = f[o:o + 3 * n * u].reshape(3 * n, u)
        o += 3 * n * u
        self._f_g = f[o:o + 3 * u].reshape(3, u)
        self._ww = np.zeros((3, 3))
        self._wad = np.zeros((3, n))
        self._Qbar = np.zeros(N + n)
        self._EPS = _levi_civita().reshape(9, 3)           # (a⊗b).ravel() @ EPS = a × b
        self._Q = np.zeros(N)
        self._M = np.zeros((N, N))

    # ------------------------------------------------------------ body frame
    def mass_matrix_body(self, a: np.ndarray) -> np.ndarray:
        """M̄(a) (6+n, 6+n) for [Aᵀ r̈, ω̄̇, ä] (a view, overwritten on the next call)."""
        ua = self._ua
        self._ua_a[:] = a
        np.multiply(self._ua_a[:, None], self._ua_a[None, :], out=self._ua_aa)
        self._Mbar_flat[self._M_var] = ua @ self._M_map
        return self._Mbar

    def forces_body(self, w: np.ndarray, a: np.ndarray, ad: np.ndarray, gb: np.ndarray,
                    J: np.ndarray) -> np.ndarray:
        """[Q̄ (6+n), C ȧ (n)]: Q̄ = body-frame Q_v + Q_g + Q_e (translational row
        times Aᵀ) [N; N m; N m per unit a], then the damping forces; gb = Aᵀ g
        [m/s²], J = J(a) (a view, overwritten on the next call)."""
        self._f_a[:] = a
        self._f_ad[:] = ad
        u = self._f_u
        ww = np.multiply(w[:, None], w[None, :], out=self._ww)
        np.multiply(ww.reshape(9, 1), u, out=self._f_ww)
        wad = np.multiply(w[:, None], ad[None, :], out=self._wad)
        np.multiply(wad.reshape(-1, 1), u, out=self._f_wad)
        np.multiply(gb[:, None], u, out=self._f_g)
        Q = np.matmul(self._feat, self._Q_map, out=self._Qbar)
        Q[3:6] -= (w[:, None] * (J @ w)[None, :]).reshape(9) @ self._EPS      # ω × J ω
        return Q

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


def _levi_civita() -> np.ndarray:
    """ε (3, 3, 3)."""
    eps = np.zeros((3, 3, 3))
    eps[0, 1, 2] = eps[1, 2, 0] = eps[2, 0, 1] = 1.0
    eps[0, 2, 1] = eps[2, 1, 0] = eps[1, 0, 2] = -1.0
    return eps
