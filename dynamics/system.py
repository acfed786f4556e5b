"""A scene compiled once into flat arrays, and its one right-hand side.

:class:`System` is built from a :class:`~flexbed.dynamics.scene.Scene`. Its
:meth:`System.rhs` gives ``dy/dt`` for the state laid out as in
:mod:`flexbed.dynamics.layout`; statics, every integrator, the
linearisation and the benchmarks call this one function.

The physics itself is :func:`flexbed.dynamics.kernel.evaluate`, compiled
with numba into one C function (:func:`flexbed.dynamics.kernel.rhs_function`).
A System is built once and does not change: its constructor turns the
scene into the Python-side arrays (bodies, mounts, laws, flexible bodies'
equations, the base's inputs as functions of time,
:class:`~flexbed.dynamics.base_inputs.BaseInputs`) and, from them, the
kernel's flat arrays, packed into two so that a call costs a few
microseconds (:func:`flexbed.dynamics.kernel_tables.kernel_storage`).
The Systems of a study's variants share what comes out the same from one
to the next — the base's compiled inputs, the kernel's tables of them, the
packed storage's layout, the tables of what the scene lacks
(:mod:`flexbed.dynamics.shared_parts`) — and build only their values: a
System is then equal, bit for bit, to one built with nothing kept.
Compiled callers (:mod:`flexbed.dynamics.steppers`) call the kernel through
:attr:`System.kernel`; :attr:`System.data` holds NumPy views of every
array of the packed storage. :meth:`System.observe`
(:func:`flexbed.dynamics.observation.observe`) evaluates the same physics
and returns everything a results file stores.

Nothing is set on a System between calls: an integrator that steps
through a segment between breakpoints passes the segment's end to every
evaluation (``seg_end``: the base's inputs give their limits from inside
the segment there; ``inf``, the default, means right-continuous). Its
attributes cannot be rebound and its arrays are read-only; the one count
it keeps, :attr:`System.nfev`, is a statistic for callers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .bounded_cache import BoundedCache
from .flexible import FlexibleEOM
from .kernel import evaluate_batch, rhs_function
from .kernel_tables import kernel_storage
from .laws import LawBank
from .layout import Layout
from .maxwell_terms import relax_states
from .observation import Observation, observe
from .rotation import A as rotation_matrix
from .scene import Scene
from .shared_parts import base_inputs

__all__ = ["System", "Observation"]


@dataclass(frozen=True, slots=True)
class _FlexCompiled:
    """A flexible body for the Python side (statics, outputs, linearisation):
    scene index ``body``, row ``slot`` among bodies 2…, its equations, and
    the slices of a and ȧ in y."""

    body: int
    slot: int
    eom: FlexibleEOM
    qa: slice
    va: slice


def _as_state(y) -> np.ndarray:
    """y as a contiguous float64 array (the kernel's one compiled signature)."""
    if isinstance(y, np.ndarray) and y.dtype == np.float64 and y.flags.c_contiguous:
        return y
    return np.ascontiguousarray(y, dtype=np.float64)


def _initial_frames(p0: np.ndarray) -> np.ndarray:
    """The bodies' rotation matrices (nb, 3, 3) at the Euler parameters p0
    (nb, 4), the base's the identity (it never rotates); read-only, made
    once for equal p0 (a study's variants seldom turn a body)."""
    def make():
        A0 = rotation_matrix(p0)
        A0[0] = np.eye(3)
        return _frozen(A0)
    return _FRAMES.get((p0.dtype.str, p0.shape, p0.tobytes()), make)


#: the initial frames of the orientations met lately (:func:`_initial_frames`)
_FRAMES = BoundedCache(16)


def _layout(nb: int, base_free: bool, modal: tuple, n_internal: int) -> Layout:
    """The state's :class:`~flexbed.dynamics.layout.Layout` (frozen), one
    for equal arguments."""
    return _STATE_LAYOUTS.get((nb, base_free, modal, n_internal), lambda: Layout(
        n_bodies=nb, base_free=base_free, rigid=tuple(range(1, nb)), modal=modal,
        n_internal=n_internal))


#: the layouts met lately (:func:`_layout`)
_STATE_LAYOUTS = BoundedCache(16)


def _frozen(a) -> np.ndarray:
    """a, made read-only."""
    a.flags.writeable = False
    return a


class System:
    """A scene compiled for evaluation; immutable once built.

    Parameters
    ----------
    scene : Scene

    Attributes
    ----------
    scene : Scene
    layout : Layout
        Where everything lives in the state (see :mod:`flexbed.dynamics.layout`).
    nb, M, ny : int
        Numbers of bodies (the base is body 0), of mounts, of state entries.
    inputs : BaseInputs
        The base's drives and loads as functions of time.
    breakpoints : tuple of float
        Times [s] where the base's drive or load (or a derivative) jumps.
    mass : (nb,) array [kg]; g : (3,) array [m/s²]; J : (nb − 1, 3, 3) array [kg m²]
        Read-only, as are the mounts' arrays ``body_i``, ``body_j``,
        ``end_body``, ``S`` [m], ``U``, ``d0`` [m].
    nfev : int
        Right-hand-side evaluations made through :meth:`rhs` and
        :meth:`rhs_batch` since construction (:meth:`observe` is not
        counted). The one thing about a System that changes: a statistic,
        which callers read before and after their work; a caller that
        evaluates :attr:`kernel` from compiled code itself adds its count.
    """

    def __init__(self, scene: Scene):
        self.scene = scene
        bodies = scene.bodies
        nb = len(bodies)
        self.nb = nb
        base = scene.base
        self.base_motion = base.motion
        flex = dict(scene.flexible)
        self.flex_index = tuple(i for i, b in enumerate(bodies) if b.name in flex)
        self.layout = _layout(nb, base.motion == "free",
                              tuple((i, flex[bodies[i].name].n_modes) for i in self.flex_index),
                              sum(s.n_states for s in scene.maxwell))
        lay = self.layout
        self.n_rigid = n = nb - 1
        self.ny = lay.ny
        self.mass = _frozen(np.array([flex[b.name].mass if b.name in flex else b.mass
                                      for b in bodies]))
        self.g = _frozen(np.array(scene.gravity, dtype=float))
        # rigid bodies: mass, principal-axes factorisation of J
        self.m_r = _frozen(self.mass[1:, None].copy())
        self.J = _frozen(np.array([flex[b.name].inertia if b.name in flex else b.inertia
                                   for b in bodies[1:]]).reshape(n, 3, 3))
        jv, jq = np.linalg.eigh(self.J) if n else (np.zeros((0, 3)), np.zeros((0, 3, 3)))
        self.J_eig = _frozen(jv)
        self.J_vec = _frozen(jq)
        # base
        self.m_base = float(bodies[0].mass)
        self.inputs = base_inputs(scene, self.g)
        # mounts, read in one pass
        mounts = scene.mounts
        M = len(mounts)
        self.M = M
        name_to_index = {b.name: i for i, b in enumerate(bodies)}
        ends, points, axes, laws, stops = [], [], [], [], []
        for m in mounts:
            ends.append(name_to_index[m.body_i])
            points.append(m.point_i)
            axes.append(m.axes)
            laws.extend(m.laws)
            stops.extend(m.stops)
        for m in mounts:
            ends.append(name_to_index[m.body_j])
            points.append(m.point_j)
        end_body = np.array(ends, dtype=np.intp)
        bi = end_body[:M]
        bj = end_body[M:]
        self.end_body = _frozen(end_body)
        self.body_i = _frozen(bi)
        self.body_j = _frozen(bj)
        self.S = _frozen(np.array(points).reshape(2 * M, 3))
        self.U = _frozen(np.array(axes).reshape(M, 3, 3))
        self.laws = LawBank(laws, stops)
        # unstrained mount vectors from the scene's initial configuration
        R0 = np.array([b.position for b in bodies])
        p0 = np.array([b.orientation for b in bodies])
        A0 = _initial_frames(p0)
        P0 = R0[end_body] + np.einsum("kij,kj->ki", A0[end_body], self.S)
        l0 = P0[M:] - P0[:M]
        l0_bar = np.einsum("mji,mj->mi", A0[bi], l0)        # A_iᵀ l0
        self.d0 = _frozen(np.einsum("mkj,mj->mk", self.U, l0_bar))   # Ū l̄0 (M, 3)
        self.initial_r = _frozen(R0)
        p0[0] = (1.0, 0.0, 0.0, 0.0)
        self.initial_p = _frozen(p0)
        self._flex = self._flexible(flex)
        self._packed, self.data = kernel_storage(self)
        self._F_addr = self._packed[0].__array_interface__["data"][0]   # as .ctypes.data,
        self._I_addr = self._packed[1].__array_interface__["data"][0]   # without its object
        self._count = [0]      # nfev: a list, so that counting rebinds nothing
        self._built = True

    def __setattr__(self, name, value):
        if getattr(self, "_built", False) and name != "nfev":
            raise AttributeError(f"a System is immutable: '{name}' cannot be set (build a new "
                                 f"System from a changed scene)")
        object.__setattr__(self, name, value)

    def __delattr__(self, name):
        raise AttributeError(f"a System is immutable: '{name}' cannot be deleted")

    def _flexible(self, flex: dict) -> tuple:
        """Per flexible body: its equations and where its modes sit in y."""
        lay = self.layout
        out = []
        for b in self.flex_index:
            fb = flex[self.scene.bodies[b].name]
            blk = lay.modal_block(b)
            q0 = lay.q_modal.start
            v0 = lay.v_modal.start
            out.append(_FlexCompiled(
                body=b, slot=b - 1, eom=FlexibleEOM(fb),
                qa=slice(q0 + blk.start, q0 + blk.stop), va=slice(v0 + blk.start, v0 + blk.stop)))
        return tuple(out)

    @property
    def nfev(self) -> int:
        """Right-hand-side evaluations through this system (see the class)."""
        return self._count[0]

    @nfev.setter
    def nfev(self, value: int) -> None:
        self._count[0] = int(value)

    @property
    def flex_compiled(self) -> tuple:
        """The compiled flexible bodies (see ``_FlexCompiled``)."""
        return self._flex

    # ------------------------------------------------------------------ base
    @property
    def breakpoints(self) -> tuple:
        """Times [s] > 0 where the base's drive or load (or a derivative) jumps."""
        return self.inputs.breakpoints

    @property
    def r0_base(self) -> np.ndarray:
        """The base's position in the scene (3,) [m]."""
        return self.inputs.r0

    def base_motion_at(self, t: float, seg_end: float = math.inf):
        """Base position [m], velocity [m/s] and acceleration [m/s²] at time t
        [s] (prescribed motions only; a free base's come from the state);
        ``seg_end`` as for :meth:`rhs`."""
        return self.inputs.motion_at(t, seg_end)

    def max_step(self, t_a: float, t_b: float) -> float:
        """Longest adaptive step [s] allowed on [t_a, t_b] by the inputs active there."""
        return self.inputs.max_step(t_a, t_b)

    def compiled_input(self, shape):
        """The compiled form (value and exact integrals) of one of the base's
        input shapes, as built once with the system."""
        return self.inputs.compiled_input(shape)

    # ------------------------------------------------------------- the physics
    def rhs(self, t: float, y: np.ndarray, seg_end: float = math.inf) -> np.ndarray:
        """dy/dt (ny,) at time t [s] for the state y (ny,); a new array each
        call (:func:`flexbed.dynamics.kernel.evaluate`).

        ``seg_end`` [s]: the end of the segment being integrated; at
        t ≥ seg_end the base's inputs give their limits from the left (from
        inside the segment); inf: right-continuous everywhere.
        """
        self._count[0] += 1
        y = _as_state(y)           # kept referenced while the kernel reads it
        dy = np.empty(self.ny)
        rhs_function()(float(t), float(seg_end), y.ctypes.data, dy.ctypes.data, self._F_addr,
                       self._I_addr)
        return dy

    def rhs_into(self, t: float, y: np.ndarray, dy: np.ndarray,
                 seg_end: float = math.inf) -> None:
        """dy/dt written into dy (ny,), contiguous float64, not counted in
        :attr:`nfev` (:func:`flexbed.dynamics.observation.observe`); as
        :meth:`rhs` otherwise. The kernel's work arrays (:attr:`data`)
        then hold this evaluation's values."""
        y = _as_state(y)
        rhs_function()(float(t), float(seg_end), y.ctypes.data, dy.ctypes.data, self._F_addr,
                       self._I_addr)

    def rhs_batch(self, t: np.ndarray, Y: np.ndarray, capture: tuple = (),
                  seg_end: float = math.inf, mounts_only: bool = False):
        """dy/dt at many states in one compiled call
        (:func:`flexbed.dynamics.kernel.evaluate_batch`).

        Parameters
        ----------
        t : (k,) array [s]
        Y : (k, ny) array
            States.
        capture : tuple of str
            Names of the kernel's work arrays (``w_*`` of
            :data:`flexbed.dynamics.kernel.FIELDS`) to keep as each
            evaluation left them.
        seg_end : float [s]
            As for :meth:`rhs` (inf: right-continuous inputs).
        mounts_only : bool
            Evaluate the right-hand side only as far as the mount forces
            (the base's motion, the bodies' rotations, the mount ends,
            deflections and forces: sections 1-4 of
            :mod:`flexbed.dynamics.kernel`), for a capture of ``w_base``,
            ``w_A``, ``w_P``, ``w_Pd``, ``w_dx``, ``w_dxd``, ``w_f`` or
            ``w_F`` alone: the same values, without the bodies' equations
            of motion; dY is then not computed (returned None).

        Returns
        -------
        dY : (k, ny) array, or None with ``mounts_only``
        captured : dict
            name → (k,) + the field's shape.
        """
        t = np.ascontiguousarray(t, dtype=np.float64).reshape(-1)
        Y = np.ascontiguousarray(Y, dtype=np.float64).reshape(t.size, self.ny)
        F = self._packed[0]
        views = [getattr(self.data, name) for name in capture]
        index = [(v.ctypes.data - F.ctypes.data) // F.itemsize + np.arange(v.size)
                 for v in views]
        idx = np.concatenate(index).astype(np.int64) if index else np.zeros(0, np.int64)
        dY = np.empty_like(Y)
        C = np.empty((t.size, idx.size))
        if mounts_only:
            I = self._packed[1]
            through = (self.data.ints.ctypes.data - I.ctypes.data) // I.itemsize + 11
            I[through] = 1
            try:
                evaluate_batch(self.kernel, float(seg_end), t, Y, dY, idx, C)
            finally:
                I[through] = 0
            dY = None
        else:
            evaluate_batch(self.kernel, float(seg_end), t, Y, dY, idx, C)
        self._count[0] += t.size
        captured, o = {}, 0
        for name, v in zip(capture, views):
            captured[name] = C[:, o:o + v.size].reshape((t.size,) + v.shape)
            o += v.size
        return dY, captured

    @property
    def kernel(self) -> tuple:
        """The right-hand side as compiled callers take it: (the C function
        of :func:`flexbed.dynamics.kernel.rhs_function`, F, I), with (F, I)
        this scene's packed storage (:func:`flexbed.dynamics.kernel.pack`)."""
        return (rhs_function(),) + tuple(self._packed)

    def observe(self, t: float, y: np.ndarray, seg_end: float = math.inf) -> Observation:
        """Everything at one (t, y); same physics as :meth:`rhs`
        (:func:`flexbed.dynamics.observation.observe`)."""
        return observe(self, t, y, seg_end)

    # ------------------------------------------------------------ the states
    def poses(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every body's pose in the state y (ny,), or in each of a stack of
        states (..., ny): positions (..., nb, 3) [m] of the frame origins
        and Euler parameters (..., nb, 4), the base's (and any body's
        without a state) from the scene."""
        parts = self.layout.split(y)
        lead = np.shape(y)[:-1]
        pos = np.broadcast_to(self.initial_r, lead + self.initial_r.shape).astype(float)
        pos[..., 1:, :] = parts["r"]
        if parts["r_base"] is not None:
            pos[..., 0, :] = parts["r_base"]
        p = np.broadcast_to(self.initial_p, lead + self.initial_p.shape).astype(float)
        p[..., 1:, :] = parts["p"]
        return pos, p

    def initial_state(self, positions: np.ndarray | None = None) -> np.ndarray:
        """The state at t = 0: positions, the scene's velocities, zero work.

        Parameters
        ----------
        positions : (ny,) array, optional
            A state whose coordinates (q: positions, Euler parameters,
            modal coordinates) are kept, e.g. the static equilibrium; its
            velocities and work are replaced. Default: the scene's initial
            positions and orientations, modal coordinates zero.

        Returns
        -------
        (ny,) array
            Velocities from the scene's bodies: ``velocity`` [m/s, inertial]
            and ``angular_velocity`` [rad/s, body frame] of bodies 2… (a
            flexible body's frame), ``velocity`` of a free base; modal rates
            zero; the Maxwell terms' states relaxed (z = d, no force:
            :func:`flexbed.dynamics.maxwell_terms.relax_states`); the work
            quadratures zero.
        """
        lay = self.layout
        bodies = self.scene.bodies
        y = np.zeros(self.ny)
        if positions is None:
            if lay.base_free:
                y[lay.q_base] = self.r0_base
            qr = y[lay.q_rigid].reshape(self.n_rigid, 7)
            qr[:, :3] = self.initial_r[1:]
            qr[:, 3:] = self.initial_p[1:]
        else:
            y[:lay.nq] = np.asarray(positions, dtype=float)[:lay.nq]
        if lay.base_free:
            y[lay.v_base] = bodies[0].velocity
        if self.n_rigid:
            vr = y[lay.v_rigid].reshape(self.n_rigid, 6)
            vr[:, :3] = [b.velocity for b in bodies[1:]]
            vr[:, 3:] = [b.angular_velocity for b in bodies[1:]]
        return relax_states(self, y)
