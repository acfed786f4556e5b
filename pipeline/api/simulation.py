"""The motion of the mount system as a library call, with the scene's
solver settings overridden by keyword.

>>> import flexbed
>>> run = flexbed.simulate(flexbed.load_scene(), t_end=1.0, integrator="radau")  # doctest: +SKIP
>>> run.complete, run.solver["method"]                                         # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
from typing import Any, Mapping

import numpy as np

from flexbed.files.elastomer import time_run_scene
from flexbed.api import bed_modes
from flexbed.api.arguments import Arguments
from flexbed.api.equilibrium import Statics
from flexbed.api.results import Results
from flexbed.errors import InputError
from flexbed.files.modes import ModesData
from flexbed.files.results import results_contents
from flexbed.files.scene import MODELS, SceneFile, read_solver
from flexbed.files.store import in_memory
from flexbed.dynamics.system import System
from flexbed.stages.simulation import Simulation, simulate_system
from flexbed.threads import limited

__all__ = ["simulate", "solver_with", "solved", "results_of", "SETTINGS"]

#: the ``[solver]`` entries :func:`simulate` and :func:`flexbed.compare` take by keyword
SETTINGS = ("integrator", "t_end", "dt", "rtol", "atol", "output_dt")


def solver_with(scene: SceneFile, settings: Mapping[str, Any], function: str = "simulate"):
    """The scene's ``[solver]`` with ``settings`` (names of :data:`SETTINGS`)
    replaced, checked as the scene file's ``[solver]`` is (messages start
    ``flexbed.<function>:``); with none, the scene's own (checked when the
    scene was read)."""
    if not settings:
        return scene.solver
    unknown = sorted(set(settings) - set(SETTINGS))
    if unknown:
        raise InputError(f"flexbed.{function}: unknown setting(s) {', '.join(unknown)} "
                         f"(known: {', '.join(SETTINGS)})")
    table = dataclasses.asdict(scene.solver)
    table.update({k: v.item() if isinstance(v, np.generic) else v for k, v in settings.items()})
    return read_solver(table, f"flexbed.{function}", where="")


@limited()
def simulate(scene: SceneFile, *, modes: ModesData | None = None,
             equilibrium: Statics | None = None, start: str | None = None,
             model: str | None = None, linear_tol: float | None = None,
             progress=None, **settings) -> Results:
    """The motion of the mount system.

    Parameters
    ----------
    scene : SceneFile
    modes : ModesData, optional
        A flexible bed's modes (default: computed in memory).
    equilibrium : Statics, optional
        The scene's equilibrium from :func:`flexbed.statics` (default: solved here).
    start : {"equilibrium", "initial"}, optional
    model : {"nonlinear", "linear", "auto"}, optional
    linear_tol : float, optional
        [m], for ``model = "auto"``.
    progress : callable(t), optional
        Called with the time reached, between chunks of steps.
    **settings
        ``integrator``, ``t_end``, ``dt``, ``rtol``, ``atol``,
        ``output_dt``: override the scene's ``[solver]``.

    Returns
    -------
    Results
        ``complete`` False (with ``message``) when the run stopped early.
    """
    return results_of(*solved(scene, modes=modes, equilibrium=equilibrium, start=start,
                              model=model, linear_tol=linear_tol, progress=progress,
                              **settings))


@limited()
def solved(scene: SceneFile, *, modes: ModesData | None = None,
           equilibrium: Statics | None = None, start: str | None = None,
           model: str | None = None, linear_tol: float | None = None,
           progress=None, **settings) -> tuple:
    """:func:`simulate`'s motion (its arguments, checked as there) before
    anything is evaluated at the output samples: (scene, system, sim,
    modes) — the compiled scene (System), the Simulation, the flexible
    bed's modes or None — which :func:`results_of` turns into Results (a
    study evaluates only what its metrics need)."""
    check = Arguments("simulate")
    scene = check.scene(scene)
    modes = check.modes(modes)
    if equilibrium is not None and not isinstance(equilibrium, Statics):
        check.bad("equilibrium", equilibrium, "the scene's equilibrium from flexbed.statics, "
                                              "or None")
    if equilibrium is not None and equilibrium.scene.statics_digest != scene.statics_digest:
        check.fail("", f"equilibrium: it is the equilibrium of another scene "
                       f"({equilibrium.scene.source.name}: its bodies, mounts or bed differ)")
    start = check.choice(start, "start", ("equilibrium", "initial"))
    model = check.choice(model, "model", MODELS)
    linear_tol = check.real(linear_tol, "linear_tol", positive=True)
    progress = check.callback(progress, "progress")
    solver = solver_with(scene, settings)
    if scene.bed.flexible and modes is None:
        modes = bed_modes.modes(scene)
    scene = time_run_scene(scene)           # elastomers: their Maxwell states
    same = (equilibrium is not None and equilibrium.scene.digest == scene.digest
            and not scene.elastomers)
    system = equilibrium.system if same else bed_modes.compiled(scene, modes)
    sim = simulate_system(scene, system, solver.settings(), start=start or solver.start,
                          model=model or solver.model,
                          linear_tol=solver.linear_tol if linear_tol is None else linear_tol,
                          eq=equilibrium.equilibrium if equilibrium is not None else None,
                          progress=progress)
    return scene, system, sim, modes


def results_of(scene: SceneFile, system: System, sim: Simulation,
               modes: ModesData | None) -> Results:
    """The :class:`Results` of a run solved by :func:`simulate` (every
    dataset of its results file, evaluated at every output sample):
    ``system`` is the compiled ``scene``, ``sim`` its motion, ``modes`` the
    flexible bed's (or None)."""
    contents = results_contents(scene, system, sim.motion.run, start=sim.start,
                                equilibrium=sim.equilibrium if sim.start == "equilibrium"
                                else None, modes_path=modes.path if modes else None,
                                model=sim.motion.attrs())
    return Results(in_memory(*contents), modes=modes if scene.bed.flexible else None,
                   datasets=contents)
