"""A scene compiled once into flat arrays, and its one right-hand side.

:class:`System` is built from a :class:`~dynamics.scene.Scene`. Its
:meth:`System.rhs` gives ``dy/dt`` for the state laid out as in
:mod:`dynamics.layout`; statics, every integrator, the linearisation and the
benchmarks call this one function. :meth:`System.observe` evaluates the same
physics and returns everything a results file stores.

Per call the right-hand side does only arithmetic on arrays allocated once
(about 35 NumPy calls for any number of bodies and mounts; each costs about
a microsecond, so the count is the cost):

1. kinematics of every body: ``X = [[1, p⊗p/|p|², R, p⊗p⊗a/|p|²],
   [0, their rates]]`` from the state (``A = Q(p)/|p|²``, so a slightly
   non-unit p still gives a rotation; ``ṗ = ½ G(p)ᵀ ω̄``);
2. one product ``X @ DT`` gives, for every mount and end at once, the mount
   vectors l and l̇, the end offsets ρ = A (s̄ + Φ_e a) and the mount axes in
   the inertial frame (rows of ``Ū A_iᵀ``);
3. every mount at once (paper eq. 2–4): ``Δx = Ū (A_iᵀ l) − Ū l̄0``,
   ``Δẋ = Ū (A_iᵀ l̇)``, forces from the law bank, ``F_i = A_i Ūᵀ f`` on P_i
   and ``−F_i`` on P_j;
4. one product maps ``[ρ_e ⊗ F_e, F_i]`` to every body's force and moment
   (and, for a flexible body, to the body-frame generalized forces as a
   linear map of A); then per-body Newton–Euler equations, all rigid bodies
   at once: ``m r̈ = F + m g``; ``ω̄̇ = J⁻¹ (n̄ − ω̄ × J ω̄)`` as one
   precomputed map of ``[n̄, ω̄⊗ω̄]``; a flexible body solves its body-frame
   ``M̄(a) v̇̄ = Q̄`` (:class:`~dynamics.flexible.FlexibleEOM`);
5. the powers that feed the energy quadratures.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .flexible import FlexibleEOM
from .layout import Layout
from .laws import LawBank
from .rotation import A as rotation_matrix
from .scene import Scene

__all__ = ["System", "Observation"]


def _quadratic_A() -> np.ndarray:
    """CA (16, 9) with A_flat = (p ⊗ p).ravel() @ CA / |p|² for any p ≠ 0."""
    def aq(p):
        e0, e = p[0], p[1:]
        sk = np.array([[0, -e[2], e[1]], [e[2], 0, -e[0]], [-e[1], e[0], 0]])
        return (e0 * e0 - e @ e) * np.eye(3) + 2 * np.outer(e, e) + 2 * e0 * sk
    eye = np.eye(4)
    out = np.zeros((4, 4, 9))
    for a in range(4):
        out[a, a] = aq(eye[a]).ravel()
        for b in range(a + 1, 4):
            mixed = 0.5 * (aq(eye[a] + eye[b]) - aq(eye[a]) - aq(eye[b])).ravel()
            out[a, b] = mixed
            out[b, a] = mixed
    return out.reshape(16, 9)


def _cross_matrix() -> np.ndarray:
    """EPS (9, 3) with (a ⊗ b).ravel() @ EPS = a × b."""
    eps = np.zeros((3, 3, 3))
    eps[0, 1, 2] = eps[1, 2, 0] = eps[2, 0, 1] = 1.0
    eps[0, 2, 1] = eps[2, 1, 0] = eps[1, 0, 2] = -1.0
    return eps.reshape(9, 3)


def _pdot_matrix() -> np.ndarray:
    """CP (12, 4) with (ω̄ ⊗ p).ravel() @ CP = ½ G(p)ᵀ ω̄ (for unit p)."""
    out = np.zeros((3, 4, 4))
    for i in range(3):
        w = np.eye(3)[i]
        for a in range(4):
            p = np.eye(4)[a]
            e0, e = p[0], p[1:]
            out[i, a, 0] = -0.5 * (e @ w)
            out[i, a, 1:] = 0.5 * (e0 * w + np.cross(e, w))
    return out.reshape(12, 4)


_CA = _quadratic_A()
_TRACE = np.eye(4).reshape(16, 1)          # (p ⊗ p).ravel() @ _TRACE = |p|²
_EPS = _cross_matrix()
_CP = _pdot_matrix()


@dataclass(frozen=True, slots=True)
class _FlexCompiled:
    """A flexible body as the right-hand side needs it: scene index ``body``,
    row ``slot`` among bodies 2…, its equations, its mount ends (indices
    into the 2M ends, their mounts, the sign of each end in l = P_j − P_i),
    their mode shapes (E, 3, n), and the slices of a and ȧ in y."""

    body: int
    slot: int
    eom: FlexibleEOM
    ends: np.ndarray
    mounts: np.ndarray
    sign: np.ndarray
    phi: np.ndarray
    qa: slice
    va: slice


@dataclass(frozen=True, slots=True)
class _FlexHot:
    """What the right-hand side reads of a flexible body: its row among
    bodies 2…, its equations, the slices of a and ȧ in y, and 6 + n."""

    slot: int
    eom: FlexibleEOM
    qa: slice
    va: slice
    N: int


class Observation:
    """Everything the physics gives at one (t, y); plain attributes.

    r (nb, 3) [m], p (nb, 4), rd (nb, 3) [m/s], w (nb, 3) [rad/s] body frame,
    rdd (nb, 3) [m/s²], wd (nb, 3) [rad/s²]; dx, dxd, f (M, 3) [m, m/s, N];
    force_i, force_j (M, 3) [N] inertial; kinetic, gravity_potential,
    mount_potential [J]; strain (nb,) [J] elastic energy of flexible bodies;
    a, ad, add (n_modal,) modal coordinates, rates and accelerations; work (4,) [J] (mount,
    external, drive, structural damping); powers.
    """

    __slots__ = ("t", "r", "p", "rd", "w", "rdd", "wd", "dx", "dxd", "f", "force_i", "force_j",
                 "kinetic", "gravity_potential", "mount_potential", "strain", "a", "ad", "add",
                 "work", "power")


class System:
    """A scene compiled for evaluation.

    Parameters
    ----------
    scene : Scene

    Attributes
    ----------
    layout : Layout
        Where everything lives in the state (see :mod:`dynamics.layout`).
    breakpoints : tuple of float
        Times [s] where the base's drive or load (or a derivative) jumps.
    nfev : int
        Right-hand-side evaluations since construction (or the last reset).
    """

    def __init__(self, scene: Scene):
        self.scene = scene
        bodies = scene.bodies
        nb = len(bodies)
        self.nb = nb
        base = scene.base
        self.base_motion = base.motion
        flex = dict(scene.flexible)
        self.flex_index = tuple(i for i, b in enumerate(bodies) if b.name in flex)
        self.layout = Layout(n_bodies=nb, base_free=base.motion == "free",
                             rigid=tuple(range(1, nb)),
                             modal=tuple((i, flex[bodies[i].name].n_modes)
                                         for i in self.flex_index))
        lay = self.layout
        self.n_rigid = n = nb - 1
        self.ny = lay.ny
        self.mass = np.array([flex[b.name].mass if b.name in flex else b.mass for b in bodies])
        self.g = np.array(scene.gravity, dtype=float)
        # rigid bodies: mass, principal-axes factorisation of J
        self.m_r = self.mass[1:, None].copy()
        self.J = np.array([flex[b.name].inertia if b.name in flex else b.inertia
                           for b in bodies[1:]]).reshape(n, 3, 3)
        jv, jq = np.linalg.eigh(self.J) if n else (np.zeros((0, 3)), np.zeros((0, 3, 3)))
        self.J_eig = jv
        self.J_vec = jq
        self.J_vecT = np.ascontiguousarray(np.swapaxes(jq, -1, -2))
        self.weight_r = self.m_r * self.g            # (n, 3) [N]
        # base
        self.r0_base = np.array(bodies[0].position, dtype=float)
        self.m_base = float(bodies[0].mass)
        self._drives = [[], [], []]
        self._loads = [[], [], []]
        bps = set()
        for d in base.drives:
            f = d.shape.compile()
            self._drives[d.direction].append(f)
            bps.update(f.breakpoints)
        for d in base.loads:
            f = d.shape.compile()
            self._loads[d.direction].append(f)
            bps.update(f.breakpoints)
        self.breakpoints = tuple(sorted(b for b in bps if b > 0.0))
        self._inputs = [f for k in range(3) for f in self._drives[k] + self._loads[k]]
        if isinstance(base.support, str):
            self.support = (-scene.total_mass * self.g if base.support == "static"
                            else np.zeros(3))
        else:
            self.support = np.array(base.support, dtype=float)
        self._has_drive = any(self._drives)
        self._has_load = any(self._loads)
        # mounts
        M = len(scene.mounts)
        self.M = M
        name_to_index = {b.name: i for i, b in enumerate(bodies)}
        bi = np.array([name_to_index[m.body_i] for m in scene.mounts], dtype=np.intp)
        bj = np.array([name_to_index[m.body_j] for m in scene.mounts], dtype=np.intp)
        self.body_i = bi
        self.body_j = bj
        self.end_body = np.concatenate([bi, bj])
        self.S = np.concatenate([np.array([m.point_i for m in scene.mounts]).reshape(M, 3),
                                 np.array([m.point_j for m in scene.mounts]).reshape(M, 3)])
        self.U = np.array([m.axes for m in scene.mounts]).reshape(M, 3, 3)
        self.laws = LawBank([law for m in scene.mounts for law in m.laws])
        # incidence: body force = E @ end forces
        # unstrained mount vectors from the scene's initial configuration
        R0 = np.array([b.position for b in bodies])
        A0 = rotation_matrix(np.array([b.orientation for b in bodies]))
        A0[0] = np.eye(3)      # the base never rotates
        P0 = R0[self.end_body] + np.einsum("kij,kj->ki", A0[self.end_body], self.S)
        l0 = P0[M:] - P0[:M]
        l0_bar = np.einsum("mji,mj->mi", A0[bi], l0)        # A_iᵀ l0
        self.d0 = np.einsum("mkj,mj->mk", self.U, l0_bar)   # Ū l̄0 (M, 3)
        self.initial_r = R0
        self.initial_p = np.array([b.orientation for b in bodies])
        self.initial_p[0] = (1.0, 0.0, 0.0, 0.0)
        self._build_maps(A0)
        self._build_flexible(flex)
        self._f = np.zeros(3 * M)
        self._acc_base = np.zeros(3)
        self._seg_end = None
        self.nfev = 0
        self._last = None

    def _build_maps(self, A0: np.ndarray) -> None:
        """Precompute the linear maps of the hot path and its buffers.

        For unit p, every rotated quantity is a fixed linear function of the
        16 products p_a p_b (``A = Σ p_a p_b CA_ab``), and a point of a
        flexible body at A (s̄ + Φ a) of the products p_a p_b a_k; the rate
        of each is the same map applied to the products' rates. So one
        matrix product of ``X = [[1, p⊗p, R, p⊗p⊗a], [0, d/dt of these]]``
        with the precomputed ``DT`` gives, for all mounts and ends at once:
        the mount vectors l and l̇, the end offsets ρ and the mount axes in
        the inertial frame (rows of Ū A_iᵀ). A second one maps the end
        forces and moments to every body's force, moment and (flexible
        bodies) the body-frame generalized forces as a map of A.
        Everything per call writes into arrays allocated here.
        """
        n, nb, M = self.n_rigid, self.nb, self.M
        lay = self.layout
        self._flex_modes = [dict(self.scene.flexible)[self.scene.bodies[b].name].n_modes
                            for b in self.flex_index]
        kf = [16 * m for m in self._flex_modes]
        K = 1 + 16 * n + 3 * nb + sum(kf)
        c_pp, c_R = 1, 1 + 16 * n
        c_f = np.cumsum([c_R + 3 * nb] + kf)[:-1].astype(int)
        CA = _CA.reshape(16, 3, 3)
        rows_l, rows_rho, rows_u = 3 * M, 6 * M, 9 * M
        D = np.zeros((rows_l + rows_rho + rows_u, K))
        rho_rows = np.zeros((2 * M, 3, K))          # ρ_e as a map of X's first row
        flex = dict(self.scene.flexible)
        for e in range(2 * M):
            b = int(self.end_body[e])
            s = self.S[e]
            if b == 0:
                rho_rows[e, :, 0] = s                  # the base never rotates
            else:
                cols = slice(c_pp + 16 * (b - 1), c_pp + 16 * b)
                rho_rows[e, :, cols] = np.einsum("akl,l->ka", CA, s)
            if b in self.flex_index:
                k = self.flex_index.index(b)
                fb = flex[self.scene.bodies[b].name]
                phi = fb.point_shapes[fb.point_index(s)]                  # (3, nm)
                cols = slice(c_f[k], c_f[k] + kf[k])
                rho_rows[e, :, cols] = np.einsum("acl,lk->cak", CA, phi).reshape(3, -1)
        for m in range(M):
            for sign, e in ((-1.0, m), (1.0, M + m)):
                b = int(self.end_body[e])
                rowsl = slice(3 * m, 3 * m + 3)
                D[rowsl] += sign * rho_rows[e]
                D[rowsl, c_R + 3 * b + np.arange(3)] += sign * np.eye(3)
        D[rows_l:rows_l + rows_rho] = rho_rows.reshape(6 * M, K)
        for m in range(M):
            b = int(self.body_i[m])
            U = self.U[m]
            r0 = rows_l + rows_rho + 9 * m
            if b == 0:
                D[r0:r0 + 9, 0] = U.reshape(-1)
            else:
                # Uw[k, c] = Σ_l U[k, l] A[c, l], A[c, l] = Σ_ab pp_ab CA[ab, c, l]
                blk = np.einsum("kl,acl->kca", U, CA).reshape(9, 16)
                D[r0:r0 + 9, c_pp + 16 * (b - 1):c_pp + 16 * b] = blk
        self._DT = np.ascontiguousarray(D.T)
        X = np.zeros((2, K))
        X[0, 0] = 1.0
        self._X = X
        self._Xpp = X[0, c_pp:c_R].reshape(n, 16)
        self._Xpp3 = self._Xpp.reshape(n, 4, 4)
        self._Xppd3 = X[1, c_pp:c_R].reshape(n, 4, 4)
        self._XR = X[0, c_R:c_R + 3 * nb].reshape(nb, 3)
        self._XRD = X[1, c_R:c_R + 3 * nb].reshape(nb, 3)
        self._XR[0] = self.r0_base
        self._XR[1:] = self.initial_r[1:]
        self._Xf = [(X[0, c:c + k].reshape(16, k // 16), X[1, c:c + k].reshape(16, k // 16))
                    for c, k in zip(c_f, kf)]
        self._O = np.zeros((2, D.shape[0]))
        O = self._O
        self._l2 = O[:, :3 * M].reshape(2, M, 3).transpose(1, 2, 0)       # (M, 3, 2): l, l̇
        self._rho = O[0, 3 * M:9 * M].reshape(2, M, 3, 1)
        self._Uw = O[0, 9 * M:].reshape(M, 3, 3)                          # rows: u_k inertial
        self._loc = np.zeros((M, 3, 2))
        self._dx = np.zeros((M, 3))
        self._dx_flat = self._dx.reshape(-1)
        self._dxd = self._loc[:, :, 1]
        self._dxd_flat = np.zeros(3 * M)
        # state gathers: y[_y_xi] -> X.flat[_x_xi] (positions, velocities of
        # bodies 2… and of a free base); y[_y_z] -> _z = [p, ω̄]
        xi, yi = [], []
        qr, vr = lay.q_rigid.start, lay.v_rigid.start
        for b in range(1, nb):
            for c in range(3):
                xi += [c_R + 3 * b + c, K + c_R + 3 * b + c]
                yi += [qr + 7 * (b - 1) + c, vr + 6 * (b - 1) + c]
        if lay.base_free:
            for c in range(3):
                xi += [c_R + c, K + c_R + c]
                yi += [lay.q_base.start + c, lay.v_base.start + c]
        self._x_xi = np.array(xi, dtype=np.intp)
        self._y_xi = np.array(yi, dtype=np.intp)
        self._y_z = np.concatenate([qr + 7 * np.arange(n)[:, None] + np.arange(3, 7),
                                    vr + 6 * np.arange(n)[:, None] + np.arange(3, 6)],
                                   axis=1).reshape(-1).astype(np.intp)
        self._z = np.zeros((n, 7))
        self._p = self._z[:, :4]
        self._w = self._z[:, 4:]
        self._wp = np.zeros((n, 3, 4))
        self._ppw = np.zeros((n, 4, 4, 3))
        # 2 p_a ṗ_b / |p|² = Σ_ci pp_ac ω_i 2 CP[(i, c), b]
        self._CPP = np.ascontiguousarray(
            2.0 * np.transpose(_CP.reshape(3, 4, 4), (1, 0, 2)).reshape(12, 4))
        self._inv2 = np.zeros((n, 1))
        # end forces -> generalized forces: G = [ρ ⊗ F (2M, 3, 3), F_i (M, 3)] @ W
        nf = len(self.flex_index)
        Ei = np.zeros((nb, M))
        Ej = np.zeros((nb, M))
        Ei[self.body_i, np.arange(M)] = 1.0
        Ej[self.body_j, np.arange(M)] = 1.0
        self._Einc = Ei - Ej
        Es = np.hstack([Ei, -Ej])                          # (nb, 2M)
        cols_tau, cols_F = 3 * nb, 3 * nb
        cols_H = [9 * (6 + k) for k in self._flex_modes]
        W = np.zeros((2 * M * 9 + 3 * M, cols_tau + cols_F + sum(cols_H)))
        # τ_b = Σ_e Es[b, e] ρ_e × F_e
        W[:18 * M, :cols_tau] = np.einsum("be,xc->exbc", Es, _EPS).reshape(18 * M, 3 * nb)
        W[18 * M:, cols_tau:cols_tau + cols_F] = np.einsum(
            "bm,cd->mcbd", self._Einc, np.eye(3)).reshape(3 * M, 3 * nb)
        h0 = cols_tau + cols_F
        self._H = []
        for k, b in enumerate(self.flex_index):
            nm = self._flex_modes[k]
            # body-frame generalized forces = A.ravel() @ H (9, 6 + nm):
            # Aᵀ F_b, Aᵀ τ_b, Σ_e Φ_eᵀ Aᵀ F_e
            Hm = np.zeros((2 * M * 9 + 3 * M, 3, 3, 6 + nm))
            Wt = W[:, :cols_tau].reshape(-1, nb, 3)[:, b]          # τ_b (., 3)
            WF = W[:, cols_tau:cols_tau + cols_F].reshape(-1, nb, 3)[:, b]
            for d in range(3):
                for c in range(3):
                    Hm[:, d, c, c] = WF[:, d]
                    Hm[:, d, c, 3 + c] = Wt[:, d]
            fb = flex[self.scene.bodies[b].name]
            for e in np.flatnonzero(self.end_body == b):
                m, sgn = e % M, (1.0 if e < M else -1.0)
                phi = fb.point_shapes[fb.point_index(self.S[e])]          # (3, nm)
                # Σ_d A[d, c] F_e[d] Φ_e[c, :], F_e = sgn F_i[m]
                Hm[18 * M + 3 * m:18 * M + 3 * m + 3, :, :, 6:] += sgn * np.einsum(
                    "dD,ck->Ddck", np.eye(3), phi)
            W[:, h0:h0 + cols_H[k]] = Hm.reshape(-1, cols_H[k])
            self._H.append(slice(h0, h0 + cols_H[k]))
            h0 += cols_H[k]
        self._W = np.ascontiguousarray(W)
        self._EF = np.zeros(W.shape[0])
        self._rhoF = self._EF[:18 * M].reshape(2, M, 3, 3)
        self._Fi = self._EF[18 * M:].reshape(M, 3)
        self._Fi1 = self._Fi.reshape(M, 1, 3)
        self._Fi4 = self._Fi.reshape(1, M, 1, 3)
        self._gen = np.zeros(W.shape[1])
        self._tau = self._gen[:cols_tau].reshape(nb, 3)
        self._tau1 = self._tau[1:, None, :]
        self._Fb = self._gen[cols_tau:cols_tau + cols_F].reshape(nb, 3)
        self._Hv = [self._gen[sl].reshape(9, -1) for sl in self._H]
        # Euler's equations, rigid bodies: ω̄̇ = [n̄, ω̄⊗ω̄] @ WE (per body)
        Jinv = np.einsum("bij,bj,bkj->bik", self.J_vec, 1.0 / self.J_eig, self.J_vec)
        gy = np.einsum("idc,bdj->bijc", _EPS.reshape(3, 3, 3), self.J).reshape(n, 9, 3)
        JinvT = np.transpose(Jinv, (0, 2, 1))
        self._WE = np.ascontiguousarray(np.concatenate([JinvT, -gy @ JinvT], axis=1))
        self._eul = np.zeros((n, 1, 12))
        self._nbar = self._eul[:, :, :3]
        self._ww = self._eul[:, 0, 3:].reshape(n, 3, 3)
        self._Ar = np.zeros((n, 9))
        self._Ar3 = self._Ar.reshape(n, 3, 3)
        self._jeig = self.J_eig.reshape(-1).copy()
        self._inv_m = 1.0 / self.m_r
        self._inv_m_base = 1.0 / self.m_base
        self._sq_base, self._sv_base = lay.q_base, lay.v_base
        self._sq_rigid, self._sv_rigid = lay.q_rigid, lay.v_rigid
        self._w0 = lay.work.start
        self._Fx = np.zeros(3)
        self._load_pairs = [(k, f.value) for k in range(3) for f in self._loads[k]]
        # the output, laid out as y
        self._dy = np.zeros(self.ny)
        dy = self._dy
        self._dq = dy[lay.q_rigid].reshape(n, 7)
        self._dq_r = self._dq[:, :3]
        self._dq_p = self._dq[:, 3:]
        dv = dy[lay.v_rigid].reshape(n, 6)
        self._rdd = dv[:, :3]
        self._wd1 = dv[:, None, 3:]
        self._wd = dv[:, 3:]
        self._pw = dy[lay.work]
        self._dq_base = dy[lay.q_base]
        self._dv_base = dy[lay.v_base]

    def _build_flexible(self, flex: dict) -> None:
        """Per flexible body: its equations, and its mount ends with their
        mode shapes (ends on a flexible body move by ``A Φ_e a`` more than
        their rigid offsets; the linear maps carry both)."""
        M = self.M
        lay = self.layout
        self._flex = []
        self._flex_hot = []
        for b in self.flex_index:
            body = self.scene.bodies[b]
            fb = flex[body.name]
            ends = np.flatnonzero(self.end_body == b)
            phi = np.array([fb.point_shapes[fb.point_index(self.S[e])] for e in ends])
            blk = lay.modal_block(b)
            q0 = lay.q_modal.start
            v0 = lay.v_modal.start
            fc = _FlexCompiled(
                body=b, slot=b - 1, eom=FlexibleEOM(fb), ends=ends, mounts=ends % M,
                sign=np.where(ends < M, -1.0, 1.0)[:, None],
                phi=phi.reshape(len(ends), 3, fb.n_modes),
                qa=slice(q0 + blk.start, q0 + blk.stop), va=slice(v0 + blk.start, v0 + blk.stop))
            self._flex.append(fc)
            self._flex_hot.append(_FlexHot(slot=fc.slot, eom=fc.eom, qa=fc.qa, va=fc.va,
                                           N=6 + fb.n_modes))

    # ------------------------------------------------------------------ base
    def set_segment(self, t_a: float | None, t_b: float | None = None) -> None:
        """Tell the inputs which segment between breakpoints is being integrated.

        At t = t_a or t_b the base's drives and loads then give their limits
        from inside [t_a, t_b] (right-continuous at t_a, left limits at t_b);
        ``set_segment(None)`` returns to the right-continuous convention
        everywhere (statics, outputs).
        """
        self._seg_end = None if t_a is None else float(t_b)

    def base_motion_at(self, t: float):
        """Base position [m], velocity [m/s] and acceleration [m/s²] at time t
        (prescribed motions only; a free base's come from the state)."""
        at = self._seg_end       # left limits at the end of the current segment
        r = self.r0_base.copy()
        v = np.zeros(3)
        a = np.zeros(3)
        for k in range(3):
            for f in self._drives[k]:
                r[k] += f.second(t, at)
                v[k] += f.first(t, at)
                a[k] += f.value(t, at)
        return r, v, a

    def max_step(self, t_a: float, t_b: float) -> float:
        """Longest adaptive step [s] allowed on [t_a, t_b] by the inputs active there."""
        out = np.inf
        for f in self._inputs:
            lo, hi = f.support
            if lo < t_b and hi > t_a:
                out = min(out, f.max_step)
        return float(out)

    def base_load_at(self, t: float) -> np.ndarray:
        """External force on the base [N] at time t (loads + support)."""
        F = self.support.copy()
        for k in range(3):
            for f in self._loads[k]:
                F[k] += f.value(t, self._seg_end)
        return F

    # ------------------------------------------------------------- the physics
    def _evaluate(self, t: float, y: np.ndarray) -> np.ndarray:
        """Fill and return the output buffer ``_dy`` (ny,) with dy/dt."""
        X = self._X
        dy = self._dy
        # 1. kinematics of the bodies
        motion = self.base_motion
        if motion == "driven" and self._has_drive:
            r_b, v_b, a_b = self.base_motion_at(t)
            self._XR[0] = r_b
            self._XRD[0] = v_b
            self._acc_base = a_b
        X.flat[self._x_xi] = y[self._y_xi]                  # R, Ṙ
        self._z.flat[:] = y[self._y_z]                       # p, ω̄
        p, w = self._p, self._w
        Xpp = self._Xpp
        np.multiply(p[:, :, None], p[:, None, :], out=self._Xpp3)
        inv2 = np.divide(1.0, Xpp @ _TRACE, out=self._inv2)                   # 1/|p|²
        np.multiply(Xpp, inv2, out=Xpp)                                         # p⊗p/|p|²
        np.multiply(w[:, :, None], p[:, None, :], out=self._wp)
        np.matmul(self._wp.reshape(-1, 12), _CP, out=self._dq_p)              # ṗ = ½ G(p)ᵀ ω̄
        np.multiply(self._Xpp3[:, :, :, None], w[:, None, None, :], out=self._ppw)
        np.matmul(self._ppw.reshape(-1, 4, 12), self._CPP, out=self._Xppd3)   # d/dt p⊗p/|p|²
        for fh, (x0, x1) in zip(self._flex_hot, self._Xf):
            a = y[fh.qa]
            ad = y[fh.va]
            pp, ppd = Xpp[fh.slot, :, None], self._Xppd3[fh.slot].reshape(16, 1)
            np.multiply(pp, a, out=x0)
            np.multiply(ppd, a, out=x1)
            x1 += pp * ad
        # 2.-3. all mounts and ends at once
        np.matmul(X, self._DT, out=self._O)
        loc = np.matmul(self._Uw, self._l2, out=self._loc)
        dx = np.subtract(loc[:, :, 0], self.d0, out=self._dx)
        dxd = self._dxd_flat
        dxd[:] = self._dxd.reshape(-1)
        f = self.laws.forces(self._dx_flat, dxd, self._f)
        np.matmul(f.reshape(-1, 1, 3), self._Uw, out=self._Fi1)              # F_i = Σ f_k u_k
        np.multiply(self._rho, self._Fi4, out=self._rhoF)                    # ρ_e ⊗ F_e
        np.matmul(self._EF, self._W, out=self._gen)
        Fb = self._Fb
        # 4. Newton–Euler per body
        np.matmul(Xpp, _CA, out=self._Ar)                                      # A (n, 9)
        np.matmul(self._tau1, self._Ar3, out=self._nbar)                       # A_bᵀ τ_b
        np.multiply(w[:, :, None], w[:, None, :], out=self._ww)
        np.matmul(self._eul, self._WE, out=self._wd1)                          # ω̄̇
        rdd = np.multiply(Fb[1:], self._inv_m, out=self._rdd)
        rdd += self.g
        self._dq_r[...] = self._XRD[1:]
        p_struct = 0.0
        for fh, Hv in zip(self._flex_hot, self._Hv):
            eom = fh.eom
            a = y[fh.qa]
            ad = y[fh.va]
            A = self._Ar3[fh.slot]
            wf = w[fh.slot]
            Mbar = eom.mass_matrix_body(a)
            Q = eom.forces_body(wf, a, ad, self.g @ A, Mbar[3:6, 3:6])
            Qv = Q[:fh.N]
            Qv += A.reshape(9) @ Hv                                         # the mounts
            vd = np.linalg.solve(Mbar, Qv)
            np.matmul(A, vd[:3], out=rdd[fh.slot])
            self._wd[fh.slot] = vd[3:6]
            dy[fh.qa] = ad
            dy[fh.va] = vd[6:]
            p_struct -= float(ad @ Q[fh.N:])
        # 5. base and powers
        w0 = self._w0
        dy[w0] = -float(f @ dxd)
        dy[w0 + 3] = p_struct
        if motion == "free":
            Fx = self._Fx
            Fx[:] = self.support
            at = self._seg_end
            for k, fun in self._load_pairs:
                Fx[k] += fun(t, at)
            ab = (Fb[0] + Fx) * self._inv_m_base + self.g
            self._dq_base[:] = self._XRD[0]
            self._dv_base[:] = ab
            dy[w0 + 1] = float(Fx @ self._XRD[0])
            self._acc_base = ab
        elif motion == "driven" and self._has_drive:
            Fd = self.m_base * (self._acc_base - self.g) - Fb[0]
            dy[w0 + 2] = float(Fd @ self._XRD[0])
        self._last = (dx, dxd.reshape(-1, 3), f, self._Fi, rdd, self._wd)
        return dy

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        """dy/dt at time t [s] for the state y (ny,); a new array each call."""
        self.nfev += 1
        return self._evaluate(t, y).copy()

    # ------------------------------------------------------------ the outputs
    def initial_state(self) -> np.ndarray:
        """The scene's initial positions, at rest, zero work."""
        y = np.zeros(self.ny)
        lay = self.layout
        if lay.base_free:
            y[lay.q_base] = self.r0_base
        qr = y[lay.q_rigid].reshape(self.n_rigid, 7)
        qr[:, :3] = self.initial_r[1:]
        qr[:, 3:] = self.initial_p[1:]
        return y

    def observe(self, t: float, y: np.ndarray) -> Observation:
        """Everything at one (t, y); same physics as :meth:`rhs`."""
        dydt = self._evaluate(t, np.asarray(y, dtype=float)).copy()
        dx, dxd, f, Fi, rdd, wd = self._last
        nb, M = self.nb, self.M
        o = Observation()
        o.t = float(t)
        o.r = self._XR.copy()
        parts = self.layout.split(y)
        o.p = np.zeros((nb, 4))
        o.p[0, 0] = 1.0
        o.p[1:] = parts["p"] / np.linalg.norm(parts["p"], axis=1, keepdims=True)
        o.rd = self._XRD.copy()
        o.w = np.zeros((nb, 3))
        o.w[1:] = parts["w"]
        o.rdd = np.zeros((nb, 3))
        o.rdd[1:] = rdd
        if self.base_motion != "fixed":
            o.rdd[0] = self._acc_base
        o.wd = np.zeros((nb, 3))
        o.wd[1:] = wd.reshape(-1, 3)
        o.dx = dx.copy()
        o.dxd = np.array(dxd)
        o.f = f.reshape(M, 3).copy()
        o.force_i = Fi.copy()
        o.force_j = -Fi
        rd = o.rd
        ke = 0.5 * self.mass * np.sum(rd * rd, axis=1)
        ke[1:] += 0.5 * np.einsum("ni,nij,nj->n", o.w[1:], self.J, o.w[1:])
        o.kinetic = ke
        o.gravity_potential = -self.mass * (o.r @ self.g)
        o.strain = np.zeros(nb)
        o.a = np.array(parts["a"], dtype=float)
        o.ad = np.array(parts["ad"], dtype=float)
        o.add = dydt[self.layout.v_modal].copy()
        for fc in self._flex:
            a, ad = y[fc.qa], y[fc.va]
            A = rotation_matrix(o.p[fc.body])
            o.kinetic[fc.body] = fc.eom.kinetic_energy(A, o.w[fc.body], a, o.rd[fc.body], ad)
            S = fc.eom.I2 + fc.eom.I3 @ a
            o.gravity_potential[fc.body] -= float((A @ S) @ self.g)
            o.strain[fc.body] = fc.eom.strain_energy(a)
        o.mount_potential = self.laws.spring_potential(dx.reshape(-1)).reshape(M, 3).sum(axis=1)
        o.work = np.array(parts["work"], dtype=float)
        o.power = dydt[self.layout.work].copy()
        return o

    @property
    def flex_compiled(self) -> tuple:
        """The compiled flexible bodies (see ``_FlexCompiled``)."""
        return tuple(self._flex)

    def reset_counter(self) -> None:
        self.nfev = 0
