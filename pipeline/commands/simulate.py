"""``flexbed simulate [SCENE] …``: run the mount system in time, write the results file."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from flexbed.dynamics.integrate import METHODS
from flexbed.dynamics.statics import Equilibrium, solve_statics

from flexbed.stages.modes import default_modes_path
from flexbed.commands.static import add_modes_file_arg
from flexbed.stages.system import compile_scene
from flexbed.errors import InputError, NumericalError
from flexbed.stages.motion import solve_motion
from flexbed.files.results import read_equilibrium, write_results
from flexbed.files.scene import MODELS, load_scene

__all__ = ["add_args", "run"]


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Simulate the mount system from its static equilibrium (default) or "
                          "its initial positions, and write the results file (HDF5).")
    parser.add_argument("scene", nargs="?", default=None,
                        help="scene file (TOML); default: the built-in reference scene")
    parser.add_argument("-o", "--output", default=None,
                        help="results file (default: <scene name>-results.h5)")
    parser.add_argument("--integrator", choices=METHODS, default=None,
                        help="time integrator; auto: radau where dop853 would be "
                             "stability-bound, else dop853 (default: the scene's)")
    parser.add_argument("--dt", type=float, default=None, help="rk4 step [s]")
    parser.add_argument("--rtol", type=float, default=None, help="relative tolerance (adaptive methods)")
    parser.add_argument("--atol", type=float, default=None, help="absolute tolerance (adaptive methods)")
    parser.add_argument("--from", dest="start", choices=("equilibrium", "initial"), default=None,
                        help="start from the static equilibrium or the scene's positions")
    parser.add_argument("--t-end", type=float, default=None, help="end time [s]")
    parser.add_argument("--output-dt", type=float, default=None, help="spacing of stored samples [s]")
    parser.add_argument("--equilibrium", default=None,
                        help="equilibrium file from 'flexbed static' (default: solve it here)")
    parser.add_argument("--model", choices=MODELS, default=None,
                        help="nonlinear integration, the linear fast path about the static "
                             "equilibrium, or auto: linear when its estimated error is below "
                             "--linear-tol (default: the scene's [solver] model)")
    parser.add_argument("--linear-tol", type=float, default=None,
                        help="position error [m] below which --model auto keeps the linear "
                             "model (default: the scene's [solver] linear_tol)")
    parser.add_argument("--no-progress", action="store_true", help="no progress line on stderr")
    add_modes_file_arg(parser)


class _Progress:
    """A one-line progress indicator on stderr, shown once a run takes over 1 s."""

    def __init__(self, t_end: float, enabled: bool):
        self.t_end = t_end
        self.enabled = enabled
        self.t0 = time.perf_counter()
        self.last = 0.0
        self.shown = False

    def __call__(self, t: float) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self.t0 < 1.0 or now - self.last < 0.25:
            return
        self.last = now
        self.shown = True
        frac = min(1.0, t / self.t_end)
        bar = "#" * int(30 * frac)
        sys.stderr.write(f"\rsimulate [{bar:<30}] t = {t:.4f} / {self.t_end:g} s "
                         f"({100 * frac:3.0f}%), {now - self.t0:.1f} s")
        sys.stderr.flush()

    def close(self) -> None:
        if self.shown:
            sys.stderr.write("\n")
            sys.stderr.flush()


def run(args: argparse.Namespace) -> int:
    sf = load_scene(args.scene)
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
    out = Path(args.output) if args.output else Path(f"{sf.scene.name}-results.h5")
    eq = None
    y_eq = None
    if start == "equilibrium":
        if args.equilibrium:
            y0 = read_equilibrium(args.equilibrium, sf, system)
            eq = Equilibrium(True, f"read from {args.equilibrium}", y0, 0, float("nan"),
                             float("nan"), np.zeros((system.n_rigid, 6)), 0, 0, 0.0,
                             solver.static_tol)
        else:
            eq = solve_statics(system, tol=solver.static_tol, sag=sf.bed.static_sag)
            if not eq.success:
                raise NumericalError(f"{sf.source.name}: {eq.message}")
            y0 = eq.y
    else:
        if args.equilibrium:
            raise InputError("--equilibrium needs --from equilibrium")
        y0 = system.initial_state()
    if model != "nonlinear":
        if eq is None:       # the linear model is about the equilibrium, whatever the start
            eq_lin = solve_statics(system, tol=solver.static_tol, sag=sf.bed.static_sag)
            if not eq_lin.success:
                raise NumericalError(f"{sf.source.name}: {eq_lin.message}")
            y_eq = eq_lin.y
        else:
            y_eq = y0
    progress = _Progress(settings.t_end, enabled=not args.no_progress)
    try:
        motion = solve_motion(system, y_eq, y0, settings, model=model, linear_tol=linear_tol,
                              progress=progress)
    finally:
        progress.close()
    result = motion.run
    write_results(out, sf, system, result, start=start, equilibrium=eq,
                  modes_path=(args.modes_file or default_modes_path(sf)) if sf.bed.flexible
                  else None, model=motion.attrs())
    st = result.stats
    if model != "nonlinear":
        print(f"model {model}: {motion.reason}")
    if motion.model == "linear":
        lr = motion.linear
        print(f"linear: {lr.pieces} exact steps, linearisation {lr.time_linearise:.3f} s, "
              f"propagation {lr.time_propagate:.3f} s, error estimate {lr.time_estimate:.3f} s "
              f"({st.rhs_evaluations} right-hand sides)")
    else:
        rej = "n/a" if st.rejected < 0 else str(st.rejected)
        if st.requested == "auto":
            print(st.reason)
        print(f"{st.method}: {st.steps} steps ({rej} rejected), {st.rhs_evaluations} right-hand "
              f"sides, {st.jacobian_evaluations} Jacobians, {st.segments} segments, "
              f"{st.wall_time:.3f} s")
    if not result.complete:
        raise NumericalError(f"{result.message}; the samples up to t = {result.t_reached:.6g} s "
                             f"are in {out} (marked incomplete)")
    print(f"wrote {out} ({result.t.size} samples, 0 – {result.t[-1]:g} s)")
    return 0
