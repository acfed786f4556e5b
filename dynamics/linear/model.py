"""The linear model: the motion linearised about the static equilibrium.

Coordinates
-----------
The linear model works in minimal deviations from the equilibrium state
``y_eq`` (see :class:`Coordinates`): for the free base δr (3); for every
other body δr (3) and a small rotation θ (3, body frame, defined by
``p = p_eq ⊗ [√(1 − |θ/2|²), θ/2]``); the modal deviations δa; then the
same blocks' rates ṙ, ω̄, ȧ. In these coordinates the equations of motion
are ``ż = f(z, t)``, built from the one right-hand side
:meth:`flexbed.dynamics.system.System.rhs`; the kinematics ``θ̇ = ω̄ + O(θ ω̄)``
come out of it exactly.

Linearisation
-------------
``ż ≈ A z + b0 + B (u(t) − u(0))`` with ``A = ∂f/∂z`` at the equilibrium
(central differences of the right-hand side), ``b0 = f(0, 0)`` (zero up to
the statics' tolerance) and the inputs ``u`` of the base:

- free base: the sum of the loads along each axis [N]; they enter only as
  the base's acceleration, so ``B = 1/m_base`` there — exactly;
- a load on a body [N or N m], one channel each: B's column is the
  right-hand side's response to that load alone at unit value
  (:func:`load_column`), exact since the rates are affine in a load;
- driven base: the drive's displacement [m] and velocity [m/s] along each
  axis; translating the base is translating every other body the other way
  (mount forces depend on relative positions and velocities only, gravity is
  uniform), so ``B = −Σ_bodies ∂f/∂δr`` and ``−Σ_bodies ∂f/∂ṙ`` in the
  dynamic rows — exactly, from the columns of A (the kinematic rows do not
  see the base).

Propagated exactly, with an estimate of its error, by
:mod:`flexbed.dynamics.linear.propagation` and
:mod:`flexbed.dynamics.linear.estimate`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import weakref
from dataclasses import dataclass

import numpy as np
from scipy.linalg import matrix_balance

from ..piecewise import PiecewisePolynomial
from ..system import System
from ..time_functions import Curve

__all__ = ["Coordinates", "Linearisation", "linearise", "difference_steps", "balanced",
           "load_column"]

_SINE_PIECE = 0.2                          # longest piece of an analytic sinusoid: 0.2/ω


def _qmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Quaternion products a ⊗ b over the leading axes, scalar first, (..., 4)."""
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    a0, a1, a2, a3 = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
    b0, b1, b2, b3 = b[..., 0], b[..., 1], b[..., 2], b[..., 3]
    out[..., 0] = a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3
    out[..., 1] = a0 * b1 + b0 * a1 + a2 * b3 - a3 * b2
    out[..., 2] = a0 * b2 + b0 * a2 + a3 * b1 - a1 * b3
    out[..., 3] = a0 * b3 + b0 * a3 + a1 * b2 - a2 * b1
    return out


def per_system(make):
    """``make(system)`` made once per System and kept while the system
    lives: for what depends on the compiled scene alone (its layout,
    inputs, points), as compile_scene's own work does."""
    cache: "weakref.WeakKeyDictionary[System, object]" = weakref.WeakKeyDictionary()

    @functools.wraps(make)
    def once(system: System):
        got = cache.get(system)
        if got is None:
            got = cache[system] = make(system)
        return got
    return once


@per_system
def _index_arrays(system: System) -> dict:
    """The attributes of :class:`Coordinates` that depend on the layout
    only (read-only arrays, shared by every linearisation of the system)."""
    lay = system.layout
    n = len(lay.rigid)
    nb3 = 3 * lay.base_free
    n_pos = nb3 + 6 * n + lay.n_modal
    d = dict(n_rigid=n, n_pos=n_pos, nz=2 * n_pos)
    body = nb3 + 6 * np.arange(n)[:, None]
    d["r_index"] = body + np.arange(3)[None, :]
    d["th_index"] = body + np.arange(3, 6)[None, :]
    d["v_index"] = n_pos + d["r_index"]
    d["w_index"] = n_pos + d["th_index"]
    d["base_index"] = np.arange(nb3)
    d["base_v_index"] = n_pos + d["base_index"]
    d["a_index"] = nb3 + 6 * n + np.arange(lay.n_modal)
    d["ad_index"] = n_pos + d["a_index"]
    qr = np.arange(lay.q_rigid.start, lay.q_rigid.stop).reshape(n, 7)
    vr = np.arange(lay.v_rigid.start, lay.v_rigid.stop).reshape(n, 6)
    d["y_r"], d["y_p"] = qr[:, :3], qr[:, 3:]
    d["y_rd"], d["y_w"] = vr[:, :3], vr[:, 3:]
    d["y_base"] = np.arange(lay.q_base.start, lay.q_base.stop)
    d["y_base_v"] = np.arange(lay.v_base.start, lay.v_base.stop)
    d["y_a"] = np.arange(lay.q_modal.start, lay.q_modal.stop)
    d["y_ad"] = np.arange(lay.v_modal.start, lay.v_modal.stop)
    # (z index, y index) of the entries added to y_eq and of those put in
    # place, for the compiled to_y of many rows
    d["_add"] = np.stack([np.concatenate([d["base_index"], d["r_index"].ravel(), d["a_index"]]),
                          np.concatenate([d["y_base"], d["y_r"].ravel(), d["y_a"]])],
                         axis=1).astype(np.int64)
    d["_put"] = np.stack([np.concatenate([d["base_v_index"], d["v_index"].ravel(),
                                          d["w_index"].ravel(), d["ad_index"]]),
                          np.concatenate([d["y_base_v"], d["y_rd"].ravel(), d["y_w"].ravel(),
                                          d["y_ad"]])], axis=1).astype(np.int64)
    # (z index, y index) of the rates taken as they are, for the compiled rate
    d["_take"] = np.stack([np.concatenate([d["base_index"], d["base_v_index"],
                                           d["r_index"].ravel(), d["v_index"].ravel(),
                                           d["w_index"].ravel(), d["a_index"], d["ad_index"]]),
                           np.concatenate([d["y_base"], d["y_base_v"], d["y_r"].ravel(),
                                           d["y_rd"].ravel(), d["y_w"].ravel(), d["y_a"],
                                           d["y_ad"]])], axis=1).astype(np.int64)
    d["_th"] = d["th_index"].astype(np.int64)
    d["_yp"] = d["y_p"].astype(np.int64)
    for v in d.values():
        if isinstance(v, np.ndarray):
            v.setflags(write=False)
    return d


class Coordinates:
    """The map between the state ``y`` and the deviations ``z`` from ``y_eq``.

    Parameters
    ----------
    system : System
    y_eq : (ny,) array
        The static equilibrium (Euler parameters of unit norm).

    Attributes
    ----------
    nz : int
        ``2 × n_pos`` with ``n_pos = 3·base_free + 6·n_rigid + n_modal``.
    r_index : (n_rigid, 3) int
        Where δr of bodies 2… sit in z.
    v_index : (n_rigid, 3) int
        Where their ṙ sit in z.
    """

    def __init__(self, system: System, y_eq: np.ndarray):
        lay = system.layout
        self.layout = lay
        self.y_eq = np.array(y_eq, dtype=float)
        self.__dict__.update(_index_arrays(system))
        p_eq = self.y_eq[self.y_p]                                      # (n, 4)
        self.p_eq = p_eq / np.sqrt(np.sum(p_eq * p_eq, axis=1))[:, None]
        self.p_eq_conj = self.p_eq * np.array([1.0, -1.0, -1.0, -1.0])

    def to_y(self, z: np.ndarray) -> np.ndarray:
        """States for deviations z (..., nz) → (..., ny); work entries from y_eq."""
        z = np.asarray(z, dtype=float)
        if z.ndim == 2 and z.shape[0] > 8:         # many rows: one compiled pass
            from .sweep import deviations_to_states
            y = np.empty((z.shape[0], self.y_eq.size))
            deviations_to_states(np.ascontiguousarray(z), self.y_eq, self._add, self._put,
                                 self._th, self._yp, self.p_eq, y)
            return y
        y = np.broadcast_to(self.y_eq, z.shape[:-1] + self.y_eq.shape).copy()
        y[..., self.y_base] += z[..., self.base_index]
        y[..., self.y_base_v] = z[..., self.base_v_index]
        y[..., self.y_r] += z[..., self.r_index]
        s = 0.5 * z[..., self.th_index]                                # (..., n, 3)
        rel = np.empty(s.shape[:-1] + (4,))
        rel[..., 0] = np.sqrt(np.maximum(1.0 - np.sum(s * s, axis=-1), 0.0))
        rel[..., 1:] = s
        y[..., self.y_p] = _qmul(self.p_eq, rel)
        y[..., self.y_rd] = z[..., self.v_index]
        y[..., self.y_w] = z[..., self.w_index]
        y[..., self.y_a] += z[..., self.a_index]
        y[..., self.y_ad] = z[..., self.ad_index]
        return y

    def to_z(self, y: np.ndarray) -> np.ndarray:
        """Deviations of states y (..., ny) → (..., nz); the inverse of :meth:`to_y`
        (one or many states: compiled,
        :func:`flexbed.dynamics.linear.sweep.states_to_deviations`)."""
        y = np.asarray(y, dtype=float)
        if y.ndim <= 2:
            from .sweep import states_to_deviations
            rows = np.ascontiguousarray(y.reshape(-1, y.shape[-1]))
            z = np.empty((rows.shape[0], self.nz))
            states_to_deviations(rows, self.y_eq, self._add, self._put, self._th, self._yp,
                                 self.p_eq_conj, z)
            return z.reshape(y.shape[:-1] + (self.nz,))
        z = np.empty(y.shape[:-1] + (self.nz,))
        z[..., self.base_index] = y[..., self.y_base] - self.y_eq[self.y_base]
        z[..., self.base_v_index] = y[..., self.y_base_v]
        z[..., self.r_index] = y[..., self.y_r] - self.y_eq[self.y_r]
        p = y[..., self.y_p]
        p = p / np.linalg.norm(p, axis=-1, keepdims=True)
        rel = _qmul(self.p_eq_conj, p)
        rel *= np.where(rel[..., :1] < 0.0, -1.0, 1.0)
        z[..., self.th_index] = 2.0 * rel[..., 1:]
        z[..., self.v_index] = y[..., self.y_rd]
        z[..., self.w_index] = y[..., self.y_w]
        z[..., self.a_index] = y[..., self.y_a] - self.y_eq[self.y_a]
        z[..., self.ad_index] = y[..., self.y_ad]
        return z

    def rate(self, dydt: np.ndarray) -> np.ndarray:
        """ż (..., nz) for state derivatives dydt (..., ny) (ṗ → θ̇ = 2 vec(p_eq* ⊗ ṗ))."""
        dydt = np.asarray(dydt, dtype=float)
        if dydt.ndim == 2 and dydt.shape[0] > 8:   # many rows: one compiled pass
            from .sweep import rates_of_states
            zd = np.empty((dydt.shape[0], self.nz))
            rates_of_states(np.ascontiguousarray(dydt), self._take, self._th, self._yp,
                            self.p_eq_conj, zd)
            return zd
        zd = np.empty(dydt.shape[:-1] + (self.nz,))
        zd[..., self.base_index] = dydt[..., self.y_base]
        zd[..., self.base_v_index] = dydt[..., self.y_base_v]
        zd[..., self.r_index] = dydt[..., self.y_r]
        zd[..., self.th_index] = 2.0 * _qmul(self.p_eq_conj, dydt[..., self.y_p])[..., 1:]
        zd[..., self.v_index] = dydt[..., self.y_rd]
        zd[..., self.w_index] = dydt[..., self.y_w]
        zd[..., self.a_index] = dydt[..., self.y_a]
        zd[..., self.ad_index] = dydt[..., self.y_ad]
        return zd


@dataclass(frozen=True)
class _Channel:
    """One input of the base: a scalar function of time and its knots [s]."""

    name: str
    values: object                 # vectorised t (k,) -> (k,)
    knots: np.ndarray
    max_piece: float = math.inf    # longest propagation piece it tolerates [s]
    #: the analytic sinusoids in it: (ω [rad/s], start [s], end [s], c_s, c_c),
    #: each adding c_s sin ωt + c_c cos ωt on [start, end) (the rest of the
    #: channel is then a polynomial of degree ≤ 1 on every piece between knots)
    sines: tuple = ()
    #: when every shape in it is piecewise polynomial: those polynomials
    #: (the channel is their sum; their breaks are among the knots)
    polys: tuple = ()


def _sine_part(shape, kind: str) -> tuple:
    """The sinusoidal part of a sinusoid's value ("load"), first ("velocity")
    or second integral ("displacement") on its window, as
    (ω, start, end, c_s, c_c): A sin(ωt + φ), φ = phase − ω·start, and its
    integrals −A/ω cos(ωt + φ), −A/ω² sin(ωt + φ) (plus polynomials)."""
    A, w = float(shape.amplitude), 2.0 * math.pi * float(shape.frequency)
    phi = float(shape.phase) - w * float(shape.start)
    c, s = math.cos(phi), math.sin(phi)
    cs, cc = {"load": (A * c, A * s), "velocity": (A / w * s, -A / w * c),
              "displacement": (-A / w ** 2 * c, -A / w ** 2 * s)}[kind]
    return (w, float(shape.start), float(shape.end), cs, cc)


@per_system
def _channels(system: System) -> tuple[tuple[_Channel, ...], tuple[tuple[str, int], ...]]:
    """The base's input channels and, for each, (kind, axis) with kind
    "load" | "displacement" | "velocity" (made once per system)."""
    base = system.scene.base
    chans, kinds = [], []
    if base.motion == "free":
        groups = [("load", k, [d.shape for d in base.loads if d.direction == k]) for k in range(3)]
    elif base.motion == "driven":
        groups = [(kind, k, [d.shape for d in base.drives if d.direction == k])
                  for kind in ("displacement", "velocity") for k in range(3)]
    else:
        groups = []
    groups += [("body", i, [ld.shape]) for i, ld in enumerate(system.scene.loads)]
    for kind, k, shapes in groups:
        if not shapes:
            continue
        fs = [system.compiled_input(s) for s in shapes]
        attr = {"load": "values", "body": "values", "displacement": "seconds",
                "velocity": "firsts"}[kind]
        funcs = [getattr(f, attr) for f in fs]
        polys = tuple(getattr(f, {"values": "value", "firsts": "first", "seconds": "second"}[attr])
                      for f in fs)
        if not all(isinstance(f, PiecewisePolynomial) for f in polys):
            polys = ()
        knots, max_piece, sines = [], math.inf, []
        for s, f in zip(shapes, fs):
            if isinstance(f.value, PiecewisePolynomial):
                knots.extend(f.value.breaks.tolist())
            else:                                              # an analytic sinusoid
                knots.extend(f.breakpoints)
                max_piece = min(max_piece, _SINE_PIECE / (2 * math.pi * float(s.frequency)))
                sines.append(_sine_part(s, "load" if kind == "body" else kind))

        def values(t, funcs=funcs):
            t = np.asarray(t, dtype=float)
            return sum(fn(t) for fn in funcs)

        label = (f"load {system.scene.loads[k].name}" if kind == "body"
                 else f"{kind} {'xyz'[k]}")
        chans.append(_Channel(label, values, np.unique(knots), max_piece, tuple(sines), polys))
        kinds.append((kind, k))
    return tuple(chans), tuple(kinds)


def balanced(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A' = S⁻¹ A S (nz, nz, C-contiguous) and the diagonal of S (nz,): A
    balanced by powers of 2, LAPACK's ``dgebal`` scaling only
    (:func:`scipy.linalg.matrix_balance`, ``permute=False``). Exact (every
    entry changes by a power of 2), and φ_j(A) = S φ_j(A') S⁻¹. ‖A'‖₁ is
    near the spectral radius where ‖A‖₁ of a mounted system counts
    stiffness over mass (the reference scene's rigid bed: about 200
    against 7.3e4 1/s), so that far fewer doublings are needed.

    Raises ``numpy.linalg.LinAlgError`` when A has NaN or infinite entries.
    """
    A = np.asarray(A, dtype=float)
    if not np.all(np.isfinite(A)):
        raise np.linalg.LinAlgError("balancing: the matrix has NaN or infinite entries")
    with np.errstate(invalid="ignore"):     # SciPy casts scales past 2^63 to int, unused here
        Ab, (scale, _) = matrix_balance(A, permute=False, separate=True)
    return np.ascontiguousarray(Ab), scale


@dataclass(frozen=True)
class Linearisation:
    """``ż = A z + b0 + B (u(t) − u(0))`` about the equilibrium.

    coords : Coordinates; A : (nz, nz) [SI per coordinate]; B : (nz, nu);
    b0 : (nz,); channels : the base's inputs (nu of them); u0 : (nu,)
    their values at t = 0; evaluations : right-hand sides it took.
    """

    coords: Coordinates
    A: np.ndarray
    B: np.ndarray
    b0: np.ndarray
    channels: tuple
    u0: np.ndarray
    evaluations: int

    @functools.cached_property
    def balanced(self) -> tuple[np.ndarray, np.ndarray]:
        """A' = S⁻¹ A S and the diagonal of S (nz,): A balanced by powers of 2
        (:func:`flexbed.dynamics.linear.model.balanced`), once, for the
        propagation's exponentials and the error estimate's φ-functions."""
        return balanced(np.ascontiguousarray(self.A))

    def f(self, system: System, t: float, z: np.ndarray) -> np.ndarray:
        """The nonlinear ż = f(z, t) (nz,), through the system's right-hand side."""
        return self.coords.rate(system.rhs(t, self.coords.to_y(z)))

    def inputs(self, t: np.ndarray) -> np.ndarray:
        """u(t) − u(0), (k, nu)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if not self.channels:
            return np.zeros((t.size, 0))
        return np.stack([c.values(t) for c in self.channels], axis=1) - self.u0


def difference_steps(system: System, coords: Coordinates, rate_step: float = 1e-6,
                     translation_step: float = 1e-6) -> np.ndarray:
    """The central-difference steps of :func:`linearise` (nz,): 1e-6 in each
    rotation and modal coordinate, ``translation_step`` in each translation,
    ``rate_step`` in each rate, modal ones times √(body mass);
    a translation's or modal coordinate's step is the increment that y_eq's
    entry can take exactly (``(y + h) − y`` in floating point), so that the
    difference quotient divides by the step the state really took."""
    step = np.full(coords.nz, 1e-6)
    step[coords.n_pos:] = rate_step
    step[coords.base_index] = translation_step
    step[coords.r_index.ravel()] = translation_step
    if coords.a_index.size:
        scale = math.sqrt(max(float(fc.eom.m) for fc in system.flex_compiled))
        step[coords.a_index] *= scale
        step[coords.ad_index] *= scale
    y = coords.y_eq
    for iz, iy in ((coords.base_index, coords.y_base), (coords.r_index.ravel(), coords.y_r.ravel()),
                   (coords.a_index, coords.y_a)):
        step[iz] = (y[iy] + step[iz]) - y[iy]
    return step


_UNIT = Curve(np.arange(4.0), np.ones(4))       # 1 from t = 0 on


def load_column(system: System, coords: Coordinates, y_eq: np.ndarray, i: int) -> np.ndarray:
    """B's column of the scene's i-th load on a body (nz,): ż at the
    equilibrium with that load alone at 1 N (or N m), less ż with no load
    on a body, from the one right-hand side (exact: the right-hand side is
    affine in a load's value; the base's inputs are the same in both)."""
    scene = system.scene
    one = dataclasses.replace(scene.loads[i], shape=_UNIT)
    with_one = System(dataclasses.replace(scene, loads=(one,)))
    without = System(dataclasses.replace(scene, loads=()))
    return coords.rate(with_one.rhs(0.0, y_eq)) - coords.rate(without.rhs(0.0, y_eq))


def linearise(system: System, y_eq: np.ndarray, rate_step: float = 1e-6,
              translation_step: float = 1e-6) -> Linearisation:
    """Linearise the system about its static equilibrium ``y_eq`` (ny,).

    Central differences of the right-hand side with steps of 1e-6 in each
    coordinate (m, rad; ``translation_step`` [m] and ``rate_step`` [m/s,
    rad/s] if given; modal coordinates scaled by the square root of the
    body's mass, which is their unit's size for a unit displacement); see
    the module docstring for the inputs' columns. At rest the forces are at
    most quadratic in the rates (linear dampers, gyroscopic terms) and, with
    linear mount laws, linear in the translations, so larger steps there
    (1e-4, as the frequency analyses take) lose nothing and keep those
    columns clear of the round-off of the preloads and positions.
    """
    coords = Coordinates(system, y_eq)
    nz = coords.nz
    nfev0 = system.nfev
    step = difference_steps(system, coords, rate_step, translation_step)

    Zp = np.zeros((2 * nz + 1, nz))                                     # 0, +steps, −steps
    Zp[1:nz + 1].flat[::nz + 1] = step
    Zp[nz + 1:].flat[::nz + 1] = -step
    Yp = coords.to_y(Zp)
    F = coords.rate(system.rhs_batch(np.zeros(Yp.shape[0]), Yp)[0])
    b0 = F[0]
    A = ((F[1:nz + 1] - F[nz + 1:]) / (2.0 * step[:, None])).T
    chans, kinds = _channels(system)
    B = np.zeros((nz, len(chans)))
    for c, (kind, k) in enumerate(kinds):
        if kind == "body":
            B[:, c] = load_column(system, coords, y_eq, k)
        elif kind == "load":
            B[coords.base_v_index[k], c] = 1.0 / system.m_base
        else:              # only the dynamic rows: the kinematic ones do not see the base
            cols = coords.r_index[:, k] if kind == "displacement" else coords.v_index[:, k]
            B[coords.n_pos:, c] = -A[coords.n_pos:, cols].sum(axis=1)
    u0 = np.array([c.values(np.zeros(1))[0] for c in chans], dtype=float)
    return Linearisation(coords, A, B, b0, tuple(chans), u0, system.nfev - nfev0)


