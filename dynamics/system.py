"""A scene compiled once into flat arrays, and its one right-hand side.

:class:`System` is built from a :class:`~dynamics.scene.Scene`. Its
:meth:`System.rhs` gives ``dy/dt`` for the state laid out as in
:mod:`dynamics.layout`; statics, every integrator, the linearisation and the
benchmarks call this one function. :meth:`System.observe` evaluates the same
physics and returns everything a results file stores.

The physics itself is :func:`dynamics.kernel.evaluate`, compiled with
numba into one C function (:func:`dynamics.kernel.rhs_function`);
:class:`System` turns the scene into the kernel's flat arrays once
(:meth:`System._compile`, packed by :func:`dynamics.kernel.pack` into two
arrays so that a call costs a few microseconds) and keeps the Python-side
pieces: the base's inputs as functions of time, breakpoints and step
limits, the flexible bodies' equations for statics and outputs, and the
observation of a state. Compiled callers (:mod:`dynamics.steppers`) call
the kernel through :attr:`System.kernel`; :attr:`System.data` holds NumPy
views of every array of the packed storage.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .flexible import FlexibleEOM
from .kernel import evaluate_batch, pack, rhs_function
from .layout import Layout
from .laws import LawBank
from .rotation import A as rotation_matrix
from .scene import Scene
from .time_functions import Sinusoid

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


def _stack_tables(rows: list, n_missing_cols: int):
    """Piecewise polynomials (``rows``: lists of equal length of
    PiecewisePolynomial or None) padded into the kernel's arrays: breaks
    (r, c, nb) +inf padded, origins (r, c, nb + 1), coefficients
    (r, c, nb + 1, d + 1) ascending, zero padded (None: the zero function).
    ``n_missing_cols``: the number of columns when there are no rows."""
    cols = len(rows[0]) if rows else n_missing_cols
    funcs = [f for r in rows for f in r if f is not None]
    nbk = max([f.breaks.size for f in funcs], default=1)
    deg = max([f.degree for f in funcs], default=0)
    b = np.full((len(rows), cols, nbk), np.inf)
    o = np.zeros((len(rows), cols, nbk + 1))
    c = np.zeros((len(rows), cols, nbk + 1, deg + 1))
    for i, r in enumerate(rows):
        for j, f in enumerate(r):
            if f is None:
                continue
            n = f.breaks.size
            b[i, j, :n] = f.breaks
            o[i, j, :n + 1] = f.origins
            o[i, j, n + 1:] = f.origins[-1]
            c[i, j, :n + 1, :f.degree + 1] = f.coeffs
            # beyond the last break the padding keeps the right tail
            c[i, j, n + 1:, :f.degree + 1] = f.coeffs[-1]
    return b, o, c


class Observation:
    """Everything the physics gives at one (t, y); plain attributes.

    r (nb, 3) [m], p (nb, 4), rd (nb, 3) [m/s], w (nb, 3) [rad/s] body frame,
    rdd (nb, 3) [m/s²], wd (nb, 3) [rad/s²]; dx, dxd, f (M, 3) [m, m/s, N];
    force_i, force_j (M, 3) [N] inertial; kinetic, gravity_potential,
    mount_potential [J]; strain (nb,) [J] elastic energy of flexible bodies;
    a, ad, add (n_modal,) modal coordinates, rates and accelerations; work (4,) [J] (mount,
    external, drive, structural damping); powers.
    """

    __slots__ = ("t", "r", "p", "rd", "w", "rdd", "wd", "dx", "dxd", "f", "force_i", "force_j",
                 "kinetic", "gravity_potential", "mount_potential", "strain", "a", "ad", "add",
                 "work", "power")


class System:
    """A scene compiled for evaluation.

    Parameters
    ----------
    scene : Scene

    Attributes
    ----------
    layout : Layout
        Where everything lives in the state (see :mod:`dynamics.layout`).
    breakpoints : tuple of float
        Times [s] where the base's drive or load (or a derivative) jumps.
    nfev : int
        Right-hand-side evaluations since construction (or the last reset).
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
        self.layout = Layout(n_bodies=nb, base_free=base.motion == "free",
                             rigid=tuple(range(1, nb)),
                             modal=tuple((i, flex[bodies[i].name].n_modes)
                                         for i in self.flex_index))
        lay = self.layout
        self.n_rigid = n = nb - 1
        self.ny = lay.ny
        self.mass = np.array([flex[b.name].mass if b.name in flex else b.mass for b in bodies])
        self.g = np.array(scene.gravity, dtype=float)
        # rigid bodies: mass, principal-axes factorisation of J
        self.m_r = self.mass[1:, None].copy()
        self.J = np.array([flex[b.name].inertia if b.name in flex else b.inertia
                           for b in bodies[1:]]).reshape(n, 3, 3)
        jv, jq = np.linalg.eigh(self.J) if n else (np.zeros((0, 3)), np.zeros((0, 3, 3)))
        self.J_eig = jv
        self.J_vec = jq
        # base
        self.r0_base = np.array(bodies[0].position, dtype=float)
        self.m_base = float(bodies[0].mass)
        self._drives = [[], [], []]
        self._loads = [[], [], []]
        bps = set()
        # each input compiled once (a curve's spline and its integrals are
        # built here and reused by the kernel's tables)
        self._compiled_inputs = [d.shape.compile() for d in list(base.drives) + list(base.loads)]
        for d, f in zip(base.drives, self._compiled_inputs):
            self._drives[d.direction].append(f)
            bps.update(f.breakpoints)
        for d, f in zip(base.loads, self._compiled_inputs[len(base.drives):]):
            self._loads[d.direction].append(f)
            bps.update(f.breakpoints)
        self.breakpoints = tuple(sorted(b for b in bps if b > 0.0))
        self._inputs = [f for k in range(3) for f in self._drives[k] + self._loads[k]]
        if isinstance(base.support, str):
            self.support = (-scene.total_mass * self.g if base.support == "static"
                            else np.zeros(3))
        else:
            self.support = np.array(base.support, dtype=float)
        # mounts
        M = len(scene.mounts)
        self.M = M
        name_to_index = {b.name: i for i, b in enumerate(bodies)}
        bi = np.array([name_to_index[m.body_i] for m in scene.mounts], dtype=np.intp)
        bj = np.array([name_to_index[m.body_j] for m in scene.mounts], dtype=np.intp)
        self.body_i = bi
        self.body_j = bj
        self.end_body = np.concatenate([bi, bj])
        self.S = np.concatenate([np.array([m.point_i for m in scene.mounts]).reshape(M, 3),
                                 np.array([m.point_j for m in scene.mounts]).reshape(M, 3)])
        self.U = np.array([m.axes for m in scene.mounts]).reshape(M, 3, 3)
        self.laws = LawBank([law for m in scene.mounts for law in m.laws])
        # incidence: body force = E @ end forces
        # unstrained mount vectors from the scene's initial configuration
        R0 = np.array([b.position for b in bodies])
        A0 = rotation_matrix(np.array([b.orientation for b in bodies]))
        A0[0] = np.eye(3)      # the base never rotates
        P0 = R0[self.end_body] + np.einsum("kij,kj->ki", A0[self.end_body], self.S)
        l0 = P0[M:] - P0[:M]
        l0_bar = np.einsum("mji,mj->mi", A0[bi], l0)        # A_iᵀ l0
        self.d0 = np.einsum("mkj,mj->mk", self.U, l0_bar)   # Ū l̄0 (M, 3)
        self.initial_r = R0
        self.initial_p = np.array([b.orientation for b in bodies])
        self.initial_p[0] = (1.0, 0.0, 0.0, 0.0)
        self._build_flexible(flex)
        self._packed, self.data = self._compile(flex)
        self._F_addr = self._packed[0].ctypes.data
        self._I_addr = self._packed[1].ctypes.data
        self._seg_end = math.inf
        self.nfev = 0

    def _compile(self, flex: dict) -> tuple:
        """The scene as the flat arrays of :class:`dynamics.kernel.Compiled`,
        packed (:func:`dynamics.kernel.pack`): ((F, I), views)."""
        nb, M, lay = self.nb, self.M, self.layout
        nf = len(self.flex_index)
        mode = {"fixed": 0, "driven": 1, "free": 2}[self.base_motion]
        ints = np.array([nb, M, nf, mode, lay.q_rigid.start, lay.v_rigid.start,
                         lay.q_base.start, lay.v_base.start, lay.work.start,
                         lay.q_modal.start, lay.v_modal.start], dtype=np.int64)
        J = np.zeros((nb, 3, 3))
        J[1:] = self.J
        Jinv = np.zeros((nb, 3, 3))
        Jinv[1:] = np.einsum("bij,bj,bkj->bik", self.J_vec, 1.0 / self.J_eig, self.J_vec)
        # laws: one table per kind, rows in law order
        bank = self.laws
        kind = np.zeros(3 * M, dtype=np.int64)
        row = np.zeros(3 * M, dtype=np.int64)
        for code, idx in ((0, bank.lin), (1, bank.poly), (2, bank.curve)):
            kind[idx] = code
            row[idx] = np.arange(idx.size)
        lin_kc = np.stack([bank.k, bank.c], axis=1) if bank.lin.size else np.zeros((0, 2))
        poly_k = np.zeros((bank.poly.size, 9))
        poly_c = np.zeros((bank.poly.size, 9))
        poly_k[:, :bank.pk.shape[1]] = bank.pk
        poly_c[:, :bank.pc.shape[1]] = bank.pc
        crv_b, crv_o, crv_c = _stack_tables([[fs, fd] for fs, fd in zip(bank.curve_springs,
                                                                      bank.curve_dampers)], 2)
        # flexible bodies, padded to the most modes
        nm = max(self._flex_modes, default=0)
        fx_ints = np.zeros((nf, 4), dtype=np.int64)
        fx = {key: np.zeros((nf,) + shape) for key, shape in (
            ("m", ()), ("I2", (3,)), ("I3", (3, nm)), ("I4", (3, nm)), ("I5", (nm, 3, nm)),
            ("I6", (nm, nm)), ("K", (nm, nm)), ("C", (nm, nm)), ("I7", (3, 3)),
            ("I8", (nm, 3, 3)), ("I9", (nm, nm, 3, 3)))}
        body_flex = np.full(nb, -1, dtype=np.int64)
        end_flex = np.full(2 * M, -1, dtype=np.int64)
        end_phi = np.zeros((2 * M, 3, nm))
        for k, fc in enumerate(self._flex):
            e = fc.eom
            n = e.n
            body_flex[fc.body] = k
            fx_ints[k] = (fc.body, n, fc.qa.start, fc.va.start)
            fx["m"][k] = e.m
            fx["I2"][k] = e.I2
            fx["I3"][k][:, :n] = e.I3
            fx["I4"][k][:, :n] = e.I4
            fx["I5"][k][:n, :, :n] = e.I5
            fx["I6"][k][:n, :n] = e.I6
            fx["K"][k][:n, :n] = e.K
            fx["C"][k][:n, :n] = e.C
            fx["I7"][k] = e.I7
            fx["I8"][k][:n] = e.I8
            fx["I9"][k][:n, :n] = e.I9
            fb = flex[self.scene.bodies[fc.body].name]
            for end in np.flatnonzero(self.end_body == fc.body):
                end_flex[end] = k
                end_phi[end, :, :n] = fb.point_shapes[fb.point_index(self.S[end])]
        # inputs of the base
        shapes = [(0, dr) for dr in self.scene.base.drives] + [(1, ld) for ld in self.scene.base.loads]
        in_ints = np.zeros((len(shapes), 3), dtype=np.int64)
        in_sin = np.zeros((len(shapes), 5))
        tables = []
        for i, (role, item) in enumerate(shapes):
            sh = item.shape
            in_ints[i] = (1 if isinstance(sh, Sinusoid) else 0, item.direction, role)
            if isinstance(sh, Sinusoid):
                in_sin[i] = (sh.amplitude, 2.0 * math.pi * sh.frequency, sh.phase, sh.start,
                             sh.start + sh.duration)
                tables.append([None, None, None])
            else:
                f = self._compiled_inputs[i]
                tables.append([f.value, f.first, f.second])
        in_b, in_o, in_c = _stack_tables(tables, 3)
        N = 6 + nm
        return pack(dict(
            ints=ints, gravity=self.g.copy(), mass=self.mass.astype(float), J=J, Jinv=Jinv,
            body_flex=body_flex, r0_base=self.r0_base.copy(),
            support=np.asarray(self.support, dtype=float).copy(),
            body_i=self.body_i.astype(np.int64), body_j=self.body_j.astype(np.int64),
            S=np.ascontiguousarray(self.S, dtype=float), U=np.ascontiguousarray(self.U),
            d0=np.ascontiguousarray(self.d0), end_flex=end_flex, end_phi=end_phi,
            law_kind=kind, law_row=row, lin_kc=np.ascontiguousarray(lin_kc, dtype=float),
            poly_k=poly_k, poly_c=poly_c, crv_b=crv_b, crv_o=crv_o, crv_c=crv_c,
            fx_ints=fx_ints, fx_m=fx["m"], fx_I2=fx["I2"], fx_I3=fx["I3"], fx_I4=fx["I4"],
            fx_I5=fx["I5"], fx_I6=fx["I6"], fx_K=fx["K"], fx_C=fx["C"], fx_I7=fx["I7"],
            fx_I8=fx["I8"], fx_I9=fx["I9"],
            in_ints=in_ints, in_sin=in_sin, in_b=in_b, in_o=in_o, in_c=in_c,
            w_A=np.zeros((nb, 3, 3)), w_P=np.zeros((2 * M, 3)), w_Pd=np.zeros((2 * M, 3)),
            w_ub=np.zeros((2 * M, 3)), w_dx=np.zeros((M, 3)), w_dxd=np.zeros((M, 3)),
            w_f=np.zeros((M, 3)), w_F=np.zeros((M, 3)), w_force=np.zeros((nb, 3)),
            w_torque=np.zeros((nb, 3)), w_flexQ=np.zeros((nf, N)), w_acc=np.zeros((nb, 6)),
            w_base=np.zeros((3, 3)), w_M=np.zeros((nf, N, N)), w_Q=np.zeros(N + nm),
            w_T=np.zeros((nm, 3, 3)), w_gb=np.zeros(3)), lay.ny)

    def _build_flexible(self, flex: dict) -> None:
        """Per flexible body: its equations and where its modes sit in y."""
        lay = self.layout
        self._flex = []
        self._flex_modes = []
        for b in self.flex_index:
            fb = flex[self.scene.bodies[b].name]
            blk = lay.modal_block(b)
            q0 = lay.q_modal.start
            v0 = lay.v_modal.start
            self._flex.append(_FlexCompiled(
                body=b, slot=b - 1, eom=FlexibleEOM(fb),
                qa=slice(q0 + blk.start, q0 + blk.stop), va=slice(v0 + blk.start, v0 + blk.stop)))
            self._flex_modes.append(fb.n_modes)

    # ------------------------------------------------------------------ base
    def set_segment(self, t_a: float | None, t_b: float | None = None) -> None:
        """Tell the inputs which segment between breakpoints is being integrated.

        At t = t_a or t_b the base's drives and loads then give their limits
        from inside [t_a, t_b] (right-continuous at t_a, left limits at t_b);
        ``set_segment(None)`` returns to the right-continuous convention
        everywhere (statics, outputs).
        """
        self._seg_end = math.inf if t_a is None else float(t_b)

    @property
    def seg_end(self) -> float:
        """End of the current segment [s] (inf: none), as the kernel takes it."""
        return self._seg_end

    def base_motion_at(self, t: float):
        """Base position [m], velocity [m/s] and acceleration [m/s²] at time t
        (prescribed motions only; a free base's come from the state)."""
        at = None if math.isinf(self._seg_end) else self._seg_end
        r = self.r0_base.copy()
        v = np.zeros(3)
        a = np.zeros(3)
        for k in range(3):
            for f in self._drives[k]:
                r[k] += f.second(t, at)
                v[k] += f.first(t, at)
                a[k] += f.value(t, at)
        return r, v, a

    def compiled_input(self, shape):
        """The compiled form (value and exact integrals) of one of the base's
        input shapes, as built once with the system."""
        for item, f in zip(list(self.scene.base.drives) + list(self.scene.base.loads),
                           self._compiled_inputs):
            if item.shape is shape:
                return f
        return shape.compile()

    def max_step(self, t_a: float, t_b: float) -> float:
        """Longest adaptive step [s] allowed on [t_a, t_b] by the inputs active there."""
        out = np.inf
        for f in self._inputs:
            lo, hi = f.support
            if lo < t_b and hi > t_a:
                out = min(out, f.max_step)
        return float(out)

    def base_load_at(self, t: float) -> np.ndarray:
        """External force on the base [N] at time t (loads + support)."""
        at = None if math.isinf(self._seg_end) else self._seg_end
        F = self.support.copy()
        for k in range(3):
            for f in self._loads[k]:
                F[k] += f.value(t, at)
        return F

    # ------------------------------------------------------------- the physics
    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        """dy/dt (ny,) at time t [s] for the state y (ny,); a new array each
        call (:func:`dynamics.kernel.evaluate`)."""
        self.nfev += 1
        dy = np.empty(self.ny)
        self._evaluate(t, _as_state(y), dy)
        return dy

    def _evaluate(self, t: float, y: np.ndarray, dy: np.ndarray) -> None:
        """The compiled right-hand side from Python: dy (ny,) for y (ny,),
        both contiguous float64."""
        rhs_function()(float(t), self._seg_end, y.ctypes.data, dy.ctypes.data, self._F_addr,
                       self._I_addr)

    def rhs_batch(self, t: np.ndarray, Y: np.ndarray, capture: tuple = ()):
        """dy/dt at many states in one compiled call
        (:func:`dynamics.kernel.evaluate_batch`).

        Parameters
        ----------
        t : (k,) array [s]
        Y : (k, ny) array
            States.
        capture : tuple of str
            Names of the kernel's work arrays (``w_*`` of
            :data:`dynamics.kernel.FIELDS`) to keep as each evaluation left
            them.

        Returns
        -------
        dY : (k, ny) array
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
        evaluate_batch(self.kernel, self._seg_end, t, Y, dY, idx, C)
        self.nfev += t.size
        captured, o = {}, 0
        for name, v in zip(capture, views):
            captured[name] = C[:, o:o + v.size].reshape((t.size,) + v.shape)
            o += v.size
        return dY, captured

    @property
    def kernel(self) -> tuple:
        """The right-hand side as compiled callers take it: (the C function
        of :func:`dynamics.kernel.rhs_function`, F, I), with (F, I) this
        scene's packed storage (:func:`dynamics.kernel.pack`)."""
        return (rhs_function(),) + tuple(self._packed)

    # ------------------------------------------------------------ the outputs
    def poses(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every body's pose in the state y (ny,): positions (nb, 3) [m] of the
        frame origins and Euler parameters (nb, 4), the base's (and any
        body's without a state) from the scene."""
        parts = self.layout.split(y)
        pos = np.array(self.initial_r, dtype=float)
        pos[1:] = parts["r"]
        if parts["r_base"] is not None:
            pos[0] = parts["r_base"]
        p = np.array(self.initial_p, dtype=float)
        p[1:] = parts["p"]
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
            zero; the work quadratures zero.
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
        return y

    def observe(self, t: float, y: np.ndarray) -> Observation:
        """Everything at one (t, y); same physics as :meth:`rhs`."""
        y = _as_state(y)
        dydt = np.empty(self.ny)
        self._evaluate(t, y, dydt)
        d = self.data
        nb, M = self.nb, self.M
        o = Observation()
        o.t = float(t)
        parts = self.layout.split(y)
        o.r = np.zeros((nb, 3))
        o.r[0] = d.w_base[0]
        o.r[1:] = parts["r"]
        o.p = np.zeros((nb, 4))
        o.p[0, 0] = 1.0
        o.p[1:] = parts["p"] / np.linalg.norm(parts["p"], axis=1, keepdims=True)
        o.rd = np.zeros((nb, 3))
        o.rd[0] = d.w_base[1]
        o.rd[1:] = parts["rd"]
        o.w = np.zeros((nb, 3))
        o.w[1:] = parts["w"]
        o.rdd = d.w_acc[:, :3].copy()
        if self.base_motion == "fixed":
            o.rdd[0] = 0.0
        o.wd = d.w_acc[:, 3:].copy()
        o.wd[0] = 0.0
        o.dx = d.w_dx.copy()
        o.dxd = d.w_dxd.copy()
        o.f = d.w_f.copy()
        o.force_i = d.w_F.copy()
        o.force_j = -o.force_i
        rd = o.rd
        ke = 0.5 * self.mass * np.sum(rd * rd, axis=1)
        ke[1:] += 0.5 * np.einsum("ni,nij,nj->n", o.w[1:], self.J, o.w[1:])
        o.kinetic = ke
        o.gravity_potential = -self.mass * (o.r @ self.g)
        o.strain = np.zeros(nb)
        o.a = np.array(parts["a"], dtype=float)
        o.ad = np.array(parts["ad"], dtype=float)
        o.add = dydt[self.layout.v_modal].copy()
        for fc in self._flex:
            a, ad = y[fc.qa], y[fc.va]
            A = rotation_matrix(o.p[fc.body])
            o.kinetic[fc.body] = fc.eom.kinetic_energy(A, o.w[fc.body], a, o.rd[fc.body], ad)
            S = fc.eom.I2 + fc.eom.I3 @ a
            o.gravity_potential[fc.body] -= float((A @ S) @ self.g)
            o.strain[fc.body] = fc.eom.strain_energy(a)
        o.mount_potential = self.laws.spring_potential(o.dx.reshape(-1)).reshape(M, 3).sum(axis=1)
        o.work = np.array(parts["work"], dtype=float)
        o.power = dydt[self.layout.work].copy()
        return o

    @property
    def flex_compiled(self) -> tuple:
        """The compiled flexible bodies (see ``_FlexCompiled``)."""
        return tuple(self._flex)

    def reset_counter(self) -> None:
        self.nfev = 0
