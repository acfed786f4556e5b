"""The linear fast path's estimate of its own error against the nonlinear
model (see :mod:`flexbed.dynamics.linear`), and its energy quadratures.

Error estimate against the nonlinear model
------------------------------------------
Along the linear solution the nonlinear model leaves the defect
``d(t) = f(z(t), t) − (A z + b0 + B Δu)``. The nonlinear solution differs
from the linear one by ``e`` with ``ė = A e + d + O(e²)``. ``d`` is
evaluated (the right-hand side in one compiled batch) on every m-th output
sample (the nodes) and taken between them as the local cubic through the
two nodes on each side; m = 8 is halved (the right-hand side evaluated
midway, one more batch) until the cubics through every other node predict
d, and each power of the energy quadratures, at the nodes between to 8 %
of its largest value — the cubics on every node then follow them to about
0.5 % (their miss is O(H⁴)). ``e`` is propagated exactly from node to node
(the φ-functions of the interval's ``A L``, one product per distinct
length, the recursion compiled); on every sample only when asked for
(:attr:`ErrorEstimate.e`, e.g. for the first-order correction: the same
cubics, propagated sample by sample, the same e at the nodes). The largest
error of a point that matters (the centres of mass of bodies 2… and both
ends of every mount on them, rotations and modes included with their lever
arms) over every sample, between the nodes the cubic Hermite interpolant
of ``T e`` and ``T ė = T (A e + d)``, is the reported estimate [m]. On the
reference scene (0–3 s, 1 ms samples) it is within 0.2 % of the estimate
with the defect evaluated on every sample (rigid bed −0.12 %, 2- and
6-mode beds −0.05 %), on an eighth of the right-hand sides. It is a
first-order (Newton) estimate, reliable while ``e`` is small against the
motion, which :attr:`ErrorEstimate.reliable` checks.

The energy quadratures of the state (works of mounts, loads, drive and
structural damping) are the exact integrals of the powers' local cubics
through their values at the nodes (on the reference scene within 1e-4 of
their largest value of those with the powers on every sample).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import matrix_balance

from .linear_model import Coordinates, Linearisation
from .linear_propagation import _lengths
from .steppers.defect import (cubic_pieces, hermite_peak, largest_point, pieces_at,
                              pieces_integral_at)
from .steppers.propagate import linear_sweep
from .system import System

__all__ = ["ErrorEstimate", "estimate_error", "defect_propagators"]


@dataclass
class ErrorEstimate:
    """First-order estimate of the linear model's error against the nonlinear one.

    position : float [m], the largest error |δP| of a point that matters
    (the centres of mass of bodies 2… and both ends of every mount on
    them, so that rotations and, on a flexible bed, the modes count with
    their lever arms) over every sample (between the nodes, the cubic
    Hermite interpolant of the points' errors and rates);
    rotation : float [rad], the largest error of a rotation coordinate,
    likewise;
    motion : float [m], the largest displacement of those points in the
    linear solution from the equilibrium, over every sample;
    reliable : bool, ``position <= 0.1 × motion`` (or both tiny);
    evaluations : right-hand sides it took; powers : (k, 4) [W] at every
    sample; nodes : (n,) int, the samples where the defect is evaluated;
    e_nodes : (n, nz), the error there; works : (k, 4) [J], the powers'
    exact integrals from the first sample. :attr:`e` gives the error on
    every sample (k, nz), computed when first asked for.
    """

    position: float
    rotation: float
    motion: float
    reliable: bool
    evaluations: int
    powers: np.ndarray = field(repr=False, default=None)
    nodes: np.ndarray = field(repr=False, default=None)
    e_nodes: np.ndarray = field(repr=False, default=None)
    works: np.ndarray = field(repr=False, default=None)
    _every_sample: object = field(repr=False, default=None)
    _e: np.ndarray = field(repr=False, default=None)

    @property
    def e(self) -> np.ndarray:
        """The error e (k, nz) on every sample: the defect's cubics between
        the nodes propagated sample by sample."""
        if self._e is None:
            self._e = self._every_sample()
        return self._e


def _point_map(system: System, coords: Coordinates) -> np.ndarray:
    """(P, 3, nz) first-order map from the deviations z to the inertial
    displacements of every point that matters: the centres of mass of
    bodies 2… and both ends of every mount on them,
    δP = δr + A_eq (δθ × (s̄ + Φ_e a_eq) + Φ_e δa). Only the position
    columns of z are non-zero."""
    from .rotation import A as rotation_matrix

    lay = system.layout
    where = {b: k for k, b in enumerate(lay.rigid)}
    ends = np.array([e for e, b in enumerate(system.end_body) if int(b) in where], dtype=np.int64)
    n = len(lay.rigid)
    P = n + ends.size
    if not P:
        return np.zeros((0, 3, coords.nz))
    end_body = np.asarray(system.end_body, dtype=np.int64)
    body = np.concatenate([np.arange(n), [where[int(b)] for b in end_body[ends]]]).astype(np.int64)
    s = np.zeros((P, 3))
    if ends.size:
        s[n:] = np.asarray(system.S, dtype=float)[ends]
    A_eq = rotation_matrix(coords.p_eq)[body]                          # (P, 3, 3)
    T = np.zeros((P, 3, coords.nz))
    rows = np.arange(P)
    T[rows[:, None], np.arange(3)[None, :], coords.r_index[body]] = 1.0
    end_phi = np.asarray(system.data.end_phi)
    modal, offset = [], 0
    for b, nm in lay.modal:
        idx = coords.a_index[offset:offset + nm]
        offset += nm
        on = np.flatnonzero(end_body[ends] == b) + n if b in where else np.zeros(0, np.int64)
        if on.size:                                   # the lever arm includes the sag
            phi = end_phi[ends[on - n]][:, :, :idx.size]                # (E, 3, nm)
            s[on] += phi @ coords.y_eq[coords.y_a[idx - coords.a_index[0]]]
            modal.append((on, idx, phi))
    # δθ × s̄ = −s̃ δθ, turned into the inertial frame
    s_tilde = np.zeros((P, 3, 3))
    s_tilde[:, 0, 1], s_tilde[:, 0, 2] = -s[:, 2], s[:, 1]
    s_tilde[:, 1, 0], s_tilde[:, 1, 2] = s[:, 2], -s[:, 0]
    s_tilde[:, 2, 0], s_tilde[:, 2, 1] = -s[:, 1], s[:, 0]
    T[rows[:, None, None], np.arange(3)[None, :, None], coords.th_index[body][:, None, :]] = \
        -A_eq @ s_tilde
    for on, idx, phi in modal:
        T[on[:, None, None], np.arange(3)[None, :, None], idx[None, None, :]] = A_eq[on] @ phi
    return T


def _largest_displacement(Z: np.ndarray, coords: Coordinates, to_points: np.ndarray) -> float:
    """Largest |δP| [m] over the samples (k, nz) and the points of :func:`_point_map`."""
    if not to_points.shape[0]:
        return 0.0
    T = to_points.reshape(-1, to_points.shape[2])                      # (3P, nz)
    d = (Z @ T.T).reshape(Z.shape[0], -1, 3)
    return float(np.sqrt(np.max(np.sum(d * d, axis=2))))


#: the defect is evaluated on every m-th sample, m the largest of these ...
_STRIDES = (8, 4, 2, 1)
#: ... for which the local cubics through every other node predict the
#: defect and the powers at the nodes between to 16 times this share of
#: their largest value: the cubics on every node then follow them to about
#: this share (their miss is O(H⁴): 16 times smaller at half the stride)
_CUBIC_SHARE = 5e-3
#: a defect below this share of the rates is the linearisation's round-off
_NOISE = 1e-8
_FACT4 = np.array([1.0, 1.0, 2.0, 6.0])


def _sample_nodes(k: int, m: int) -> np.ndarray:
    """Every m-th of k samples, and the last."""
    nodes = np.arange(0, k, m)
    return nodes if nodes[-1] == k - 1 else np.append(nodes, k - 1)


def _cubics(tn: np.ndarray, V: np.ndarray) -> np.ndarray:
    """The local cubics (n − 1, 4, c) of V (n, c) at the nodes tn (n ≥ 2):
    :func:`flexbed.dynamics.steppers.defect.cubic_pieces`."""
    C = np.empty((tn.size - 1, 4, V.shape[1]))
    cubic_pieces(tn, np.ascontiguousarray(V), C)
    return C


def _cubic_miss(tn: np.ndarray, V: np.ndarray, scale: np.ndarray) -> float:
    """The largest miss, over the columns of V (n, c) each divided by its
    scale (c,), of the local cubics through every other node (and the last)
    at the nodes they skip; inf below 7 nodes."""
    if tn.size < 7:
        return math.inf
    keep = _sample_nodes(tn.size, 2)
    skip = np.arange(1, tn.size - 1, 2)
    pred = np.empty((skip.size, V.shape[1]))
    pieces_at(tn[skip], tn[keep], _cubics(tn[keep], V[keep]), pred)
    return float(np.max(np.abs(pred - V[skip]) / scale))


def _defect_nodes(system: System, lin: Linearisation, t: np.ndarray,
                  Z: np.ndarray) -> tuple:
    """The nodes, and the defect d = R − A z (n, nz) (R: the nonlinear
    rates less b0 + B Δu) and the powers (n, 4) [W] there: every 8th
    sample first, the stride then halved (the right-hand side evaluated
    midway between the nodes, one compiled batch each time) until the
    local cubics through every other node miss d and each power at the
    nodes between by at most 16 × :data:`_CUBIC_SHARE` of its largest
    value (d's scale at least :data:`_NOISE` times the largest R), or
    every sample."""
    k = t.size
    coords = lin.coords
    work = system.layout.work
    AT = lin.A.T

    def evaluate(idx):
        tn = t[idx]
        dY, _ = system.rhs_batch(tn, coords.to_y(Z[idx]))
        return coords.rate(dY) - lin.b0 - lin.inputs(tn) @ lin.B.T, dY[:, work]

    system.set_segment(None)
    nodes = _sample_nodes(k, _STRIDES[0])
    R, W = evaluate(nodes)
    D = R - Z[nodes] @ AT
    while nodes.size < k:
        tn = t[nodes]
        d_scale = max(float(np.max(np.abs(D))), _NOISE * float(np.max(np.abs(R))), 1e-300)
        w_scale = np.maximum(np.max(np.abs(W), axis=0), 1e-300)
        if (_cubic_miss(tn, D, np.array([d_scale])) <= 16.0 * _CUBIC_SHARE
                and _cubic_miss(tn, W, w_scale) <= 16.0 * _CUBIC_SHARE):
            break
        a, b = nodes[:-1], nodes[1:]
        new = ((a + b) // 2)[b - a >= 2]
        R2, W2 = evaluate(new)
        order = np.argsort(np.concatenate([nodes, new]), kind="stable")
        nodes = np.concatenate([nodes, new])[order]
        R = np.concatenate([R, R2])[order]
        W = np.concatenate([W, W2])[order]
        D = R - Z[nodes] @ AT
    return nodes, D, W


#: the propagators' Taylor series are summed over h = L / 2^s, ‖hA‖₁ (balanced)
#: at most this ...
_TAYLOR_NORM = 0.5
#: ... to (hA)^(this + 1) (the next term is below 1e-17 of the first) ...
_TAYLOR_TERMS = 15
#: ... with the last two below this in ‖·‖₁ (else L / 2^(s + 1))
_TAYLOR_TAIL = 1e-17


@functools.lru_cache(maxsize=4)
def _taylor_tables(degree: int) -> tuple:
    """The Taylor coefficients 1/(k + j)! (j = 0 … degree + 1 rows, k = 0 …
    K columns) of φ_j, and the doublings' mixing 1/(p − i)! (i ≤ p) and
    2^−p: P_p ← 2^−p (Φ P_p + Σ_i P_i mix[i, p])."""
    q, K = degree + 1, _TAYLOR_TERMS + 1
    coef = np.array([[1.0 / math.factorial(k + j) for k in range(K + 1)] for j in range(q + 1)])
    mix = np.array([[1.0 / math.factorial(p - i) if i <= p else 0.0 for p in range(q)]
                    for i in range(q)])
    return coef, mix, 2.0 ** -np.arange(q)


def defect_propagators(A: np.ndarray, lengths: np.ndarray, degree: int = 3) -> tuple:
    """Φ (m, nz, nz) and P (m, degree + 1, nz, nz) of ė = A e + d over each
    length L (m,) [s], d a polynomial of σ = t/L ∈ [0, 1] with σ-derivatives
    w_p at 0: ``e(L) = Φ e(0) + Σ_p P_p w_p``, ``P_p = L φ_{p+1}(L A)``,
    φ_j(X) = Σ_k X^k/(k + j)! (the blocks of Van Loan's exponential).
    Scaling and squaring on the nz × nz blocks: the Taylor series over
    h = L / 2^s to (hA)^16, then s exact doublings
    Φ ← Φ², P_p ← 2^−p (Φ P_p + Σ_{i ≤ p} P_i/(p − i)!) (one product
    Φ [P_0 … P_degree Φ] each); a length that is another's half, quarter …
    is taken from that one's doublings. A is balanced first (LAPACK's
    diagonal scaling by powers of 2, exact: ``A = S A' S⁻¹``,
    ``φ_j(A) = S φ_j(A') S⁻¹``; ‖A'‖₁ is near the spectral radius where
    ‖A‖₁ counts stiffness over mass: 217 against 7.3e4 1/s on the
    reference scene's rigid bed); s is the least with ‖hA'‖₁ ≤ 1/2, raised
    while the series' last two terms are above 1e-17 in ‖·‖₁."""
    nz = A.shape[0]
    q = degree + 1
    Ab, (scale, _) = matrix_balance(A, permute=False, separate=True)
    norm = float(np.linalg.norm(Ab, 1))
    Phis = np.empty((lengths.size, nz, nz))
    Ps = np.empty((lengths.size, q, nz, nz))
    K = _TAYLOR_TERMS + 1
    coef, mix, halves = _taylor_tables(degree)
    done = np.zeros(lengths.size, dtype=bool)
    for i in np.argsort(-lengths, kind="stable"):
        if done[i]:
            continue
        L = float(lengths[i])
        x = norm * L
        s = max(0, math.ceil(math.log2(x / _TAYLOR_NORM))) if x > _TAYLOR_NORM else 0
        h = L / 2.0 ** s
        X = h * Ab
        powers = np.empty((K + 1, nz, nz))
        powers[0] = np.eye(nz)
        for k in range(K):
            np.matmul(powers[k], X, out=powers[k + 1])
        while max(float(np.linalg.norm(powers[k], 1)) / math.factorial(k)
                  for k in (K - 1, K)) > _TAYLOR_TAIL:
            s, h = s + 1, 0.5 * h                  # X/2: the powers X^k scale by 2^−k
            powers *= (0.5 ** np.arange(K + 1))[:, None, None]
        F = (coef @ powers.reshape(K + 1, -1)).reshape(q + 1, nz, nz)   # φ_0 … φ_q (hA)
        Phi = F[0]
        P = h * F[1:]                                                    # (q, nz, nz)
        for level in range(s, -1, -1):
            length = L / 2.0 ** level
            # the other lengths equal to this one (to 1e-12 relative) take it
            same = ~done & (np.abs(lengths - length) <= 1e-12 * L)
            Phis[same], Ps[same] = Phi, P
            done |= same
            if level:
                prod = Phi @ np.concatenate([P.transpose(1, 0, 2).reshape(nz, -1), Phi], axis=1)
                PhiP = prod[:, :q * nz].reshape(nz, q, nz).transpose(1, 0, 2)
                P = (PhiP + np.tensordot(mix, P, axes=(0, 0))) * halves[:, None, None]
                Phi = prod[:, q * nz:]
        done[i] = True
    ratio = scale[:, None] / scale[None, :]                             # S · S⁻¹
    return Phis * ratio, Ps * ratio


def _propagate_defect(A: np.ndarray, tn: np.ndarray, C: np.ndarray) -> np.ndarray:
    """e (n, nz) at the times tn (n,) of ė = A e + d, e(0) = 0, d on each
    interval the cubic of C (n − 1, 4, nz) (ascending powers of σ):
    ``e_{j+1} = Φ e_j + Σ_p P_p w_p``, w_p = p! C[j, p] its σ-derivatives
    at the interval's start; the sums Σ_p P_p w_p as one matrix product
    per distinct interval length, the recursion compiled
    (:func:`flexbed.dynamics.steppers.propagate.linear_sweep`)."""
    nz = A.shape[0]
    lengths, which = _lengths(np.diff(tn))
    Phis, Ps = defect_propagators(A, lengths)
    W = (C * _FACT4[None, :, None]).reshape(C.shape[0], -1)            # (n − 1, 4 nz)
    Pcat = Ps.transpose(0, 2, 1, 3).reshape(lengths.size, nz, -1)       # [P0 P1 P2 P3]
    counts = np.bincount(which, minlength=lengths.size)
    main = int(np.argmax(counts))
    Q = W @ Pcat[main].T
    for i in np.flatnonzero(counts):
        if i != main:
            sel = np.flatnonzero(which == i)
            Q[sel] = W[sel] @ Pcat[i].T
    E = np.empty((tn.size, nz))
    linear_sweep(Phis, which, Q, np.zeros(nz), E)
    return E


def _error_on_every_sample(A: np.ndarray, t: np.ndarray, nodes: np.ndarray,
                           C: np.ndarray) -> np.ndarray:
    """e (k, nz) on every sample from e(0) = 0: the defect's local cubics
    C (n − 1, 4, nz) between the nodes, each restricted to the samples'
    intervals and propagated exactly sample by sample (at the nodes the
    same e as the sweep over the nodes, to round-off)."""
    tn = t[nodes]
    j = np.clip(np.searchsorted(nodes, np.arange(t.size - 1), side="right") - 1, 0, nodes.size - 2)
    H = tn[j + 1] - tn[j]
    s = ((t[:-1] - tn[j]) / H)[:, None]
    r = (np.diff(t) / H)[:, None]
    c0, c1, c2, c3 = (C[j, p] for p in range(4))
    # the cubic on each sample interval, in that interval's own σ (powers)
    C_samples = np.stack([c0 + s * (c1 + s * (c2 + s * c3)),
                          r * (c1 + s * (2.0 * c2 + 3.0 * s * c3)),
                          r * r * (c2 + 3.0 * s * c3), r ** 3 * c3], axis=1)
    return _propagate_defect(A, t, C_samples)


_ROWS = 128     # samples per block of the motion scan: 128 × 3P doubles stay
                # below glibc's mmap threshold, so the block reuses heap pages


def _largest_motion(Zp: np.ndarray, T: np.ndarray) -> float:
    """The largest |point| [m] of T z over the rows of Zp (k, n_pos), T
    (3P, n_pos): the product a block of samples at a time into one
    buffer, never the whole (k, 3P) array (fresh pages of a 1–2 MB array
    cost more than the product on them)."""
    k = Zp.shape[0]
    buf = np.empty((min(k, _ROWS), T.shape[0]))
    best = 0.0
    for a in range(0, k, _ROWS):
        out = buf[:min(_ROWS, k - a)]
        np.matmul(Zp[a:a + _ROWS], T.T, out=out)
        best = max(best, largest_point(out))
    return best


def estimate_error(system: System, lin: Linearisation, t: np.ndarray,
                   Z: np.ndarray) -> ErrorEstimate:
    """Defect of the linear solution in the nonlinear equations, propagated
    (see the module docstring). Also returns the powers at the samples
    (k, 4) [W] and their integrals [J] for the energy quadratures."""
    coords = lin.coords
    nfev0 = system.nfev
    npos = coords.n_pos
    T = _point_map(system, coords).reshape(-1, coords.nz)[:, :npos]     # (3P, n_pos)
    A = np.ascontiguousarray(lin.A)
    motion = _largest_motion(Z[:, :npos], T) if T.shape[0] else 0.0
    k = t.size
    if k < 2:                                  # the start only: e(0) = 0
        none = np.zeros((k, system.layout.work.stop - system.layout.work.start))
        return ErrorEstimate(0.0, 0.0, motion, True, 0, none, np.arange(k),
                             np.zeros((k, coords.nz)), none, _e=np.zeros((k, coords.nz)))
    nodes, D, W = _defect_nodes(system, lin, t, Z)
    tn = t[nodes]
    C = _cubics(tn, D)
    CW = _cubics(tn, W)
    powers, works = np.empty((k, W.shape[1])), np.empty((k, W.shape[1]))
    pieces_at(t, tn, CW, powers)
    pieces_integral_at(t, tn, CW, works)
    # ė = A e + d, d the local cubics: Φ, P0 … P3 per distinct interval
    En = _propagate_defect(A, tn, C)
    # the points' errors between the nodes: cubic Hermite with ė = A e + d there
    Ed = En @ A.T + D
    pos = hermite_peak(t, nodes, En[:, :npos] @ T.T, Ed[:, :npos] @ T.T) if T.shape[0] else 0.0
    rot = 0.0
    if coords.n_rigid:                         # each rotation alone: (θ_i, 0, 0)
        th = coords.th_index.reshape(-1)
        V, Vd = np.zeros((nodes.size, 3 * th.size)), np.zeros((nodes.size, 3 * th.size))
        V[:, ::3], Vd[:, ::3] = En[:, th], Ed[:, th]
        rot = hermite_peak(t, nodes, V, Vd)
    reliable = pos <= 0.1 * motion or pos < 1e-12
    return ErrorEstimate(pos, rot, motion, reliable, system.nfev - nfev0, powers, nodes, En,
                         works, lambda: _error_on_every_sample(A, t, nodes, C))
