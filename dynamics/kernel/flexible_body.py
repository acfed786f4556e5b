"""A flexible body's floating-frame equations in compiled code: its
body-frame mass matrix and forces from the modal invariants (the formulas
are in :mod:`flexbed.dynamics.flexible`), solved by Cholesky."""

from __future__ import annotations

import math

from numba import njit

__all__ = ["flex_T", "flex_mass_body", "flex_forces_body", "cholesky_solve"]


@njit(cache=True, no_cpython_wrapper=True)
def cholesky_solve(M, b, n):
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
    :mod:`flexbed.dynamics.flexible`, padded arrays of at least n modes; T from
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

