"""``flexbed simulate [SCENE] …``: run the mount system in time, write the results file."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from flexbed.commands.arguments import add_scene_arg, number, file_name
from flexbed.dynamics.integrate import METHODS
from flexbed.dynamics.statics import Equilibrium

from flexbed.stages.modes import default_modes_path
from flexbed.commands.static import add_modes_file_arg
from flexbed.stages.system import compile_scene
from flexbed.files.destination import check_destination, refuse_inputs
from flexbed.errors import InputError, NumericalError
from flexbed.stages.plausibility import mount_statics, mount_table
from flexbed.stages.simulation import simulate_system
from flexbed.files.results import read_equilibrium, results_contents
from flexbed.interrupts import kept
from flexbed.stages.keep import write_kept
from flexbed.files.elastomer import time_run_scene
from flexbed.files.scene import MODELS, load_scene
from flexbed.words import count

__all__ = ["add_args", "run"]


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Simulate the mount system from its static equilibrium (default) or "
                          "its initial positions, and write the results file (HDF5).")
    add_scene_arg(parser)
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="FILE",
                        help="results file (default: <scene file stem>-results.h5)")
    parser.add_argument("--integrator", choices=METHODS, default=None,
                        help="time integrator; auto: radau where dop853 would be "
                             "stability-bound, else dop853 (default: the scene's)")
    parser.add_argument("--dt", type=number, default=None, metavar="DT", help="rk4 step [s]")
    parser.add_argument("--rtol", type=number, default=None, metavar="R",
                        help="relative tolerance (adaptive methods)")
    parser.add_argument("--atol", type=number, default=None, metavar="A",
                        help="absolute tolerance (adaptive methods)")
    parser.add_argument("--from", dest="start", choices=("equilibrium", "initial"), default=None,
                        help="start from the static equilibrium or the scene's positions, "
                             "with the scene's velocities either way")
    parser.add_argument("--t-end", type=number, default=None, metavar="T",
                        help="end time [s] (default: the scene's [solver] t_end)")
    parser.add_argument("--output-dt", type=number, default=None, metavar="DT",
                        help="spacing of stored samples [s] (default: the scene's [solver] "
                             "output_dt)")
    parser.add_argument("--equilibrium", default=None, metavar="FILE",
                        help="equilibrium file from 'flexbed static' (default: solve it here)")
    parser.add_argument("--model", choices=MODELS, default=None,
                        help="nonlinear integration, the linear fast path about the static "
                             "equilibrium, or auto: linear when its estimated error is below "
                             "--linear-tol (default: the scene's [solver] model)")
    parser.add_argument("--linear-tol", type=number, default=None, metavar="M",
                        help="position error [m] below which --model auto keeps the linear "
                             "model (default: the scene's [solver] linear_tol)")
    parser.add_argument("--no-progress", action="store_true", help="no progress line on stderr")
    add_modes_file_arg(parser)


class Progress:
    """A one-line progress indicator on stderr, shown once a run takes over
    1 s, redrawn at most every 0.25 s; :meth:`close` draws the final state
    (100 % for a complete run) and ends the line."""

    def __init__(self, t_end: float, enabled: bool, stream=None):
        self.t_end = t_end
        self.enabled = enabled
        self.stream = stream if stream is not None else sys.stderr
        self.t0 = time.perf_counter()
        self.last = 0.0
        self.shown = False
        self.closed = False
        self.width = 0                  # characters of the line as last drawn

    def draw(self, t: float) -> None:
        """Write the line for time ``t`` [s]."""
        frac = min(1.0, max(0.0, t / self.t_end))
        bar = "#" * int(round(30 * frac))
        line = (f"simulate [{bar:<30}] t = {t:.4f} / {self.t_end:g} s "
                f"({100 * frac:3.0f}%), {time.perf_counter() - self.t0:.1f} s")
        self.shown = True               # first: a signal may land inside the write
        self.width = len(line)
        self.stream.write("\r" + line)
        self.stream.flush()

    def __call__(self, t: float) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self.t0 < 1.0 or now - self.last < 0.25:
            return
        self.last = now
        self.draw(t)

    def phase(self, t: float, what: str) -> None:
        """Redraw the line at time ``t`` [s] followed by what is being done
        now (e.g. "writing FILE"), if the line is shown."""
        if self.shown:
            self.draw(t)
            self.width += len(what) + 4
            self.stream.write(f"; {what} …")
            self.stream.flush()

    def rub(self) -> None:
        """Rub the line out (carriage return), so that a message can take
        its place; the next draw starts afresh."""
        if self.shown:
            self.stream.write("\r" + " " * self.width + "\r")
            self.stream.flush()

    def close(self, t_reached: float | None = None, *, interrupted: bool = False) -> None:
        """End the line, first drawing ``t_reached`` [s] (where the run
        stopped; the end time for a complete run) if the line was shown.
        ``interrupted``: rub the line out instead (carriage return), so
        that the one line saying what was kept takes its place."""
        if self.shown and not self.closed:
            if interrupted:
                self.rub()
            else:
                if t_reached is not None:
                    self.draw(t_reached)
                self.stream.write("\n")
            self.stream.flush()
        self.closed = True


def run(args: argparse.Namespace) -> int:
    sf = load_scene(args.scene)
    sf = time_run_scene(sf)
    system = compile_scene(sf, args.modes_file)
    solver = sf.solver
    method = args.integrator or solver.integrator
    if args.dt is not None and method != "rk4":
        raise InputError(f"--dt applies to the fixed-step rk4 only (integrator is {method!r}); "
                         f"use --rtol/--atol")
    if method == "rk4" and (args.rtol is not None or args.atol is not None):
        raise InputError("--rtol/--atol apply to the adaptive integrators, not rk4; use --dt")
    try:
        settings = solver.settings(method=method, dt=args.dt, rtol=args.rtol, atol=args.atol,
                                   t_end=args.t_end, output_dt=args.output_dt)
    except ValueError as exc:
        raise InputError(f"option: {exc}") from None
    start = args.start or solver.start
    model = args.model or solver.model
    linear_tol = solver.linear_tol if args.linear_tol is None else args.linear_tol
    if not (np.isfinite(linear_tol) and linear_tol > 0):
        raise InputError(f"option: --linear-tol = {linear_tol!r} must be > 0")
    out = Path(args.output) if args.output else Path(f"{sf.output_name}-results.h5")
    check_destination(out)          # refused before any work, not after
    refuse_inputs(out, sf.source, args.modes_file, args.equilibrium)
    eq = None
    if args.equilibrium:
        if start != "equilibrium":
            raise InputError("--equilibrium needs --from equilibrium")
        y_rest = read_equilibrium(args.equilibrium, sf, system)
        eq = Equilibrium(True, f"read from {args.equilibrium}", y_rest, 0, float("nan"),
                         float("nan"), np.zeros((system.n_rigid, 6)), 0, 0, 0.0,
                         solver.static_tol)
    progress = Progress(settings.t_end, enabled=not args.no_progress)
    try:
        sim = simulate_system(sf, system, settings, start=start, model=model,
                              linear_tol=linear_tol, eq=eq, progress=progress)
    except KeyboardInterrupt:           # before any sample: nothing to keep
        progress.close(interrupted=True)
        raise
    except BaseException:
        progress.close(None)
        raise
    motion = sim.motion
    if sim.equilibrium is not None and sim.equilibrium.instability is not None:
        progress.rub()
        print(f"flexbed simulate: warning: {sf.source.name}: "
              f"{sim.equilibrium.instability.line()}", file=sys.stderr)
    eq = sim.equilibrium if start == "equilibrium" else None
    result = motion.run
    modes_path = ((args.modes_file or default_modes_path(sf)) if sf.bed.flexible else None)
    said = []

    def contents():
        # the line says "writing" inside what write_kept guards: a signal that lands
        # as it is said is one that arrived while the results were written (they are
        # kept, marked incomplete), not one that loses them
        if not said:
            said.append(True)
            progress.phase(result.t_reached, f"writing {out}")
        return results_contents(sf, system, result, start=start, equilibrium=eq,
                                modes_path=modes_path, model=motion.attrs())

    try:
        interrupt = write_kept(out, contents, result.interrupt)
    except BaseException:
        progress.close(result.t_reached)
        raise
    if interrupt is not None:
        progress.close(interrupted=True)
        raise kept(interrupt, f"at t = {result.t_reached:.6g} s; the samples up to there "
                              f"are in {out} (marked incomplete)")
    progress.close(result.t_reached)
    if eq is not None:
        print("mounts at rest (static force [N] and deflection [mm] along u1, u2, u3):")
        print(mount_table(mount_statics(system, eq.y)))
    st = result.stats
    if model != "nonlinear":
        print(f"model {model}: {motion.reason}")
    if motion.model == "linear":
        lr = motion.linear
        print(f"linear: {count(lr.pieces, 'exact step')}, linearisation {lr.time_linearise:.3f} s, "
              f"propagation {lr.time_propagate:.3f} s, error estimate {lr.time_estimate:.3f} s "
              f"({count(st.rhs_evaluations, 'right-hand side')})")
    else:
        rej = "n/a" if st.rejected < 0 else str(st.rejected)
        if st.requested == "auto":
            print(st.reason)
        print(f"{st.method}: {count(st.steps, 'step')} ({rej} rejected), "
              f"{count(st.rhs_evaluations, 'right-hand side')}, "
              f"{count(st.jacobian_evaluations, 'Jacobian')}, {count(st.segments, 'segment')}, "
              f"{st.wall_time:.3f} s")
    if not result.complete:
        raise NumericalError(f"{result.message}; the samples up to t = {result.t_reached:.6g} s "
                             f"are in {out} (marked incomplete)")
    print(f"wrote {out} ({count(result.t.size, 'sample')}, 0 – {result.t[-1]:g} s)")
    return 0
