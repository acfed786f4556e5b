"""The right-hand side of the equations of motion, compiled (numba).

:func:`evaluate` is the one implementation of the physics of a scene at a
time t and state y (layout: :mod:`dynamics.layout`). It reads a scene
compiled into flat arrays (:class:`Compiled`, built by
:class:`dynamics.system.System`) and does arithmetic only, in this order:

1. the base: prescribed position, velocity and acceleration from the
   drives (their exact integrals), or the state of a free base and its
   external loads (piecewise polynomials or windowed sinusoids);
2. every body: ``A = Q(p)/|p|²`` (so a slightly non-unit p still gives a
   rotation) and ``ṗ = ½ p ⊗ (0, ω̄)``;
3. every mount end e on body b at body-frame point ū_e = s̄_e (+ Φ_e a on a
   flexible body): ``P = r + A ū``, ``Ṗ = ṙ + A (ω̄ × ū + Φ_e ȧ)``;
4. every mount (paper eq. 2–4): ``l = P_j − P_i``, ``Δx = U (A_iᵀ l) − d0``,
   ``Δẋ = U (A_iᵀ l̇)``, forces f from the mount's laws, ``F = A_i Uᵀ f`` on
   P_i and ``−F`` on P_j;
5. Newton–Euler per rigid body (``m r̈ = F + m g``,
   ``J ω̄̇ = n̄ − ω̄ × J ω̄``) and, per flexible body, the floating-frame
   equations in the body frame ``M̄(a) [Aᵀ r̈, ω̄̇, ä] = Q̄`` from the modal
   invariants (:func:`flex_mass_body`, :func:`flex_forces_body`; the
   formulas are in :mod:`dynamics.flexible`), solved by Cholesky;
6. the powers that feed the energy quadratures.

Everything per call writes into arrays of :class:`Compiled` (the ``w_*``
work arrays), so a call allocates nothing; ``w_dx``, ``w_dxd``, ``w_f``,
``w_F``, ``w_acc`` and ``w_base`` keep the last call's mount deflections,
rates, forces, inertial mount forces, accelerations and base motion for
:meth:`dynamics.system.System.observe`.

Inputs (drives and loads of the base), one row each: ``in_kind`` 0 for a
piecewise polynomial (value, first and second integral as three tables of
breaks, origins and ascending coefficients, padded with +inf breaks and
zero rows), 1 for a windowed sinusoid (``in_sin`` = amplitude, ω, phase,
start, end). At t ≥ ``seg_end`` an input gives its limit from the left
(from inside the segment an integrator is stepping through); elsewhere it
is right-continuous. ``seg_end = inf`` means right-continuous everywhere.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

__all__ = ["Compiled", "FIELDS", "KINDS", "pack", "unpack", "evaluate", "evaluate_packed", "evaluate_many", "flex_T", "flex_mass_body", "flex_forces_body",
           "piecewise_value"]

#: Fields of :class:`Compiled` (all NumPy arrays; shapes with nb bodies,
#: n = nb − 1 moving bodies, M mounts, E = 2M ends, nf flexible bodies of
#: at most nm modes, ni inputs; see System._compile for every entry).
FIELDS = (
    # sizes and layout: [nb, M, nf, base_mode (0 fixed, 1 driven, 2 free), qr, vr, qb, vb,
    #                    w0, qm, vm]
    "ints",
    "gravity",          # (3,) [m/s²]
    "mass",             # (nb,) [kg]
    "J", "Jinv",        # (nb, 3, 3) [kg m², 1/(kg m²)] (row 0 unused)
    "body_flex",        # (nb,) int: flexible body index, or -1
    "r0_base",          # (3,) [m]
    "support",          # (3,) [N]
    # mounts
    "body_i", "body_j",  # (M,) int
    "S",                # (E, 3) [m] ends in their body's frame, i ends first
    "U",                # (M, 3, 3) rows u_k in body i's frame
    "d0",               # (M, 3) [m] U (A_iᵀ l0)
    "end_flex",         # (E,) int: flexible body index of the end's body, or -1
    "end_phi",          # (E, 3, nm) mode shapes at the ends [kg^-1/2]
    # laws, one per (mount, direction) = 3 M entries
    "law_kind",         # (3M,) int: 0 linear, 1 polynomial, 2 curve
    "law_row",          # (3M,) int: row in the kind's table
    "lin_kc",           # (·, 2) k [N/m], c [N s/m]
    "poly_k", "poly_c",  # (·, 9) ascending coefficients
    "crv_b", "crv_o", "crv_c",   # (·, 2, nbk), (·, 2, nbk + 1), (·, 2, nbk + 1, 4) spring, damper
    # flexible bodies
    "fx_ints",          # (nf, 4): body, n modes, offset of a in y, offset of ȧ in y
    "fx_m",             # (nf,) [kg]
    "fx_I2",            # (nf, 3)
    "fx_I3", "fx_I4",   # (nf, 3, nm)
    "fx_I5",            # (nf, nm, 3, nm)
    "fx_I6", "fx_K", "fx_C",   # (nf, nm, nm)
    "fx_I7",            # (nf, 3, 3)
    "fx_I8",            # (nf, nm, 3, 3)
    "fx_I9",            # (nf, nm, nm, 3, 3)
    # inputs of the base
    "in_ints",          # (ni, 3): kind, direction, role (0 drive, 1 load)
    "in_sin",           # (ni, 5): amplitude, ω [rad/s], phase [rad], start, end [s]
    "in_b",             # (ni, 3, nbi) breaks of value, first, second integral (+inf padded)
    "in_o",             # (ni, 3, nbi + 1) origins
    "in_c",             # (ni, 3, nbi + 1, dmax + 1) ascending coefficients
    # work arrays
    "w_A",              # (nb, 3, 3)
    "w_P", "w_Pd",      # (E, 3) end positions, velocities [m, m/s]
    "w_ub",             # (E, 3) ū of each end in its body frame [m]
    "w_dx", "w_dxd", "w_f",    # (M, 3) [m, m/s, N]
    "w_F",              # (M, 3) [N] inertial force on P_i
    "w_force", "w_torque",     # (nb, 3) [N] inertial; [N m] body frame (rigid bodies)
    "w_flexQ",          # (nf, 6 + nm) body-frame generalized mount forces
    "w_acc",            # (nb, 6): r̈ [m/s²] inertial, ω̄̇ [rad/s²] body frame
    "w_base",           # (3, 3): base r, ṙ, r̈
    "w_M",              # (6 + nm, 6 + nm)
    "w_Q",              # (6 + nm + nm,) Q̄ then C ȧ
    "w_T",              # (nm, 3, 3) T_k = I8_k + Σ_l a_l I9_kl
    "w_gb",             # (3,) Aᵀ g
)

Compiled = namedtuple("Compiled", FIELDS)

#: Storage of each field: 'f' float64 or 'i' int64, and its number of dimensions.
KINDS = {
    "ints": ("i", 1), "gravity": ("f", 1), "mass": ("f", 1), "J": ("f", 3), "Jinv": ("f", 3),
    "body_flex": ("i", 1), "r0_base": ("f", 1), "support": ("f", 1), "body_i": ("i", 1),
    "body_j": ("i", 1), "S": ("f", 2), "U": ("f", 3), "d0": ("f", 2), "end_flex": ("i", 1),
    "end_phi": ("f", 3), "law_kind": ("i", 1), "law_row": ("i", 1), "lin_kc": ("f", 2),
    "poly_k": ("f", 2), "poly_c": ("f", 2), "crv_b": ("f", 3), "crv_o": ("f", 3),
    "crv_c": ("f", 4), "fx_ints": ("i", 2), "fx_m": ("f", 1), "fx_I2": ("f", 2),
    "fx_I3": ("f", 3), "fx_I4": ("f", 3), "fx_I5": ("f", 4), "fx_I6": ("f", 3),
    "fx_K": ("f", 3), "fx_C": ("f", 3), "fx_I7": ("f", 3), "fx_I8": ("f", 4), "fx_I9": ("f", 5),
    "in_ints": ("i", 2), "in_sin": ("f", 2), "in_b": ("f", 3), "in_o": ("f", 3),
    "in_c": ("f", 4), "w_A": ("f", 3), "w_P": ("f", 2), "w_Pd": ("f", 2), "w_ub": ("f", 2),
    "w_dx": ("f", 2), "w_dxd": ("f", 2), "w_f": ("f", 2), "w_F": ("f", 2), "w_force": ("f", 2),
    "w_torque": ("f", 2), "w_flexQ": ("f", 2), "w_acc": ("f", 2), "w_base": ("f", 2),
    "w_M": ("f", 2), "w_Q": ("f", 1), "w_T": ("f", 3), "w_gb": ("f", 1),
}


# ------------------------------------------------------------- small pieces
@njit(cache=True)
def piecewise_value(breaks, origins, coeffs, x, seg_end):
    """A piecewise polynomial at x (see :mod:`dynamics.piecewise`).

    breaks (nb,) increasing, +inf padded; origins (nb + 1,); coeffs
    (nb + 1, d + 1) ascending. Right-continuous, except at x ≥ seg_end: the
    piece to the left.
    """
    lo = 0
    hi = breaks.shape[0]
    if x >= seg_end:                  # count of breaks < x
        while lo < hi:
            mid = (lo + hi) // 2
            if breaks[mid] < x:
                lo = mid + 1
            else:
                hi = mid
    else:                             # count of breaks <= x
        while lo < hi:
            mid = (lo + hi) // 2
            if breaks[mid] <= x:
                lo = mid + 1
            else:
                hi = mid
    u = x - origins[lo]
    d = coeffs.shape[1]
    acc = 0.0
    for j in range(d - 1, -1, -1):
        acc = acc * u + coeffs[lo, j]
    return acc


@njit(cache=True)
def _sinusoid(p, which, t, seg_end):
    """Windowed sinusoid a(t) = A sin(ω (t − s) + φ) on [s, e): value (0),
    first (1) or second (2) integral from s."""
    A, w, ph, s, e = p[0], p[1], p[2], p[3], p[4]
    cph, sph = math.cos(ph), math.sin(ph)
    if which == 0:
        if t >= seg_end:
            inside = s < t <= e
        else:
            inside = s <= t < e
        return A * math.sin(w * (t - s) + ph) if inside else 0.0
    if t <= s:
        return 0.0
    u = min(t, e) - s
    v = A / w * (cph - math.cos(w * u + ph))
    if which == 1:
        return v
    dist = A / w * cph * u - A / (w * w) * (math.sin(w * u + ph) - sph)
    if t > e:
        dist += v * (t - e)
    return dist


@njit(cache=True)
def _input(kind, sin, b, o, c, which, t, seg_end):
    """Input value (which = 0), first (1) or second (2) integral at t; one
    row of the ``in_*`` arrays."""
    if kind == 1:
        return _sinusoid(sin, which, t, seg_end)
    return piecewise_value(b[which], o[which], c[which], t, seg_end)


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
def _horner(c, x):
    acc = 0.0
    for j in range(c.shape[0] - 1, -1, -1):
        acc = acc * x + c[j]
    return acc


@njit(cache=True)
def _law(kind, row, lin_kc, poly_k, poly_c, crv_b, crv_o, crv_c, x, v):
    """Force [N] of a law (``kind``, its ``row`` in that kind's table) at
    Δx [m], Δẋ [m/s]."""
    if kind == 0:
        return lin_kc[row, 0] * x + lin_kc[row, 1] * v
    if kind == 1:
        return _horner(poly_k[row], x) + _horner(poly_c[row], v)
    inf = np.inf
    return (piecewise_value(crv_b[row, 0], crv_o[row, 0], crv_c[row, 0], x, inf)
            + piecewise_value(crv_b[row, 1], crv_o[row, 1], crv_c[row, 1], v, inf))


@njit(cache=True)
def _cholesky_solve(M, b, n):
    """Solve M x = b in place (x in b) for the leading n × n block of a
    symmetric positive definite M, overwritten by its Cholesky factor."""
    for j in range(n):
        s = M[j, j]
        for k in range(j):
            s -= M[j, k] * M[j, k]
        ljj = math.sqrt(s)
        M[j, j] = ljj
        for i in range(j + 1, n):
            s = M[i, j]
            for k in range(j):
                s -= M[i, k] * M[j, k]
            M[i, j] = s / ljj
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= M[i, k] * b[k]
        b[i] = s / M[i, i]
    for i in range(n - 1, -1, -1):
        s = b[i]
        for k in range(i + 1, n):
            s -= M[k, i] * b[k]
        b[i] = s / M[i, i]


# ---------------------------------------------------------- flexible bodies
@njit(cache=True)
def flex_T(I8, I9, n, a, T):
    """T_k = I8_k + Σ_l a_l I9_kl into T[:n] (n, 3, 3); I8 (≥n, 3, 3),
    I9 (≥n, ≥n, 3, 3), a (n,) [kg^1/2 m]."""
    for k in range(n):
        for i in range(3):
            for j in range(3):
                s = I8[k, i, j]
                for l in range(n):
                    s += a[l] * I9[k, l, i, j]
                T[k, i, j] = s


@njit(cache=True)
def flex_mass_body(m, I2, I3, I4, I5, I6, I7, I8, T, n, a, M):
    """Body-frame mass matrix M̄(a) of a flexible body into M[:6+n, :6+n].

    M̄ = [[m I, −S̃, I3], [S̃, J(a), C(a)], [I3ᵀ, C(a)ᵀ, I6]] with
    S = I2 + I3 a, J(a) = I7 + Σ a_k (I8_k + I8_kᵀ) + Σ a_k a_l I9_kl
    = I7 + Σ a_k (T_k + I8_kᵀ), C(a) = I4 + Σ a_k I5[k] (the invariants of
    :mod:`dynamics.flexible`, padded arrays of at least n modes; T from
    :func:`flex_T` at this a). m [kg]; a (n,); M (≥ 6+n, ≥ 6+n).
    """
    N = 6 + n
    for i in range(N):
        for j in range(N):
            M[i, j] = 0.0
    S0 = I2[0]
    S1 = I2[1]
    S2 = I2[2]
    for q in range(n):
        S0 += I3[0, q] * a[q]
        S1 += I3[1, q] * a[q]
        S2 += I3[2, q] * a[q]
    for i in range(3):
        M[i, i] = m
    # -S̃ (rows 0-2, cols 3-5) and S̃ = (−S̃)ᵀ (rows 3-5, cols 0-2)
    M[0, 4] = S2
    M[0, 5] = -S1
    M[1, 3] = -S2
    M[1, 5] = S0
    M[2, 3] = S1
    M[2, 4] = -S0
    for i in range(3):
        for j in range(3):
            M[3 + j, i] = M[i, 3 + j]
            s = I7[i, j]
            for q in range(n):
                s += a[q] * (T[q, i, j] + I8[q, j, i])
            M[3 + i, 3 + j] = s
    for i in range(3):
        for l in range(n):
            M[i, 6 + l] = I3[i, l]
            M[6 + l, i] = I3[i, l]
            s = I4[i, l]
            for q in range(n):
                s += a[q] * I5[q, i, l]
            M[3 + i, 6 + l] = s
            M[6 + l, 3 + i] = s
    for i in range(n):
        for j in range(n):
            M[6 + i, 6 + j] = I6[i, j]


@njit(cache=True)
def flex_forces_body(m, I2, I3, I5, K, C, T, n, w, a, ad, gb, M, Q):
    """Body-frame forces of a flexible body: Q[:6+n] = Q̄_v + Q̄_g + Q̄_e,
    Q[6+n:6+2n] = C ȧ (the structural damping forces).

    w (3,) ω̄ [rad/s]; a, ad (n,); gb (3,) Aᵀ g [m/s²]; T from
    :func:`flex_T` and M from :func:`flex_mass_body` at this a (its J(a)
    block is used).

    Q̄_r = −ω̄ × (ω̄ × S) − 2 ω̄ × (I3 ȧ) + m Aᵀg;
    Q̄_ω = −ω̄ × J ω̄ − 2 (Σ_k ȧ_k T_k) ω̄ + S × Aᵀg;
    Q̄_a[k] = ω̄ᵀ T_k ω̄ + 2 ω̄ᵀ I5[k] ȧ + I3ᵀ Aᵀg − K a − C ȧ.
    """
    S0 = I2[0]
    S1 = I2[1]
    S2 = I2[2]
    Ia0 = 0.0
    Ia1 = 0.0
    Ia2 = 0.0
    for q in range(n):
        S0 += I3[0, q] * a[q]
        S1 += I3[1, q] * a[q]
        S2 += I3[2, q] * a[q]
        Ia0 += I3[0, q] * ad[q]
        Ia1 += I3[1, q] * ad[q]
        Ia2 += I3[2, q] * ad[q]
    w0, w1, w2 = w[0], w[1], w[2]
    c0 = w1 * S2 - w2 * S1                     # ω × S
    c1 = w2 * S0 - w0 * S2
    c2 = w0 * S1 - w1 * S0
    Q[0] = -(w1 * c2 - w2 * c1) - 2.0 * (w1 * Ia2 - w2 * Ia1) + m * gb[0]
    Q[1] = -(w2 * c0 - w0 * c2) - 2.0 * (w2 * Ia0 - w0 * Ia2) + m * gb[1]
    Q[2] = -(w0 * c1 - w1 * c0) - 2.0 * (w0 * Ia1 - w1 * Ia0) + m * gb[2]
    Jw0 = M[3, 3] * w0 + M[3, 4] * w1 + M[3, 5] * w2
    Jw1 = M[4, 3] * w0 + M[4, 4] * w1 + M[4, 5] * w2
    Jw2 = M[5, 3] * w0 + M[5, 4] * w1 + M[5, 5] * w2
    Q[3] = -(w1 * Jw2 - w2 * Jw1) + (S1 * gb[2] - S2 * gb[1])
    Q[4] = -(w2 * Jw0 - w0 * Jw2) + (S2 * gb[0] - S0 * gb[2])
    Q[5] = -(w0 * Jw1 - w1 * Jw0) + (S0 * gb[1] - S1 * gb[0])
    for q in range(n):
        Tq = T[q]
        tw0 = Tq[0, 0] * w0 + Tq[0, 1] * w1 + Tq[0, 2] * w2
        tw1 = Tq[1, 0] * w0 + Tq[1, 1] * w1 + Tq[1, 2] * w2
        tw2 = Tq[2, 0] * w0 + Tq[2, 1] * w1 + Tq[2, 2] * w2
        Q[3] -= 2.0 * ad[q] * tw0
        Q[4] -= 2.0 * ad[q] * tw1
        Q[5] -= 2.0 * ad[q] * tw2
        s = w0 * tw0 + w1 * tw1 + w2 * tw2
        s += I3[0, q] * gb[0] + I3[1, q] * gb[1] + I3[2, q] * gb[2]
        cad = 0.0
        for l in range(n):
            s += 2.0 * (w0 * I5[q, 0, l] + w1 * I5[q, 1, l] + w2 * I5[q, 2, l]) * ad[l]
            s -= K[q, l] * a[l]
            cad += C[q, l] * ad[l]
        Q[6 + q] = s - cad
        Q[6 + n + q] = cad


# ------------------------------------------------------------------ physics
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
                    base[2 - which, c] += _input(kind, in_sin[i], in_b[i], in_o[i], in_c[i],
                                                 which, t, seg_end)
        elif mode == 2:
            val = _input(kind, in_sin[i], in_b[i], in_o[i], in_c[i], 0, t, seg_end)
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
            f = _law(law_kind[il], law_row[il], lin_kc, poly_k, poly_c, crv_b, crv_o, crv_c,
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
        _cholesky_solve(Mb, Q, N)
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
def _v1(a, meta, k):
    o = meta[k, 0]
    return a[o:o + meta[k, 1]]


@njit(cache=True)
def _v2(a, meta, k):
    o = meta[k, 0]
    return a[o:o + meta[k, 1] * meta[k, 2]].reshape((meta[k, 1], meta[k, 2]))


@njit(cache=True)
def _v3(a, meta, k):
    o = meta[k, 0]
    s = (meta[k, 1], meta[k, 2], meta[k, 3])
    return a[o:o + s[0] * s[1] * s[2]].reshape(s)


@njit(cache=True)
def _v4(a, meta, k):
    o = meta[k, 0]
    s = (meta[k, 1], meta[k, 2], meta[k, 3], meta[k, 4])
    return a[o:o + s[0] * s[1] * s[2] * s[3]].reshape(s)


@njit(cache=True)
def _v5(a, meta, k):
    o = meta[k, 0]
    s = (meta[k, 1], meta[k, 2], meta[k, 3], meta[k, 4], meta[k, 5])
    return a[o:o + s[0] * s[1] * s[2] * s[3] * s[4]].reshape(s)


@njit(cache=True)
def unpack(F, I, meta):
    """The :class:`Compiled` views of the packed storage (see :func:`pack`)."""
    return Compiled(
        _v1(I, meta, 0),
        _v1(F, meta, 1),
        _v1(F, meta, 2),
        _v3(F, meta, 3),
        _v3(F, meta, 4),
        _v1(I, meta, 5),
        _v1(F, meta, 6),
        _v1(F, meta, 7),
        _v1(I, meta, 8),
        _v1(I, meta, 9),
        _v2(F, meta, 10),
        _v3(F, meta, 11),
        _v2(F, meta, 12),
        _v1(I, meta, 13),
        _v3(F, meta, 14),
        _v1(I, meta, 15),
        _v1(I, meta, 16),
        _v2(F, meta, 17),
        _v2(F, meta, 18),
        _v2(F, meta, 19),
        _v3(F, meta, 20),
        _v3(F, meta, 21),
        _v4(F, meta, 22),
        _v2(I, meta, 23),
        _v1(F, meta, 24),
        _v2(F, meta, 25),
        _v3(F, meta, 26),
        _v3(F, meta, 27),
        _v4(F, meta, 28),
        _v3(F, meta, 29),
        _v3(F, meta, 30),
        _v3(F, meta, 31),
        _v3(F, meta, 32),
        _v4(F, meta, 33),
        _v5(F, meta, 34),
        _v2(I, meta, 35),
        _v2(F, meta, 36),
        _v3(F, meta, 37),
        _v3(F, meta, 38),
        _v4(F, meta, 39),
        _v3(F, meta, 40),
        _v2(F, meta, 41),
        _v2(F, meta, 42),
        _v2(F, meta, 43),
        _v2(F, meta, 44),
        _v2(F, meta, 45),
        _v2(F, meta, 46),
        _v2(F, meta, 47),
        _v2(F, meta, 48),
        _v2(F, meta, 49),
        _v2(F, meta, 50),
        _v2(F, meta, 51),
        _v2(F, meta, 52),
        _v2(F, meta, 53),
        _v1(F, meta, 54),
        _v3(F, meta, 55),
        _v1(F, meta, 56))


def pack(fields: dict):
    """Pack a scene's arrays into one float64 and one int64 array.

    Calling compiled code with two arrays costs a microsecond; with the
    ~60 arrays of :class:`Compiled` it costs tens. The kernel's entry point
    from Python, :func:`evaluate_packed`, rebuilds the views inside
    compiled code.

    Parameters
    ----------
    fields : dict
        Every name of :data:`FIELDS` → array (any shape of the declared
        number of dimensions, :data:`KINDS`).

    Returns
    -------
    packed : tuple (F, I, meta)
        F (·,) float64, I (·,) int64 storage; meta (len(FIELDS), 6) int64:
        offset, then the shape padded with 1.
    views : Compiled
        NumPy views of every field into F and I (writes go to the storage).
    """
    meta = np.zeros((len(FIELDS), 6), dtype=np.int64)
    offsets = {"f": 0, "i": 0}
    arrays = []
    for k, name in enumerate(FIELDS):
        kind, ndim = KINDS[name]
        a = np.asarray(fields[name], dtype=np.float64 if kind == "f" else np.int64)
        if a.ndim != ndim:
            raise ValueError(f"kernel field {name}: {a.ndim} dimensions, expected {ndim}")
        meta[k, 0] = offsets[kind]
        meta[k, 1:1 + ndim] = a.shape
        meta[k, 1 + ndim:] = 1
        offsets[kind] += a.size
        arrays.append(a)
    F = np.zeros(max(offsets["f"], 1))
    I = np.zeros(max(offsets["i"], 1), dtype=np.int64)
    views = {}
    for k, name in enumerate(FIELDS):
        kind, ndim = KINDS[name]
        store = F if kind == "f" else I
        o = int(meta[k, 0])
        shape = tuple(int(v) for v in meta[k, 1:1 + ndim])
        v = store[o:o + int(np.prod(shape))].reshape(shape)
        v[...] = arrays[k]
        views[name] = v
    return (F, I, meta), Compiled(**views)


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
