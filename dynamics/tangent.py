"""The exact tangent stiffness and damping at rest, block-sparse by the mount graph.

At a state where nothing moves (every body's ṙ, ω̄, ȧ and the base's
velocity nil: a static equilibrium) the derivatives of the generalized
forces are written out analytically, so that the mounted system's K and C
carry round-off only, where central differences of the right-hand side
(:mod:`flexbed.dynamics.jacobian`) carry the step's truncation and the
preloads' cancellation (on the reference scene 2.8e-11 of K's largest
entry, up to 1.8e-9 of an entry), which a mode with ζ ≈ 1e-5 amplifies
1/(2ζ)-fold at its resonance.

Positions, deflections and forces come from one evaluation of the one
right-hand side (its work arrays: ``w_A``, ``w_P``, ``w_ub``, ``w_dx``,
``w_f``, ``w_F``); only their derivatives are written here. With a body's
unknowns δr (inertial), δθ (body frame, ``p ← p ⊗ p(δθ)``) and δa, the
end e of a mount on body b moves by ``δP_e = E_e δq_b`` with
``E_e = [I, −A_b ū_e~, A_b Φ_e]`` (and its velocity by ``E_e δv_b``). For
mount m (ends i, j; axes U in body i; λ = A_iᵀ (P_j − P_i); Δx = U λ − d0;
f = f(Δx, Δẋ); F̄ = Uᵀ f; F = A_i F̄ on P_i, −F on P_j):

    δλ  = A_iᵀ (E_j δq_j − E_i δq_i) + λ~ δθ_i
    δΔx = U δλ,   δf = f'(Δx) δΔx,   δF = A_i (Uᵀ δf − F̄~ δθ_i)

(f' the law's slope: k, the polynomial's or the spline's derivative, plus a
bump stop's contact stiffness when in contact). On the end's body (sign s =
+1 at i, −1 at j; ḡ = A_bᵀ F, body frame) the generalized force is
``s [F; ū × ḡ; Φ_eᵀ ḡ]``, so

    δḡ = A_bᵀ δF + ḡ~ δθ_b
    δQ = s [δF;  ū~ δḡ − ḡ~ Φ_e δa_b;  Φ_eᵀ δḡ]

— the first two terms of the moment row and ḡ~ δθ_b are the geometric
stiffness of the preloaded mount, whose axes turn with body i. The rates
alike, at rest: ``δΔẋ = U A_iᵀ (E_j δv_j − E_i δv_i)``, ``δf = c'(Δẋ) δΔẋ``,
``δF = A_i Uᵀ δf`` (the velocity-quadratic terms have no first derivative
at rest). A flexible body's own terms (body frame, ḡ_b = A_bᵀ g, S = I2 + I3 a):
the moment of its weight ``S × ḡ_b`` and its modal weight ``I3ᵀ ḡ_b``
turn with it, its elastic and structural forces are ``−K a − C ȧ``:

    δQ_ω = S~ ḡ_b~ δθ − ḡ_b~ I3 δa,   δQ_a = I3ᵀ ḡ_b~ δθ − K δa − C δȧ.

A rigid body's weight acts at its centre of mass (no moment) and is fixed
in the inertial frame: no term. A load on a body at ū (+ Φ a), of body-frame
value ḡ at t: fixed in space (ḡ = A_bᵀ F, δḡ = ḡ~ δθ), it adds
``ū~ ḡ~ δθ`` to the moment and ``Φᵀ ḡ~ δθ`` to the modal rows; turning with
the body, ``−A_b ḡ~ δθ`` to the force; both ``−ḡ~ Φ δa`` to the moment; a
moment fixed in space on a rigid body ``ḡ~ δθ`` (the kernel applies no
moment to a flexible body's equations). The rows are those of
:func:`flexbed.dynamics.block_linearisation.linearised` (``M v̇``: inertial
force, body-frame moment, modal forces); terms proportional to the
accelerations at the state (nil at an equilibrium, to the statics'
tolerance) are left out.

Not covered (:func:`uncovered` says why; the callers then take central
differences of everything): a state with motion (or a moving base), a
flexible body's frame without its modal coordinates, a law kind other than
linear, polynomial or curve data, loads on bodies at or past ``seg_end``.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .jacobian import by_topology, mount_graph
from .system import System

__all__ = ["Tangent", "tangent", "uncovered", "law_slopes"]

_KINDS = (0, 1, 2)              # linear, polynomial, curve data
_FIELDS = ("w_A", "w_P", "w_Pd", "w_ub", "w_dx", "w_dxd", "w_f", "w_F")


@dataclass(frozen=True)
class Tangent:
    """The exact derivatives of the generalized forces at rest.

    Kq, Kv : (n, n) sparse CSR (or arrays) — ∂(M v̇)/∂q [N/m, N/rad, …] and
    ∂(M v̇)/∂v [N s/m, …] in the unknowns of
    :func:`flexbed.dynamics.jacobian.mount_graph` (Kv None when not asked
    for: ``rates=False``); outputs_q, outputs_v :
    dict name → (3M, n) sparse CSR (or arrays), the derivatives of the
    mount fields ``w_dx`` [m], ``w_dxd`` [m/s], ``w_f`` [N], ``w_F`` [N];
    evaluations : int — right-hand sides it took (1).
    """

    Kq: sp.csr_matrix
    Kv: sp.csr_matrix
    outputs_q: dict
    outputs_v: dict
    evaluations: int


def uncovered(system: System, y: np.ndarray, modal: bool = True) -> str:
    """Why :func:`tangent` does not apply at the state y (ny,), or "" when it does
    (the base's velocity is checked by :func:`tangent` itself)."""
    lay = system.layout
    if system.flex_compiled and not modal:
        return "a flexible body's frame without its modal coordinates"
    if not set(np.unique(system.data.law_kind).tolist()) <= set(_KINDS):
        return "a mount law of another kind"
    v = np.concatenate([y[lay.v_rigid], y[lay.v_modal]])
    if np.any(v != 0.0):
        return "the bodies move"
    return ""


def _skew(v: np.ndarray) -> np.ndarray:
    """v~ (..., 3, 3) with v~ x = v × x, for v (..., 3)."""
    S = np.zeros(v.shape[:-1] + (3, 3))
    S[..., 0, 1], S[..., 0, 2] = -v[..., 2], v[..., 1]
    S[..., 1, 0], S[..., 1, 2] = v[..., 2], -v[..., 0]
    S[..., 2, 0], S[..., 2, 1] = -v[..., 1], v[..., 0]
    return S


def _poly_slope(c: np.ndarray, x: np.ndarray) -> np.ndarray:
    """d/dx Σ c_j x^j for rows c (k, d+1) at x (k,)."""
    acc = np.zeros_like(x)
    for j in range(c.shape[1] - 1, 0, -1):
        acc = acc * x + j * c[:, j]
    return acc


def _curve_slope(b: np.ndarray, o: np.ndarray, c: np.ndarray, x: float) -> float:
    """Slope of a piecewise polynomial (breaks b, origins o, ascending
    coefficients c; the piece the kernel's ``piecewise_value`` takes at x:
    right-continuous) at x."""
    lo = int(np.searchsorted(b, x, side="right"))
    u = x - o[lo]
    acc = 0.0
    for j in range(c.shape[1] - 1, 0, -1):
        acc = acc * u + j * c[lo, j]
    return acc


def law_slopes(system: System, dx: np.ndarray, dxd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """∂f/∂Δx [N/m] and ∂f/∂Δẋ [N s/m] (3M,) of every mount direction at
    the deflections dx and rates dxd (3M,), bump stops in contact included
    (decided as the kernel decides: by Δx, or held by an integrator)."""
    d = system.data
    kind, row = np.asarray(d.law_kind), np.asarray(d.law_row)
    kx, kv = np.zeros(kind.size), np.zeros(kind.size)
    lin = kind == 0
    kx[lin] = d.lin_kc[row[lin], 0]
    kv[lin] = d.lin_kc[row[lin], 1]
    poly = kind == 1
    if poly.any():
        kx[poly] = _poly_slope(np.asarray(d.poly_k)[row[poly]], dx[poly])
        kv[poly] = _poly_slope(np.asarray(d.poly_c)[row[poly]], dxd[poly])
    for il in np.flatnonzero(kind == 2):
        r = row[il]
        kx[il] = _curve_slope(d.crv_b[r, 0], d.crv_o[r, 0], d.crv_c[r, 0], dx[il])
        kv[il] = _curve_slope(d.crv_b[r, 1], d.crv_o[r, 1], d.crv_c[r, 1], dxd[il])
    gap = np.asarray(d.stop_gap)
    if gap.shape[0]:
        if d.w_hold[0] > 0.0:
            s = np.asarray(d.w_contact)
        else:
            s = np.where(dx < -gap[:, 0], -1.0, np.where(dx > gap[:, 1], 1.0, 0.0))
        on = s != 0.0
        kx[on] += d.stop_kc[on, 0]
        kv[on] += d.stop_kc[on, 1]
    return kx, kv


def _end_maps(system: System, graph, A: np.ndarray, ub: np.ndarray):
    """Per mount end (2M): E (3, W), the map from its body's unknowns (or
    rates) to the end's inertial displacement (velocity); Θ and Φ (3, W),
    the maps to the body's δθ and to the end's δū = Φ_e δa."""
    M, W = system.M, graph.width
    body = np.concatenate([system.body_i, system.body_j])
    slot = np.concatenate([graph.end_slot[:, 0], graph.end_slot[:, 1]])
    on = (slot >= 0)[:, None, None]
    Ab = A[body]
    eye = np.eye(3)
    E = np.zeros((2 * M, 3, W))
    Th = np.zeros((2 * M, 3, W))
    Ph = np.zeros((2 * M, 3, W))
    E[:, :, :3] = eye * on
    E[:, :, 3:6] = -(Ab @ _skew(ub)) * on
    Th[:, :, 3:6] = eye * on
    if graph.modal:
        end_flex = np.asarray(system.data.end_flex)
        for k, fc in enumerate(system.flex_compiled):
            ends = np.flatnonzero(end_flex == k)
            phi = np.asarray(system.data.end_phi)[ends, :, :fc.eom.n]
            Ph[ends, :, 6:6 + fc.eom.n] = phi
            E[ends, :, 6:6 + fc.eom.n] = Ab[ends] @ phi
    return E, Th, Ph, Ab


def tangent(system: System, y: np.ndarray, *, t: float = 0.0, seg_end: float = math.inf,
            modal: bool = True, capture: tuple = (), dense: bool = False,
            rates: bool = True) -> Tangent | None:
    """The exact :class:`Tangent` at the state y (ny,) at rest, or None where
    it does not apply (:func:`uncovered`, or the base moving at t).

    Parameters
    ----------
    system : System
    y : (ny,) array
        A state at rest (a static equilibrium).
    t, seg_end : float
        Time [s] and segment end of the one evaluation (as for ``System.rhs``).
    modal : bool
        The flexible bodies' modal coordinates are unknowns.
    capture : tuple of str
        Mount fields to differentiate too (``w_dx``, ``w_dxd``, ``w_f``, ``w_F``).
    dense : bool
        The matrices as arrays rather than CSR (cheaper for small systems).
    rates : bool
        Compute Kv and ``outputs_v`` too (False: the statics' Newton steps,
        which need Kq alone; they are then None and {}).
    """
    if uncovered(system, y, modal) or (system.scene.loads and t >= seg_end):
        return None
    system.rhs(float(t), y, seg_end)                # its work arrays keep this call's fields
    cap = {k: np.array(getattr(system.data, k)) for k in _FIELDS}
    if np.any(cap["w_Pd"] != 0.0) or not all(np.all(np.isfinite(v)) for v in cap.values()):
        return None
    g = mount_graph(system, modal)
    pat = _pattern(system, modal)
    M, W = system.M, g.width
    A, P, ub = cap["w_A"], cap["w_P"], cap["w_ub"]
    E, Th, Ph, Ab = _end_maps(system, g, A, ub)
    U = np.asarray(system.U)
    Ut = np.swapaxes(U, 1, 2)
    Ai = Ab[:M]
    AiT = np.swapaxes(Ai, 1, 2)
    lam = np.einsum("mji,mj->mi", Ai, P[M:] - P[:M])                    # A_iᵀ l
    Fbar = np.einsum("mkj,mk->mj", U, cap["w_f"])                       # Uᵀ f
    kx, kv = law_slopes(system, cap["w_dx"].ravel(), cap["w_dxd"].ravel())
    kx, kv = kx.reshape(M, 3, 1), kv.reshape(M, 3, 1)
    dl = np.concatenate([-E[:M], E[M:]], axis=2)                        # (M, 3, 2W)
    Thi = np.concatenate([Th[:M], np.zeros((M, 3, W))], axis=2)
    # positions
    dDx = U @ (AiT @ dl + _skew(lam) @ Thi)
    df = kx * dDx
    dF = Ai @ (Ut @ df - _skew(Fbar) @ Thi)
    # rates (at rest)
    if rates:
        dDv = U @ (AiT @ dl)
        dfv = kv * dDv
        dFv = Ai @ (Ut @ dfv)
    # the ends' generalized forces
    sg = np.concatenate([np.ones(M), -np.ones(M)])[:, None, None]
    own = np.zeros((2 * M, 3, 2 * W))
    own_phi = np.zeros((2 * M, 3, 2 * W))
    own[:M, :, :W], own[M:, :, W:] = Th[:M], Th[M:]
    own_phi[:M, :, :W], own_phi[M:, :, W:] = Ph[:M], Ph[M:]
    gx = _skew(np.einsum("eji,ej->ei", Ab, np.concatenate([cap["w_F"], cap["w_F"]])))
    AbT = np.swapaxes(Ab, 1, 2)
    ubx = _skew(ub)
    PhT = np.swapaxes(Ph[:, :, 6:], 1, 2)                               # (2M, W−6, 3)

    def end_rows(dFm, geometric):
        dFe = np.concatenate([dFm, dFm])                                 # (2M, 3, 2W)
        dg = AbT @ dFe
        if geometric:
            dg += gx @ own
        Q = np.empty((2 * M, W, 2 * W))
        Q[:, :3] = dFe
        Q[:, 3:6] = ubx @ dg
        if geometric:
            Q[:, 3:6] -= gx @ own_phi
        Q[:, 6:] = PhT @ dg
        return (sg * Q)[pat.ends]

    own_q, own_v = _own_terms(system, A, y, float(t))
    K, out = (pat.K.dense, pat.out.dense) if dense else (pat.K.csr, pat.out.csr)
    Kq = K(np.concatenate([end_rows(dF, True)] + own_q))
    fields_q = {"w_dx": dDx, "w_dxd": np.zeros_like(dDx), "w_f": df, "w_F": dF}
    outputs_q = {k: out(fields_q[k][pat.mounts]) for k in capture}
    if not rates:
        return Tangent(Kq, None, outputs_q, {}, 1)
    Kv = K(np.concatenate([end_rows(dFv, False)] + own_v))
    fields_v = {"w_dx": np.zeros_like(dDv), "w_dxd": dDv, "w_f": dfv, "w_F": dFv}
    outputs_v = {k: out(fields_v[k][pat.mounts]) for k in capture}
    return Tangent(Kq, Kv, outputs_q, outputs_v, 1)


@dataclass(frozen=True)
class _Scatter:
    """A sparsity pattern made once: entries (rows, cols) with repeats →
    a CSR matrix whose values are the sums of the entries' (:meth:`csr`)."""

    inverse: np.ndarray
    indices: np.ndarray
    indptr: np.ndarray
    shape: tuple
    flat: np.ndarray

    @classmethod
    def of(cls, rows: np.ndarray, cols: np.ndarray, shape: tuple) -> "_Scatter":
        lin = rows.astype(np.int64) * shape[1] + cols
        uniq, inverse = np.unique(lin, return_inverse=True)
        r = uniq // shape[1]
        indptr = np.searchsorted(r, np.arange(shape[0] + 1)).astype(np.int32)
        return cls(inverse.ravel(), (uniq % shape[1]).astype(np.int32), indptr, shape, lin)

    def csr(self, values: np.ndarray) -> sp.csr_matrix:
        data = np.bincount(self.inverse, weights=values, minlength=self.indices.size)
        return sp.csr_matrix((data, self.indices, self.indptr), shape=self.shape)

    def dense(self, values: np.ndarray) -> np.ndarray:
        return np.bincount(self.flat, weights=values,
                           minlength=self.shape[0] * self.shape[1]).reshape(self.shape)


@dataclass(frozen=True)
class _Pattern:
    """Where the ends' rows (``ends``: mask of (2M, W, 2W)) and the mounts'
    fields (``mounts``: mask of (M, 3, 2W)) go, and the patterns of K and
    of the mount fields' derivatives."""

    ends: np.ndarray
    mounts: np.ndarray
    K: _Scatter
    out: _Scatter


_PATTERNS: "weakref.WeakKeyDictionary[System, dict]" = weakref.WeakKeyDictionary()


def _pattern(system: System, modal: bool) -> _Pattern:
    """The :class:`_Pattern` of a system (made once per topology and
    ``modal``: :func:`flexbed.dynamics.jacobian.by_topology`)."""
    per = _PATTERNS.setdefault(system, {})
    if modal not in per:
        per[modal] = by_topology(system, f"tangent-pattern-{modal}",
                                 lambda: _make_pattern(system, modal))
    return per[modal]


def _make_pattern(system: System, modal: bool) -> _Pattern:
    g = mount_graph(system, modal)
    M, W, n = system.M, g.width, g.n
    table = np.full((len(g.blocks) + 1, W), -1, dtype=np.intp)    # last row: the base
    for s, blk in enumerate(g.blocks):
        table[s, :blk.size] = blk
    rows = table[np.concatenate([g.end_slot[:, 0], g.end_slot[:, 1]])]        # (2M, W)
    cols_m = np.concatenate([table[g.end_slot[:, 0]], table[g.end_slot[:, 1]]], axis=1)
    cols = np.concatenate([cols_m, cols_m])                                   # (2M, 2W)
    ends = (rows[:, :, None] >= 0) & (cols[:, None, :] >= 0)
    R = [np.broadcast_to(rows[:, :, None], ends.shape)[ends]]
    C = [np.broadcast_to(cols[:, None, :], ends.shape)[ends]]
    for slot in _own_slots(system):
        blk = g.blocks[slot]
        R.append(np.repeat(blk, blk.size))
        C.append(np.tile(blk, blk.size))
    mounts = np.broadcast_to((cols_m >= 0)[:, None, :], (M, 3, 2 * W))
    orow = np.broadcast_to((3 * np.arange(M)[:, None] + np.arange(3))[:, :, None],
                           mounts.shape)[mounts]
    ocol = np.broadcast_to(cols_m[:, None, :], mounts.shape)[mounts]
    return _Pattern(ends, mounts, _Scatter.of(np.concatenate(R), np.concatenate(C), (n, n)),
                    _Scatter.of(orow, ocol, (3 * M, n)))


def _own_slots(system: System) -> list:
    """The slots of the bodies with terms of their own: flexible, or loaded."""
    ints = np.asarray(system.data.in_ints)
    loaded = ints[ints[:, 2] == 2, 3] - 1
    return sorted({fc.slot for fc in system.flex_compiled} | set(loaded.tolist()))


def _own_terms(system: System, A: np.ndarray, y: np.ndarray, t: float):
    """A flexible body's weight turning with it, its modal stiffness and
    damping, and the loads on bodies (follower or fixed in space): lists of
    the values of each body's block (row-major, :func:`_own_slots`) in Kq and
    Kv."""
    d = system.data
    ints = np.asarray(d.in_ints)
    flex = {fc.slot: fc for fc in system.flex_compiled}
    q, v = [], []
    for slot in _own_slots(system):
        fc = flex.get(slot)
        nm = fc.eom.n if fc is not None else 0
        D = np.zeros((6 + nm, 6 + nm))
        Dv = np.zeros_like(D)
        Ab = A[slot + 1]
        if fc is not None:
            e = fc.eom
            gb = Ab.T @ np.asarray(system.g)
            I3 = np.asarray(e.I3)[:, :nm]
            S = np.asarray(e.I2) + I3 @ y[fc.qa]
            D[3:6, 3:6] = _skew(S) @ _skew(gb)
            D[3:6, 6:] = -_skew(gb) @ I3
            D[6:, 3:6] = I3.T @ _skew(gb)
            D[6:, 6:] = -np.asarray(e.K)[:nm, :nm]
            Dv[6:, 6:] = -np.asarray(e.C)[:nm, :nm]
        for i in np.flatnonzero((ints[:, 2] == 2) & (ints[:, 3] == slot + 1)):
            _, c, _, _, body_frame, moment = ints[i]
            val = float(system.inputs.compiled[i].values(np.array([t]))[0])
            gbar = val * (np.eye(3)[c] if body_frame else Ab[c])          # body frame [N, N m]
            gx = _skew(gbar)
            if moment:                       # a flexible body's moments: none (as the kernel)
                if fc is None and not body_frame:
                    D[3:6, 3:6] += gx
                continue
            phi = np.asarray(d.in_phi)[i, :, :nm]
            u = np.asarray(d.in_pt)[i] + (phi @ y[fc.qa] if fc is not None else 0.0)
            if body_frame:
                D[:3, 3:6] -= Ab @ gx
            else:
                D[3:6, 3:6] += _skew(u) @ gx
                D[6:, 3:6] += phi.T @ gx
            D[3:6, 6:] -= gx @ phi
        q.append(D.ravel())
        v.append(Dv.ravel())
    return q, v
