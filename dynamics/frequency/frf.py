"""Frequency responses of the mounted system: transmissibility and the
frequency grid that resolves every resonance.

Steady state under ``e^{iωt}`` (a response is ``Re(H e^{iωt})``, so the
phase of H is the response's lead over the input), with
``G(ω) = K − ω² M + iω C``
(:class:`~flexbed.dynamics.frequency.mounted.MountedSystem`):

- base acceleration of unit amplitude along axis d: the base moves by
  ``x_b = −e_d/ω²``; in the relative coordinates ``u = q − ι x_b``,
  ``G u = −M ι_d`` (the inertial load of the base's motion), ``q = u + ι x_b``;
- a unit force along axis d at a point with position Jacobian ``J`` (3, n):
  ``G q = J[d]ᵀ`` (virtual work), the base at rest.

An output is linear in the motion: ``y = Y_q q + Y_b x_b`` for positions
(a point's, given by its Jacobian over [base translation (3), q]), and
``F_q u + iω F_v u`` for the mount forces and the force on the base (they
see only relative motion). Accelerations are ``−ω²`` times positions; an
acceleration's transmissibility from the base is ``−ω² y`` [1].
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from .blocks import block_plan, solve_blocks
from .modal import Modes
from .mounted import MountedSystem

__all__ = ["Outputs", "Input", "Sweep", "responses", "resonance_grid", "peak_search", "sweep",
           "mount_outputs", "isolation", "unit_crossings", "base_responses",
           "dynamic_stiffness"]

_CHUNK = 128                          # frequencies per batched solve
#: above this many coordinates the sparse path (:func:`_responses_sparse`;
#: the reference scene has 18, and keeps the batched dense solves)
DENSE_LIMIT = 30


@dataclass(frozen=True)
class Input:
    """What drives the system: ``kind`` "base" (unit base acceleration
    [m/s²] along ``axis``) or "force" (unit force [N] with generalized
    force ``load`` (n,), real, or complex for forces in quadrature such as
    a rotating unbalance's, base at rest)."""

    kind: str
    axis: int
    load: np.ndarray | None = None


@dataclass(frozen=True)
class Outputs:
    """Linear outputs: ``positions`` (p, 3 + n) Jacobians of point
    coordinates over [base translation, q] [m per m]; ``forces`` (f, n)
    and ``force_rates`` (f, n) of forces over relative q and q̇ [N per m,
    N s per m] (any output linear in the relative motion: a mount's
    deflection is ``D`` with zero rates). Rows of each kind in the caller's
    order. ``order``: the points' time derivative returned, 0
    displacement [m], 1 velocity [m/s], 2 acceleration [m/s²] (default).
    ``elastomer`` (f, r): how each force row takes the elastomer rows'
    extra forces (:meth:`~flexbed.dynamics.frequency.elastomer.ComplexStiffness.force_rows`),
    or None (no elastomer mounts, or outputs that ignore them)."""

    positions: np.ndarray
    forces: np.ndarray
    force_rates: np.ndarray
    order: int = 2
    elastomer: np.ndarray | None = None


def mount_outputs(ms: MountedSystem) -> tuple[np.ndarray, np.ndarray]:
    """The forces along every mount axis, then the total force on the base
    (X, Y, Z): ``(forces (3M + 3, n), force_rates (3M + 3, n))``."""
    return np.vstack([ms.Fq, ms.Bq]), np.vstack([ms.Fv, ms.Bv])


def responses(ms: MountedSystem, omega: np.ndarray, inp: Input, out: Outputs):
    """H at the angular frequencies ``omega`` (k,) [rad/s], all > 0.

    Returns
    -------
    acceleration : (k, p) complex
        Point accelerations per unit input [1 or m/s² per N] (``−ω²``
        times the positions); with ``out.order`` 1 or 0 the velocities
        (``iω`` times) [s, m/s per N] or the displacements [s², m per N].
    force : (k, f) complex
        Forces per unit input [N per m/s², or N per N].
    """
    omega = np.asarray(omega, dtype=float).reshape(-1)
    n = ms.n
    if n > DENSE_LIMIT and ms.sparse is not None:
        return _responses_sparse(ms, omega, inp, out)
    acc = np.empty((omega.size, out.positions.shape[0]), dtype=complex)
    frc = np.empty((omega.size, out.forces.shape[0]), dtype=complex)
    if inp.kind == "base":
        rhs = -(ms.M @ ms.iota[:, inp.axis])
    else:
        rhs = np.asarray(inp.load)                  # real, or complex (an unbalance)
    Yb, Yq = out.positions[:, :3], out.positions[:, 3:]
    for s in range(0, omega.size, _CHUNK):
        w = omega[s:s + _CHUNK]
        G = dynamic_stiffness(ms, w)
        x = np.linalg.solve(G, np.broadcast_to(rhs + 0j, (w.size, n))[..., None])[..., 0]
        if inp.kind == "base":
            xb = -1.0 / (w * w)                                    # base displacement
            u = x
            q = u + xb[:, None] * ms.iota[:, inp.axis][None, :]
            pos = q @ Yq.T + xb[:, None] * Yb[:, inp.axis][None, :]
        else:
            u = q = x
            pos = q @ Yq.T
        acc[s:s + w.size] = _derivative(pos, w, out.order)
        frc[s:s + w.size] = u @ out.forces.T + (1j * w)[:, None] * (u @ out.force_rates.T)
        if out.elastomer is not None:
            frc[s:s + w.size] += ms.elastomer.force_rows(w, u) @ out.elastomer.T
    return acc, frc


def dynamic_stiffness(ms: MountedSystem, w: np.ndarray) -> np.ndarray:
    """``G(ω) = K − ω² M + iω C`` (k, n, n) complex at ω (k,) [rad/s], plus
    the elastomer mounts' complex stiffness less their static one
    (:mod:`flexbed.dynamics.frequency.elastomer`) when ``ms`` has any."""
    G = (ms.K[None] - (w * w)[:, None, None] * ms.M[None]
         + (1j * w)[:, None, None] * ms.C[None])
    if ms.elastomer is not None:
        G += ms.elastomer.added(w)
    return G


def base_responses(ms: MountedSystem, omega: np.ndarray, axes: list[int], out: Outputs
                   ) -> tuple[np.ndarray, np.ndarray]:
    """:func:`responses` to unit base accelerations along several ``axes``
    (r,) at once: one factorisation of G per frequency for all of them.

    Returns ``(points (k, r, p), forces (k, r, f))`` complex, as
    :func:`responses` per axis (the same equations; a system above
    :data:`DENSE_LIMIT` coordinates is solved by :func:`responses`, axis by
    axis)."""
    omega = np.asarray(omega, dtype=float).reshape(-1)
    r = len(axes)
    pts = np.empty((omega.size, r, out.positions.shape[0]), dtype=complex)
    frc = np.empty((omega.size, r, out.forces.shape[0]), dtype=complex)
    if ms.n > DENSE_LIMIT and ms.sparse is not None:
        for j, d in enumerate(axes):
            pts[:, j], frc[:, j] = responses(ms, omega, Input("base", d), out)
        return pts, frc
    iota = ms.iota[:, axes]                                          # (n, r)
    rhs = -(ms.M @ iota) + 0j                                        # (n, r)
    Yb, Yq = out.positions[:, :3], out.positions[:, 3:]
    for s in range(0, omega.size, _CHUNK):
        w = omega[s:s + _CHUNK]
        u = np.linalg.solve(dynamic_stiffness(ms, w),
                            np.broadcast_to(rhs, (w.size,) + rhs.shape))   # (k, n, r)
        u = u.transpose(0, 2, 1).reshape(-1, ms.n)                   # (k r, n)
        xb = np.repeat(-1.0 / (w * w), r)                            # base displacement
        q = u + xb[:, None] * np.tile(iota.T, (w.size, 1))
        pos = _real_product(q, Yq.T) + xb[:, None] * np.tile(Yb[:, axes].T, (w.size, 1))
        pts[s:s + w.size] = _derivative(pos, np.repeat(w, r), out.order).reshape(
            w.size, r, -1)
        f = _real_product(u, out.forces.T) + np.repeat(1j * w, r)[:, None] * _real_product(
            u, out.force_rates.T)
        if out.elastomer is not None:
            f += ms.elastomer.force_rows(np.repeat(w, r), u) @ out.elastomer.T
        frc[s:s + w.size] = f.reshape(w.size, r, -1)
    return pts, frc


def _real_product(z: np.ndarray, a: np.ndarray) -> np.ndarray:
    """``z @ a`` for complex z (m, n) and real a (n, p), as two real products."""
    out = np.empty((z.shape[0], a.shape[1]), dtype=complex)
    out.real = z.real @ a
    out.imag = z.imag @ a
    return out


def _derivative(pos: np.ndarray, w: np.ndarray, order: int) -> np.ndarray:
    """``(iω)^order`` times the positions (k, p) at ω (k,) [rad/s]."""
    if order == 2:
        return -(w * w)[:, None] * pos
    if order == 1:
        return (1j * w)[:, None] * pos
    return pos


_PLANS: dict = {}


def _plan(ms: MountedSystem):
    """The block plan of ``ms`` (made once per mounted system)."""
    key = id(ms)
    got = _PLANS.get(key)
    if got is None or got[0]() is not ms:
        Ms, Ks, Cs = ms.sparse
        got = _PLANS[key] = (weakref.ref(ms), block_plan(Ks, Ms, Cs, ms.body))
        weakref.finalize(ms, _PLANS.pop, key, None)
    return got[1]


def _responses_sparse(ms: MountedSystem, omega: np.ndarray, inp: Input, out: Outputs):
    """:func:`responses` of a large system: the dynamic stiffness
    ``G(ω) = K − ω² M + iω C`` solved by blocks
    (:mod:`flexbed.dynamics.frequency.blocks`: the leaf bodies eliminated,
    many frequencies at once) or, when the hubs are many, factorised sparse
    per frequency (SuperLU); the outputs through sparse matrices. Same
    equations, same results to round-off."""
    Ms, Ks, Cs = ms.sparse
    n = ms.n
    iota = ms.iota[:, inp.axis]
    rhs = -(Ms @ iota) if inp.kind == "base" else np.asarray(inp.load)
    rhs = rhs.astype(complex)
    plan = _plan(ms)
    if plan is not None:
        X = solve_blocks(plan, omega, rhs)
    else:
        Kc, Mc, Cc = (sp.csc_matrix(a, dtype=complex) for a in (Ks, Ms, Cs))
        X = np.empty((omega.size, n), dtype=complex)
        for k, w in enumerate(omega):
            X[k] = splu(Kc - (w * w) * Mc + (1j * w) * Cc).solve(rhs)
    Yb, Yq = out.positions[:, :3], sp.csr_matrix(out.positions[:, 3:])
    Fs, Fr = sp.csr_matrix(out.forces), sp.csr_matrix(out.force_rates)
    w = omega
    if inp.kind == "base":
        xb = -1.0 / (w * w)
        U = X
        Q = U + xb[:, None] * iota[None, :]
        pos = (Yq @ Q.T).T + xb[:, None] * Yb[:, inp.axis][None, :]
    else:
        U = X
        pos = (Yq @ X.T).T
    acc = _derivative(pos, w, out.order)
    frc = (Fs @ U.T).T + (1j * w)[:, None] * (Fr @ U.T).T
    return acc, frc


#: Most golden-section steps of :func:`peak_search` (a bound it never meets
#: on finite brackets: about 75 steps close any; see there).
PEAK_SEARCH_STEPS = 200


def resonance_grid(modes: Modes, f_min: float, f_max: float, n: int) -> np.ndarray:
    """Frequencies [Hz]: n log-spaced on [f_min, f_max] plus, around each
    mode in the band, points at ``fₙ(1 + ζ s)`` for s = 0, ±0.1, ±0.25,
    ±0.5, ±0.75, ±1 (the half-power points), ±1.5, ±2, ±3, ±5, ±8 (an
    undamped mode: at ``fₙ(1 ± 10⁻³ s)``, s ≠ 0, its peak being infinite)."""
    base = np.geomspace(f_min, f_max, n) if n > 1 else np.array([f_min, f_max])
    s = np.array([0.1, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0, 8.0])
    extra = []
    for f, z in zip(modes.frequency, modes.damping_ratio):
        if not (np.isfinite(f) and f_min <= f <= f_max and f > 0.0):
            continue
        if 0.0 < z < 1.0:
            extra.append(f * (1.0 + z * np.concatenate([[0.0], s, -s])))
        elif z == 0.0:
            extra.append(f * (1.0 + 1e-3 * np.concatenate([s, -s])))
    g = np.concatenate([base] + extra)
    g = np.unique(g[(g >= f_min) & (g <= f_max) & (g > 0.0)])
    return g


def peak_search(evaluate, lo: np.ndarray, hi: np.ndarray, xtol: np.ndarray,
                columns: np.ndarray) -> np.ndarray:
    """Golden-section search for the maxima of |H|, all brackets at once.

    Parameters
    ----------
    evaluate : callable
        f (k,) [Hz] → |H| (k, outputs).
    lo, hi : (P,) arrays
        Brackets [Hz], each holding one local maximum of its column.
    xtol : (P,) array
        Width [Hz] at which a bracket is resolved.
    columns : (P,) int
        The output whose peak each bracket holds.

    Returns
    -------
    (P,) array
        Peak frequencies [Hz], within xtol/2 of the maximum (xtol raised to
        8 units in the last place of the bracket's ends where it is finer:
        a bracket cannot be narrower than the spacing of doubles).

    The search ends: each step shrinks every open bracket by the golden
    ratio, so one of width W closes within log(W/xtol)/log(1.618) steps,
    and since W ≤ 2 max(|lo|, |hi|) and xtol ≥ 8 of that end's spacing
    (2.2e-16 of it, or the subnormal spacing), within about 75 steps;
    :data:`PEAK_SEARCH_STEPS` bounds the loop besides.
    """
    g = (np.sqrt(5.0) - 1.0) / 2.0
    a, b = lo.astype(float).copy(), hi.astype(float).copy()
    xtol = np.maximum(xtol, 8.0 * np.spacing(np.maximum(np.abs(a), np.abs(b))))
    c = b - g * (b - a)
    d = a + g * (b - a)
    def at(x):
        """|H| of each bracket's column at its x (P,): every distinct
        frequency solved once (brackets of many outputs between the same
        grid points ask for the same frequencies)."""
        ux, inv = np.unique(x, return_inverse=True)
        return evaluate(ux)[inv, columns]

    fc = at(c)
    fd = at(d)
    for _ in range(PEAK_SEARCH_STEPS):
        if not np.any(b - a > xtol):
            break
        left = fc > fd                       # the maximum is in [a, d]
        a, b = np.where(left, a, c), np.where(left, d, b)
        x = np.where(left, b - g * (b - a), a + g * (b - a))
        fx = at(x)
        c, d, fc, fd = (np.where(left, x, d), np.where(left, c, x),
                        np.where(left, fx, fd), np.where(left, fc, fx))
    return 0.5 * (a + b)


@dataclass(frozen=True)
class Sweep:
    """An FRF over a grid that resolves its resonances.

    frequency : (k,) [Hz]; acceleration : (k, p) complex; force : (k, f)
    complex (as :func:`responses`); peaks : (P, 3) rows (output column in
    [acceleration | force], peak frequency [Hz], peak |H|), each local
    maximum of each output located to 0.1 % of its mode's half-power
    bandwidth 2ζfₙ; evaluations : frequencies solved for.
    """

    frequency: np.ndarray
    acceleration: np.ndarray
    force: np.ndarray
    peaks: np.ndarray
    evaluations: int


def sweep(ms: MountedSystem, modes: Modes, inp: Input, out: Outputs, f_min: float,
          f_max: float, n: int = 400, frequencies: np.ndarray | None = None,
          resolution: float = 1e-3) -> Sweep:
    """The FRF on :func:`resonance_grid` (or on ``frequencies`` [Hz] as
    given, unrefined), with every local maximum of every output's |H| that
    lies near a damped mode refined by :func:`peak_search` to ``resolution``
    times that mode's half-power bandwidth and added to the grid."""
    count = [0]

    def solve(f):
        count[0] += f.size
        a, fr = responses(ms, 2.0 * np.pi * f, inp, out)
        return a, fr

    if frequencies is not None:
        f = np.asarray(frequencies, dtype=float)
        a, fr = solve(f)
        return Sweep(f, a, fr, np.zeros((0, 3)), count[0])
    f = resonance_grid(modes, f_min, f_max, n)
    a, fr = solve(f)
    mag = np.abs(np.hstack([a, fr]))
    interior = (mag[1:-1] >= mag[:-2]) & (mag[1:-1] >= mag[2:]) & (mag[1:-1] > 0.0)
    i, col = np.nonzero(interior)
    i = i + 1
    fn, zeta = modes.frequency, modes.damping_ratio
    damped = (zeta > 0.0) & (zeta < 1.0) & np.isfinite(fn)
    peaks = np.zeros((0, 3))
    if i.size and np.any(damped):
        log_fn = np.where(damped, np.log(np.where(fn > 0.0, fn, 1.0)), np.inf)
        near = np.argmin(np.abs(np.log(f[i])[:, None] - log_fn[None, :]), axis=1)
        xtol = resolution * 2.0 * zeta[near] * fn[near]
        lo, hi = f[i - 1], f[i + 1]

        def evaluate(x):
            aa, ff = solve(x)
            return np.abs(np.hstack([aa, ff]))

        fp = peak_search(evaluate, lo, hi, xtol, col)
        ap, frp = solve(fp)
        hp = np.abs(np.hstack([ap, frp]))[np.arange(fp.size), col]
        peaks = np.column_stack([col, fp, hp])
        f_all = np.concatenate([f, fp])
        order = np.argsort(f_all, kind="stable")
        keep = np.concatenate([[True], np.diff(f_all[order]) > 0.0])
        f = f_all[order][keep]
        a = np.vstack([a, ap])[order][keep]
        fr = np.vstack([fr, frp])[order][keep]
    return Sweep(f, a, fr, peaks, count[0])


def isolation(transmissibility: np.ndarray) -> np.ndarray:
    """Isolation efficiency 1 − |T| [1] where |T| < 1, NaN elsewhere."""
    m = np.abs(transmissibility)
    return np.where(m < 1.0, 1.0 - m, np.nan)


def unit_crossings(evaluate, frequency: np.ndarray, magnitude: np.ndarray,
                   rtol: float = 1e-12, batched: bool = False) -> np.ndarray:
    """The frequency above which each output's |H| stays below 1 (the
    isolation crossing), located between grid points rather than read off
    the grid.

    Parameters
    ----------
    evaluate : callable
        f (k,) [Hz] → |H| (k, outputs) of the same outputs.
    frequency : (k,) array
        The grid [Hz], increasing.
    magnitude : (k, o) array
        |H| on the grid.
    rtol : float
        Relative width [1] at which a crossing is located (Brent's method on
        ``|H(f)| − 1`` between the last grid point with |H| ≥ 1 and the next).
    batched : bool
        Every output's search at once (:func:`_crossings_batched`: one call
        of ``evaluate`` per step for all of them, where a large system's
        per-call cost dominates) rather than Brent's method output by output.

    Returns
    -------
    (o,) array
        The crossing [Hz]; NaN where |H| ≥ 1 at the grid's top (no isolation
        in the band) or |H| < 1 on the whole grid (no crossing in it).
    """
    from scipy.optimize import brentq

    out = np.full(magnitude.shape[1], np.nan)
    if batched:
        last = np.array([np.flatnonzero(magnitude[:, j] >= 1.0)[-1]
                         if np.any(magnitude[:, j] >= 1.0) else -1
                         for j in range(magnitude.shape[1])])
        cols = np.flatnonzero((last >= 0) & (last + 1 < frequency.size))
        if cols.size:
            i = last[cols]
            out[cols] = _crossings_batched(evaluate, frequency[i], frequency[i + 1],
                                           magnitude[i, cols] - 1.0,
                                           magnitude[i + 1, cols] - 1.0, cols, rtol)
        return out
    for j in range(magnitude.shape[1]):
        above = np.flatnonzero(magnitude[:, j] >= 1.0)
        if not above.size or above[-1] + 1 >= frequency.size:
            continue
        lo, hi = frequency[above[-1]], frequency[above[-1] + 1]
        out[j] = brentq(lambda f, j=j: float(evaluate(np.array([f]))[0, j]) - 1.0, lo, hi,
                        xtol=rtol * hi, rtol=4.0 * np.finfo(float).eps)
    return out


#: most steps of :func:`_crossings_batched` (each at least halves a bracket
#: once in two steps; 2 × 64 halvings close any bracket of doubles)
CROSSING_STEPS = 200


def _crossings_batched(evaluate, a: np.ndarray, b: np.ndarray, fa: np.ndarray,
                       fb: np.ndarray, columns: np.ndarray, rtol: float) -> np.ndarray:
    """Roots of ``|H_j(f)| − 1`` in [a_j, b_j] (P,) for every column j at
    once, by Chandrupatla's method (inverse quadratic interpolation where
    it is safe, bisection otherwise: Chandrupatla, Adv. Eng. Software 28,
    1997), all brackets advanced together so that each step is one call of
    ``evaluate`` at P frequencies. fa ≥ 0 > fb (|H| − 1 at the ends). A
    bracket ends when its width is within ``rtol`` of its end (as brentq's
    ``xtol = rtol · hi``) or 4 units in the last place; returns the end
    of smaller |f| (P,) [Hz]."""
    a, b, fa, fb = (np.asarray(v, dtype=float).copy() for v in (a, b, fa, fb))
    c, fc = a.copy(), fa.copy()
    t = np.full(a.shape, 0.5)
    done = (fa == 0.0) | (fb == 0.0)
    xm = np.where(np.abs(fa) < np.abs(fb), a, b)
    for _ in range(CROSSING_STEPS):
        if done.all():
            break
        x = a + t * (b - a)
        live = ~done
        fx = np.zeros_like(x)
        ux, inv = np.unique(x[live], return_inverse=True)
        fx[live] = evaluate(ux)[inv, columns[live]] - 1.0
        same = np.sign(fx) == np.sign(fa)
        c = np.where(live, np.where(same, a, b), c)
        fc = np.where(live, np.where(same, fa, fb), fc)
        b = np.where(live & ~same, a, b)
        fb = np.where(live & ~same, fa, fb)
        a = np.where(live, x, a)
        fa = np.where(live, fx, fa)
        small = np.abs(fa) < np.abs(fb)
        xm = np.where(live, np.where(small, a, b), xm)
        fm = np.where(small, fa, fb)
        tol = np.maximum(rtol * np.maximum(np.abs(b), np.abs(c)),
                         4.0 * np.spacing(np.abs(xm)))
        width = np.abs(b - c)
        tlim = np.divide(tol, width, out=np.ones_like(tol), where=width > 0.0)
        done |= (tlim > 0.5) | (fm == 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            xi = (a - b) / (c - b)
            ph = (fa - fb) / (fc - fb)
            iqi = (ph * ph < xi) & ((1.0 - ph) ** 2 < 1.0 - xi)
            t_iqi = (fa / (fb - fa) * fc / (fb - fc)
                     + (c - a) / (b - a) * fa / (fc - fa) * fb / (fc - fb))
        t = np.where(iqi & np.isfinite(t_iqi), t_iqi, 0.5)
        t = np.clip(t, tlim, 1.0 - tlim)
    return xm
