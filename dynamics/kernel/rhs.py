"""The right-hand side :func:`evaluate` (see :mod:`flexbed.dynamics.kernel`
for what it computes, in order), compiled once as a C function.

:func:`evaluate` builds its views of the scene's fields, then calls one
compiled function per section: :func:`_base_inputs` (1),
:func:`_rotations` (2), :func:`_mount_ends` (3), :func:`_maxwell_sums`
(4a), :func:`_mount_forces` (4), :func:`_body_loads` (4b),
:func:`_newton_euler` and :func:`_floating_frame` (5),
:func:`_rates_and_powers` (6), :func:`_maxwell_rates` (7). They take the
views already built, and numba inlines them (``inline="always"``) into the one C function, which
is the code of one long function, operation for operation: same results
to the bit, same speed (called as separate functions, with their
arrays passed at each call, it measured a few per cent slower).

Compiled code that calls the right-hand side (the steppers, the history of
a run) calls it through a function pointer: the C function
``void rhs(double t, double seg_end, double *y, double *dy, double *F,
int64 *I)`` on the packed storage (F, I) of :func:`.storage.pack`
(:data:`PROTOTYPE`), obtained from :func:`rhs_function` and passed to the
compiled callers as an argument. Numba links a callee's code into each of
its compiled callers and optimises it again there; through a pointer, the
right-hand side (the largest function by far) is compiled once, in one
place, and its callers are compiled without it. It takes two arrays
rather than a tuple of ~60 (whose hundreds of scalar arguments made it
twice as slow to compile) and builds its views of the fields itself
(cheap: an address and a shape each). Its helpers that only compiled code
calls have no wrapper for calls from Python. It uses NumPy's error model:
a division by zero gives inf or nan (the steppers stop at a non-finite
state) and nothing raises.
"""

from __future__ import annotations

import ctypes

import numpy as np
from numba import carray, cfunc, njit, types

from .flexible_body import cholesky_solve, flex_forces_body, flex_mass_body, flex_T
from .inputs import input_value
from .mount_laws import law_force
from .storage import HEADER, view1 as _v1, view2 as _v2, view3 as _v3, view4 as _v4, view5 as _v5

__all__ = ["evaluate", "rhs_function", "rhs_loaded", "PROTOTYPE", "evaluate_many"]

#: ctypes prototype of the compiled right-hand side:
#: (t [s], seg_end [s], y, dy, F, I) → None, arrays by address.
PROTOTYPE = ctypes.CFUNCTYPE(None, ctypes.c_double, ctypes.c_double, ctypes.c_void_p,
                             ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)
_SIGNATURE = types.void(types.float64, types.float64, types.voidptr, types.voidptr,
                        types.voidptr, types.voidptr)


@njit(cache=True, no_cpython_wrapper=True, inline="always")
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


@njit(cache=True, no_cpython_wrapper=True, inline="always")
def _base_inputs(t, seg_end, y, mode, qb, vb, r0_base, support, in_ints, in_sin, in_b, in_o,
                 in_c, base):
    """Section 1: the base's motion and the external load on a free base.

    Parameters
    ----------
    t, seg_end : float
        Time and end of the segment [s] (as for :func:`evaluate`).
    y : (ny,) float64
        State.
    mode : int
        The base's motion: 0 fixed, 1 driven, 2 free.
    qb, vb : int
        Offsets in y of a free base's position and velocity.
    r0_base : (3,) float64
        The base's position in the scene [m].
    support : (3,) float64
        Constant external force on the base [N].
    in_ints, in_sin, in_b, in_o, in_c
        The base's inputs (:data:`flexbed.dynamics.kernel.FIELDS`).
    base : (3, 3) float64
        Written: the base's position [m], velocity [m/s] and, when driven,
        acceleration [m/s²] (zero otherwise; a free base's is set in
        section 6).

    Returns
    -------
    Fx : tuple of 3 float
        External force on a free base [N], inertial: ``support`` plus the
        loads (``support`` alone for other bases).
    """
    for c in range(3):
        base[0, c] = r0_base[c]
        base[1, c] = 0.0
        base[2, c] = 0.0
    Fx0 = support[0]
    Fx1 = support[1]
    Fx2 = support[2]
    if mode == 2:
        for c in range(3):
            base[0, c] = y[qb + c]
            base[1, c] = y[vb + c]
    for i in range(in_ints.shape[0]):
        kind = in_ints[i, 0]
        c = in_ints[i, 1]
        if in_ints[i, 2] == 0:
            if mode == 1:
                for which in range(3):
                    base[2 - which, c] += input_value(kind, in_sin[i], in_b[i], in_o[i], in_c[i],
                                                 which, t, seg_end)
        elif mode == 2 and in_ints[i, 2] == 1:
            # a load's value: which = role − 1 = 0, a number known at run time only
            # (a literal 0 would compile input_value a second time)
            val = input_value(kind, in_sin[i], in_b[i], in_o[i], in_c[i], in_ints[i, 2] - 1, t,
                              seg_end)
            if c == 0:
                Fx0 += val
            elif c == 1:
                Fx1 += val
            else:
                Fx2 += val
    return (Fx0, Fx1, Fx2)


@njit(cache=True, no_cpython_wrapper=True, inline="always")
def _rotations(y, dy, nb, qr, vr, A):
    """Section 2: every body's rotation matrix, ṙ and ṗ.

    Parameters
    ----------
    y : (ny,) float64
        State.
    dy : (ny,) float64
        Written: ṙ [m/s] and ṗ [1/s] of bodies 1 … nb − 1.
    nb : int
        Number of bodies (the base is body 0).
    qr, vr : int
        Offsets in y of the bodies' positions and Euler parameters (7 per
        body) and of their velocities (6 per body: ṙ [m/s] inertial,
        ω̄ [rad/s] body frame).
    A : (nb, 3, 3) float64
        Written: A = Q(p)/|p|² of every body (the identity for the base).
    """
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


@njit(cache=True, no_cpython_wrapper=True, inline="always")
def _mount_ends(y, M, qr, vr, body_i, body_j, S, end_flex, end_phi, fx_ints, base, A, ub, P,
                Pd):
    """Section 3: position and velocity of every mount end (E = 2 M ends,
    the ends on body i first).

    Parameters
    ----------
    y : (ny,) float64
        State.
    M : int
        Number of mounts.
    qr, vr : int
        Offsets in y of the bodies' coordinates and velocities.
    body_i, body_j : (M,) int64
        The bodies of each mount's ends (0: the base).
    S : (E, 3) float64
        The ends in their body's frame, undeformed [m].
    end_flex : (E,) int64
        Flexible body index of the end's body, or −1.
    end_phi : (E, 3, nm) float64
        Mode shapes at the ends [kg^-1/2].
    fx_ints : (nf, 4) int64
        Per flexible body: body, modes n, offsets of a and ȧ in y.
    base : (3, 3) float64
        The base's position [m] and velocity [m/s] (section 1).
    A : (nb, 3, 3) float64
        Rotation matrices (section 2).
    ub, P, Pd : (E, 3) float64
        Written: ū = s̄ (+ Φ a) in the body frame [m], the inertial
        position P [m] and velocity Ṗ [m/s] of each end.
    """
    for e in range(2 * M):
        m = e % M
        b = body_i[m] if e < M else body_j[m]
        k = end_flex[e]
        for c in range(3):
            ub[e, c] = S[e, c]
        if k >= 0:
            n = fx_ints[k, 1]
            oa = fx_ints[k, 2]
            for c in range(3):
                s = 0.0
                for j in range(n):
                    s += end_phi[e, c, j] * y[oa + j]
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
            n = fx_ints[k, 1]
            ov = fx_ints[k, 3]
            for j in range(n):
                rx += end_phi[e, 0, j] * y[ov + j]
                ry += end_phi[e, 1, j] * y[ov + j]
                rz += end_phi[e, 2, j] * y[ov + j]
        Ab = A[b]
        for c in range(3):
            P[e, c] = y[q + c] + Ab[c, 0] * ub[e, 0] + Ab[c, 1] * ub[e, 1] + Ab[c, 2] * ub[e, 2]
            Pd[e, c] = y[v + c] + Ab[c, 0] * rx + Ab[c, 1] * ry + Ab[c, 2] * rz


@njit(cache=True, no_cpython_wrapper=True, inline="always")
def _mount_forces(M, nb, nf, body_i, body_j, U, d0, end_flex, end_phi, fx_ints, law_kind,
                  law_row, lin_kc, poly_k, poly_c, crv_b, crv_o, crv_c, extras, A, P, Pd, ub,
                  w_dx, w_dxd, w_f, w_F, force, torque, w_flexQ):
    """Section 4: every mount's deflections, rates and forces (paper eq.
    2–4), summed into the bodies' forces and moments.

    Parameters
    ----------
    M, nb, nf : int
        Numbers of mounts, bodies and flexible bodies.
    body_i, body_j, U, d0, end_flex, end_phi, fx_ints
        The mounts and flexible bodies (:data:`flexbed.dynamics.kernel.FIELDS`):
        U (M, 3, 3) the directions u_k in body i's frame (rows), d0 (M, 3)
        [m] the unstrained deflections.
    law_kind, law_row, lin_kc, poly_k, poly_c, crv_b, crv_o, crv_c
        The mount laws, one per (mount, direction).
    extras : tuple (stops, w_mx, sums)
        The bump stops, the Maxwell terms and whether to sum the forces
        into the bodies' (False: the mount forces alone, for
        :meth:`System.rhs_batch` ``mounts_only``; ``force``, ``torque`` and
        ``w_flexQ`` then stay zero). One tuple: a call of 30 arguments or
        more is compiled as ``*args``, which numba cannot inline.
    stops : tuple (stop_gap, stop_kc, w_contact, w_hold)
        The bump stops. stop_gap,
        stop_kc (3M or 0, 2): gaps [m] (inf: no stop that side), contact
        stiffness [N/m] and damping [N s/m] (no rows: no stop); past a gap
        (Δx < −g_c or Δx > g_e) the contact force k (Δx ± g) + c Δẋ adds
        to the law's. w_contact (3M or 0,), w_hold (1,): with
        ``w_hold[0] = 1`` the contacts are those of ``w_contact`` (−1, 0,
        +1: held by an integrator between the instants it located,
        :mod:`flexbed.dynamics.contacts`); with 0, decided by Δx.
    w_mx : (3M or 0, 2) float64
        The elastomer mounts' Maxwell terms per row 3 m + k
        (:func:`_maxwell_sums`): ``f += w_mx[row, 0] Δx − w_mx[row, 1]``
        (no rows: no terms).
    A : (nb, 3, 3) float64
        Rotation matrices (section 2).
    P, Pd, ub : (E, 3) float64
        The ends' positions [m], velocities [m/s] and body-frame ū [m]
        (section 3).
    w_dx, w_dxd, w_f : (M, 3) float64
        Written: Δx [m], Δẋ [m/s] and force f [N] per direction.
    w_F : (M, 3) float64
        Written: the inertial force F = A_i Uᵀ f on P_i [N] (−F on P_j).
    force : (nb, 3) float64
        Written: the sum of the mount forces on each body, inertial [N].
    torque : (nb, 3) float64
        Written: their moments about each body's frame origin, body frame
        [N m] (row 0, the base, stays 0).
    w_flexQ : (nf, 6 + nm) float64
        Written: the generalized mount forces on each flexible body, body
        frame (force, moment, modal).

    Returns
    -------
    float
        The power of the mount forces, −Σ f Δẋ [W].
    """
    for b in range(nb):
        for c in range(3):
            force[b, c] = 0.0
            torque[b, c] = 0.0
    for k in range(nf):
        for c in range(w_flexQ.shape[1]):
            w_flexQ[k, c] = 0.0
    p_mount = 0.0
    stops, w_mx, sums = extras
    stop_gap, stop_kc, w_contact, w_hold = stops
    for m in range(M):
        bi = body_i[m]
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
            u0, u1, u2 = U[m, kd, 0], U[m, kd, 1], U[m, kd, 2]
            x = u0 * lb0 + u1 * lb1 + u2 * lb2 - d0[m, kd]
            xd = u0 * vb0 + u1 * vb1 + u2 * vb2
            il = 3 * m + kd
            f = law_force(law_kind[il], law_row[il], lin_kc, poly_k, poly_c, crv_b, crv_o, crv_c,
                     x, xd)
            if stop_gap.shape[0] > 0:
                gc = stop_gap[il, 0]
                ge = stop_gap[il, 1]
                if w_hold[0] > 0.0:
                    s = w_contact[il]
                elif x < -gc:
                    s = -1.0
                elif x > ge:
                    s = 1.0
                else:
                    s = 0.0
                if s < 0.0:
                    f += stop_kc[il, 0] * (x + gc) + stop_kc[il, 1] * xd
                elif s > 0.0:
                    f += stop_kc[il, 0] * (x - ge) + stop_kc[il, 1] * xd
            if w_mx.shape[0] > 0:
                f += w_mx[il, 0] * x - w_mx[il, 1]
            w_dx[m, kd] = x
            w_dxd[m, kd] = xd
            w_f[m, kd] = f
            p_mount -= f * xd
            Fb0 += f * u0
            Fb1 += f * u1
            Fb2 += f * u2
        # inertial force on P_i (and its opposite on P_j)
        F0 = Ai[0, 0] * Fb0 + Ai[0, 1] * Fb1 + Ai[0, 2] * Fb2
        F1 = Ai[1, 0] * Fb0 + Ai[1, 1] * Fb1 + Ai[1, 2] * Fb2
        F2 = Ai[2, 0] * Fb0 + Ai[2, 1] * Fb1 + Ai[2, 2] * Fb2
        w_F[m, 0] = F0
        w_F[m, 1] = F1
        w_F[m, 2] = F2
        if not sums:                    # the mount forces alone (System.rhs_batch)
            continue
        for side in range(2):
            e = m + side * M
            b = bi if side == 0 else body_j[m]
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
            k = end_flex[e]
            if k >= 0:
                Qk = w_flexQ[k]
                Qk[0] += g0
                Qk[1] += g1
                Qk[2] += g2
                Qk[3] += t0
                Qk[4] += t1
                Qk[5] += t2
                for j in range(fx_ints[k, 1]):
                    Qk[6 + j] += (end_phi[e, 0, j] * g0 + end_phi[e, 1, j] * g1
                                  + end_phi[e, 2, j] * g2)
    return p_mount


@njit(cache=True, no_cpython_wrapper=True, inline="always")
def _body_loads(t, seg_end, y, qr, vr, in_ints, in_sin, in_b, in_o, in_c, in_pt, in_phi,
                body_flex, fx_ints, A, force, torque, w_flexQ):
    """Section 4b: the external loads on bodies (role 2 inputs), added to
    the bodies' forces and moments and to the flexible bodies' generalized
    forces as a mount end's force is (:func:`_mount_forces`).

    Parameters
    ----------
    t, seg_end : float
        Time and end of the segment [s].
    y : (ny,) float64
        State.
    qr, vr : int
        Offsets in y of the bodies' coordinates and velocities.
    in_ints, in_sin, in_b, in_o, in_c, in_pt, in_phi
        The inputs (:data:`flexbed.dynamics.kernel.FIELDS`).
    body_flex, fx_ints
        Flexible body index per body; per flexible body its modes and
        their offsets in y.
    A : (nb, 3, 3) float64
        Rotation matrices (section 2).
    force, torque, w_flexQ
        Added to: inertial force [N], body-frame moment about the frame
        origin [N m], body-frame generalized force of a flexible body.

    Returns
    -------
    float
        The power of the loads [W]: F · Ṗ for a force at P, m̄ · ω̄ for a
        moment.
    """
    p_load = 0.0
    for i in range(in_ints.shape[0]):
        if in_ints[i, 2] != 2:
            continue
        # which = role − 2 = 0, known at run time only (see _base_inputs)
        val = input_value(in_ints[i, 0], in_sin[i], in_b[i], in_o[i], in_c[i],
                          in_ints[i, 2] - 2, t, seg_end)
        b = in_ints[i, 3]
        c = in_ints[i, 1]
        Ab = A[b]
        # the load's axis in the body frame
        if in_ints[i, 4] == 1:
            g0 = val if c == 0 else 0.0
            g1 = val if c == 1 else 0.0
            g2 = val if c == 2 else 0.0
        else:
            g0 = Ab[c, 0] * val
            g1 = Ab[c, 1] * val
            g2 = Ab[c, 2] * val
        v = vr + 6 * (b - 1)
        wx, wy, wz = y[v + 3], y[v + 4], y[v + 5]
        if in_ints[i, 5] == 1:              # a moment
            torque[b, 0] += g0
            torque[b, 1] += g1
            torque[b, 2] += g2
            p_load += g0 * wx + g1 * wy + g2 * wz
            continue
        for r in range(3):
            force[b, r] += Ab[r, 0] * g0 + Ab[r, 1] * g1 + Ab[r, 2] * g2
        u0, u1, u2 = in_pt[i, 0], in_pt[i, 1], in_pt[i, 2]
        k = body_flex[b]
        # body-frame velocity of the point relative to the frame's: ω̄ × ū (+ Φ ȧ)
        d0 = 0.0
        d1 = 0.0
        d2 = 0.0
        if k >= 0:
            n = fx_ints[k, 1]
            oa = fx_ints[k, 2]
            ov = fx_ints[k, 3]
            for j in range(n):
                u0 += in_phi[i, 0, j] * y[oa + j]
                u1 += in_phi[i, 1, j] * y[oa + j]
                u2 += in_phi[i, 2, j] * y[oa + j]
                d0 += in_phi[i, 0, j] * y[ov + j]
                d1 += in_phi[i, 1, j] * y[ov + j]
                d2 += in_phi[i, 2, j] * y[ov + j]
        t0 = u1 * g2 - u2 * g1
        t1 = u2 * g0 - u0 * g2
        t2 = u0 * g1 - u1 * g0
        torque[b, 0] += t0
        torque[b, 1] += t1
        torque[b, 2] += t2
        d0 += wy * u2 - wz * u1
        d1 += wz * u0 - wx * u2
        d2 += wx * u1 - wy * u0
        # Aᵀ ṙ: the frame's velocity in the body frame
        rd0, rd1, rd2 = y[v], y[v + 1], y[v + 2]
        d0 += Ab[0, 0] * rd0 + Ab[1, 0] * rd1 + Ab[2, 0] * rd2
        d1 += Ab[0, 1] * rd0 + Ab[1, 1] * rd1 + Ab[2, 1] * rd2
        d2 += Ab[0, 2] * rd0 + Ab[1, 2] * rd1 + Ab[2, 2] * rd2
        p_load += g0 * d0 + g1 * d1 + g2 * d2
        if k >= 0:
            Qk = w_flexQ[k]
            Qk[0] += g0
            Qk[1] += g1
            Qk[2] += g2
            Qk[3] += t0
            Qk[4] += t1
            Qk[5] += t2
            for j in range(fx_ints[k, 1]):
                Qk[6 + j] += in_phi[i, 0, j] * g0 + in_phi[i, 1, j] * g1 + in_phi[i, 2, j] * g2
    return p_load


@njit(cache=True, no_cpython_wrapper=True, inline="always")
def _newton_euler(y, nb, vr, g, mass, J, Jinv, body_flex, force, torque, acc):
    """Section 5, rigid bodies: ``m r̈ = F + m g``, ``J ω̄̇ = n̄ − ω̄ × J ω̄``.

    Parameters
    ----------
    y : (ny,) float64
        State.
    nb : int
        Number of bodies.
    vr : int
        Offset in y of the bodies' velocities.
    g : (3,) float64
        Gravity [m/s²].
    mass : (nb,) float64
        Masses [kg].
    J, Jinv : (nb, 3, 3) float64
        Inertia tensors about the centre of mass, body frame [kg m²], and
        their inverses [1/(kg m²)].
    body_flex : (nb,) int64
        Flexible body index (such bodies are skipped), or −1.
    force, torque : (nb, 3) float64
        The mount forces [N] inertial and moments [N m] body frame
        (section 4).
    acc : (nb, 6) float64
        Written for the rigid bodies 1 …: r̈ [m/s²] inertial, ω̄̇ [rad/s²]
        body frame.
    """
    for b in range(1, nb):
        if body_flex[b] >= 0:
            continue
        v = vr + 6 * (b - 1)
        inv_m = 1.0 / mass[b]
        for c in range(3):
            acc[b, c] = force[b, c] * inv_m + g[c]
        w = y[v + 3:v + 6]
        Jb = J[b]
        Jw0 = Jb[0, 0] * w[0] + Jb[0, 1] * w[1] + Jb[0, 2] * w[2]
        Jw1 = Jb[1, 0] * w[0] + Jb[1, 1] * w[1] + Jb[1, 2] * w[2]
        Jw2 = Jb[2, 0] * w[0] + Jb[2, 1] * w[1] + Jb[2, 2] * w[2]
        n0 = torque[b, 0] - (w[1] * Jw2 - w[2] * Jw1)
        n1 = torque[b, 1] - (w[2] * Jw0 - w[0] * Jw2)
        n2 = torque[b, 2] - (w[0] * Jw1 - w[1] * Jw0)
        Ji = Jinv[b]
        acc[b, 3] = Ji[0, 0] * n0 + Ji[0, 1] * n1 + Ji[0, 2] * n2
        acc[b, 4] = Ji[1, 0] * n0 + Ji[1, 1] * n1 + Ji[1, 2] * n2
        acc[b, 5] = Ji[2, 0] * n0 + Ji[2, 1] * n1 + Ji[2, 2] * n2


@njit(cache=True, no_cpython_wrapper=True, inline="always")
def _floating_frame(y, dy, nf, vr, g, fx_ints, fx_m, fx_I2, fx_I3, fx_I4, fx_I5, fx_I6, fx_K,
                    fx_C, fx_I7, fx_I8, fx_I9, A, w_flexQ, acc, w_M, Q, T, gb):
    """Section 5, flexible bodies: ``M̄(a) [Aᵀ r̈, ω̄̇, ä] = Q̄`` in the body
    frame, M̄ and Q̄ from the modal invariants
    (:func:`.flexible_body.flex_mass_body`,
    :func:`.flexible_body.flex_forces_body`), solved by Cholesky.

    Parameters
    ----------
    y : (ny,) float64
        State.
    dy : (ny,) float64
        Written: ȧ and ä of the flexible bodies.
    nf : int
        Number of flexible bodies.
    vr : int
        Offset in y of the bodies' velocities.
    g : (3,) float64
        Gravity [m/s²].
    fx_ints, fx_m, fx_I2 … fx_I9, fx_K, fx_C
        The flexible bodies' layout, invariants, modal stiffness and
        damping (:data:`flexbed.dynamics.kernel.FIELDS`).
    A : (nb, 3, 3) float64
        Rotation matrices (section 2).
    w_flexQ : (nf, 6 + nm) float64
        The generalized mount forces (section 4).
    acc : (nb, 6) float64
        Written for the flexible bodies: r̈ [m/s²] inertial, ω̄̇ [rad/s²]
        body frame.
    w_M : (nf, 6 + nm, 6 + nm) float64
        Written: each flexible body's M̄(a), then its Cholesky factor.
    Q : (6 + 2 nm,) float64
        Work: Q̄, then C ȧ.
    T : (nm, 3, 3) float64
        Work: T_k = I8_k + Σ_l a_l I9_kl.
    gb : (3,) float64
        Work: Aᵀ g [m/s²].

    Returns
    -------
    float
        The power of the structural damping, −Σ ȧ C ȧ [W].
    """
    p_struct = 0.0
    for k in range(nf):
        b = fx_ints[k, 0]
        n = fx_ints[k, 1]
        Mb = w_M[k]
        oa = fx_ints[k, 2]
        ov = fx_ints[k, 3]
        N = 6 + n
        v = vr + 6 * (b - 1)
        a = y[oa:oa + n]
        ad = y[ov:ov + n]
        Ab = A[b]
        for c in range(3):
            gb[c] = Ab[0, c] * g[0] + Ab[1, c] * g[1] + Ab[2, c] * g[2]
        I3, I8 = fx_I3[k], fx_I8[k]
        flex_T(I8, fx_I9[k], n, a, T)
        flex_mass_body(fx_m[k], fx_I2[k], I3, fx_I4[k], fx_I5[k], fx_I6[k],
                       fx_I7[k], I8, T, n, a, Mb)
        flex_forces_body(fx_m[k], fx_I2[k], I3, fx_I5[k], fx_K[k], fx_C[k], T, n,
                         y[v + 3:v + 6], a, ad, gb, Mb, Q)
        for j in range(n):
            p_struct -= ad[j] * Q[N + j]
        for j in range(N):
            Q[j] += w_flexQ[k, j]
        cholesky_solve(Mb, Q, N)
        for c in range(3):
            acc[b, c] = Ab[c, 0] * Q[0] + Ab[c, 1] * Q[1] + Ab[c, 2] * Q[2]
            acc[b, 3 + c] = Q[3 + c]
        for j in range(n):
            dy[oa + j] = ad[j]
            dy[ov + j] = Q[6 + j]
    return p_struct


@njit(cache=True, no_cpython_wrapper=True, inline="always")
def _rates_and_powers(y, dy, nb, vr, mode, qb, vb, w0, mass, g, force, Fx, base, acc, p_mount,
                      p_struct, p_load):
    """Section 6: the bodies' velocity rates into dy, a free base's
    equations and the powers that feed the energy quadratures.

    The rates are copied here, in a loop of their own, rather than where
    section 5 computes them: dy may alias any array (it comes by address),
    so a write to it inside those loops would make them reload what they
    read (5–10 % slower in all, measured).

    Parameters
    ----------
    y : (ny,) float64
        State.
    dy : (ny,) float64
        Written: the velocity rates of bodies 1 … (from ``acc``); the four
        powers at ``w0`` (mounts, external loads on a free base, the drive
        of a driven base, structural damping) [W]; a free base's ṙ [m/s]
        and r̈ [m/s²].
    nb : int
        Number of bodies.
    vr : int
        Offset in y of the bodies' velocities.
    mode : int
        The base's motion: 0 fixed, 1 driven, 2 free.
    qb, vb, w0 : int
        Offsets in y of a free base's position and velocity, and of the
        work quadratures.
    mass : (nb,) float64
        Masses [kg] (the base's first).
    g : (3,) float64
        Gravity [m/s²].
    force : (nb, 3) float64
        The mount forces on each body, inertial [N] (section 4).
    Fx : tuple of 3 float
        External force on a free base [N] (section 1).
    base : (3, 3) float64
        The base's r, ṙ, r̈; a free base's r̈ written here.
    acc : (nb, 6) float64
        The bodies' r̈ [m/s²] inertial and ω̄̇ [rad/s²] body frame
        (section 5); row 0 written: the base's r̈ [m/s²].
    p_mount, p_struct : float
        The powers of the mounts (section 4) and of the structural damping
        (section 5) [W].
    p_load : float
        The power of the loads on bodies (section 4b) [W], counted with the
        external loads' work.
    """
    for b in range(1, nb):
        v = vr + 6 * (b - 1)
        for c in range(6):
            dy[v + c] = acc[b, c]
    dy[w0] = p_mount
    dy[w0 + 1] = p_load
    dy[w0 + 2] = 0.0
    dy[w0 + 3] = p_struct
    if mode == 2:
        inv_mb = 1.0 / mass[0]
        for c in range(3):
            dy[qb + c] = y[vb + c]
            ab = (force[0, c] + Fx[c]) * inv_mb + g[c]
            dy[vb + c] = ab
            base[2, c] = ab
            dy[w0 + 1] += Fx[c] * y[vb + c]
    elif mode == 1:
        for c in range(3):
            Fd = mass[0] * (base[2, c] - g[c]) - force[0, c]
            dy[w0 + 2] += Fd * base[1, c]
    for c in range(3):
        acc[0, c] = base[2, c]


@njit(cache=True, no_cpython_wrapper=True, inline="always")
def _maxwell_sums(y, mx_ints, mx_k, w_relax, w_mx):
    """Section 4a: per mount row 3 m + k, the Maxwell terms' Σ k_i [N/m] and
    Σ k_i z_i [N] into ``w_mx`` (3M or 0, 2), so that section 4 adds
    Σ k_i (Δx − z_i) to the row's force; zero while ``w_relax[0] = 1``.

    Parameters
    ----------
    y : (ny,) float64
        State.
    mx_ints : (nt, 2) int64
        Per term: its row 3 m + k and the offset of its state z_i in y.
    mx_k : (nt, 2) float64
        Per term: k_i [N/m] and 1/τ_i [1/s].
    w_relax : (1,) float64
        1: the terms relaxed (statics: no force).
    w_mx : (3M or 0, 2) float64
        Written.
    """
    for r in range(w_mx.shape[0]):
        w_mx[r, 0] = 0.0
        w_mx[r, 1] = 0.0
    if w_relax[0] != 0.0:
        return
    for j in range(mx_ints.shape[0]):
        r = mx_ints[j, 0]
        w_mx[r, 0] += mx_k[j, 0]
        w_mx[r, 1] += mx_k[j, 0] * y[mx_ints[j, 1]]


@njit(cache=True, no_cpython_wrapper=True, inline="always")
def _maxwell_rates(dy, y, mx_ints, mx_k, w_relax, w_dx):
    """Section 7: the Maxwell terms' rates ż_i = (Δx − z_i)/τ_i into dy
    (0 while ``w_relax[0] = 1``), from the deflections of section 4
    (``w_dx`` (M, 3) [m]); ``mx_ints``, ``mx_k`` as for :func:`_mount_forces`."""
    for j in range(mx_ints.shape[0]):
        row = mx_ints[j, 0]
        o = mx_ints[j, 1]
        if w_relax[0] == 0.0:
            dy[o] = (w_dx[row // 3, row % 3] - y[o]) * mx_k[j, 1]
        else:
            dy[o] = 0.0


def evaluate(t, seg_end, y_ptr, dy_ptr, F_ptr, I_ptr):
    """dy/dt for the state y at time t, on the packed storage (F, I).

    Compiled once as the C function of :func:`rhs_function`; every array
    comes by address.

    Parameters
    ----------
    t : float
        Time [s].
    seg_end : float
        End of the segment being integrated (inputs give their left limits
        at and beyond it); ``inf`` for right-continuous inputs.
    y_ptr : address of (ny,) float64
        State (:mod:`flexbed.dynamics.layout`); ny is in I's header.
    dy_ptr : address of (ny,) float64
        Output, overwritten in full.
    F_ptr, I_ptr : addresses of the float64 and int64 storage
        The scene (:func:`.storage.pack`); the work arrays in F are written.
    """
    head = carray(I_ptr, HEADER, np.int64)
    y = carray(y_ptr, head[0], np.float64)
    dy = carray(dy_ptr, head[0], np.float64)
    meta = carray(I_ptr, (HEADER + 6 * head[3],), np.int64)[HEADER:].reshape((head[3], 6))
    # the views of every field of FIELDS, in its order (checked by a test)
    ints = _v1(I_ptr, meta[0], np.int64)
    gravity = _v1(F_ptr, meta[1], np.float64)
    mass = _v1(F_ptr, meta[2], np.float64)
    J = _v3(F_ptr, meta[3], np.float64)
    Jinv = _v3(F_ptr, meta[4], np.float64)
    body_flex = _v1(I_ptr, meta[5], np.int64)
    r0_base = _v1(F_ptr, meta[6], np.float64)
    support = _v1(F_ptr, meta[7], np.float64)
    body_i = _v1(I_ptr, meta[8], np.int64)
    body_j = _v1(I_ptr, meta[9], np.int64)
    S = _v2(F_ptr, meta[10], np.float64)
    U = _v3(F_ptr, meta[11], np.float64)
    d0 = _v2(F_ptr, meta[12], np.float64)
    end_flex = _v1(I_ptr, meta[13], np.int64)
    end_phi = _v3(F_ptr, meta[14], np.float64)
    law_kind = _v1(I_ptr, meta[15], np.int64)
    law_row = _v1(I_ptr, meta[16], np.int64)
    lin_kc = _v2(F_ptr, meta[17], np.float64)
    poly_k = _v2(F_ptr, meta[18], np.float64)
    poly_c = _v2(F_ptr, meta[19], np.float64)
    crv_b = _v3(F_ptr, meta[20], np.float64)
    crv_o = _v3(F_ptr, meta[21], np.float64)
    crv_c = _v4(F_ptr, meta[22], np.float64)
    fx_ints = _v2(I_ptr, meta[23], np.int64)
    fx_m = _v1(F_ptr, meta[24], np.float64)
    fx_I2 = _v2(F_ptr, meta[25], np.float64)
    fx_I3 = _v3(F_ptr, meta[26], np.float64)
    fx_I4 = _v3(F_ptr, meta[27], np.float64)
    fx_I5 = _v4(F_ptr, meta[28], np.float64)
    fx_I6 = _v3(F_ptr, meta[29], np.float64)
    fx_K = _v3(F_ptr, meta[30], np.float64)
    fx_C = _v3(F_ptr, meta[31], np.float64)
    fx_I7 = _v3(F_ptr, meta[32], np.float64)
    fx_I8 = _v4(F_ptr, meta[33], np.float64)
    fx_I9 = _v5(F_ptr, meta[34], np.float64)
    in_ints = _v2(I_ptr, meta[35], np.int64)
    in_sin = _v2(F_ptr, meta[36], np.float64)
    in_b = _v3(F_ptr, meta[37], np.float64)
    in_o = _v3(F_ptr, meta[38], np.float64)
    in_c = _v4(F_ptr, meta[39], np.float64)
    w_A = _v3(F_ptr, meta[40], np.float64)
    w_P = _v2(F_ptr, meta[41], np.float64)
    w_Pd = _v2(F_ptr, meta[42], np.float64)
    w_ub = _v2(F_ptr, meta[43], np.float64)
    w_dx = _v2(F_ptr, meta[44], np.float64)
    w_dxd = _v2(F_ptr, meta[45], np.float64)
    w_f = _v2(F_ptr, meta[46], np.float64)
    w_F = _v2(F_ptr, meta[47], np.float64)
    w_force = _v2(F_ptr, meta[48], np.float64)
    w_torque = _v2(F_ptr, meta[49], np.float64)
    w_flexQ = _v2(F_ptr, meta[50], np.float64)
    w_acc = _v2(F_ptr, meta[51], np.float64)
    w_base = _v2(F_ptr, meta[52], np.float64)
    w_M = _v3(F_ptr, meta[53], np.float64)
    w_Q = _v1(F_ptr, meta[54], np.float64)
    w_T = _v3(F_ptr, meta[55], np.float64)
    w_gb = _v1(F_ptr, meta[56], np.float64)
    stop_gap = _v2(F_ptr, meta[57], np.float64)
    stop_kc = _v2(F_ptr, meta[58], np.float64)
    w_contact = _v1(F_ptr, meta[59], np.float64)
    w_hold = _v1(F_ptr, meta[60], np.float64)
    in_pt = _v2(F_ptr, meta[61], np.float64)
    in_phi = _v3(F_ptr, meta[62], np.float64)
    mx_ints = _v2(I_ptr, meta[63], np.int64)
    mx_k = _v2(F_ptr, meta[64], np.float64)
    w_relax = _v1(F_ptr, meta[65], np.float64)
    w_mx = _v2(F_ptr, meta[66], np.float64)
    nb, M, nf, mode = ints[0], ints[1], ints[2], ints[3]
    qr, vr, qb, vb, w0 = ints[4], ints[5], ints[6], ints[7], ints[8]
    # the six sections of flexbed.dynamics.kernel, in order
    Fx = _base_inputs(t, seg_end, y, mode, qb, vb, r0_base, support, in_ints, in_sin, in_b, in_o,
                      in_c, w_base)                                            # 1.
    _rotations(y, dy, nb, qr, vr, w_A)                                         # 2.
    _mount_ends(y, M, qr, vr, body_i, body_j, S, end_flex, end_phi, fx_ints, w_base, w_A, w_ub,
                w_P, w_Pd)                                                     # 3.
    _maxwell_sums(y, mx_ints, mx_k, w_relax, w_mx)                             # 4a.
    p_mount = _mount_forces(M, nb, nf, body_i, body_j, U, d0, end_flex, end_phi, fx_ints,
                            law_kind, law_row, lin_kc, poly_k, poly_c, crv_b, crv_o, crv_c,
                            ((stop_gap, stop_kc, w_contact, w_hold), w_mx, ints[11] == 0),
                            w_A, w_P, w_Pd, w_ub, w_dx, w_dxd, w_f, w_F, w_force, w_torque,
                            w_flexQ)                                           # 4.
    if ints[11] == 1:                       # the mount forces alone (System.rhs_batch)
        return
    p_load = _body_loads(t, seg_end, y, qr, vr, in_ints, in_sin, in_b, in_o, in_c, in_pt,
                         in_phi, body_flex, fx_ints, w_A, w_force, w_torque, w_flexQ)  # 4b.
    _newton_euler(y, nb, vr, gravity, mass, J, Jinv, body_flex, w_force, w_torque, w_acc)  # 5.
    p_struct = _floating_frame(y, dy, nf, vr, gravity, fx_ints, fx_m, fx_I2, fx_I3, fx_I4, fx_I5,
                               fx_I6, fx_K, fx_C, fx_I7, fx_I8, fx_I9, w_A, w_flexQ, w_acc, w_M,
                               w_Q, w_T, w_gb)
    _rates_and_powers(y, dy, nb, vr, mode, qb, vb, w0, mass, gravity, w_force, Fx, w_base, w_acc,
                      p_mount, p_struct, p_load)                               # 6.
    _maxwell_rates(dy, y, mx_ints, mx_k, w_relax, w_dx)                        # 7.

_compiled = []


def rhs_function():
    """The compiled right-hand side as a ctypes function of :data:`PROTOTYPE`.

    Compiled (or loaded from numba's cache) at the first call in a process.
    Pass it to compiled code as an argument, not as a global: the address
    of a global would be frozen into the machine code, which then could not
    be cached.
    """
    if not _compiled:
        c = cfunc(_SIGNATURE, cache=True, error_model="numpy")(evaluate)
        _compiled.append((c, PROTOTYPE(c.address)))
    return _compiled[0][1]


def rhs_loaded() -> bool:
    """Whether this process holds the compiled right-hand side already
    (:func:`rhs_function` was called)."""
    return bool(_compiled)


@njit(cache=True)
def evaluate_many(n, t, seg_end, y, dy, kernel):
    """n calls of the compiled right-hand side from compiled code, as the
    steppers call it (the kernel's own cost, for the benchmark); kernel =
    (:func:`rhs_function`, F, I)."""
    fn, F, I = kernel
    for _ in range(n):
        fn(t, seg_end, y.ctypes, dy.ctypes, F.ctypes, I.ctypes)
