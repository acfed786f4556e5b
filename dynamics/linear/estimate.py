"""The linear fast path's estimate of its own error against the nonlinear
model (see :mod:`flexbed.dynamics.linear`), and its energy quadratures.

Error estimate against the nonlinear model
------------------------------------------
Along the linear solution the nonlinear model leaves the defect
``d(t) = f(z(t), t) − (A z + b0 + B Δu)``. The nonlinear solution differs
from the linear one by ``e`` with ``ė = A e + d + O(e²)``. ``d`` is
evaluated (the right-hand side and the whole refinement below in one
compiled pass) at some of the propagation's piece ends (the output
samples and the inputs' knots between them), the nodes, and taken
between them as the local cubic
through the two nodes on each side. Every 16th piece end first (runs of
longer pieces, where the knots stop, every few, so that the intervals
have one length near 16 of the shortest pieces where the runs' lengths
allow it); then, round by round, every node interval next
to a node where the local cubics through the nodes it was added to miss
d, or a power of the energy quadratures, by more than 8 % of its largest
value is halved (the right-hand side evaluated midway): the cubics on the
nodes kept then follow them to about 0.5 % (their miss is O(H⁴)), and a
quiet stretch keeps its long intervals. ``e`` is propagated exactly from
node to node (the φ-functions of the interval's ``A L``, one series and
its doublings per family of lengths, compiled, on the defect's non-zero
columns only; the products and the recursion in one compiled pass; the
points' peaks in another); on every output sample only when
asked for (:attr:`ErrorEstimate.e`, e.g. for the first-order correction:
the same cubics, propagated piece by piece, the same e at the nodes). The
largest error of a point that matters (the centres of mass of bodies 2…
and both ends of every mount on them, rotations and modes included with
their lever arms) over every piece end, between the nodes the cubic
Hermite interpolant of ``T e`` and ``T ė = T (A e + d)``, is the reported
estimate [m]. On the reference scene (0–1.5 s, 1 ms samples, rigid bed)
it is within 0.3 % of the estimate with the defect evaluated on every
sample, e within 1.6 % and the works within 8e-4 of their largest, on
133 right-hand sides against 1501 (every 8th sample: 188). The same
scene with 10 ms output samples (10 ms pieces once the load has stopped;
nodes every 20 ms at first) gives it within 0.04 %, e within 2.7 %, on
116. It is a first-order (Newton) estimate, reliable
while ``e`` is small against the motion, which
:attr:`ErrorEstimate.reliable` checks.

The energy quadratures of the state (works of mounts, loads, drive and
structural damping) are the exact integrals of the powers' local cubics
through their values at the nodes (on the reference scene within 8e-4 of
their largest value of those with the powers on every sample).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..system import System
from .defect import (cubic_pieces, defect_sweep, error_peaks, largest_motion, modal_point_rows,
                     pieces_at, pieces_integral_at, point_rows, refine_nodes)
from .model import Coordinates, Linearisation, balanced, per_system
from .phi import doubling_tables, halvings, norm1, phi_double, phi_functions
from .propagation import _lengths

__all__ = ["ErrorEstimate", "estimate_error", "defect_propagators"]


@dataclass
class ErrorEstimate:
    """First-order estimate of the linear model's error against the nonlinear one.

    position : float [m], the largest error |δP| of a point that matters
    (the centres of mass of bodies 2… and both ends of every mount on
    them, so that rotations and, on a flexible bed, the modes count with
    their lever arms) over every piece end of the propagation (the output
    samples and the inputs' knots between them; between the nodes, the
    cubic Hermite interpolant of the points' errors and rates);
    rotation : float [rad], the largest error of a rotation coordinate,
    likewise;
    motion : float [m], the largest displacement of those points in the
    linear solution from the equilibrium, over the output samples;
    reliable : bool, ``position <= 0.1 × motion`` (or both tiny);
    evaluations : right-hand sides it took; powers : (k, 4) [W] at every
    output sample; nodes : (n,) int, the piece ends where the defect is
    evaluated (the output samples' indices when no knot lies between
    them); e_nodes : (n, nz), the error there; works : (k, 4) [J], the
    powers' exact integrals from the first sample. :attr:`e` gives the
    error on every output sample (k, nz), computed when first asked for.
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


@per_system
def _point_structure(system: System) -> tuple:
    """What :func:`_point_map` needs of the system alone (made once per
    system): the points' bodies (their positions among bodies 2…), their
    body-frame arms s̄ (P, 3), and for each flexible body among them the
    points on it, the columns of its modes and the mode shapes there."""
    lay = system.layout
    where = {b: k for k, b in enumerate(lay.rigid)}
    end_body = np.asarray(system.end_body, dtype=np.int64)
    ends = np.array([e for e, b in enumerate(end_body) if int(b) in where], dtype=np.int64)
    n = len(lay.rigid)
    body = np.concatenate([np.arange(n), [where[int(b)] for b in end_body[ends]]]).astype(np.int64)
    arms = np.zeros((body.size, 3))
    if ends.size:
        arms[n:] = np.asarray(system.S, dtype=float)[ends]
    end_phi = np.asarray(system.data.end_phi)
    modal, offset = [], 0
    for b, nm in lay.modal:
        first = offset
        offset += nm
        on = np.flatnonzero(end_body[ends] == b) + n if b in where else np.zeros(0, np.int64)
        if on.size:
            modal.append((on, first, nm, np.ascontiguousarray(end_phi[ends[on - n]][:, :, :nm])))
    return body, arms, tuple(modal)


def _point_map(system: System, coords: Coordinates) -> np.ndarray:
    """(P, 3, nz) first-order map from the deviations z to the inertial
    displacements of every point that matters: the centres of mass of
    bodies 2… and both ends of every mount on them,
    δP = δr + A_eq (δθ × (s̄ + Φ_e a_eq) + Φ_e δa) (the rigid part
    compiled: :func:`flexbed.dynamics.linear.defect.point_rows` and
    ``modal_point_rows``). Only
    the position columns of z are non-zero."""
    body, arms, modal = _point_structure(system)
    P = body.size
    T = np.empty((P, 3, coords.nz))
    if not P:
        return T
    s = arms
    if modal:                                         # the lever arm includes the sag
        s = arms.copy()
        for on, first, nm, phi in modal:
            s[on] += phi @ coords.y_eq[coords.y_a[first:first + nm]]
    point_rows(body, s, coords.p_eq, coords.r_index, coords.th_index, T)
    for on, first, nm, phi in modal:
        modal_point_rows(on, body, coords.p_eq, phi, coords.a_index[first:first + nm], T)
    return T


def _largest_displacement(Z: np.ndarray, coords: Coordinates, to_points: np.ndarray) -> float:
    """Largest |δP| [m] over the samples (k, nz) and the points of :func:`_point_map`."""
    if not to_points.shape[0]:
        return 0.0
    T = to_points.reshape(-1, to_points.shape[2])                      # (3P, nz)
    d = (Z @ T.T).reshape(Z.shape[0], -1, 3)
    return float(np.sqrt(np.max(np.sum(d * d, axis=2))))


#: the defect is first evaluated on every this-many-th sample (fewer when
#: that leaves under 9 nodes) ...
_START = 16
#: ... and a node interval is halved (the right-hand side evaluated midway)
#: next to every node where the local cubics through the nodes it was added
#: to miss the defect or a power by more than 16 times this share of its
#: largest value: the cubics on the nodes kept then follow them to about
#: this share (their miss is O(H⁴): 16 times smaller at half the interval)
_CUBIC_SHARE = 5e-3
#: a defect below this share of the rates is the linearisation's round-off
_NOISE = 1e-8


def _sample_nodes(k: int, m: int) -> np.ndarray:
    """Every m-th of k samples, and the last."""
    nodes = np.arange(0, k, m)
    return nodes if nodes[-1] == k - 1 else np.append(nodes, k - 1)


def _cubics(tn: np.ndarray, V: np.ndarray) -> np.ndarray:
    """The local cubics (n − 1, 4, c) of V (n, c) at the nodes tn (n ≥ 2):
    :func:`flexbed.dynamics.linear.defect.cubic_pieces`."""
    C = np.empty((tn.size - 1, 4, V.shape[1]))
    cubic_pieces(tn, np.ascontiguousarray(V), C)
    return C


def _first_nodes(t: np.ndarray) -> np.ndarray:
    """The first nodes among the piece ends t (k,): every m-th, m =
    :data:`_START` (less when that would leave under 9 nodes). Where the
    pieces are longer in long runs (an input's knots closer than the
    output samples elsewhere, e.g. once the load's samples stop), each run
    of equal pieces starts at a node and takes every few ends: when the
    runs' lengths are whole multiples of the shortest, one node interval
    for all of them, the least common multiple of their lengths at or
    above m of the shortest (at most 4 m), so that the intervals have one
    length and its halves (one family of the error's propagators); else
    the number of pieces nearest to m of the shortest (at least one).
    Pieces of changing lengths that do not form long runs (knots between
    the samples) keep every m-th end."""
    k = t.size
    m = max(1, min(_START, (k - 1) // 8))
    if k < 3:
        return _sample_nodes(k, m)
    h = np.diff(t)
    lengths, which = _lengths(h)
    if lengths.size == 1:
        return _sample_nodes(k, m)
    starts = np.concatenate([[0], np.flatnonzero(np.diff(which)) + 1])   # a run's first piece
    if starts.size > max(4, (k - 1) // (4 * _START)):                     # short runs
        return _sample_nodes(k, m)
    ends = np.append(starts[1:], k - 1)
    ratio = lengths / float(np.min(lengths))
    whole = np.round(ratio).astype(np.int64)
    lcm = int(np.lcm.reduce(whole)) if np.all(np.abs(ratio - whole) <= 1e-9 * ratio) else 0
    if 0 < lcm <= 4 * m:
        span = lcm * -(-m // lcm)                 # H in shortest pieces
        steps = span // whole
    else:
        steps = np.maximum(1, np.minimum(m, np.round(m / ratio).astype(np.int64)))
    # the runs in order, each from its first end: ascending, the last end after them
    out = [np.arange(a, b, steps[which[a]]) for a, b in zip(starts, ends)]
    return np.concatenate(out + [np.array([k - 1])])


def _defect_nodes(system: System, lin: Linearisation, t: np.ndarray,
                  Z: np.ndarray) -> tuple:
    """The nodes, and the defect d = R − A z (n, nz) (R: the nonlinear
    rates less b0 + B Δu) and the powers (n, 4) [W] there.

    The nodes of :func:`_first_nodes` first; they are then refined where
    they need it: the right-hand side is evaluated midway in every node
    interval next to a node where the local cubics through the nodes it
    was added to (at first every other node) miss d or a power by more
    than 16 × :data:`_CUBIC_SHARE` of its largest value (d's scale at least
    :data:`_NOISE` times the largest R), round by round, until no node
    misses or the intervals are single pieces: one compiled pass
    (:func:`flexbed.dynamics.linear.defect.refine_nodes`). A quiet
    stretch of the run keeps long intervals."""
    coords = lin.coords
    work = system.layout.work
    nz = lin.A.shape[0]
    conv = (coords.y_eq, coords._add, coords._put, coords._th, coords._yp, coords.p_eq,
            coords._take, coords.p_eq_conj)
    V = np.empty((t.size, nz + work.stop - work.start))
    nodes = refine_nodes(system.kernel, math.inf, t, Z, lin.inputs(t), conv, lin.b0,
                         lin.B, np.ascontiguousarray(lin.A.T), work.start, _first_nodes(t),
                         16.0 * _CUBIC_SHARE, _NOISE, V)
    system.nfev += nodes.size
    return nodes, V[:nodes.size, :nz], V[:nodes.size, nz:]


def defect_propagators(A: np.ndarray, lengths: np.ndarray, degree: int = 3,
                       cols: np.ndarray | None = None) -> tuple:
    """Φ (m, nz, nz) and P (m, nz, degree + 1, c) of ė = A e + d over each
    length L (m,) [s], d a polynomial of σ = t/L ∈ [0, 1] with σ-derivatives
    w_p at 0: ``e(L) = Φ e(0) + Σ_p P_p w_p``, ``P_p = L φ_{p+1}(L A)`` =
    ``P[:, :, p]`` (its columns ``cols`` (c,) only, d being zero in the
    others; all by default),
    φ_j(X) = Σ_k X^k/(k + j)! (the blocks of Van Loan's exponential).
    A is balanced first (a diagonal scaling by powers of 2 as LAPACK's
    ``dgebal``, exact: ``A = S A' S⁻¹``, ``φ_j(A) = S φ_j(A') S⁻¹``; ‖A'‖₁
    is near the spectral radius where ‖A‖₁ counts stiffness over mass: 217
    against 7.3e4 1/s on the reference scene's rigid bed;
    :func:`flexbed.dynamics.linear.model.balanced`); the φ-functions of A'
    are those of :func:`_balanced_propagators`, and S · S⁻¹ is put back."""
    nz = A.shape[0]
    cols = np.arange(nz) if cols is None else np.asarray(cols, dtype=np.int64)
    Ab, scale = balanced(A)
    Phis, Ps = _balanced_propagators(Ab, lengths, degree, cols)
    Phis *= scale[:, None] / scale[None, :]
    Ps *= (scale[:, None] / scale[None, cols])[:, None, :]
    return Phis, Ps


def _balanced_propagators(Ab: np.ndarray, lengths: np.ndarray, degree: int,
                          cols: np.ndarray) -> tuple:
    """:func:`defect_propagators` of the balanced A' (nz, nz), without the
    scaling put back. Scaling and squaring on the nz × nz blocks: the
    φ-functions of h A', h = L / 2^s
    (:func:`flexbed.dynamics.linear.phi.phi_functions`: φ_4 by its
    series, the others by φ_j = X φ_{j+1} + I/j!), then s exact doublings
    Φ ← Φ², P_p ← 2^−p (Φ P_p + Σ_{i ≤ p} P_i/(p − i)!) (one product
    Φ [P_0 … P_degree Φ] each); a length that is another's half, quarter
    … is taken from that one's doublings; s is the least with
    ‖hA'‖₁ ≤ 2 (and deep enough to pass through the shorter lengths
    L/2^j)."""
    nz = Ab.shape[0]
    q = degree + 1
    c = cols.size
    norm = norm1(Ab)
    Phis = np.empty((lengths.size, nz, nz))
    Ps = np.empty((lengths.size, nz, q, c))
    mix, halves = doubling_tables(degree)
    F = np.empty((q + 1, nz, nz))
    Ls = [float(v) for v in lengths]                # a few lengths: plain floats
    done = [False] * len(Ls)
    for i in sorted(range(len(Ls)), key=lambda i: -Ls[i]):
        if done[i]:
            continue
        L = Ls[i]
        x = norm * L
        s = halvings(x)
        # deep enough to pass through every shorter length that is L / 2^j
        for j, other in enumerate(Ls):
            if not done[j] and 0.0 < other < L:
                r = math.log2(L / other)
                if abs(r - round(r)) <= 1e-9:
                    s = max(s, round(r))
        h = L / 2.0 ** s
        phi_functions(Ab * h, F)
        Phi = np.ascontiguousarray(F[0])
        P = np.ascontiguousarray(h * F[1:][:, :, cols])                  # (q, nz, c)
        for level in range(s, -1, -1):
            length = L / 2.0 ** level
            # the lengths equal to this one (to 1e-12 relative) take it
            for j, other in enumerate(Ls):
                if not done[j] and abs(other - length) <= 1e-12 * L:
                    Phis[j], Ps[j] = Phi, P.transpose(1, 0, 2)
                    done[j] = True
            if level:
                phi_double(Phi, P, mix, halves)
    return Phis, Ps


def _propagate_defect(A: np.ndarray, tn: np.ndarray, C: np.ndarray,
                      cols: np.ndarray | None = None, balance: tuple | None = None) -> np.ndarray:
    """e (n, nz) at the times tn (n,) of ė = A e + d, e(0) = 0, d on each
    interval the cubic of C (n − 1, 4, c) (ascending powers of σ) in its
    columns ``cols`` (c,) and zero in the others (all columns by default;
    a translation's kinematic row ṙ = v is exact: its defect is 0):
    ``e_{j+1} = Φ e_j + Σ_p P_p w_p``, w_p = p! C[j, p] its σ-derivatives
    at the interval's start. In the balanced coordinates e' = S⁻¹ e of
    :func:`defect_propagators` (d' = S⁻¹ d, e = S e' at the end: the
    propagators are used as computed); the sums Σ_p P_p w_p as one matrix
    product per distinct interval length, and the recursion, in one
    compiled pass (:func:`flexbed.dynamics.linear.defect.defect_sweep`).
    ``balance`` is (A', S) when already made
    (:attr:`Linearisation.balanced`)."""
    nz = A.shape[0]
    cols = np.arange(nz) if cols is None else cols
    lengths, which = _lengths(np.diff(tn))
    Ab, scale = balanced(A) if balance is None else balance
    Phis, Ps = _balanced_propagators(Ab, lengths, 3, cols)
    E = np.empty((tn.size, nz))
    defect_sweep(Phis, Ps.reshape(lengths.size, nz, -1), which, np.ascontiguousarray(C),
                 scale[cols], scale, E)
    return E


def _error_on_every_sample(A: np.ndarray, t: np.ndarray, nodes: np.ndarray,
                           C: np.ndarray, cols: np.ndarray | None = None,
                           balance: tuple | None = None) -> np.ndarray:
    """e (k, nz) on every sample from e(0) = 0: the defect's local cubics
    C (n − 1, 4, c) between the nodes (its columns ``cols``, all by
    default), each restricted to the samples' intervals and propagated
    exactly sample by sample (at the nodes the same e as the sweep over
    the nodes, to round-off)."""
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
    return _propagate_defect(A, t, C_samples, cols, balance)


def estimate_error(system: System, lin: Linearisation, t: np.ndarray, Z: np.ndarray,
                   samples: np.ndarray | None = None) -> ErrorEstimate:
    """Defect of the linear solution in the nonlinear equations, propagated
    (see the module docstring).

    Parameters
    ----------
    t : (k,) [s], Z : (k, nz)
        The linear solution at the piece ends of its propagation
        (:func:`flexbed.dynamics.linear.propagation.propagate_pieces`):
        the nodes are among them, and the largest errors are taken over
        all of them.
    samples : (s,) int, optional
        Where the output samples are among them (all by default): the
        motion is taken over them, and the powers, their integrals and
        :attr:`ErrorEstimate.e` are given there.
    """
    coords = lin.coords
    nfev0 = system.nfev
    npos = coords.n_pos
    T = _point_map(system, coords).reshape(-1, coords.nz)[:, :npos]     # (3P, n_pos)
    A = np.ascontiguousarray(lin.A)
    samples = np.arange(t.size) if samples is None else samples
    ts = t[samples]
    motion = largest_motion(Z, samples, np.ascontiguousarray(T)) if T.shape[0] else 0.0
    k = t.size
    if k < 2:                                  # the start only: e(0) = 0
        none = np.zeros((ts.size, system.layout.work.stop - system.layout.work.start))
        return ErrorEstimate(0.0, 0.0, motion, True, 0, none, np.arange(k),
                             np.zeros((k, coords.nz)), none, _e=np.zeros((ts.size, coords.nz)))
    nodes, D, W = _defect_nodes(system, lin, t, Z)
    tn = t[nodes]
    cols = np.flatnonzero(np.any(D != 0.0, axis=0))      # d's columns that are not all 0
    C = _cubics(tn, D[:, cols])
    CW = _cubics(tn, W)
    powers, works = np.empty((ts.size, W.shape[1])), np.empty((ts.size, W.shape[1]))
    pieces_at(ts, tn, CW, powers)
    pieces_integral_at(ts, tn, CW, works)
    # ė = A e + d, d the local cubics: Φ, P0 … P3 per distinct interval
    En = _propagate_defect(A, tn, C, cols, lin.balanced)
    # the points' errors between the nodes: cubic Hermite with ė = A e + d
    # there; each rotation alone likewise, as (θ_i, 0, 0)
    pos, rot = error_peaks(t, nodes, En, np.ascontiguousarray(D), A, np.ascontiguousarray(T),
                           coords._th.reshape(-1))
    reliable = pos <= 0.1 * motion or pos < 1e-12

    def every_sample():
        return _error_on_every_sample(A, t, nodes, C, cols, lin.balanced)[samples]

    return ErrorEstimate(pos, rot, motion, reliable, system.nfev - nfev0, powers, nodes, En,
                         works, every_sample)
