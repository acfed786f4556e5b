"""A scene compiled once into flat arrays, and its one right-hand side.

:class:`System` is built from a :class:`~dynamics.scene.Scene`. Its
:meth:`System.rhs` gives ``dy/dt`` for the state laid out as in
:mod:`dynamics.layout`; statics, every integrator, the linearisation and the
benchmarks call this one function. :meth:`System.observe` evaluates the same
physics and returns everything a results file stores.

Per call the right-hand side does only arithmetic on preallocated arrays:

1. kinematics of every body: position ``R`` (nb, 3), rotation ``A``
   (nb, 3, 3), velocity ``Ṙ`` (nb, 3), body angular velocity ``ω̄`` (nb, 3);
   the base's from its motion, the rigid bodies' from the state
   (``A = Q(p)/|p|²``, so a slightly non-unit p still gives a rotation);
2. the mount ends (2M points: ends i, then ends j): positions and velocities
   from their body-frame offsets ``s̄`` (the place where a flexible body will
   add ``Φ(s̄) a``);
3. every mount at once (paper eq. 2–4): ``Δx = Ū (A_iᵀ l) − Ū l̄0``,
   ``Δẋ = Ū (A_iᵀ l̇)``, forces from the law bank, ``F_i = A_i Ūᵀ f`` on P_i
   and ``−F_i`` on P_j;
4. the generalized forces per body (sum of the end forces and of their
   moments), then per-body Newton–Euler equations:
   ``m r̈ = F + m g``; ``J ω̄̇ = n̄ − ω̄ × J ω̄`` (solved with J's principal
   axes factorisation); ``ṗ = ½ G(p)ᵀ ω̄``;
5. the powers that feed the energy quadratures.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .flexible import FlexibleEOM, cross
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
        """Precompute the linear maps of the hot path.

        For unit p, every rotated quantity is a fixed linear function of the
        16 products p_a p_b (``A = Σ p_a p_b CA_ab``), and its rate is the same
        map applied to 2 p_a ṗ_b. So one matrix product of
        ``X = [[p⊗p (all rigid bodies), R (all bodies)], [2 p⊗ṗ, Ṙ]]`` with
        the precomputed ``DT`` gives, for all mounts and ends at once: the
        mount vectors l and l̇, the end offsets ρ = A s̄ and the mount axes in
        the inertial frame (rows of Ū A_iᵀ).
        """
        n, nb, M = self.n_rigid, self.nb, self.M
        K = 16 * n + 3 * nb
        CA = _CA.reshape(16, 3, 3)
        rows_l, rows_rho, rows_u = 3 * M, 6 * M, 9 * M
        D = np.zeros((rows_l + rows_rho + rows_u, K))
        c0 = np.zeros(rows_l + rows_rho + rows_u)
        rho_rows = np.zeros((2 * M, 3, K))         # ρ_e as a map of X's first row
        rho_const = np.zeros((2 * M, 3))
        for e in range(2 * M):
            b = int(self.end_body[e])
            s = self.S[e]
            if b == 0:
                rho_const[e] = s                    # the base never rotates
            else:
                cols = slice(16 * (b - 1), 16 * b)
                rho_rows[e, :, cols] = np.einsum("akl,l->ka", CA, s)
        for m in range(M):
            for sign, e in ((-1.0, m), (1.0, M + m)):
                b = int(self.end_body[e])
                rowsl = slice(3 * m, 3 * m + 3)
                D[rowsl] += sign * rho_rows[e]
                c0[rowsl] += sign * rho_const[e]
                D[rowsl, 16 * n + 3 * b + np.arange(3)] += sign * np.eye(3)
        D[rows_l:rows_l + rows_rho] = rho_rows.reshape(6 * M, K)
        c0[rows_l:rows_l + rows_rho] = rho_const.reshape(-1)
        for m in range(M):
            b = int(self.body_i[m])
            U = self.U[m]
            r0 = rows_l + rows_rho + 9 * m
            if b == 0:
                c0[r0:r0 + 9] = U.reshape(-1)
            else:
                # Uw[k, c] = Σ_l U[k, l] A[c, l], A[c, l] = Σ_ab pp_ab CA[ab, c, l]
                blk = np.einsum("kl,acl->kca", U, CA).reshape(9, 16)
                D[r0:r0 + 9, 16 * (b - 1):16 * b] = blk
        self._DT = np.ascontiguousarray(D.T)
        self._c0 = c0
        self._X = np.zeros((2, K))
        self._Xpp = self._X[0, :16 * n].reshape(n, 16)
        self._Xppd = self._X[1, :16 * n].reshape(n, 16)
        self._XR = self._X[0, 16 * n:].reshape(nb, 3)
        self._XRD = self._X[1, 16 * n:].reshape(nb, 3)
        self._XR[0] = self.r0_base
        self._XR[1:] = self.initial_r[1:]
        # body incidence: force on body b = Einc @ F_i; torques: Es @ (ρ × F)
        Ei = np.zeros((nb, M))
        Ej = np.zeros((nb, M))
        Ei[self.body_i, np.arange(M)] = 1.0
        Ej[self.body_j, np.arange(M)] = 1.0
        self._Einc = Ei - Ej
        self._Es = np.hstack([Ei, -Ej])
        # Euler's equations: block-diagonal J and its principal-axes factors
        self._Jblk = np.zeros((3 * n, 3 * n))
        self._Qblk = np.zeros((3 * n, 3 * n))
        for b in range(n):
            sl = slice(3 * b, 3 * b + 3)
            self._Jblk[sl, sl] = self.J[b]
            self._Qblk[sl, sl] = self.J_vec[b]
        self._QTblk = np.ascontiguousarray(self._Qblk.T)
        self._jeig = self.J_eig.reshape(-1).copy()
        self._inv_m = 1.0 / self.m_r
        self._inv_m_base = 1.0 / self.m_base
        lay = self.layout
        self._sq_base, self._sv_base = lay.q_base, lay.v_base
        self._sq_rigid, self._sv_rigid = lay.q_rigid, lay.v_rigid
        self._w0 = lay.work.start
        self._Fx = np.zeros(3)
        self._load_pairs = [(k, f.value) for k in range(3) for f in self._loads[k]]

    def _build_flexible(self, flex: dict) -> None:
        """Per flexible body: its equations, and its mount ends with their
        mode shapes (ends on a flexible body move by ``A Φ_e a`` more than
        the rigid offsets the linear maps already give)."""
        M = self.M
        lay = self.layout
        self._flex = []
        for b in self.flex_index:
            body = self.scene.bodies[b]
            fb = flex[body.name]
            ends = np.flatnonzero(self.end_body == b)
            phi = np.array([fb.point_shapes[fb.point_index(self.S[e])] for e in ends])
            blk = lay.modal_block(b)
            q0 = lay.q_modal.start
            v0 = lay.v_modal.start
            self._flex.append(_FlexCompiled(
                body=b, slot=b - 1, eom=FlexibleEOM(fb), ends=ends, mounts=ends % M,
                sign=np.where(ends < M, -1.0, 1.0)[:, None],
                phi=phi.reshape(len(ends), 3, fb.n_modes),
                qa=slice(q0 + blk.start, q0 + blk.stop), va=slice(v0 + blk.start, v0 + blk.stop)))

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
    def _evaluate(self, t: float, y: np.ndarray, dydt: np.ndarray) -> None:
        n, M = self.n_rigid, self.M
        X = self._X
        # 1. kinematics of the bodies
        motion = self.base_motion
        if motion == "driven":
            if self._has_drive:
                r_b, v_b, a_b = self.base_motion_at(t)
                self._XR[0] = r_b
                self._XRD[0] = v_b
                self._acc_base = a_b
        elif motion == "free":
            self._XR[0] = y[self._sq_base]
            self._XRD[0] = y[self._sv_base]
        qr = y[self._sq_rigid].reshape(n, 7)
        vr = y[self._sv_rigid].reshape(n, 6)
        p = qr[:, 3:]
        wr = vr[:, 3:]
        pp = (p[:, :, None] * p[:, None, :]).reshape(n, 16)
        inv2 = 1.0 / (pp @ _TRACE)                                          # 1/|p|², (n, 1)
        pdot = (wr[:, :, None] * p[:, None, :]).reshape(n, 12) @ _CP       # ½ G(p)ᵀ ω̄
        np.multiply(pp, inv2, out=self._Xpp)
        pds = pdot * (2.0 * inv2)
        np.multiply(p[:, :, None], pds[:, None, :], out=self._Xppd.reshape(n, 4, 4))
        self._XR[1:] = qr[:, :3]
        self._XRD[1:] = vr[:, :3]
        # 2.-3. all mounts and ends at once
        O = X @ self._DT
        O[0] += self._c0
        l2 = O[:, :3 * M].reshape(2, M, 3).transpose(1, 2, 0)             # (M, 3, 2): l, l̇
        rho = O[0, 3 * M:9 * M].reshape(2, M, 3)
        Uw = O[0, 9 * M:].reshape(M, 3, 3)                                  # rows: u_k inertial
        flex_state = []
        for fc in self._flex:
            a = y[fc.qa]
            ad = y[fc.va]
            A = (self._Xpp[fc.slot] @ _CA).reshape(3, 3)
            w = wr[fc.slot]
            u = fc.phi @ a                                                   # Φ_e a (E, 3)
            drho = u @ A.T
            drhod = (cross(w, u) + fc.phi @ ad) @ A.T
            np.add.at(rho.reshape(2 * M, 3), fc.ends, drho)
            np.add.at(l2[:, :, 0], fc.mounts, fc.sign * drho)
            np.add.at(l2[:, :, 1], fc.mounts, fc.sign * drhod)
            flex_state.append((A, w, a, ad))
        loc = Uw @ l2
        dx = loc[:, :, 0] - self.d0
        dxd = loc[:, :, 1]
        f = self.laws.forces(dx.reshape(-1), dxd.reshape(-1), self._f)
        Fi = (f.reshape(M, 1, 3) @ Uw)[:, 0, :]                            # Σ f_k u_k on P_i
        # 4. generalized forces, Newton–Euler per body
        Fb = self._Einc @ Fi
        tau = self._Es @ ((rho[:, :, :, None] * Fi[None, :, None, :]).reshape(2 * M, 9) @ _EPS)
        Ar = (self._Xpp @ _CA).reshape(n, 3, 3)
        nbar = (tau[1:, None, :] @ Ar)[:, 0, :]                             # A_bᵀ τ_b
        Jw = (self._Jblk @ wr.reshape(-1)).reshape(n, 3)
        rhs_w = nbar - (wr[:, :, None] * Jw[:, None, :]).reshape(n, 9) @ _EPS
        wd = self._Qblk @ ((self._QTblk @ rhs_w.reshape(-1)) / self._jeig)
        rdd = Fb[1:] * self._inv_m + self.g
        dq = dydt[self._sq_rigid].reshape(n, 7)
        dq[:, :3] = vr[:, :3]
        dq[:, 3:] = pdot
        dv = dydt[self._sv_rigid].reshape(n, 6)
        dv[:, :3] = rdd
        dv[:, 3:] = wd.reshape(n, 3)
        p_struct = 0.0
        for fc, (A, w, a, ad) in zip(self._flex, flex_state):
            eom = fc.eom
            J = eom.inertia(a)                                              # once per call
            Q = eom.forces(A, w, a, ad, self.g, J)
            Fe = -fc.sign * Fi[fc.mounts]                                   # forces on its ends
            Q[:3] += Fb[fc.body]
            Q[3:6] += tau[fc.body] @ A
            Q[6:] += np.einsum("eij,ei->j", fc.phi, Fe @ A)
            vd = np.linalg.solve(eom.mass_matrix(A, a, J), Q)
            dv[fc.slot, :3] = vd[:3]
            dv[fc.slot, 3:] = vd[3:6]
            dydt[fc.qa] = ad
            dydt[fc.va] = vd[6:]
            rdd[fc.slot] = vd[:3]
            wd.reshape(n, 3)[fc.slot] = vd[3:6]
            p_struct -= float(ad @ eom.C @ ad)
        # 5. base and powers
        p_mount = -float(f @ dxd.reshape(-1))
        p_ext = 0.0
        p_drive = 0.0
        if motion == "free":
            Fx = self._Fx
            Fx[:] = self.support
            at = self._seg_end
            for k, fun in self._load_pairs:
                Fx[k] += fun(t, at)
            ab = (Fb[0] + Fx) * self._inv_m_base + self.g
            dydt[self._sq_base] = self._XRD[0]
            dydt[self._sv_base] = ab
            p_ext = float(Fx @ self._XRD[0])
            self._acc_base = ab
        elif motion == "driven" and self._has_drive:
            Fd = self.m_base * (self._acc_base - self.g) - Fb[0]
            p_drive = float(Fd @ self._XRD[0])
        w0 = self._w0
        dydt[w0] = p_mount
        dydt[w0 + 1] = p_ext
        dydt[w0 + 2] = p_drive
        dydt[w0 + 3] = p_struct
        self._last = (dx, dxd, f, Fi, rdd, wd)

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        """dy/dt at time t [s] for the state y (ny,); a new array each call."""
        self.nfev += 1
        dydt = np.empty(self.ny)
        self._evaluate(t, y, dydt)
        return dydt

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
        dydt = np.empty(self.ny)
        self._evaluate(t, np.asarray(y, dtype=float), dydt)
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
