"""The linear fast path's error estimate in compiled loops (see
:mod:`flexbed.dynamics.linear.estimate`): the defect at the nodes and
their refinement (one pass), local cubics through the defect's nodes (and
the powers'), the defect's propagation over the nodes, the points'
first-order map, the largest point and rotation error between the nodes,
and the largest point displacement over the samples.

A node interval ``[t_j, t_{j+1}]`` carries the cubic through the four
nodes ``j0 … j0 + 3``, ``j0 = min(max(j − 1, 0), n − 4)`` (the two
nodes on each side; one-sided at the ends), in ascending powers of
``σ = (t − t_j)/(t_{j+1} − t_j)``: a cubic is reproduced exactly.
"""

from __future__ import annotations

import math

import numpy as np

from .sweep import deviations_to_states, inner, jit, linear_sweep, rates_of_states

__all__ = ["cubic_pieces", "pieces_at", "pieces_integral_at", "hermite_peak",
           "defect_rows", "cubic_misses", "refine_nodes", "defect_sweep", "error_peaks",
           "largest_motion", "point_rows", "modal_point_rows"]


@jit
def cubic_pieces(tn, V, C):
    """The local cubics (module docstring) of the values V at the nodes.

    Parameters
    ----------
    tn : (n,) float64, n ≥ 2
        The nodes' times [s], ascending (below 4 nodes, the polynomial
        through all of them).
    V : (n, c) float64
        The values there.
    C : (n − 1, 4, c) float64
        Written: the coefficients of σ⁰ … σ³ on each interval.
    """
    n, c = V.shape
    m = min(n, 4)
    for j in range(n - 1):
        j0 = min(max(j - 1, 0), n - m)
        h = tn[j + 1] - tn[j]
        for p in range(4):
            for q in range(c):
                C[j, p, q] = 0.0
        for a in range(m):
            # Lagrange's basis polynomial of node j0 + a, expanded in σ
            sa = (tn[j0 + a] - tn[j]) / h
            b0, b1, b2, b3 = 1.0, 0.0, 0.0, 0.0
            for b in range(m):
                if b == a:
                    continue
                sb = (tn[j0 + b] - tn[j]) / h
                inv = 1.0 / (sa - sb)
                # (b0 + b1 σ + b2 σ² + b3 σ³)(σ − sb) / (sa − sb)
                b3 = (b2 - sb * b3) * inv
                b2 = (b1 - sb * b2) * inv
                b1 = (b0 - sb * b1) * inv
                b0 = -sb * b0 * inv
            for q in range(c):
                v = V[j0 + a, q]
                C[j, 0, q] += b0 * v
                C[j, 1, q] += b1 * v
                C[j, 2, q] += b2 * v
                C[j, 3, q] += b3 * v


@jit
def pieces_at(tq, tn, C, out):
    """The local cubics C of :func:`cubic_pieces` at the times tq.

    Parameters
    ----------
    tq : (q,) float64 [s]
        Ascending, within ``[tn[0], tn[-1]]``.
    tn : (n,) float64 [s]
        The nodes.
    C : (n − 1, 4, c) float64
    out : (q, c) float64
        Written.
    """
    n = tn.size
    c = C.shape[2]
    j = 0
    for i in range(tq.size):
        while j < n - 2 and tq[i] >= tn[j + 1]:
            j += 1
        s = (tq[i] - tn[j]) / (tn[j + 1] - tn[j])
        for q in range(c):
            out[i, q] = C[j, 0, q] + s * (C[j, 1, q] + s * (C[j, 2, q] + s * C[j, 3, q]))


@jit
def pieces_integral_at(tq, tn, C, out):
    """The integrals from tn[0] of the local cubics C of :func:`cubic_pieces`
    to the times tq (ascending, within ``[tn[0], tn[-1]]``), written in
    out (q, c) [unit of C times s]: the whole intervals' exact integrals
    summed, plus the part of the last."""
    n = tn.size
    c = C.shape[2]
    j = 0
    acc = np.zeros(c)
    for i in range(tq.size):
        while j < n - 2 and tq[i] >= tn[j + 1]:
            h = tn[j + 1] - tn[j]
            for q in range(c):
                acc[q] += h * (C[j, 0, q] + C[j, 1, q] / 2.0 + C[j, 2, q] / 3.0 + C[j, 3, q] / 4.0)
            j += 1
        h = tn[j + 1] - tn[j]
        s = (tq[i] - tn[j]) / h
        for q in range(c):
            out[i, q] = acc[q] + h * s * (C[j, 0, q] + s * (C[j, 1, q] / 2.0 + s * (
                C[j, 2, q] / 3.0 + s * C[j, 3, q] / 4.0)))


@jit
def hermite_peak(t, nodes, V, Vd):
    """The largest |point| over every sample of the cubic Hermite
    interpolant of the points' values V and their rates Vd at the nodes.

    An interval is skipped when no point can rise there above the largest
    so far: on it |p| ≤ max(|V_a|, |V_b|) + 4/27 h (|Vd_a| + |Vd_b|) (the
    Hermite basis: h00 + h01 = 1, both ≥ 0; |h10|, |h11| ≤ 4/27 h).

    Parameters
    ----------
    t : (k,) float64 [s]
        The samples.
    nodes : (n,) int64
        Ascending sample indices, first 0, last k − 1.
    V, Vd : (n, 3P) float64
        x, y, z of P points at the nodes [m] and their rates [m/s].

    Returns
    -------
    float
        The largest length [m].
    """
    n, c = V.shape
    npts = c // 3
    nv = np.empty((n, npts))
    nd = np.empty((n, npts))
    best = 0.0
    for j in range(n):
        for p in range(npts):
            a2 = 0.0
            b2 = 0.0
            for q in range(3):
                a2 += V[j, 3 * p + q] ** 2
                b2 += Vd[j, 3 * p + q] ** 2
            nv[j, p] = math.sqrt(a2)
            nd[j, p] = math.sqrt(b2)
            if a2 > best:
                best = a2
    best = math.sqrt(best)
    for j in range(n - 1):
        a, b = nodes[j], nodes[j + 1]
        h = t[b] - t[a]
        bound = 0.0
        for p in range(npts):
            v = max(nv[j, p], nv[j + 1, p]) + 4.0 / 27.0 * h * (nd[j, p] + nd[j + 1, p])
            if v > bound:
                bound = v
        if bound <= best:
            continue
        for i in range(a + 1, b):
            s = (t[i] - t[a]) / h
            s2 = s * s
            s3 = s2 * s
            h00 = 2.0 * s3 - 3.0 * s2 + 1.0
            h10 = (s3 - 2.0 * s2 + s) * h
            h01 = -2.0 * s3 + 3.0 * s2
            h11 = (s3 - s2) * h
            for p in range(npts):
                s2p = 0.0
                for q in range(3):
                    col = 3 * p + q
                    v = (h00 * V[j, col] + h10 * Vd[j, col]
                         + h01 * V[j + 1, col] + h11 * Vd[j + 1, col])
                    s2p += v * v
                s2p = math.sqrt(s2p)
                if s2p > best:
                    best = s2p
    return best


@jit
def largest_motion(Z, rows, T):
    """The largest |point| [m] of T z over the rows ``rows`` of Z.

    Each point on its non-zero columns of T only (a rigid body's point:
    its translation and rotation, 6 of them); the points with the same
    columns (those of one body) form a group, and at each row a group is
    skipped when the bound Σ_j w_j |z_j| (w_j the largest |T_p e_j| of
    its points) is no larger than the largest length so far, which starts
    from each group's row of the largest bound.

    Parameters
    ----------
    Z : (k, nz) float64
    rows : (s,) int64
    T : (3P, c) float64
        x, y, z of P points against the first c columns of Z.
    """
    P = T.shape[0] // 3
    c = T.shape[1]
    if rows.size == 0 or P == 0:
        return 0.0
    count = np.zeros(P, dtype=np.int64)
    cols = np.empty((P, c), dtype=np.int64)
    vals = np.empty((P, c, 3))
    for p in range(P):
        for j in range(c):
            if T[3 * p, j] != 0.0 or T[3 * p + 1, j] != 0.0 or T[3 * p + 2, j] != 0.0:
                m = count[p]
                cols[p, m] = j
                for q in range(3):
                    vals[p, m, q] = T[3 * p + q, j]
                count[p] = m + 1
    # the groups: points with the same columns; each group's bound weights
    group = np.empty(P, dtype=np.int64)
    lead = np.empty(P, dtype=np.int64)              # a group's first point
    weight = np.zeros((P, c))
    ng = 0
    for p in range(P):
        g = -1
        for h in range(ng):
            q = lead[h]
            if count[q] == count[p]:
                same = True
                for m in range(count[p]):
                    if cols[q, m] != cols[p, m]:
                        same = False
                        break
                if same:
                    g = h
                    break
        if g < 0:
            g = ng
            lead[g] = p
            ng += 1
        group[p] = g
        for m in range(count[p]):
            w = math.sqrt(vals[p, m, 0] ** 2 + vals[p, m, 1] ** 2 + vals[p, m, 2] ** 2)
            weight[g, m] = max(weight[g, m], w)
    members = np.empty(P, dtype=np.int64)           # the points, group by group
    start = np.zeros(ng + 1, dtype=np.int64)
    for p in range(P):
        start[group[p] + 1] += 1
    for g in range(ng):
        start[g + 1] += start[g]
    fill = start[:ng].copy()
    for p in range(P):
        members[fill[group[p]]] = p
        fill[group[p]] += 1
    # every row's bounds; the rows of the largest bounds first, so that the
    # others are mostly skipped
    bounds = np.empty((rows.size, ng))
    top = np.zeros(ng, dtype=np.int64)
    for r in range(rows.size):
        z = Z[rows[r]]
        for g in range(ng):
            q = lead[g]
            bound = 0.0
            for m in range(count[q]):
                bound += weight[g, m] * abs(z[cols[q, m]])
            bounds[r, g] = bound
            if bound > bounds[top[g], g]:
                top[g] = r
    best = 0.0                                      # squared
    for g in range(ng):
        best = _group_peak(Z[rows[top[g]]], members[start[g]:start[g + 1]], count, cols, vals,
                           best)
    for r in range(rows.size):
        for g in range(ng):
            if bounds[r, g] ** 2 > best:
                best = _group_peak(Z[rows[r]], members[start[g]:start[g + 1]], count, cols,
                                   vals, best)
    return math.sqrt(best)


@inner
def _group_peak(z, points, count, cols, vals, best):
    """max(best, the largest |T_p z|² of the points) (:func:`largest_motion`)."""
    for p in points:
        x = 0.0
        y = 0.0
        w = 0.0
        for m in range(count[p]):
            zc = z[cols[p, m]]
            x += vals[p, m, 0] * zc
            y += vals[p, m, 1] * zc
            w += vals[p, m, 2] * zc
        s = x * x + y * y + w * w
        if s > best:
            best = s
    return best


@inner
def defect_rows(kernel, seg_end, t, Z, idx, coords, b0, B, du, w0, V):
    """The rates and the powers at the samples idx (q,), one compiled pass:
    V[r] = [R, ẏ_i[w0 : w0 + c]], i = idx[r], R = ż(f(t_i, y(z_i))) − b0
    − B du[r] (the nonlinear rates less the linear model's inputs: the
    defect once A z_i is taken off).

    Parameters
    ----------
    kernel : tuple (function, F, I)
        The compiled right-hand side (:attr:`flexbed.dynamics.system.System.kernel`).
    seg_end : float [s]
    t : (k,) float64 [s]; Z : (k, nz) float64
        The linear solution.
    idx : (q,) int64
    coords : tuple
        (y_eq, add, put, th_index, p_index, p_eq, take, p_conj) of
        :func:`flexbed.dynamics.linear.sweep.deviations_to_states` and
        :func:`~flexbed.dynamics.linear.sweep.rates_of_states`.
    b0 : (nz,); B : (nz, nu); du : (q, nu) float64
    w0 : int
        Where the powers start in ẏ.
    V : (q, nz + c) float64
        Written.

    Returns
    -------
    float
        The largest |R| (the rates' scale).
    """
    fn, F, I = kernel
    y_eq, add, put, th, yp, p_eq, take, p_conj = coords
    nz = b0.size
    nu = B.shape[1]
    nw = V.shape[1] - nz
    y = np.empty((1, y_eq.size))
    dy = np.empty((1, y_eq.size))
    zd = np.empty((1, nz))
    r_max = 0.0
    for r in range(idx.size):
        i = idx[r]
        deviations_to_states(Z[i:i + 1], y_eq, add, put, th, yp, p_eq, y)
        fn(t[i], seg_end, y[0].ctypes, dy[0].ctypes, F.ctypes, I.ctypes)
        rates_of_states(dy, take, th, yp, p_conj, zd)
        for a in range(nz):
            R = zd[0, a] - b0[a]
            for u in range(nu):
                R -= B[a, u] * du[r, u]
            if abs(R) > r_max:
                r_max = abs(R)
            V[r, a] = R
        for c in range(nw):
            V[r, nz + c] = dy[0, w0 + c]
    return r_max


@inner
def cubic_misses(t_old, V_old, t_new, V_new, scale, miss):
    """miss[r] = the largest |p(t_new[r]) − V_new[r]| / scale over the
    columns, p the local cubics (module docstring) through the nodes t_old
    (n ≥ 4, ascending) with values V_old (n, c); scale (c,)."""
    n, c = V_old.shape
    j = 0
    for r in range(t_new.size):
        tq = t_new[r]
        while j < n - 2 and tq >= t_old[j + 1]:
            j += 1
        j0 = min(max(j - 1, 0), n - 4)
        best = 0.0
        # Lagrange's weights of the four nodes at tq
        w = np.empty(4)
        for a in range(4):
            wa = 1.0
            for b in range(4):
                if b != a:
                    wa *= (tq - t_old[j0 + b]) / (t_old[j0 + a] - t_old[j0 + b])
            w[a] = wa
        for q in range(c):
            p = (w[0] * V_old[j0, q] + w[1] * V_old[j0 + 1, q] + w[2] * V_old[j0 + 2, q]
                 + w[3] * V_old[j0 + 3, q])
            m = abs(p - V_new[r, q]) / scale[q]
            if m > best:
                best = m
        miss[r] = best


@inner
def _defect_at(kernel, seg_end, t, Z, idx, coords, b0, B, du, w0, AT, V):
    """V (q, nz + c) = [d | powers] at the piece ends idx (q,):
    :func:`defect_rows`, then A z off; returns the largest |R|."""
    nz = b0.size
    r = defect_rows(kernel, seg_end, t, Z, idx, coords, b0, B, du[idx], w0, V)
    Az = np.dot(Z[idx], AT)
    for i in range(idx.size):
        for a in range(nz):
            V[i, a] -= Az[i, a]
    return r


@jit
def refine_nodes(kernel, seg_end, t, Z, du, coords, b0, B, AT, w0, first, tol, noise, V):
    """The error estimate's node refinement in one compiled pass (see
    :func:`flexbed.dynamics.linear.estimate._defect_nodes`): the defect and
    the powers at the first nodes; then, round by round, every node
    interval next to a node (at first every other node, the last kept)
    where the local cubics through the nodes it was added to miss d or a
    power by more than ``tol`` of its largest value (d's scale at least
    ``noise`` times the largest rate) is halved, the right-hand side
    evaluated midway, until no node misses or the intervals are single
    pieces.

    Parameters
    ----------
    kernel, seg_end, t, Z, coords, b0, B, w0
        As :func:`defect_rows`; Z (k, nz) the linear solution at the
        piece ends t (k,).
    du : (k, nu) float64
        The inputs u − u(0) at every piece end.
    AT : (nz, nz) float64
        Aᵀ, C-contiguous.
    first : (n0,) int64
        The first nodes (ascending, first 0, last k − 1).
    tol, noise : float
    V : (k, nz + c) float64
        Written: [d | powers] at the nodes in its first n rows.

    Returns
    -------
    nodes : (n,) int64
        The nodes.
    """
    k = t.size
    nz = b0.size
    nv = V.shape[1]
    n = first.size
    nodes = first.copy()
    r_max = _defect_at(kernel, seg_end, t, Z, nodes, coords, b0, B, du, w0, AT, V[:n])
    vmax = np.zeros(nv)
    for i in range(n):
        for a in range(nv):
            vmax[a] = max(vmax[a], abs(V[i, a]))
    is_new = np.zeros(n, dtype=np.bool_)                  # every other node, the last kept
    for i in range(1, n - 1, 2):
        is_new[i] = True
    W = np.empty((k, nv))                                  # the merge's other buffer
    scale = np.empty(nv)
    while True:
        n_new = 0
        for i in range(n):
            if is_new[i]:
                n_new += 1
        if n_new == 0:
            break
        old = np.empty(n - n_new, dtype=np.int64)
        new = np.empty(n_new, dtype=np.int64)
        a = 0
        b = 0
        for i in range(n):
            if is_new[i]:
                new[b] = i
                b += 1
            else:
                old[a] = i
                a += 1
        dmax = 0.0
        for c in range(nz):
            dmax = max(dmax, vmax[c])
        for c in range(nv):
            scale[c] = max(vmax[c], 1e-300)
        for c in range(nz):
            scale[c] = max(dmax, noise * r_max, 1e-300)
        miss = np.full(n_new, np.inf)
        if old.size >= 4:
            cubic_misses(t[nodes[old]], V[old], t[nodes[new]], V[new], scale, miss)
        # the intervals on either side of each node that misses, two pieces or longer
        side = np.zeros(n, dtype=np.bool_)
        for r in range(n_new):
            if miss[r] > tol:
                side[new[r]] = True
                side[new[r] - 1] = True
        mids = np.empty(n, dtype=np.int64)
        m = 0
        for j in range(n - 1):
            if side[j] and nodes[j + 1] - nodes[j] >= 2:
                mids[m] = (nodes[j] + nodes[j + 1]) // 2
                m += 1
        if m == 0:
            break
        mids = mids[:m]
        V2 = np.empty((m, nv))
        r_max = max(r_max, _defect_at(kernel, seg_end, t, Z, mids, coords, b0, B, du, w0,
                                      AT, V2))
        for i in range(m):
            for c in range(nv):
                vmax[c] = max(vmax[c], abs(V2[i, c]))
        # merge the two ascending lists (a midpoint lies strictly inside its interval)
        merged = np.empty(n + m, dtype=np.int64)
        is_new = np.zeros(n + m, dtype=np.bool_)
        i = 0
        j = 0
        for r in range(n + m):
            if j < m and (i >= n or mids[j] < nodes[i]):
                merged[r] = mids[j]
                for c in range(nv):
                    W[r, c] = V2[j, c]
                is_new[r] = True
                j += 1
            else:
                merged[r] = nodes[i]
                for c in range(nv):
                    W[r, c] = V[i, c]
                i += 1
        n += m
        nodes = merged
        for r in range(n):
            for c in range(nv):
                V[r, c] = W[r, c]
    return nodes


@jit
def defect_sweep(Phis, Ps, which, C, col_scale, scale, E):
    """The error e (n, nz) at the nodes from e_0 = 0 (see
    :func:`flexbed.dynamics.linear.estimate._propagate_defect`), in the
    balanced coordinates e' = S⁻¹ e of the propagators:
    ``e'_{j+1} = Φ e'_j + Σ_p P_p w_p``, w_p = p! C[j, p] / S_cols (d's
    σ-derivatives at the interval's start, its columns only); the sums as
    one matrix product per distinct length over the intervals of that
    length (gathered), the recursion by :func:`linear_sweep`; then
    e = S e'.

    Parameters
    ----------
    Phis : (m, nz, nz) float64
    Ps : (m, nz, 4 c) float64
        [P_0 … P_3] of each length (their columns ``cols``).
    which : (n − 1,) int64
        Each interval's length.
    C : (n − 1, 4, c) float64
        The defect's local cubics (ascending powers of σ).
    col_scale : (c,) float64
        S at d's columns.
    scale : (nz,) float64
        S.
    E : (n, nz) float64
        Written.
    """
    n1, q, c = C.shape
    m, nz = Phis.shape[0], Phis.shape[1]
    W = np.empty((n1, q * c))
    for j in range(n1):
        f = 1.0
        for p in range(q):
            if p > 1:
                f *= p
            for a in range(c):
                W[j, p * c + a] = C[j, p, a] * f / col_scale[a]
    if m == 1:
        Q = np.dot(W, Ps[0].T)
    else:
        Q = np.empty((n1, nz))
        counts = np.zeros(m, dtype=np.int64)
        for j in range(n1):
            counts[which[j]] += 1
        for i in range(m):
            if counts[i] == 0:
                continue
            sel = np.empty(counts[i], dtype=np.int64)
            r = 0
            for j in range(n1):
                if which[j] == i:
                    sel[r] = j
                    r += 1
            Qi = np.dot(W[sel], Ps[i].T)
            for r in range(sel.size):
                for a in range(nz):
                    Q[sel[r], a] = Qi[r, a]
    linear_sweep(Phis, which, Q, np.zeros(nz), E)
    for j in range(E.shape[0]):
        for a in range(nz):
            E[j, a] *= scale[a]


@jit
def error_peaks(t, nodes, E, D, A, T, th):
    """The largest error of a point and of a rotation over every piece end
    (see :func:`flexbed.dynamics.linear.estimate.estimate_error`): the
    points' errors T e and rates T ė, ė = A e + d, at the nodes, between
    them their cubic Hermite interpolant (:func:`hermite_peak`); each
    rotation coordinate alone likewise.

    Parameters
    ----------
    t : (k,) float64 [s]
    nodes : (n,) int64
    E, D : (n, nz) float64
        The error e and the defect d at the nodes.
    A : (nz, nz) float64
    T : (3P, n_pos) float64
        The points' map (position columns: the first n_pos of z).
    th : (r,) int64
        The rotation coordinates (among the first n_pos).

    Returns
    -------
    (float, float)
        The largest point error [m] and rotation error [rad].
    """
    n = E.shape[0]
    npos = T.shape[1]
    Ep = np.ascontiguousarray(E[:, :npos])
    Ed = np.dot(E, A[:npos].T)
    for i in range(n):
        for a in range(npos):
            Ed[i, a] += D[i, a]
    pos = 0.0
    if T.shape[0]:
        pos = hermite_peak(t, nodes, np.dot(Ep, T.T), np.dot(Ed, T.T))
    rot = 0.0
    if th.size:
        V = np.zeros((n, 3 * th.size))
        Vd = np.zeros((n, 3 * th.size))
        for i in range(n):
            for r in range(th.size):
                V[i, 3 * r] = E[i, th[r]]
                Vd[i, 3 * r] = Ed[i, th[r]]
        rot = hermite_peak(t, nodes, V, Vd)
    return pos, rot


@jit
def point_rows(body, s, p_eq, r_index, th_index, T):
    """The rigid-body part of the first-order map from the deviations z to
    the inertial displacements of points, into T (P, 3, nz) (zeroed
    first): δP = δr + A_eq (δθ × s) for a point at the body-frame arm s
    (the sag of a flexible body's modes included) on body ``body``,
    A_eq the rotation matrix of its equilibrium Euler parameters.

    Parameters
    ----------
    body : (P,) int64
        Each point's body (its row in p_eq, r_index, th_index).
    s : (P, 3) float64 [m]
    p_eq : (n, 4) float64
        Unit Euler parameters (scalar first).
    r_index, th_index : (n, 3) int64
        The columns of z of each body's translation and rotation.
    T : (P, 3, nz) float64
        Written.
    """
    T[:] = 0.0
    R = np.empty((3, 3))
    for i in range(body.size):
        b = body[i]
        _rotation(p_eq[b], R)
        sx, sy, sz = s[i, 0], s[i, 1], s[i, 2]
        for k in range(3):
            T[i, k, r_index[b, k]] = 1.0
            # columns of A_eq (e_j × s): e_x × s = (0, −sz, sy), e_y × s =
            # (sz, 0, −sx), e_z × s = (−sy, sx, 0)
            T[i, k, th_index[b, 0]] = -R[k, 1] * sz + R[k, 2] * sy
            T[i, k, th_index[b, 1]] = R[k, 0] * sz - R[k, 2] * sx
            T[i, k, th_index[b, 2]] = -R[k, 0] * sy + R[k, 1] * sx


@jit
def modal_point_rows(on, body, p_eq, phi, idx, T):
    """The modal part of :func:`point_rows`, added for the points ``on``
    (c,) of one flexible body: T[on[i], :, idx] = A_eq Φ_e,i, with Φ_e,i
    (3, nm) the mode shapes at the point and ``idx`` (nm,) the columns of
    the body's modal deviations.

    Parameters
    ----------
    on : (c,) int64
        The points (rows of T).
    body : (P,) int64
        Each point's body (its row in p_eq).
    p_eq : (n, 4) float64
    phi : (c, 3, nm) float64 [m per unit modal coordinate]
    idx : (nm,) int64
    T : (P, 3, nz) float64
        Written in those entries.
    """
    R = np.empty((3, 3))
    for i in range(on.size):
        row = on[i]
        _rotation(p_eq[body[row]], R)
        for k in range(3):
            for j in range(idx.size):
                T[row, k, idx[j]] = (R[k, 0] * phi[i, 0, j] + R[k, 1] * phi[i, 1, j]
                                     + R[k, 2] * phi[i, 2, j])


@inner
def _rotation(p, R):
    """The rotation matrix of unit Euler parameters p (4,) (scalar first)
    into R (3, 3) (:func:`flexbed.dynamics.rotation.A`)."""
    e0, e1, e2, e3 = p[0], p[1], p[2], p[3]
    R[0, 0] = 2.0 * (e0 * e0 + e1 * e1) - 1.0
    R[0, 1] = 2.0 * (e1 * e2 - e0 * e3)
    R[0, 2] = 2.0 * (e1 * e3 + e0 * e2)
    R[1, 0] = 2.0 * (e1 * e2 + e0 * e3)
    R[1, 1] = 2.0 * (e0 * e0 + e2 * e2) - 1.0
    R[1, 2] = 2.0 * (e2 * e3 - e0 * e1)
    R[2, 0] = 2.0 * (e1 * e3 - e0 * e2)
    R[2, 1] = 2.0 * (e2 * e3 + e0 * e1)
    R[2, 2] = 2.0 * (e0 * e0 + e3 * e3) - 1.0
