"""Static equilibrium by Newton–Raphson (paper section 3.2).

The unknowns are the free coordinates of every rigid body: a translation
δr (3) [m] and a small rotation δθ (3) [rad] about the body axes, applied as
``p ← p ⊗ p(δθ)``. The base is held at its scene position. The residual is
the generalized force on each body at rest, ``[m r̈, J ω̄̇]`` from the one
right-hand side (N, N·m). The Jacobian is the exact tangent stiffness at
rest (:func:`flexbed.dynamics.tangent.tangent`: one right-hand side and its
derivatives written out), where it applies; it leaves out the terms
proportional to the accelerations (a flexible body's ∂M(q)/∂q v̇, nil at an
equilibrium), so near the solution the steps are Newton's. For a scene of
rigid bodies with no loads of their own the tangent and the state update
are compiled (:mod:`flexbed.dynamics.rigid_statics`: the same formulas,
the tangent equal to round-off, the update bit for bit). Where the
tangent does not cover the scene (a law of another kind, a flexible body's
frame without its modal coordinates) the Jacobian is by central
differences (eq. 21) by colour classes of the mount graph
(:func:`flexbed.dynamics.jacobian.force_jacobian`).

Convergence: the Newton step is below ``tol`` (m, rad) and every residual
component is below ``tol`` times the body's force scale (its weight, or
1 N·(1 m) without gravity). Once converged, up to ``polish`` more steps are
taken while they still shrink, with the last Jacobian (a sparse one's factors
kept; a dense one of a few dozen unknowns is factorised again, some 10 µs),
which costs little and takes the answer to round-off.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from .rotation import A as rotation_matrix
from .jacobian import force_jacobian, perturbed_positions
from .maxwell_terms import relax_states, relaxed
from .rotation import quat_mul, rotvec_to_p
from .rigid_statics import rigid_tangent, step_state
from .system import System
from .tangent import _KINDS, _own_slots, law_slopes, tangent

__all__ = ["Equilibrium", "solve_statics", "COORDINATES", "DENSE_LIMIT"]

COORDINATES = ("x", "y", "z", "roll", "pitch", "yaw")

#: above this many unknowns the Newton steps use a sparse factorisation
#: (the reference scene has 18, 20 with two modes of its bed; SVDs of a few
#: hundred cost much more than the sparse test)
DENSE_LIMIT = 48

#: a direction is free when the smallest singular value of the scaled
#: Jacobian is below this fraction of the largest
SINGULAR_RATIO = 1e-11


@dataclass(frozen=True, slots=True)
class Equilibrium:
    """Result of :func:`solve_statics`.

    success : bool; message : str; y : (ny,) state at rest (the last iterate
    if it failed); iterations : int; residual : float — max |generalized
    force| scaled by the body's force scale [–]; step : float — last Newton
    step [m or rad]; residual_force : (n_rigid, 6) generalized forces [N, N m];
    jacobian_evaluations : int; rhs_evaluations : int; wall_time : float [s];
    tol : float; stability : "stable", "unstable" or "not checked" (set by
    whoever checks it, with :func:`flexbed.dynamics.stability.instability`);
    instability : :class:`~flexbed.dynamics.stability.Instability` when
    unstable, else None; jacobian : (n, n) array or CSR, or None — the last
    Newton Jacobian when it was the exact tangent stiffness
    (:func:`flexbed.dynamics.tangent.tangent`, or for rigid bodies
    :func:`flexbed.dynamics.rigid_statics.rigid_tangent`: ∂(M v̇)/∂q in the unknowns,
    6 per rigid body then the modal coordinates with ``sag``
    [N/m, N/rad, N m/m, N m/rad, …]), at the iterate before the polishing
    steps (which move the state by less than ``tol``); None when it was by
    differences or the solve failed. The stability check reuses it.
    mounts : (dx, f), each (M, 3), or None — the mounts' deflections [m] and
    forces [N] along their axes at ``y`` (the right-hand side's, the numbers
    of :func:`flexbed.dynamics.observation.observe` at t = 0 bit for bit),
    kept by a successful solve of a scene without Maxwell terms; None
    otherwise (then observe the state).
    """

    success: bool
    message: str
    y: np.ndarray
    iterations: int
    residual: float
    step: float
    residual_force: np.ndarray
    jacobian_evaluations: int
    rhs_evaluations: int
    wall_time: float
    tol: float
    history: tuple = field(default=())
    stability: str = "not checked"
    instability: object = None
    jacobian: object = field(default=None, repr=False, compare=False)
    mounts: tuple | None = field(default=None, repr=False, compare=False)


def _residual(system: System, y: np.ndarray, sag: bool = True) -> np.ndarray:
    """Generalized forces at rest, flat: 6 per body (N, N m) then, with
    ``sag``, the modal forces of the flexible bodies."""
    d = system.rhs(0.0, y)
    vr = d[system.layout.v_rigid].reshape(system.n_rigid, 6)
    rdd = vr[:, :3]                       # (n, 3): the slot of ṙ holds r̈
    wd = vr[:, 3:]
    R = np.empty((system.n_rigid, 6))
    R[:, :3] = system.m_r * rdd
    R[:, 3:] = np.einsum("nij,nj->ni", system.J, wd)
    if not system.flex_compiled:
        return R.ravel()
    modal = []
    p = system.layout.split(y)["p"]
    for fc in system.flex_compiled:      # flexible bodies: M(q) v̇, coupled blocks
        A = rotation_matrix(p[fc.slot])
        vd = np.concatenate([rdd[fc.slot], wd[fc.slot], d[fc.va]])
        Q = fc.eom.mass_matrix(A, y[fc.qa]) @ vd
        R[fc.slot] = Q[:6]
        modal.append(Q[6:])
    if sag and modal:
        return np.concatenate([R.ravel()] + modal)
    return R.ravel()


def _residual_rows(system: System, dY: np.ndarray, Y: np.ndarray, sag: bool) -> np.ndarray:
    """:func:`_residual` of many states Y (k, ny) whose rates are dY (k, ny) → (k, n)."""
    lay = system.layout
    n = system.n_rigid
    k = Y.shape[0]
    vr = dY[:, lay.v_rigid].reshape(k, n, 6)
    R = np.empty((k, n, 6))
    R[:, :, :3] = system.m_r[None, :, :] * vr[:, :, :3]
    R[:, :, 3:] = np.einsum("nij,knj->kni", system.J, vr[:, :, 3:])
    modal = []
    p = Y[:, lay.q_rigid].reshape(k, n, 7)[:, :, 3:]
    for fc in system.flex_compiled:
        Q = np.empty((k, 6 + fc.eom.n))
        for row in range(k):
            A = rotation_matrix(p[row, fc.slot])
            vd = np.concatenate([vr[row, fc.slot], dY[row, fc.va]])
            Q[row] = fc.eom.mass_matrix(A, Y[row, fc.qa]) @ vd
        R[:, fc.slot] = Q[:, :6]
        modal.append(Q[:, 6:])
    if sag and modal:
        return np.concatenate([R.reshape(k, 6 * n)] + modal, axis=1)
    return R.reshape(k, 6 * n)


def _apply(system: System, y: np.ndarray, dx: np.ndarray) -> np.ndarray:
    """New state: translations added, rotations composed, modal
    coordinates added (dx : flat, 6 per body then modal)."""
    y = y.copy()
    n = system.n_rigid
    parts = system.layout.split(y)
    body = dx[:6 * n].reshape(n, 6)
    parts["r"][...] += body[:, :3]
    for b in range(n):
        p = quat_mul(parts["p"][b], rotvec_to_p(body[b, 3:]))
        parts["p"][b] = p / np.linalg.norm(p)
    if dx.size > 6 * n:
        y[system.layout.q_modal] += dx[6 * n:]
    return y


def solve_statics(system: System, y0: np.ndarray | None = None, *, tol: float = 1e-6,
                  max_iter: int = 50, polish: int = 3, fd_step: float = 1e-6,
                  max_move: float | None = None, sag: bool = True,
                  sparse: bool | None = None) -> Equilibrium:
    """Static equilibrium of the free rigid bodies, the base held.

    Parameters
    ----------
    system : System
    y0 : (ny,) array, optional
        Starting state (velocities are ignored); default: the scene's
        initial positions.
    tol : float
        Tolerance on the Newton step [m, rad] and on the scaled residual.
    max_iter : int
        Newton iterations allowed.
    polish : int
        Extra iterations after convergence while the step still shrinks.
    fd_step : float
        Central-difference step [m, rad].
    max_move : float, optional
        A body moving further than this from its start [m] means divergence;
        default 100 × (1 m + the scene's largest coordinate).
    sag : bool
        Solve for the flexible bodies' modal coordinates too (their elastic
        sag); False holds them at zero (the paper's statics).
    sparse : bool, optional
        Factorise the Jacobian as a sparse matrix (SuperLU) and test it for
        a free direction by inverse iteration, rather than densely (LU and
        an SVD); default: sparse above :data:`DENSE_LIMIT` unknowns.

    Returns
    -------
    Equilibrium
        ``success = False`` with a message naming the body and direction when
        the Jacobian is singular (a body free in some direction) or the
        iteration diverges; never NaN in ``y``. Elastomer mounts' Maxwell
        terms are relaxed throughout (the static stiffness is the law's k)
        and their states at rest in ``y`` (z = d,
        :mod:`flexbed.dynamics.maxwell_terms`).
    """
    options = dict(tol=tol, max_iter=max_iter, polish=polish, fd_step=fd_step,
                   max_move=max_move, sag=sag, sparse=sparse)
    if not system.layout.n_internal:
        return _solve_statics(system, y0, **options)
    with relaxed(system):
        eq = _solve_statics(system, y0, **options)
    return dataclasses.replace(eq, y=relax_states(system, eq.y))


def _solve_statics(system: System, y0, *, tol, max_iter, polish, fd_step, max_move, sag,
                   sparse) -> Equilibrium:
    """:func:`solve_statics`, its options all given."""
    t_start = time.perf_counter()
    n = system.n_rigid
    nfev0 = system.nfev
    y = (system.initial_state() if y0 is None else np.array(y0, dtype=float)).copy()
    lay = system.layout
    y[lay.nq:] = 0.0
    names = [b.name for b in system.scene.bodies]
    rigid_names = [names[i] for i in lay.rigid]
    g = float(np.linalg.norm(system.g))
    scale = np.repeat(system.m_r[:, 0] * g if g > 0 else np.ones(n), 6)
    scale = np.where(scale > 0, scale, 1.0)
    step_unit = np.ones(6 * n)
    if sag and lay.n_modal:
        # modal unknowns [kg^1/2 m]: forces scaled by g sqrt(m), steps by 1/sqrt(m)
        for fc in system.flex_compiled:
            root_m = math.sqrt(fc.eom.m)
            k = fc.eom.n
            scale = np.concatenate([scale, np.full(k, (g if g > 0 else 1.0) * root_m)])
            step_unit = np.concatenate([step_unit, np.full(k, 1.0 / root_m)])
    n_unknown = scale.size
    modal = bool(sag and lay.n_modal)
    steps = np.full(n_unknown, fd_step)
    use_sparse = n_unknown > DENSE_LIMIT if sparse is None else bool(sparse)
    compiled = not use_sparse and _rigid_only(system)

    def residual_rows(dY, Y):
        return _residual_rows(system, dY, Y, sag)
    start_r = y[lay.q_rigid].reshape(n, 7)[:, :3].copy()
    if max_move is None:
        max_move = 100.0 * (1.0 + float(np.max(np.abs(system.initial_r))))

    def result(success, message, it, res, step, rf, njev, history, jacobian=None):
        return Equilibrium(success, message, y, it, res, step, rf[:6 * n].reshape(n, 6), njev,
                           system.nfev - nfev0, time.perf_counter() - t_start, tol,
                           tuple(history), jacobian=jacobian,
                           mounts=_mounts_at(system, y) if success else None)

    def name_of(c: int, verb: str = "in") -> str:
        if c < 6 * n:
            b, k = divmod(c, 6)
            return f"body {rigid_names[b]!r} {verb} {COORDINATES[k]}"
        return f"modal coordinate {c - 6 * n + 1}" + (" is free" if verb != "in" else "")

    if n == 0:
        return result(True, "no free bodies", 0, 0.0, 0.0, np.zeros(0), 0, [])
    R = _residual(system, y, sag)
    res = float(np.max(np.abs(R) / scale))
    step = math.inf
    njev = 0
    history = []
    converged_at = None
    prev_step = math.inf
    solve = None
    for it in range(1, max_iter + 1):
        # a new Jacobian per iteration; polishing (converged) reuses the last one:
        # its change over a step at round-off level is below what the step can
        # resolve
        if converged_at is None or solve is None:
            jac = _rigid_jacobian(system) if compiled else None
            exact = jac is not None
            if jac is None:
                jac, exact = _jacobian(system, y, residual_rows, steps, modal, use_sparse)
            njev += 1
            values = jac.data if use_sparse else jac
            if not (np.all(np.isfinite(values)) and np.all(np.isfinite(R))):
                bad_cols = np.zeros(n_unknown, dtype=bool)
                if use_sparse:
                    coo = jac.tocoo()
                    bad_cols[coo.col[~np.isfinite(coo.data)]] = True
                else:
                    bad_cols = ~np.all(np.isfinite(jac), axis=0)
                bad = int(np.argmax(bad_cols | ~np.isfinite(R)))
                return result(False, f"no static equilibrium: the forces on {name_of(bad)} are "
                              f"not finite (floating-point overflow: a mass, stiffness or load "
                              f"too large for double precision)", it - 1, res, step, R, njev,
                              history)
            if use_sparse:
                singular, solve = _sparse_solver(jac)
            else:
                Jac = jac
                singular = _singular_direction(Jac)
                solve = functools.partial(np.linalg.solve, Jac)
            if singular is not None:
                return result(False, f"no static equilibrium: "
                              f"{name_of(singular, 'is free in')} (the stiffness matrix is "
                              f"singular: no mount holds that direction)", it - 1, res, step, R,
                              njev, history)
        dx = -solve(R)
        step = float(np.max(np.abs(dx) * step_unit))
        if converged_at is not None and not step < prev_step:
            break       # polishing no longer helps; keep the previous iterate
        if compiled:
            y_new = np.empty_like(y)
            step_state(y, lay.q_rigid.start, n, dx, y_new)
        else:
            y_new = perturbed_positions(system, y, dx[None, :])[0]
        R_new = _residual(system, y_new, sag)
        moved = np.abs(y_new[lay.q_rigid].reshape(n, 7)[:, :3] - start_r)
        if not np.all(np.isfinite(R_new)) or float(np.max(moved)) > max_move:
            b, k = np.unravel_index(int(np.argmax(np.where(np.isfinite(moved), moved, np.inf))),
                                    moved.shape)
            return result(False, f"no static equilibrium: Newton–Raphson diverged, body "
                          f"{rigid_names[b]!r} moved {float(moved[b, k]):.3g} m along "
                          f"{COORDINATES[k]} (a softening mount law, or too little stiffness "
                          f"to carry the load)", it, res, step, R, njev, history)
        y, R = y_new, R_new
        res = float(np.max(np.abs(R) / scale))
        history.append((step, res))
        prev_step = step
        if converged_at is None and step < tol and res < tol:
            converged_at = it
        if converged_at is not None and (it - converged_at >= polish or step == 0.0):
            break
    else:
        if converged_at is None:
            worst = int(np.argmax(np.abs(R) / scale))
            rounding = 4 * np.finfo(float).eps * (1.0 + float(np.max(np.abs(start_r))))
            if step <= rounding:
                return result(False, f"no static equilibrium: the residual on {name_of(worst)} "
                              f"({float(np.abs(R)[worst]):.3g}) cannot be reduced: the Newton "
                              f"steps ({step:.3g}) are below the rounding of the coordinates "
                              f"({rounding:.2g}; a stiffness out of scale with the loads, too "
                              f"large for double precision)", max_iter, res, step, R, njev,
                              history)
            return result(False, f"no static equilibrium after {max_iter} Newton–Raphson "
                          f"iterations: largest residual on {name_of(worst)} "
                          f"({float(np.abs(R)[worst]):.3g}); step {step:.3g}", max_iter, res,
                          step, R, njev, history)
    return result(True, f"converged in {len(history)} iterations", len(history), res, step, R,
                  njev, history, jac if exact else None)


def _mounts_at(system: System, y: np.ndarray) -> tuple | None:
    """The mounts' deflections and forces (M, 3) along their axes at the
    state y at rest (t = 0; one right-hand side, not counted: what
    :func:`flexbed.dynamics.observation.observe` reads), or None for a
    scene with Maxwell terms (its statics run them relaxed, and its state
    is then relaxed again)."""
    if system.layout.n_internal:
        return None
    system.rhs_into(0.0, y, np.empty(system.ny))
    return system.data.w_dx.copy(), system.data.w_f.copy()


def _jacobian(system: System, y: np.ndarray, residual_rows, steps: np.ndarray, modal: bool,
              sparse: bool):
    """∂R/∂(unknowns) at the state y at rest: the exact tangent stiffness
    (:func:`flexbed.dynamics.tangent.tangent`) where it applies, else
    central differences by colour classes of the mount graph
    (:func:`flexbed.dynamics.jacobian.force_jacobian`, steps (n,)). A CSR
    matrix when ``sparse``, else an array (n, n); and whether it is the
    exact tangent."""
    tg = tangent(system, y, modal=modal, dense=not sparse, rates=False)
    if tg is not None:
        return tg.Kq, True
    fj = force_jacobian(system, y, residual_rows, functools.partial(perturbed_positions, system, y),
                        steps, modal=modal, capture=())
    return (fj.R if sparse else fj.R.toarray()), False


def _rigid_only(system: System) -> bool:
    """Whether the compiled Newton pieces (:mod:`flexbed.dynamics.rigid_statics`)
    apply: every body rigid, no loads on bodies, laws the tangent covers."""
    return (not system.flex_compiled and not _own_slots(system)
            and set(np.unique(system.data.law_kind).tolist()) <= set(_KINDS))


def _rigid_jacobian(system: System) -> np.ndarray | None:
    """The exact tangent stiffness (6n, 6n) of a scene of rigid bodies at
    the state of the system's last right-hand side, at rest (its work
    arrays: the Newton loop's residual at the iterate has just been
    evaluated) (:func:`flexbed.dynamics.rigid_statics.rigid_tangent`,
    the numbers of :func:`flexbed.dynamics.tangent.tangent` to round-off),
    or None where :func:`tangent` would not give it either (a moving base,
    forces not finite): the caller then takes :func:`_jacobian`."""
    d = system.data
    if np.any(d.w_Pd != 0.0):
        return None
    kx, _ = law_slopes(system, d.w_dx.ravel(), d.w_dxd.ravel())
    n = system.n_rigid
    K = np.zeros((6 * n, 6 * n))
    rigid_tangent(d.w_A, d.w_P, d.w_ub, d.w_f, d.w_F, system.U, kx, system.body_i,
                  system.body_j, K)
    return K if np.all(np.isfinite(K)) else None


def _singular_direction(Jac: np.ndarray) -> int | None:
    """Index of the free coordinate most involved in a null direction, or None."""
    d = np.sqrt(np.abs(np.diag(Jac)))
    colnorm = np.linalg.norm(Jac, axis=0)
    bad = np.flatnonzero(~(np.isfinite(colnorm) & (colnorm != 0.0)))
    if bad.size:
        return int(bad[0])
    s_col = 1.0 / np.where(d > 0, d, colnorm)
    Js = Jac * s_col[None, :] * s_col[:, None]
    sv = np.linalg.svd(Js, compute_uv=False)
    if sv[-1] <= SINGULAR_RATIO * sv[0]:
        u, sv, vt = np.linalg.svd(Js)
        return int(np.argmax(np.abs(vt[-1])))
    return None


def _scaling(jac) -> tuple[np.ndarray, int | None]:
    """The symmetric scaling of :func:`_singular_direction` for a sparse
    Jacobian, and the first column that is zero or not finite (or None)."""
    d = np.sqrt(np.abs(jac.diagonal()))
    colnorm = np.sqrt(np.asarray(abs(jac).power(2).sum(axis=0)).ravel())
    bad = np.flatnonzero((colnorm == 0.0) | ~np.isfinite(colnorm))
    if bad.size:
        return d, int(bad[0])
    return 1.0 / np.where(d > 0, d, colnorm), None


def _sparse_solver(jac):
    """(free direction or None, solve) for a sparse Jacobian (n, n).

    SuperLU of the scaled Jacobian ``Js = S J S`` (S as in
    :func:`_singular_direction`); its largest singular value by 30 power
    iterations on JsᵀJs, its smallest and the null direction by 8 inverse
    iterations with the factors (a gap of 1e11 converges in one or two).
    An exactly singular factorisation falls back to the dense test."""
    s, bad = _scaling(jac)
    if bad is not None:
        return bad, None
    S = sp.diags(s)
    Js = (S @ jac @ S).tocsc()
    try:
        lu = splu(Js)
    except RuntimeError:                       # exactly singular: the dense test names it
        return _singular_direction(jac.toarray()), None
    n = Js.shape[0]
    x = np.ones(n) / math.sqrt(n)
    for _ in range(30):
        x = Js.T @ (Js @ x)
        nx = np.linalg.norm(x)
        if nx == 0.0:
            break
        x /= nx
    sig_max = math.sqrt(float(np.linalg.norm(Js.T @ (Js @ x))))
    v = np.cos(np.arange(n) + 0.5)             # a fixed start, not orthogonal to anything simple
    v /= np.linalg.norm(v)
    grow = 1.0
    for _ in range(8):
        w = lu.solve(lu.solve(v, trans="T"))
        grow = float(np.linalg.norm(w))
        if not np.isfinite(grow) or grow == 0.0:
            break
        v = w / grow
    sig_min = 1.0 / math.sqrt(grow) if np.isfinite(grow) and grow > 0 else 0.0
    if not np.isfinite(grow) or sig_min <= SINGULAR_RATIO * sig_max:
        return int(np.argmax(np.abs(v))), None

    def solve(rhs):
        return s * lu.solve(s * rhs)
    return None, solve
