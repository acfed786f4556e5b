"""The right-hand side :func:`evaluate` (see :mod:`flexbed.dynamics.kernel`
for what it computes, in order) and its entry points from Python."""

from __future__ import annotations

from numba import njit

from .flexible_body import cholesky_solve, flex_forces_body, flex_mass_body, flex_T
from .inputs import input_value
from .mount_laws import law_force
from .storage import unpack

__all__ = ["evaluate", "evaluate_packed", "evaluate_many"]


@njit(cache=True)
def _rotation(p, A):
    """A = Q(p)/|p|² (3, 3) for Euler parameters p (4,), scalar first."""
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    s = 1.0 / (e0 * e0 + e1 * e1 + e2 * e2 + e3 * e3)
    d = e0 * e0 - e1 * e1 - e2 * e2 - e3 * e3
    A[0, 0] = (d + 2.0 * e1 * e1) * s
    A[1, 1] = (d + 2.0 * e2 * e2) * s
    A[2, 2] = (d + 2.0 * e3 * e3) * s
    A[0, 1] = 2.0 * (e1 * e2 - e0 * e3) * s
    A[1, 0] = 2.0 * (e1 * e2 + e0 * e3) * s
    A[0, 2] = 2.0 * (e1 * e3 + e0 * e2) * s
    A[2, 0] = 2.0 * (e1 * e3 - e0 * e2) * s
    A[1, 2] = 2.0 * (e2 * e3 - e0 * e1) * s
    A[2, 1] = 2.0 * (e2 * e3 + e0 * e1) * s


@njit(cache=True)
def evaluate(t, seg_end, y, dy, d):
    """dy/dt for the state y at time t.

    Parameters
    ----------
    t : float
        Time [s].
    seg_end : float
        End of the segment being integrated (inputs give their left limits
        at and beyond it); ``inf`` for right-continuous inputs.
    y : (ny,) float array
        State (:mod:`dynamics.layout`).
    dy : (ny,) float array
        Output, overwritten in full.
    d : Compiled
        The scene.
    """
    nb, M, nf, mode = d.ints[0], d.ints[1], d.ints[2], d.ints[3]
    qr, vr, qb, vb, w0 = d.ints[4], d.ints[5], d.ints[6], d.ints[7], d.ints[8]
    g = d.gravity
    A = d.w_A
    base = d.w_base
    # 1. the base
    for c in range(3):
        base[0, c] = d.r0_base[c]
        base[1, c] = 0.0
        base[2, c] = 0.0
    Fx0 = d.support[0]
    Fx1 = d.support[1]
    Fx2 = d.support[2]
    if mode == 2:
        for c in range(3):
            base[0, c] = y[qb + c]
            base[1, c] = y[vb + c]
    in_ints, in_sin, in_b, in_o, in_c = d.in_ints, d.in_sin, d.in_b, d.in_o, d.in_c
    for i in range(in_ints.shape[0]):
        kind = in_ints[i, 0]
        c = in_ints[i, 1]
        if in_ints[i, 2] == 0:
            if mode == 1:
                for which in range(3):
                    base[2 - which, c] += input_value(kind, in_sin[i], in_b[i], in_o[i], in_c[i],
                                                 which, t, seg_end)
        elif mode == 2:
            val = input_value(kind, in_sin[i], in_b[i], in_o[i], in_c[i], 0, t, seg_end)
            if c == 0:
                Fx0 += val
            elif c == 1:
                Fx1 += val
            else:
                Fx2 += val
    # 2. rotations, ṗ, ṙ
    for i in range(3):
        for j in range(3):
            A[0, i, j] = 1.0 if i == j else 0.0
    for b in range(1, nb):
        q = qr + 7 * (b - 1)
        v = vr + 6 * (b - 1)
        _rotation(y[q + 3:q + 7], A[b])
        e0, e1, e2, e3 = y[q + 3], y[q + 4], y[q + 5], y[q + 6]
        wx, wy, wz = y[v + 3], y[v + 4], y[v + 5]
        dy[q] = y[v]
        dy[q + 1] = y[v + 1]
        dy[q + 2] = y[v + 2]
        dy[q + 3] = -0.5 * (e1 * wx + e2 * wy + e3 * wz)
        dy[q + 4] = 0.5 * (e0 * wx + e2 * wz - e3 * wy)
        dy[q + 5] = 0.5 * (e0 * wy + e3 * wx - e1 * wz)
        dy[q + 6] = 0.5 * (e0 * wz + e1 * wy - e2 * wx)
    # 3. mount ends
    P = d.w_P
    Pd = d.w_Pd
    ub = d.w_ub
    for e in range(2 * M):
        m = e % M
        b = d.body_i[m] if e < M else d.body_j[m]
        k = d.end_flex[e]
        for c in range(3):
            ub[e, c] = d.S[e, c]
        if k >= 0:
            n = d.fx_ints[k, 1]
            oa = d.fx_ints[k, 2]
            for c in range(3):
                s = 0.0
                for j in range(n):
                    s += d.end_phi[e, c, j] * y[oa + j]
                ub[e, c] += s
        if b == 0:
            for c in range(3):
                P[e, c] = base[0, c] + ub[e, c]
                Pd[e, c] = base[1, c]
            continue
        q = qr + 7 * (b - 1)
        v = vr + 6 * (b - 1)
        wx, wy, wz = y[v + 3], y[v + 4], y[v + 5]
        # body-frame velocity of the point relative to the frame: ω̄ × ū (+ Φ ȧ)
        rx = wy * ub[e, 2] - wz * ub[e, 1]
        ry = wz * ub[e, 0] - wx * ub[e, 2]
        rz = wx * ub[e, 1] - wy * ub[e, 0]
        if k >= 0:
            n = d.fx_ints[k, 1]
            ov = d.fx_ints[k, 3]
            for j in range(n):
                rx += d.end_phi[e, 0, j] * y[ov + j]
                ry += d.end_phi[e, 1, j] * y[ov + j]
                rz += d.end_phi[e, 2, j] * y[ov + j]
        Ab = A[b]
        for c in range(3):
            P[e, c] = y[q + c] + Ab[c, 0] * ub[e, 0] + Ab[c, 1] * ub[e, 1] + Ab[c, 2] * ub[e, 2]
            Pd[e, c] = y[v + c] + Ab[c, 0] * rx + Ab[c, 1] * ry + Ab[c, 2] * rz
    # 4. mounts
    force = d.w_force
    torque = d.w_torque
    for b in range(nb):
        for c in range(3):
            force[b, c] = 0.0
            torque[b, c] = 0.0
    for k in range(nf):
        for c in range(d.w_flexQ.shape[1]):
            d.w_flexQ[k, c] = 0.0
    p_mount = 0.0
    law_kind, law_row, lin_kc = d.law_kind, d.law_row, d.lin_kc
    poly_k, poly_c, crv_b, crv_o, crv_c = d.poly_k, d.poly_c, d.crv_b, d.crv_o, d.crv_c
    for m in range(M):
        bi = d.body_i[m]
        Ai = A[bi]
        l0 = P[M + m, 0] - P[m, 0]
        l1 = P[M + m, 1] - P[m, 1]
        l2 = P[M + m, 2] - P[m, 2]
        v0 = Pd[M + m, 0] - Pd[m, 0]
        v1 = Pd[M + m, 1] - Pd[m, 1]
        v2 = Pd[M + m, 2] - Pd[m, 2]
        # in body i's frame
        lb0 = Ai[0, 0] * l0 + Ai[1, 0] * l1 + Ai[2, 0] * l2
        lb1 = Ai[0, 1] * l0 + Ai[1, 1] * l1 + Ai[2, 1] * l2
        lb2 = Ai[0, 2] * l0 + Ai[1, 2] * l1 + Ai[2, 2] * l2
        vb0 = Ai[0, 0] * v0 + Ai[1, 0] * v1 + Ai[2, 0] * v2
        vb1 = Ai[0, 1] * v0 + Ai[1, 1] * v1 + Ai[2, 1] * v2
        vb2 = Ai[0, 2] * v0 + Ai[1, 2] * v1 + Ai[2, 2] * v2
        Fb0 = 0.0
        Fb1 = 0.0
        Fb2 = 0.0
        for kd in range(3):
            u0, u1, u2 = d.U[m, kd, 0], d.U[m, kd, 1], d.U[m, kd, 2]
            x = u0 * lb0 + u1 * lb1 + u2 * lb2 - d.d0[m, kd]
            xd = u0 * vb0 + u1 * vb1 + u2 * vb2
            il = 3 * m + kd
            f = law_force(law_kind[il], law_row[il], lin_kc, poly_k, poly_c, crv_b, crv_o, crv_c,
                     x, xd)
            d.w_dx[m, kd] = x
            d.w_dxd[m, kd] = xd
            d.w_f[m, kd] = f
            p_mount -= f * xd
            Fb0 += f * u0
            Fb1 += f * u1
            Fb2 += f * u2
        # inertial force on P_i (and its opposite on P_j)
        F0 = Ai[0, 0] * Fb0 + Ai[0, 1] * Fb1 + Ai[0, 2] * Fb2
        F1 = Ai[1, 0] * Fb0 + Ai[1, 1] * Fb1 + Ai[1, 2] * Fb2
        F2 = Ai[2, 0] * Fb0 + Ai[2, 1] * Fb1 + Ai[2, 2] * Fb2
        d.w_F[m, 0] = F0
        d.w_F[m, 1] = F1
        d.w_F[m, 2] = F2
        for side in range(2):
            e = m + side * M
            b = bi if side == 0 else d.body_j[m]
            sg = 1.0 if side == 0 else -1.0
            force[b, 0] += sg * F0
            force[b, 1] += sg * F1
            force[b, 2] += sg * F2
            if b == 0:
                continue
            Ab = A[b]
            # the force in the body frame, the moment about the frame origin
            g0 = sg * (Ab[0, 0] * F0 + Ab[1, 0] * F1 + Ab[2, 0] * F2)
            g1 = sg * (Ab[0, 1] * F0 + Ab[1, 1] * F1 + Ab[2, 1] * F2)
            g2 = sg * (Ab[0, 2] * F0 + Ab[1, 2] * F1 + Ab[2, 2] * F2)
            t0 = ub[e, 1] * g2 - ub[e, 2] * g1
            t1 = ub[e, 2] * g0 - ub[e, 0] * g2
            t2 = ub[e, 0] * g1 - ub[e, 1] * g0
            torque[b, 0] += t0
            torque[b, 1] += t1
            torque[b, 2] += t2
            k = d.end_flex[e]
            if k >= 0:
                Qk = d.w_flexQ[k]
                Qk[0] += g0
                Qk[1] += g1
                Qk[2] += g2
                Qk[3] += t0
                Qk[4] += t1
                Qk[5] += t2
                for j in range(d.fx_ints[k, 1]):
                    Qk[6 + j] += (d.end_phi[e, 0, j] * g0 + d.end_phi[e, 1, j] * g1
                                  + d.end_phi[e, 2, j] * g2)
    # 5. Newton–Euler, rigid bodies (flexible ones are overwritten below)
    acc = d.w_acc
    for b in range(1, nb):
        if d.body_flex[b] >= 0:
            continue
        v = vr + 6 * (b - 1)
        inv_m = 1.0 / d.mass[b]
        for c in range(3):
            acc[b, c] = force[b, c] * inv_m + g[c]
        w = y[v + 3:v + 6]
        J = d.J[b]
        Jw0 = J[0, 0] * w[0] + J[0, 1] * w[1] + J[0, 2] * w[2]
        Jw1 = J[1, 0] * w[0] + J[1, 1] * w[1] + J[1, 2] * w[2]
        Jw2 = J[2, 0] * w[0] + J[2, 1] * w[1] + J[2, 2] * w[2]
        n0 = torque[b, 0] - (w[1] * Jw2 - w[2] * Jw1)
        n1 = torque[b, 1] - (w[2] * Jw0 - w[0] * Jw2)
        n2 = torque[b, 2] - (w[0] * Jw1 - w[1] * Jw0)
        Ji = d.Jinv[b]
        acc[b, 3] = Ji[0, 0] * n0 + Ji[0, 1] * n1 + Ji[0, 2] * n2
        acc[b, 4] = Ji[1, 0] * n0 + Ji[1, 1] * n1 + Ji[1, 2] * n2
        acc[b, 5] = Ji[2, 0] * n0 + Ji[2, 1] * n1 + Ji[2, 2] * n2
    p_struct = 0.0
    Mb = d.w_M
    Q = d.w_Q
    for k in range(nf):
        b = d.fx_ints[k, 0]
        n = d.fx_ints[k, 1]
        oa = d.fx_ints[k, 2]
        ov = d.fx_ints[k, 3]
        N = 6 + n
        v = vr + 6 * (b - 1)
        a = y[oa:oa + n]
        ad = y[ov:ov + n]
        Ab = A[b]
        gb = d.w_gb
        for c in range(3):
            gb[c] = Ab[0, c] * g[0] + Ab[1, c] * g[1] + Ab[2, c] * g[2]
        I3, I8, T = d.fx_I3[k], d.fx_I8[k], d.w_T
        flex_T(I8, d.fx_I9[k], n, a, T)
        flex_mass_body(d.fx_m[k], d.fx_I2[k], I3, d.fx_I4[k], d.fx_I5[k], d.fx_I6[k],
                       d.fx_I7[k], I8, T, n, a, Mb)
        flex_forces_body(d.fx_m[k], d.fx_I2[k], I3, d.fx_I5[k], d.fx_K[k], d.fx_C[k], T, n,
                         y[v + 3:v + 6], a, ad, gb, Mb, Q)
        for j in range(n):
            p_struct -= ad[j] * Q[N + j]
        for j in range(N):
            Q[j] += d.w_flexQ[k, j]
        cholesky_solve(Mb, Q, N)
        for c in range(3):
            acc[b, c] = Ab[c, 0] * Q[0] + Ab[c, 1] * Q[1] + Ab[c, 2] * Q[2]
            acc[b, 3 + c] = Q[3 + c]
        for j in range(n):
            dy[oa + j] = ad[j]
            dy[ov + j] = Q[6 + j]
    for b in range(1, nb):
        v = vr + 6 * (b - 1)
        for c in range(6):
            dy[v + c] = acc[b, c]
    # 6. the base and the powers
    dy[w0] = p_mount
    dy[w0 + 1] = 0.0
    dy[w0 + 2] = 0.0
    dy[w0 + 3] = p_struct
    if mode == 2:
        inv_mb = 1.0 / d.mass[0]
        Fx = (Fx0, Fx1, Fx2)
        for c in range(3):
            dy[qb + c] = y[vb + c]
            ab = (force[0, c] + Fx[c]) * inv_mb + g[c]
            dy[vb + c] = ab
            base[2, c] = ab
            dy[w0 + 1] += Fx[c] * y[vb + c]
    elif mode == 1:
        for c in range(3):
            Fd = d.mass[0] * (base[2, c] - g[c]) - force[0, c]
            dy[w0 + 2] += Fd * base[1, c]
    for c in range(3):
        acc[0, c] = base[2, c]


@njit(cache=True)
def evaluate_packed(t, seg_end, y, dy, F, I, meta):
    """:func:`evaluate` on packed storage (the cheap call from Python)."""
    evaluate(t, seg_end, y, dy, unpack(F, I, meta))


@njit(cache=True)
def evaluate_many(n, t, seg_end, y, dy, d):
    """n calls of :func:`evaluate` in compiled code (the kernel's own cost,
    as the compiled steppers see it, for the benchmark)."""
    for _ in range(n):
        evaluate(t, seg_end, y, dy, d)
