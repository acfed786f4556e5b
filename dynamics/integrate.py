"""Time integration of a compiled system, segment by segment between breakpoints.

Methods
-------
``rk4``     classical 4th-order Runge–Kutta, fixed step (the paper's choice);
            each segment between breakpoints is cut into equal steps of at
            most ``dt``; cubic Hermite dense output (4th order). Compiled.
``adams``   variable-order, variable-step Adams (SciPy's LSODA, which may
            switch to BDF by itself when it finds the problem stiff) — the
            role of the paper's DE/STEP.
``bdf``     implicit variable-order BDF (SciPy), for stiff scenes.
``radau``   implicit Radau IIA of order 5, for stiff scenes. Compiled.
``auto``    (the default) radau where dop853 would be stability-bound,
            else dop853 (:func:`flexbed.dynamics.method_choice.auto_method`);
            the run's statistics say which ran and why.
``dop853``  explicit adaptive Dormand–Prince 8(5,3). Compiled.

"Compiled": the whole stepping loop runs in numba
(:mod:`flexbed.dynamics.steppers`) and calls the compiled right-hand side
(:func:`flexbed.dynamics.kernel.evaluate`) through its pointer, in chunks
of at most ``CHUNK_STEPS`` accepted steps (between chunks the driver
reports progress and a Ctrl-C can stop the run); the
step control of ``dop853`` and ``radau`` is SciPy's. ``adams`` and ``bdf``
are SciPy's steppers driven from Python, one step at a time, calling
``System.rhs``.

Every method restarts at each breakpoint (pulse corners, ends of curve
data; the stepper is built anew with that breakpoint as its bound, so no
step crosses it), and the inputs are evaluated with their one-sided limits
from inside the segment (its end is passed to every evaluation, as
``seg_end``). While an input of the base is active, adaptive steps are
bounded by its ``max_step`` (:mod:`flexbed.dynamics.time_functions`) and
the first step after a restart is 1/20 of that, so that a solver starting
at rest cannot step over the load it has not yet felt.

The steppers integrate the deviation from the start, ``z = y − y0`` in the
positions and Euler parameters, so that relative tolerances act on the
motion rather than on where the bodies sit.

Euler parameters are projected back onto |p| = 1 at every restart and,
for ``rk4`` and ``dop853``, after every accepted step (the derivative kept
by the stepper is rescaled consistently, so no extra evaluation is
needed); the multistep and implicit methods keep their own history, so
they are projected at restarts only (the right-hand side uses p/|p|
throughout, so |p| drift never enters the physics).

Stiff scenes and the explicit methods: before ``rk4`` or ``dop853``
starts, the stiffness check of :mod:`flexbed.dynamics.stiffness` may refuse
the run (one line saying why and what to use; ``stiff_steps = 0`` turns it
off).

``bdf`` and ``radau`` get their Jacobian from the same forward
differences (over q and v, steps sqrt(eps)·max(1, |y_j|); the
quadratures' columns are zero, since nothing depends on them). SciPy's
own differences scale their steps with ``atol``: at tight tolerances the
steps of components near zero (the deviations from the start, velocities
at rest) shrink towards round-off, and the quadratures' atol of 1e30
overflows them; Newton then fails and the Jacobian is recomputed at
nearly every step (radau at rtol 1e-8 on a 20-mode damped bed: 519
Jacobians and 28 s, against 6 and 3.3 s).

The energy quadratures (the last entries of y) are integrated with the
motion but left out of the error control (their absolute tolerance is
1e30), like quadrature variables in SUNDIALS; they follow the step sequence
of the motion at the method's order.

Output: the state on the uniform grid ``0, output_dt, 2 output_dt, …`` and
at ``t_end``, from each step's dense output. A failure or an interrupt
(KeyboardInterrupt, which the command line also makes of a SIGTERM) returns
what was computed, marked incomplete, with the reason (the interrupt itself
in ``Run.interrupt``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from . import steppers
from .steppers import N_COUNTS
from .contacts import Contacts
from .method_choice import auto_method
from .stiffness import jacobian_columns, motion_eigenvalues, segments, stable_step, stiff_message
from .system import System

__all__ = ["Settings", "Stats", "Run", "integrate", "warm_up", "METHODS", "output_grid",
           "motion_eigenvalues", "stable_step", "stiff_message", "forced_steps", "too_many_steps"]


METHODS = ("auto", "rk4", "adams", "bdf", "radau", "dop853")


def _scipy_stepper(method: str):
    """SciPy's LSODA (adams) or BDF class, imported when one of them runs:
    ``scipy.integrate``'s ``__init__`` costs about 0.3 s of CPU that the
    compiled methods do not need."""
    from scipy.integrate import BDF, LSODA
    return {"adams": LSODA, "bdf": BDF}[method]


#: the most output samples a run may ask for (t_end / output_dt + 1): each
#: sample holds the whole state and the history computed from it (of the
#: reference scene, about 2.4 kB), so 1e7 samples are some 24 GB; refused
#: before anything is allocated or solved
MAX_OUTPUT_SAMPLES = 10_000_000


def output_samples(t_end: float, output_dt: float) -> float:
    """How many output samples [0, t_end] every output_dt [s] holds."""
    return t_end / output_dt + 1.0


@dataclass(frozen=True, slots=True)
class Settings:
    """Integration settings.

    method : one of METHODS; t_end : float > 0 [s]; dt : float > 0 [s]
    (rk4 step); rtol : float > 0 [–]; atol : float > 0 [SI units of each
    state component]; output_dt : float > 0 [s]; max_steps : int;
    stiff_steps : int ≥ 0, the most steps over [0, t_end] that the stability
    of ``dop853`` may force before the run is refused as a stiff scene (0:
    no stiffness check, for ``rk4`` either; see the module docstring); with
    ``auto``, more than that many makes radau run.
    """

    method: str = "auto"
    t_end: float = 3.0
    dt: float = 1e-3
    rtol: float = 1e-8
    atol: float = 1e-10
    output_dt: float = 1e-3
    max_steps: int = 10_000_000
    stiff_steps: int = 100_000

    def __post_init__(self):
        if self.method not in METHODS:
            raise ValueError(f"integrator = {self.method!r} must be one of {', '.join(METHODS)}")
        for key in ("t_end", "dt", "rtol", "atol", "output_dt"):
            v = float(getattr(self, key))
            if not (math.isfinite(v) and v > 0.0):
                raise ValueError(f"{key} = {v!r} must be > 0")
            object.__setattr__(self, key, v)
        n = output_samples(self.t_end, self.output_dt)
        if n > MAX_OUTPUT_SAMPLES:
            raise ValueError(f"output_dt = {self.output_dt:g} s over t_end = {self.t_end:g} s "
                             f"gives {n:.3g} output samples; the limit is "
                             f"{MAX_OUTPUT_SAMPLES:.0e} (a larger output_dt, or a shorter t_end)")
        if int(self.max_steps) < 1:
            raise ValueError(f"max_steps = {self.max_steps!r} must be >= 1")
        if int(self.stiff_steps) < 0:
            raise ValueError(f"stiff_steps = {self.stiff_steps!r} must be >= 0")


@dataclass(slots=True)
class Stats:
    """Solver statistics of one run.

    steps : accepted steps; rejected : rejected step attempts (rk4: none;
    dop853, radau: exact, counted by the compiled steppers; adams, bdf:
    counted from the distinct trial times of their right-hand-side calls,
    since SciPy does not report them); rhs_evaluations : every call of the
    right-hand side, Jacobian differences and the stiffness check included;
    jacobian_evaluations, lu_decompositions : implicit methods (0
    otherwise; radau counts a real and a complex factorisation as one);
    segments : restarts
    at breakpoints + 1; wall_time : [s] the solve's own time (the stiffness
    check or the ``auto`` choice, and the stepping; the compiled code is
    loaded, or compiled, before the clock starts); load_time : [s] that
    loading; rejected_source : how ``rejected`` was counted; requested :
    the method asked for (e.g. ``auto``); reason : why ``method`` ran.
    """

    method: str
    steps: int = 0
    rejected: int = 0
    rhs_evaluations: int = 0
    jacobian_evaluations: int = 0
    lu_decompositions: int = 0
    segments: int = 0
    wall_time: float = 0.0
    rejected_source: str = ""
    requested: str = ""
    reason: str = "requested"
    load_time: float = 0.0


@dataclass(frozen=True, slots=True)
class Run:
    """What :func:`integrate` returns.

    t : (k,) [s] output times reached; y : (k, ny) states there;
    complete : bool; message : str; stats : Stats; settings : Settings;
    t_reached : float [s] last time the solution reached; interrupt : the
    KeyboardInterrupt (or subclass: a SIGTERM the command line turned into
    one) that stopped the run, None otherwise — a caller that keeps the
    samples raises it again once they are safe; events : the bump stops'
    contacts that began or ended (:class:`flexbed.dynamics.contacts.ContactEvent`),
    in time order.
    """

    t: np.ndarray
    y: np.ndarray
    complete: bool
    message: str
    stats: Stats
    settings: Settings
    t_reached: float
    interrupt: BaseException | None = None
    events: tuple = ()



def output_grid(t_end: float, output_dt: float) -> np.ndarray:
    """0, output_dt, … up to t_end, and t_end itself."""
    n = int(math.floor(t_end / output_dt + 1e-9))
    t = output_dt * np.arange(n + 1)
    if t_end - t[-1] > 1e-9 * output_dt:
        t = np.append(t, t_end)
    else:
        t[-1] = t_end
    return t


class _Projector:
    """Puts every body's Euler parameters back on |p| = 1.

    Works on the shifted state z = y − shift the steppers see (see
    :func:`integrate`); ``shift=None`` for y itself.
    """

    def __init__(self, system: System, shift: np.ndarray | None = None):
        self.sl = system.layout.q_rigid
        self.n = system.n_rigid
        self.p0 = (None if shift is None or self.n == 0
                   else shift[self.sl].reshape(self.n, 7)[:, 3:].copy())

    def __call__(self, z: np.ndarray, f: np.ndarray | None = None) -> None:
        if self.n == 0:
            return
        zp = z[self.sl].reshape(self.n, 7)[:, 3:]
        p = zp if self.p0 is None else zp + self.p0
        nrm = np.sqrt(np.einsum("ij,ij->i", p, p))[:, None]
        if self.p0 is None:
            zp /= nrm
        else:
            zp[...] = p / nrm - self.p0
        if f is not None:                                 # ṗ = ½ Gᵀ ω̄ is linear in p
            f[self.sl].reshape(self.n, 7)[:, 3:] /= nrm


class _TrialTimes:
    """Counts step attempts of SciPy's LSODA and BDF.

    Those solvers do not report rejected steps. Every attempt evaluates the
    right-hand side at its own trial time beyond the step's start, so the
    number of distinct such times counts the attempts.
    """

    def __init__(self, fun):
        self.fun = fun
        self.seen = set()

    def __call__(self, t, y):
        self.seen.add(t)
        return self.fun(t, y)

    def attempts_since(self, t_old: float) -> int:
        k = sum(1 for s in self.seen if s > t_old)
        self.seen.clear()
        return max(1, k)


def integrate(system: System, y0: np.ndarray, settings: Settings, *,
              progress=None) -> Run:
    """Integrate from t = 0 to ``settings.t_end``.

    Parameters
    ----------
    system : System
    y0 : (ny,) array
        State at t = 0 (see :mod:`flexbed.dynamics.layout`).
    settings : Settings
    progress : callable(t: float) -> None, optional
        Called after every accepted step (SciPy's methods) or every chunk of
        at most ``CHUNK_STEPS`` steps (the compiled ones).

    Returns
    -------
    Run
        Samples on the output grid up to where the solution got; never raises
        for a solver failure or an interrupt (``complete = False``).
    """
    load0 = time.perf_counter()
    requested_settings = settings
    requested = settings.method
    _load_kernel(system, requested)
    wall0 = time.perf_counter()
    load_time = wall0 - load0
    method = requested
    t_end = settings.t_end
    grid = output_grid(t_end, settings.output_dt)
    Y = np.empty((grid.size, y0.size))
    stats = Stats(method=method, requested=requested)
    nfev0 = system.nfev
    y = np.array(y0, dtype=float)
    _Projector(system)(y)
    Y[0] = y
    # The steppers integrate the deviation z = y − shift from the start
    # (positions and Euler parameters), so that relative tolerances act on
    # the motion, not on where the bodies happen to sit (|r| ≈ 5 m).
    lay = system.layout
    shift = np.zeros(y.size)
    shift[lay.q_base] = y[lay.q_base]
    shift[lay.q_rigid] = y[lay.q_rigid]
    project = _Projector(system, shift)
    z = y - shift
    bounds = [b for _, b in segments(system, t_end)]
    rtol = settings.rtol
    # the energy quadratures are outputs: kept out of the error control
    atol = np.full(y.size, settings.atol)
    atol[system.layout.work] = 1e30
    state = {"t": 0.0, "k_out": 1}
    counts = np.zeros(N_COUNTS, dtype=np.int64)
    complete, message, interrupt = True, "completed", None
    contacts = Contacts(system)
    try:
        refusal = too_many_steps(system, settings)
        if refusal:
            raise _Stop(f"refused before integrating: {refusal}")
        watch = _Watch(system, y)
        state["watch"] = watch
        if requested == "auto":
            method, stats.reason = auto_method(system, y, settings)
            settings = replace(settings, method=method)
        else:
            refused = stiff_message(system, y, settings)
            if refused:
                raise _Stop(refused)
        stats.method = method
        stats.rejected_source = {"rk4": "none (fixed step)", "dop853": "exact", "radau": "exact"
                                 }.get(method, "counted from distinct trial times")
        if contacts:
            contacts.start(0.0, y, bounds[0] if bounds else math.inf)
        with contacts.held():
            if method in _COMPILED:
                load_time += _run_compiled(system, z, shift, settings, grid, Y, bounds, rtol,
                                           atol, counts, state, stats, project, progress,
                                           contacts)
            else:
                _run_scipy(system, z, shift, settings, grid, Y, bounds, rtol, atol, state, stats,
                           project, progress, contacts)
    except _Stop as exc:
        complete, message = False, str(exc)
    except KeyboardInterrupt as exc:
        what = str(exc) if str(exc).startswith("SIG") else "SIGINT"
        complete, message, interrupt = False, f"interrupted ({what}) at t = {state['t']:.6g} s", exc
    except FloatingPointError as exc:
        complete, message = False, (f"{method}: floating-point error at t = "
                                    f"{state['t']:.6g} s: {exc}")
    if method in _COMPILED:
        stats.steps = int(counts[1])
        stats.rejected = int(counts[2])
        stats.jacobian_evaluations = int(counts[3])
        stats.lu_decompositions = int(counts[4])
    stats.rhs_evaluations = system.nfev - nfev0 + int(counts[0])
    stats.load_time = load_time
    stats.wall_time = time.perf_counter() - load0 - load_time
    k_out = state["k_out"]
    return Run(t=grid[:k_out].copy(), y=Y[:k_out].copy(), complete=complete, message=message,
               stats=stats, settings=requested_settings, t_reached=state["t"], interrupt=interrupt,
               events=tuple(contacts.events))


def _load_kernel(system: System, method: str) -> None:
    """Load (or compile) the compiled right-hand side, and the batch
    evaluation of the stiffness check for the methods that have one."""
    _ = system.kernel   # the property loads (or compiles) the right-hand side
    if method in ("auto", "rk4", "dop853"):
        system.rhs_batch(np.zeros(0), np.zeros((0, system.ny)))


def warm_up(system: System, y0: np.ndarray, methods=None) -> None:
    """Compile (or load from numba's cache) the right-hand side and the
    compiled steppers ``methods`` (default: all of them), by a few short
    steps of each, so that timings that follow measure the work, not the
    compilation. A run needs only its own method: :func:`integrate` loads
    nothing else."""
    for method in (_COMPILED if methods is None else methods):
        integrate(system, y0, Settings(method, t_end=1e-6, dt=1e-6, output_dt=1e-6,
                                       stiff_steps=0))


#: Accepted steps per call of a compiled stepper: between calls the driver
#: reports progress and Python can take a Ctrl-C.
CHUNK_STEPS = 50

#: The compiled steppers' names in :mod:`flexbed.dynamics.steppers`.
_COMPILED = {"rk4": "rk4_segment", "dop853": "dop853_segment", "radau": "radau_segment"}


def _first_step(system: System, t: float, tb: float) -> tuple[float, float]:
    """(h_max, first step) of an adaptive method on [t, tb]: the inputs'
    ``max_step`` and 1/20 of it, or (inf, 0 = automatic) with no input there."""
    hmax = system.max_step(t, tb)
    if np.isfinite(hmax):
        return hmax, min(0.05 * hmax, 0.5 * (tb - t))
    return math.inf, 0.0


def _run_compiled(system, z, shift, settings, grid, Y, bounds, rtol, atol, counts, state,
                  stats, project, progress, contacts):
    """The compiled steppers (:mod:`flexbed.dynamics.steppers`), segment by segment,
    in chunks of at most CHUNK_STEPS accepted steps (one step at a time
    with bump stops, whose contacts are located after each,
    :mod:`flexbed.dynamics.contacts`). Returns the time [s] spent loading
    (or compiling) the stepper, by a call that takes no step, before the
    first one."""
    method = settings.method
    step = getattr(steppers, _COMPILED[method])
    lay = system.layout
    p_idx = np.ascontiguousarray(lay.p_indices(), dtype=np.int64).reshape(-1, 4)
    n_motion = lay.n_motion
    work = steppers.radau_workspace(z.size) if method == "radau" else ()
    kernel = system.kernel
    grid = np.ascontiguousarray(grid, dtype=float)
    load0 = time.perf_counter()
    step(0.0, 0.0, z, shift, kernel, rtol, atol, 0.0, math.inf, grid, Y, 1, 1, p_idx, n_motion,
         counts, work)
    load_time = time.perf_counter() - load0
    chunk = 1 if contacts else CHUNK_STEPS
    for tb in bounds:
        t = state["t"]
        stats.segments += 1
        project(z)
        if method == "rk4":
            hmax, h = math.inf, settings.dt
        else:
            hmax, h = _first_step(system, t, tb)
        if method == "radau":
            steppers.radau_reset(work)
        while True:
            budget = min(chunk, settings.max_steps - int(counts[1]))
            if budget <= 0:
                raise _Stop(f"the maximum number of steps ({settings.max_steps}) was reached "
                            f"at t = {t:.6g} s; raise max_steps or loosen the tolerances")
            if contacts:
                t0, z0, k0 = t, z.copy(), state["k_out"]
            status, t, h, k_out = step(t, tb, z, shift, kernel, rtol, atol, h, hmax, grid,
                                       Y, state["k_out"], budget, p_idx, n_motion, counts, work)
            state["t"], state["k_out"] = float(t), int(k_out)
            if progress is not None:
                progress(float(t))
            if status == -1:
                raise _Stop(state["watch"].collapsed(method, float(t), float(h), z + shift, tb))
            if status != -2:
                state["watch"].check(float(t), z + shift, tb)
            if status == -2:
                raise _Stop(f"{method}: the state became non-finite at t = {t:.6g} s "
                            f"(unstable step; try a smaller step or an implicit method)")
            if contacts and float(t) > t0:
                which = contacts.crossed(float(t), z + shift, tb)
                if which.size:
                    t = _contact_restart(step, system, contacts, which, t0, float(t), z0, z,
                                         shift, kernel, rtol, atol, hmax, grid, Y, k0, p_idx,
                                         n_motion, counts, work, settings, tb, state, stats)
                    project(z)
                    h = settings.dt if method == "rk4" else _first_step(system, t, tb)[1]
                    if method == "radau":
                        steppers.radau_reset(work)
                    if t < tb:
                        continue
                    break
            if status == 0:
                break
    return load_time


def _contact_restart(step, system, contacts, which, t0, t1, z0, z, shift, kernel, rtol, atol,
                     hmax, grid, Y, k0, p_idx, n_motion, counts, work, settings, tb, state,
                     stats) -> float:
    """A step from t0 (state z0, output rows from k0) to t1 crossed a stop's
    gap (entries ``which``): locate the earliest crossing by re-stepping
    from t0 (scratch output, counted as right-hand sides only), step from
    t0 to it for real (z and the rows up to it), switch that contact.
    Returns the instant [s]."""
    trial_counts = np.zeros_like(counts)
    trial_work = steppers.radau_workspace(z.size) if settings.method == "radau" else ()
    no_grid, no_rows = np.zeros(0), np.zeros((0, z.size))
    h0 = settings.dt if settings.method == "rk4" else 0.0

    def state_at(tau: float) -> np.ndarray:
        zt = z0.copy()
        if tau > t0:
            if settings.method == "radau":
                steppers.radau_reset(trial_work)
            step(t0, tau, zt, shift, kernel, rtol, atol, h0 or (tau - t0), hmax, no_grid,
                 no_rows, 0, settings.max_steps, p_idx, n_motion, trial_counts, trial_work)
        return zt + shift

    tau, j, _ = contacts.locate(which, t0, t1, state_at, tb)
    z[:] = z0
    if settings.method == "radau":
        steppers.radau_reset(work)
    counts[1] -= 1              # the step that crossed is replaced by the step(s) to tau
    status, t, _, k_out = step(t0, tau, z, shift, kernel, rtol, atol, h0 or (tau - t0), hmax,
                               grid, Y, k0, settings.max_steps, p_idx, n_motion, counts, work)
    counts[0] += trial_counts[0]
    if status != 0:
        raise _Stop(f"{settings.method}: could not step to the bump stop's contact at "
                    f"t = {tau:.6g} s (status {status})")
    # rows after tau written by the step that crossed: rewritten from here on
    Y[k_out:][grid[k_out:] <= t1 + 1e-12 * max(1.0, t1)] = np.nan
    state["t"], state["k_out"] = float(t), int(k_out)
    try:
        contacts.switch(j, float(t), z + shift, tb)
    except RuntimeError as exc:
        raise _Stop(str(exc)) from None
    stats.segments += 1
    return float(t)


def _run_scipy(system, z, shift, settings, grid, Y, bounds, rtol, atol, state, stats, project,
               progress, contacts):
    """SciPy's LSODA (adams) and BDF, one step at a time (a bump stop's
    contact located on the step's dense output, and the stepper built anew
    from there)."""
    lay = system.layout
    project_y = _Projector(system)
    n_motion = lay.n_motion
    stepper = None
    try:
        for tb in bounds:
            while state["t"] < tb:
                stepper = _scipy_segment(system, z, shift, settings, grid, Y, tb, rtol, atol,
                                         state, stats, project, project_y, n_motion, progress,
                                         contacts)
                stats.jacobian_evaluations += int(getattr(stepper, "njev", 0) or 0)
                stats.lu_decompositions += int(getattr(stepper, "nlu", 0) or 0)
                stepper = None
    finally:
        if stepper is not None:
            stats.jacobian_evaluations += int(getattr(stepper, "njev", 0) or 0)
            stats.lu_decompositions += int(getattr(stepper, "nlu", 0) or 0)


def _write_dense(Y, grid, state, t_new, y_end, dense, shift, project_y) -> None:
    """The output rows in (t_old, t_new]: from the dense output inside, the
    end state at t_new."""
    k_out = state["k_out"]
    k_end = k_out
    while k_end < grid.size and grid[k_end] <= t_new + 1e-12 * max(1.0, t_new):
        k_end += 1
    if k_end > k_out:
        ts = grid[k_out:k_end]
        inside = ts < t_new - 1e-12 * max(1.0, t_new)
        if np.any(inside):
            Y[k_out:k_end][inside] = dense(ts[inside]).T + shift
        Y[k_out:k_end][~inside] = y_end + shift
        for k in range(k_out, k_end):
            project_y(Y[k])
        state["k_out"] = k_end


def _scipy_segment(system, z, shift, settings, grid, Y, tb, rtol, atol, state, stats, project,
                   project_y, n_motion, progress, contacts):
    """One SciPy stepper from state["t"] to tb, or to the first bump-stop
    contact before it (then switched). Returns the stepper."""
    method = settings.method
    t = state["t"]
    stats.segments += 1
    project(z)
    fun = _shifted_rhs(system, shift, tb)
    trial = _TrialTimes(fun)
    hmax, h0 = _first_step(system, t, tb)
    extra = {"max_step": hmax, "first_step": h0} if h0 > 0 else {}
    if method == "bdf":
        extra["jac"] = _difference_jacobian(fun, shift, n_motion)
    stepper = _scipy_stepper(method)(trial, t, z, tb, rtol=rtol, atol=atol, **extra)
    while stepper.status == "running":
        if stats.steps >= settings.max_steps:
            raise _Stop(f"the maximum number of steps ({settings.max_steps}) was "
                        f"reached at t = {stepper.t:.6g} s; raise max_steps or loosen "
                        f"the tolerances")
        t_old = stepper.t
        msg = stepper.step()
        if stepper.status == "failed":
            if "step size" in str(msg):
                raise _Stop(state["watch"].collapsed(method, stepper.t,
                                                     stepper.step_size or 0.0,
                                                     stepper.y + shift, tb))
            raise _Stop(f"{method} failed at t = {stepper.t:.6g} s: {msg}")
        stats.steps += 1
        stats.rejected += trial.attempts_since(t_old) - 1
        t_new = stepper.t
        y_new = stepper.y
        if not np.all(np.isfinite(y_new)):
            raise _Stop(f"{method}: the state became non-finite at t = {t_new:.6g} s "
                        f"(unstable step; try a smaller step or an implicit method)")
        state["watch"].check(t_new, y_new + shift, tb)
        if contacts:
            which = contacts.crossed(t_new, y_new + shift, tb)
            if which.size:
                dense = stepper.dense_output()
                tau, j, y_tau = contacts.locate(which, t_old, t_new,
                                                lambda s, d=dense: d(s) + shift, tb)
                _write_dense(Y, grid, state, tau, y_tau - shift, dense, shift, project_y)
                z[:] = y_tau - shift
                state["t"] = tau
                try:
                    contacts.switch(j, tau, y_tau, tb)
                except RuntimeError as exc:
                    raise _Stop(str(exc)) from None
                if progress is not None:
                    progress(tau)
                return stepper
        _write_dense(Y, grid, state, t_new, y_new, stepper.dense_output(), shift, project_y)
        state["t"] = t_new
        if progress is not None:
            progress(t_new)
    z[:] = stepper.y
    state["t"] = max(state["t"], tb)
    return stepper


def _shifted_rhs(system: System, shift: np.ndarray, seg_end: float):
    """f(t, z) = dy/dt at y = z + shift, the inputs' one-sided limits those
    of the segment ending at ``seg_end`` [s] (for SciPy's steppers)."""
    rhs = system.rhs

    def fun(t, zz):
        return rhs(t, zz + shift, seg_end)

    return fun


def _difference_jacobian(fun, shift: np.ndarray, n_motion: int):
    """The Jacobian of ``fun`` for SciPy's BDF: forward differences over the
    first ``n_motion`` entries (q and v), zero columns for the quadratures."""
    def implicit_jac(t, zz):
        out = np.zeros((zz.size, zz.size))
        out[:, :n_motion] = jacobian_columns(fun, t, zz, n_motion, zz + shift)
        return out

    return implicit_jac


class _Stop(Exception):
    pass


#: A body further than this many times the scene's size from where it
#: started (relative to the base, beyond what its initial velocity and
#: gravity alone would carry it) is taken as diverging.
DIVERGE_FACTOR = 1e3


class _Watch:
    """Stops a run whose motion grows without bound, naming the body.

    The scene's size L is the largest distance of a body's or a mount
    point's start from the base's centre (at least 1 m). A body diverges
    when its displacement from its start, relative to the base, exceeds
    ``DIVERGE_FACTOR`` · L + |v₀| t + ½ |g| t² (v₀: its initial velocity
    relative to the base), or is not finite. Checked between chunks of
    the compiled steppers and after every step of SciPy's.
    """

    def __init__(self, system: System, y0: np.ndarray):
        self.system = system
        self.lay = lay = system.layout
        pos, _ = system.poses(y0)
        rel = pos - pos[0]
        points = np.abs(system.S).max() if system.S.size else 0.0
        self.size = max(1.0, float(np.linalg.norm(rel, axis=1).max()), float(points))
        parts = lay.split(y0)
        self.r0 = np.array(parts["r"], dtype=float)
        self.rb0 = np.array(parts["r_base"], dtype=float) if lay.base_free else None
        rd = np.array(parts["rd"], dtype=float)
        if lay.base_free:
            rd = rd - parts["rd_base"]
        self.v0 = np.linalg.norm(rd, axis=1) if rd.size else np.zeros(0)
        self.g = float(np.linalg.norm(system.g))
        self.names = [system.scene.bodies[i].name for i in lay.rigid]
        self.driven = system.base_motion == "driven"

    def _displacements(self, t: float, y: np.ndarray, driven: bool = True,
                       seg_end: float = math.inf) -> np.ndarray:
        """|Δr| (n,) [m] of every body from its start, relative to the base
        (to a driven base's drive only if ``driven``, evaluated as in the
        segment ending at ``seg_end`` [s])."""
        parts = self.lay.split(y)
        d = parts["r"] - self.r0
        if self.rb0 is not None:
            d = d - (parts["r_base"] - self.rb0)
        elif self.driven and driven:
            d = d - (self.system.base_motion_at(t, seg_end)[0] - self.system.r0_base)
        return np.linalg.norm(d, axis=1)

    def check(self, t: float, y: np.ndarray, seg_end: float = math.inf) -> None:
        """Raise _Stop if a body of the state y (ny,) at t [s] diverges
        (t in the segment ending at ``seg_end`` [s])."""
        if not self.names:
            return
        limit = DIVERGE_FACTOR * self.size + self.v0 * t + 0.5 * self.g * t * t
        d = self._displacements(t, y, driven=False)
        if np.all(d <= limit):
            return
        if self.driven:             # only now: the drive's displacement, evaluated in Python
            d = self._displacements(t, y, seg_end=seg_end)
        bad = ~(d <= limit)
        if np.any(bad):
            i = int(np.argmax(np.where(bad, np.nan_to_num(d, nan=np.inf), -1.0)))
            raise _Stop(f"diverged at t = {t:.6g} s: body '{self.names[i]}' is {d[i]:.3g} m "
                        f"from where it started (relative to the base; beyond "
                        f"{DIVERGE_FACTOR:g} x the scene's size of {self.size:.3g} m): "
                        f"the motion grows without bound (if the scene is stable, the "
                        f"integration is not: try a smaller step or an implicit method)")

    def collapsed(self, method: str, t: float, h: float, y: np.ndarray,
                  seg_end: float = math.inf) -> str:
        """The message for a step size that collapsed at t (in the segment
        ending at ``seg_end`` [s]): the run diverges (in finite time),
        naming the body moving fastest."""
        parts = self.lay.split(y)
        rd = parts["rd"] - (parts["rd_base"] if self.rb0 is not None else 0.0)
        speed = np.linalg.norm(rd, axis=1)
        d = self._displacements(t, y, seg_end=seg_end)
        i = int(np.argmax(np.nan_to_num(speed, nan=np.inf))) if self.names else 0
        who = (f"body '{self.names[i]}' at {speed[i]:.3g} m/s, {d[i]:.3g} m from where it "
               f"started" if self.names else "the base")
        return (f"diverged at t = {t:.6g} s: {who}; {method}'s step size collapsed to "
                f"{h:.3g} s (a motion that blows up; if it should not, try an implicit "
                f"method or looser tolerances)")


def forced_steps(system: System, settings: Settings, method: str) -> tuple[float, float]:
    """(steps, shortest step [s]): the fewest steps the inputs force over
    [0, t_end] — rk4's fixed steps, or an adaptive method's ``max_step``
    of the inputs active on each segment (a 1e12 Hz sinusoid forces
    4e12 per second)."""
    t, n, h_min = 0.0, 0.0, math.inf
    for _, tb in segments(system, settings.t_end):
        if method == "rk4":
            n += math.ceil((tb - t) / settings.dt - 1e-9)
            h_min = min(h_min, settings.dt)
        else:
            h = system.max_step(t, tb)
            if math.isfinite(h):
                n += (tb - t) / h
                h_min = min(h_min, h)
        t = tb
    return n, h_min


def too_many_steps(system: System, settings: Settings) -> str | None:
    """Why a run cannot finish within ``settings.max_steps``, or None: rk4's
    step dt, or the longest step the base inputs allow (dop853's), would
    need more steps over 0 – t_end (a load at 1e12 Hz would otherwise
    crawl)."""
    rk4 = settings.method == "rk4"
    need, h = forced_steps(system, settings, "rk4" if rk4 else "dop853")
    if need <= settings.max_steps:
        return None
    what = "rk4's step dt" if rk4 else "the base inputs' longest step"
    return (f"{what} of {h:.3g} s would take {need:.3g} steps over 0 – {settings.t_end:g} s, "
            f"more than [solver] max_steps = {settings.max_steps}; shorten t_end, lower the "
            f"input's frequency (or sample it) or raise max_steps")
