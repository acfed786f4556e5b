"""The linear fast path's exact propagation of the linear model
(:mod:`flexbed.dynamics.linear.model`) over the output samples.

Exact propagation
-----------------
Time is cut at the output samples and at every knot of the inputs (curve
samples, pulse corners, sinusoid window ends). On each piece
``[t_k, t_k + h]`` each input channel is the sum of its analytic sinusoids
``c_s sin ωt + c_c cos ωt`` (while the piece lies in their window) and a
polynomial of degree ≤ 5 in ``σ = (t − t_k)/h`` — exactly so for the
scene's piecewise inputs (cubic spline loads, their first and second
integrals for drives: degree 5; pulses; a sinusoid's integrals: degree 1),
whose coefficients come from six samples at Chebyshev points inside the
piece. A sinusoid is the solution of a two-state linear system: with
``x_s = c_s sin ωt + c_c cos ωt`` and ``x_c = c_s cos ωt − c_c sin ωt``,
``d/dσ (x_s, x_c) = ωh (x_c, −x_s)``. The state, the polynomials'
σ-derivatives ``w_m`` (shifted: ``w_m' = w_{m+1}``), the constant of b0
and the sinusoids' pairs together obey a constant linear system,

    d/dσ [z; w] = [[h A, h G], [0, S]] [z; w],

so one matrix exponential per distinct piece length gives
``z(t_k + h) = Φ z(t_k) + Ψ w_k`` without any truncation error (Van Loan's
block method); a uniform output grid has one or a few lengths. Without
sinusoids the blocks are ``Φ = e^{hA}`` and ``Ψ = [h φ_{m+1}(hA) B_j … |
h φ_1(hA) b0]``, summed by their series to round-off on A balanced by
powers of 2 (:class:`_Exponential`). The
recursion runs in compiled code
(:func:`flexbed.dynamics.linear.sweep.linear_sweep`), the products
``Ψ w_k`` as one matrix product per length.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy.linalg import expm

from ..integrate import output_grid
from ..piecewise import PiecewisePolynomial
from .model import Linearisation
from .phi import doubling_tables, exp_and_phi_columns, halvings, norm1, phi_double
from .sweep import few_distinct, linear_sweep, merge_cuts, poly_derivatives

__all__ = ["propagate", "propagate_pieces"]

_DEG = 5                                   # degree of the inputs' local polynomials
_FEW = 32                                  # distinct piece lengths found without sorting
_POWER_MAX = 16                            # a length up to this times the shortest: its power
_NODES = 0.5 - 0.5 * np.cos((2 * np.arange(_DEG + 1) + 1) * np.pi / (2 * (_DEG + 1)))
_VINV = np.linalg.inv(_NODES[:, None] ** np.arange(_DEG + 1)[None, :])
_FACT = np.array([math.factorial(m) for m in range(_DEG + 1)], dtype=float)


def _pieces(lin: Linearisation, grid: np.ndarray) -> np.ndarray:
    """Piece boundaries: the output grid, the inputs' knots inside it, and
    extra cuts where a channel needs shorter pieces (none for analytic
    sinusoids: they are propagated exactly); a cut within 1e-9 of the
    output spacing of another time, or of a grid time, left out (compiled
    merge, :func:`flexbed.dynamics.linear.sweep.merge_cuts`)."""
    t_end = float(grid[-1])
    cuts = [grid]
    for c in lin.channels:
        kn = c.knots[(c.knots > 0.0) & (c.knots < t_end)]
        cuts.append(kn)
        if math.isfinite(c.max_piece) and not c.sines:
            cuts.append(np.arange(0.0, t_end, c.max_piece))
    tol = 1e-9 * (float(np.min(np.diff(grid))) if grid.size > 1 else t_end)
    if len(cuts) > 2:
        extra = np.sort(np.concatenate(cuts[1:]))
    else:                                         # one channel's knots: sorted already
        extra = cuts[1] if len(cuts) == 2 else np.zeros(0)
    out = np.empty(grid.size + extra.size)
    n = merge_cuts(grid, np.ascontiguousarray(extra, dtype=float), tol, out)
    return out[:n].copy() if n < out.size else out


def _lengths(h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct piece lengths (lengths equal to 1e-12 relative share one)
    and the index of each piece's: (m,) [s], (k,) int64."""
    if not h.size:
        return np.zeros(0), np.zeros(0, dtype=np.int64)
    keys = np.round(h * (1e12 / float(np.max(h))))
    which = np.empty(h.size, dtype=np.int64)
    first = np.empty(_FEW, dtype=np.int64)
    m = few_distinct(keys, which, first, _FEW)
    if m > 0:
        return h[first[:m]], which
    _, first, which = np.unique(keys, return_index=True, return_inverse=True)
    return h[first], which.astype(np.int64).reshape(-1)


def _sine_terms(lin: Linearisation) -> list[tuple[int, tuple]]:
    """(channel index, (ω, start, end, c_s, c_c)) of every analytic sinusoid."""
    return [(j, term) for j, c in enumerate(lin.channels) for term in c.sines]


def _propagators(lin: Linearisation, lengths: np.ndarray, terms: list) -> tuple:
    """Φ (m, nz, nz) and Ψ (m, nz, nw) of each distinct piece length h: the
    exponential of the state augmented with the inputs (module docstring),

        d/dσ [z; w] = [[h A, h G], [0, S]] [z; w],

    w = (each channel's polynomial σ-derivatives, degree ≤ 5; 1 for b0;
    each sinusoid's (x_s, x_c) rotating at ωh) (:class:`_Exponential`). A
    length k times the shortest (k ≤ 16) is the shortest's exponential to
    the k-th power (in t-derivatives: binary powers, a few products
    instead of an exponential)."""
    nz, nu = lin.B.shape
    d1 = _DEG + 1
    nw = nu * d1 + 1 + 2 * len(terms)
    Phis = np.empty((lengths.size, nz, nz))
    Psis = np.empty((lengths.size, nz, nw))
    # the σ-derivatives are h^m times the t-derivatives: E(h) = T_h E_t(h) T_h⁻¹
    # with E_t(h) = exp(h M_t), M_t free of h, so that E_t(k h) = E_t(h)^k
    degree = np.tile(np.arange(d1), nu)

    def scaling(h):
        s = np.ones(nz + nw)
        s[nz:nz + nu * d1] = h ** degree
        return s

    base = None
    exponential = _Exponential(lin, terms)
    for i in np.argsort(lengths, kind="stable"):
        h = float(lengths[i])
        k = round(h / base[0]) if base is not None else 0
        if base is not None and 2 <= k <= _POWER_MAX and abs(h - k * base[0]) <= 1e-12 * h:
            s = scaling(h)
            E = np.linalg.matrix_power(base[1], k) * (s[:, None] / s[None, :])
        else:
            E = exponential(h)
            if base is None:
                s = scaling(h)
                base = (h, E * (s[None, :] / s[:, None]))
        Phis[i], Psis[i] = E[:nz, :nz], E[:nz, nz:]
    return Phis, Psis


@functools.lru_cache(maxsize=8)
def _shift_exponential(nu: int) -> np.ndarray:
    """The exponential of the inputs' block without sinusoids (nu (deg + 1)
    + 1 square): each channel's shift of its σ-derivatives, 1/(m' − m)! at
    (m, m' ≥ m), and 1 for b0's constant (read-only)."""
    n = nu * (_DEG + 1) + 1
    E = np.zeros((n, n))
    for j in range(nu):
        c0 = j * (_DEG + 1)
        for m in range(_DEG + 1):
            for m2 in range(m, _DEG + 1):
                E[c0 + m, c0 + m2] = 1.0 / _FACT[m2 - m]
    E[-1, -1] = 1.0
    E.setflags(write=False)
    return E


class _Exponential:
    """The exponential E(h) ((nz + nw)², see :func:`_propagators`) of the
    augmented matrix of a piece of length h.

    Without sinusoids the inputs' block is the shift of each channel's
    σ-derivatives (and b0's constant): its exponential is known
    (1/(m' − m)! above the diagonal), and the rest is Φ = e^{hA} and
    Ψ = [h φ_{m+1}(hA) B_j … | h φ_1(hA) b0] (Van Loan's blocks): by
    their series in compiled code on the balanced A' = S⁻¹ A S
    (:func:`flexbed.dynamics.linear.phi.exp_and_phi_columns`, matrix–
    vector products for the columns; A' is :attr:`Linearisation.balanced`,
    shared with the error estimate), h halved s times to ‖hA'‖₁ ≤ 2
    and doubled back exactly (:func:`flexbed.dynamics.linear.phi.phi_double`).
    With sinusoids (their rotating pairs in the block): SciPy's ``expm`` of
    the whole augmented matrix."""

    def __init__(self, lin: Linearisation, terms: list):
        self.lin, self.terms = lin, terms
        nz, nu = lin.B.shape
        self.nz, self.nu = nz, nu
        self.nw = nu * (_DEG + 1) + 1 + 2 * len(terms)
        if not terms:
            self.Ab, self.scale = lin.balanced
            self.norm = norm1(self.Ab)
            G = np.column_stack([lin.B, lin.b0])
            self.G = np.ascontiguousarray(G / self.scale[:, None])        # S⁻¹ [B b0]
            self.tail = _shift_exponential(nu)                            # the inputs' block

    def __call__(self, h: float) -> np.ndarray:
        nz, nu, nw = self.nz, self.nu, self.nw
        if self.terms:
            return expm(self._matrix(h))
        x = self.norm * h
        s = halvings(x)
        hs = h / 2.0 ** s
        Phi = np.empty((nz, nz))
        P = np.empty((_DEG + 1, nz, nu + 1))
        exp_and_phi_columns(self.Ab * hs, self.G, hs, Phi, P)
        if s:
            mix, halves = doubling_tables(_DEG)
            for _ in range(s):
                phi_double(Phi, P, mix, halves)
        E = np.empty((nz + nw, nz + nw))
        E[nz:, :nz] = 0.0
        E[nz:, nz:] = self.tail
        sc = self.scale
        E[:nz, :nz] = Phi * (sc[:, None] / sc[None, :])
        # Ψ: channel j's σ-derivative m takes P_m B_j; b0 takes P_0 b0
        E[:nz, nz:nz + nu * (_DEG + 1)] = (P[:, :, :nu].transpose(1, 2, 0)
                                            .reshape(nz, -1) * sc[:, None])
        E[:nz, nz + nu * (_DEG + 1)] = P[0, :, nu] * sc
        return E

    def _matrix(self, h: float) -> np.ndarray:
        """The augmented matrix of a piece of length h (with sinusoids)."""
        lin, nz, nu = self.lin, self.nz, self.nu
        d1 = _DEG + 1
        M = np.zeros((nz + self.nw, nz + self.nw))
        M[:nz, :nz] = h * lin.A
        for j in range(nu):
            c0 = nz + j * d1
            M[:nz, c0] = h * lin.B[:, j]
            for m in range(_DEG):
                M[c0 + m, c0 + m + 1] = 1.0
        M[:nz, nz + nu * d1] = h * lin.b0
        for q, (j, (w, *_)) in enumerate(self.terms):
            cs = nz + nu * d1 + 1 + 2 * q
            M[:nz, cs] = h * lin.B[:, j]
            M[cs, cs + 1] = w * h
            M[cs + 1, cs] = -w * h
        return M


def _poly_derivatives(f: PiecewisePolynomial, t0: np.ndarray, h: np.ndarray,
                      out: np.ndarray) -> None:
    """Adds to out (k, 6) the σ-derivatives at σ = 0 of f on the pieces
    [t0, t0 + h] (each inside one of f's pieces, degree ≤ 5): h^m f^(m)(t0),
    by Horner from f's own coefficients (compiled:
    :func:`flexbed.dynamics.linear.sweep.poly_derivatives`)."""
    idx = np.searchsorted(f.breaks, t0 + 0.5 * h, side="right")
    poly_derivatives(f.coeffs, f.origins, idx, t0, h, out)


def _inputs_on_pieces(lin: Linearisation, t: np.ndarray, terms: list) -> np.ndarray:
    """The inputs' state w at the start of every piece (k, nw): each
    channel's remainder (less its sinusoids), a polynomial of degree ≤ 5
    in σ = (t − t_k)/h, by its σ-derivatives at 0 — from the channel's own
    piecewise polynomials where it has them (sampled loads and drives,
    pulses), else from six samples at Chebyshev points inside the piece;
    1 for b0; each sinusoid's x_s = c_s sin ωt_k + c_c cos ωt_k,
    x_c = c_s cos ωt_k − c_c sin ωt_k while the piece lies in its window
    (else 0)."""
    h = np.diff(t)
    k = h.size
    nu = len(lin.channels)
    mid = t[:-1] + 0.5 * h
    parts = []
    exact = [j for j, c in enumerate(lin.channels)
             if c.polys and not c.sines and max(f.degree for f in c.polys) <= _DEG]
    if nu and len(exact) == nu:
        Wd = np.zeros((k, nu, _DEG + 1))
        t0 = t[:-1]
        for j, c in enumerate(lin.channels):
            for f in c.polys:
                _poly_derivatives(f, t0, h, Wd[:, j])
            Wd[:, j, 0] -= lin.u0[j]
        parts.append(Wd.reshape(k, -1))
        parts.append(np.ones((k, 1)))
        return np.concatenate(parts, axis=1)
    ts = t[:-1, None] + h[:, None] * _NODES[None, :]                    # (k, 6)
    if nu:
        U = lin.inputs(ts.reshape(-1)).reshape(k, _DEG + 1, nu)
        S = np.empty((k, 2 * len(terms)))
        for q, (j, (w, start, end, cs, cc)) in enumerate(terms):
            on = ((mid >= start) & (mid < end)).astype(float)
            U[:, :, j] -= on[:, None] * (cs * np.sin(w * ts) + cc * np.cos(w * ts))
            sk, ck = np.sin(w * t[:-1]), np.cos(w * t[:-1])
            S[:, 2 * q] = on * (cs * sk + cc * ck)
            S[:, 2 * q + 1] = on * (cs * ck - cc * sk)
        C = np.einsum("mi,kiu->kum", _VINV, U)                          # σ^m coefficients
        parts.append((C * _FACT).reshape(k, -1))                         # σ-derivatives at 0
    parts.append(np.ones((k, 1)))
    if nu:
        parts.append(S)
    return np.concatenate(parts, axis=1)


def _step_inputs(Psis: np.ndarray, which: np.ndarray, W: np.ndarray,
                 out: np.ndarray) -> np.ndarray:
    """P_i = Ψ_{which[i]} W_i written into ``out`` (k, nz): one matrix
    product per run of equal pieces when they come in a few runs (the
    load's knots, then longer output samples), else one per distinct
    length."""
    if Psis.shape[0] == 1:
        return np.matmul(W, Psis[0].T, out=out)
    cuts = np.flatnonzero(np.diff(which)) + 1
    if cuts.size < 16:
        for a, b in zip(np.concatenate([[0], cuts]), np.append(cuts, which.size)):
            np.matmul(W[a:b], Psis[which[a]].T, out=out[a:b])
        return out
    for i in range(Psis.shape[0]):
        sel = which == i
        out[sel] = W[sel] @ Psis[i].T
    return out


def propagate_pieces(lin: Linearisation, z0: np.ndarray, t_end: float,
                     output_dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact solution of the linear model at every piece end: the output
    samples and the inputs' knots between them.

    Returns
    -------
    t : (k,) [s], the piece ends; Z : (k, nz) deviations there;
    samples : (s,) int, where the output samples are among them.
    """
    grid = output_grid(t_end, output_dt)
    t = _pieces(lin, grid)
    lengths, which = _lengths(np.diff(t))
    terms = _sine_terms(lin)
    Phis, Psis = _propagators(lin, lengths, terms)
    # the inputs' parts P_i are written into Z[1:] and the sweep adds Φ z_i
    # to them in place: no second (k, nz) array (fresh pages cost more
    # than the products on them)
    Z = np.empty((t.size, lin.A.shape[0]))
    P = _step_inputs(Psis, which, _inputs_on_pieces(lin, t, terms), Z[1:])
    linear_sweep(Phis, which, P, np.ascontiguousarray(z0, dtype=float), Z)
    samples = np.arange(t.size) if t.size == grid.size else np.searchsorted(t, grid)
    return t, Z, samples


def propagate(lin: Linearisation, z0: np.ndarray, t_end: float,
              output_dt: float) -> tuple[np.ndarray, np.ndarray, int]:
    """Exact solution of the linear model on the output grid.

    Returns
    -------
    t : (k,) [s]; Z : (k, nz) deviations; pieces : int, pieces propagated.
    """
    t, Z, samples = propagate_pieces(lin, z0, t_end, output_dt)
    if samples.size == t.size:               # no knot between the output samples
        return t, Z, int(t.size - 1)
    return t[samples], Z[samples], int(t.size - 1)
