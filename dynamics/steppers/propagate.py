"""The linear fast path's compiled loops: the recursion
x_{i+1} = Φ_{j(i)} x_i + p_i over every piece with precomputed propagators,
the scan of the point displacements (largest motion, stride check), the
error estimate's sweep over the defect's nodes (see
:mod:`flexbed.dynamics.linear`) and the states of the linear model's
deviations (:meth:`flexbed.dynamics.linear_model.Coordinates.to_y`)."""

from __future__ import annotations

import math

import numba

#: as :data:`flexbed.dynamics.steppers.common.jit`, with the sums' terms
#: free to be reordered and fused (vectorised dot products: 3–4 times
#: faster; the results change by round-off only); NaNs and infinities keep
#: their meaning
jit = numba.njit(cache=True, error_model="numpy", fastmath={"reassoc", "contract"})

__all__ = ["linear_sweep", "point_scan", "defect_sweep", "deviations_to_states"]


@jit
def linear_sweep(Phis, which, P, x0, X):
    """X[0] = x0; X[i + 1] = Phis[which[i]] @ X[i] + P[i], i = 0 … k − 1.

    Parameters
    ----------
    Phis : (m, n, n) float64
        The propagators, one per distinct piece length.
    which : (k,) int64
        The propagator of each piece.
    P : (k, n) float64
        The inputs' part of each piece's step.
    x0 : (n,) float64
    X : (k + 1, n) float64
        Written.
    """
    n = x0.size
    for j in range(n):
        X[0, j] = x0[j]
    for i in range(which.size):
        Phi = Phis[which[i]]
        for r in range(n):
            s = P[i, r]
            for c in range(n):
                s += Phi[r, c] * X[i, c]
            X[i + 1, r] = s


@jit
def point_scan(t, dP, strides, misses):
    """One pass over the point displacements of the linear solution.

    Parameters
    ----------
    t : (k,) float64 [s]
        The samples.
    dP : (k, 3P) float64 [m]
        Each sample's inertial displacements of P points, x, y, z per point.
    strides : (s,) int64
        Candidate strides m: nodes 0, m, 2m, … and k − 1.
    misses : (s,) float64
        Written: for each stride, the largest |dP − straight line between
        the nodes| at the sample midway between each pair of nodes [m].

    Returns
    -------
    motion : float [m]
        The largest |δP| of a point over the samples.
    scale : float [m]
        The largest |dP[i, c] − dP[0, c]|.
    """
    k, c = dP.shape
    motion2 = 0.0
    scale = 0.0
    for i in range(k):
        for p in range(c // 3):
            s = 0.0
            for q in range(3):
                v = dP[i, 3 * p + q]
                s += v * v
            if s > motion2:
                motion2 = s
        for j in range(c):
            v = abs(dP[i, j] - dP[0, j])
            if v > scale:
                scale = v
    for n in range(strides.size):
        m = strides[n]
        worst = 0.0
        a = 0
        while a < k - 1:
            b = min(a + m, k - 1)
            mid = (a + b) // 2
            w = (t[mid] - t[a]) / (t[b] - t[a])
            for j in range(c):
                v = abs(dP[mid, j] - (dP[a, j] * (1.0 - w) + dP[b, j] * w))
                if v > worst:
                    worst = v
            a = b
        misses[n] = worst
    return math.sqrt(motion2), scale


@jit
def defect_sweep(R, Zn, A, Phis, P0s, P1s, which, T, rot_index, D, E):
    """The first-order error e of the linear solution at the defect's
    nodes: ė = A e + d, e(0) = 0, d linear between the nodes, each interval
    propagated exactly, e_{j+1} = Φ e_j + P0 d_j + P1 (d_{j+1} − d_j).

    Parameters
    ----------
    R : (n, nz) float64
        At each node, the nonlinear rate ż less b0 + B Δu.
    Zn : (n, nz) float64
        The linear solution at the nodes.
    A : (nz, nz) float64
        The linearisation.
    Phis, P0s, P1s : (m, nz, nz) float64
        The propagators of each distinct interval length (Φ; P0 of a
        constant defect; P1 of one rising linearly from 0 to 1).
    which : (n − 1,) int64
        Each interval's length.
    T : (3P, nz) float64
        The map from deviations to point displacements [m].
    rot_index : (r,) int64
        Where the rotations sit in z.
    D : (n, nz) float64
        Written: the defect d = R − A z at the nodes.
    E : (n, nz) float64
        Written: e at the nodes.

    Returns
    -------
    position : float [m]
        The largest |T e| of a point over the nodes.
    rotation : float [rad]
        The largest |e| of a rotation over the nodes.
    """
    n, nz = Zn.shape
    npts = T.shape[0] // 3
    for i in range(n):
        for r in range(nz):
            s = R[i, r]
            for c in range(nz):
                s -= A[r, c] * Zn[i, c]
            D[i, r] = s
    for r in range(nz):
        E[0, r] = 0.0
    pos2 = 0.0
    rot = 0.0
    for i in range(n - 1):
        j = which[i]
        Phi, P0, P1 = Phis[j], P0s[j], P1s[j]
        for r in range(nz):
            s = 0.0
            for c in range(nz):
                s += Phi[r, c] * E[i, c] + P0[r, c] * D[i, c] + P1[r, c] * (D[i + 1, c] - D[i, c])
            E[i + 1, r] = s
        for p in range(npts):
            s2 = 0.0
            for q in range(3):
                s = 0.0
                for c in range(nz):
                    s += T[3 * p + q, c] * E[i + 1, c]
                s2 += s * s
            if s2 > pos2:
                pos2 = s2
        for q in range(rot_index.size):
            v = abs(E[i + 1, rot_index[q]])
            if v > rot:
                rot = v
    return math.sqrt(pos2), rot


@jit
def deviations_to_states(Z, y_eq, add, put, th_index, p_index, p_eq, Y):
    """States Y (k, ny) of deviations Z (k, nz) (see
    :meth:`flexbed.dynamics.linear_model.Coordinates.to_y`): y_eq, plus
    ``Z[:, add[:, 0]]`` at ``add[:, 1]``, ``Z[:, put[:, 0]]`` put at
    ``put[:, 1]``, and each body's Euler parameters p_eq ⊗ (√(1 − |θ/2|²), θ/2),
    θ at ``th_index`` (n, 3), written at ``p_index`` (n, 4)."""
    k = Z.shape[0]
    for i in range(k):
        for j in range(y_eq.size):
            Y[i, j] = y_eq[j]
        for j in range(add.shape[0]):
            Y[i, add[j, 1]] += Z[i, add[j, 0]]
        for j in range(put.shape[0]):
            Y[i, put[j, 1]] = Z[i, put[j, 0]]
        for b in range(th_index.shape[0]):
            s1 = 0.5 * Z[i, th_index[b, 0]]
            s2 = 0.5 * Z[i, th_index[b, 1]]
            s3 = 0.5 * Z[i, th_index[b, 2]]
            s0 = math.sqrt(max(1.0 - (s1 * s1 + s2 * s2 + s3 * s3), 0.0))
            a0, a1, a2, a3 = p_eq[b, 0], p_eq[b, 1], p_eq[b, 2], p_eq[b, 3]
            Y[i, p_index[b, 0]] = a0 * s0 - a1 * s1 - a2 * s2 - a3 * s3
            Y[i, p_index[b, 1]] = a0 * s1 + s0 * a1 + a2 * s3 - a3 * s2
            Y[i, p_index[b, 2]] = a0 * s2 + s0 * a2 + a3 * s1 - a1 * s3
            Y[i, p_index[b, 3]] = a0 * s3 + s0 * a3 + a1 * s2 - a2 * s1
