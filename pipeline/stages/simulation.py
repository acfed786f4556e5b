"""The statics and simulation stages on a compiled scene: the static
equilibrium, then the motion from it (or from the scene's initial state)
with the requested model — what ``flexbed static``, ``simulate``,
``compare``, ``run`` and the Python API share."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from flexbed.dynamics.integrate import Settings, output_samples, too_many_steps
from flexbed.dynamics.precompile import compile_in_parallel, likely_steppers
from flexbed.dynamics.stability import instability
from flexbed.dynamics.statics import Equilibrium, solve_statics
from flexbed.dynamics.system import System
from flexbed.errors import InputError, NumericalError
from flexbed.files.scene import SceneFile
from flexbed.stages.motion import Motion, solve_motion
from flexbed.stages.plausibility import check_equilibrium

__all__ = ["Simulation", "equilibrium", "checked", "simulate_system"]


@dataclass(frozen=True)
class Simulation:
    """A motion and where it started.

    motion : Motion; equilibrium : Equilibrium or None (solved or given,
    when the run started there or the linear model needed it); start :
    "equilibrium" or "initial"; y0 : (ny,) the state at t = 0.
    """

    motion: Motion
    equilibrium: Equilibrium | None
    start: str
    y0: np.ndarray


def equilibrium(sf: SceneFile, system: System, *, tol: float | None = None,
                sag: bool | None = None) -> Equilibrium:
    """The static equilibrium (base held) by Newton–Raphson.

    tol : float, optional — default the scene's ``static_tol``; sag : bool,
    optional — include the bed's elastic sag (default the scene's
    ``static_sag``). Raises NumericalError when it is not found or is
    unstable (unless the scene allows it), InputError when it is
    implausible (:mod:`flexbed.stages.plausibility`)."""
    eq = solve_statics(system, tol=sf.solver.static_tol if tol is None else tol,
                       sag=sf.bed.static_sag if sag is None else sag)
    if not eq.success:
        raise NumericalError(f"{sf.source.name}: {eq.message}")
    eq = checked(system, eq)
    check_equilibrium(sf, system, eq)
    return eq


def checked(system: System, eq: Equilibrium) -> Equilibrium:
    """``eq`` with its stability checked (``instability`` set when the
    stiffness at rest has a negative eigenvalue; see
    :mod:`flexbed.dynamics.stability`; from the statics' own tangent
    stiffness where it has one)."""
    found = instability(system, eq.y, jacobian=eq.jacobian)
    return replace(eq, stability="unstable" if found else "stable", instability=found)


def _check_steps(sf: SceneFile, system: System, settings: Settings) -> None:
    """InputError, before any work, when the inputs (or rk4's dt) force more
    steps than ``max_steps``."""
    refusal = too_many_steps(system, settings)
    if refusal:
        raise InputError(f"{sf.source.name}: {refusal}")


#: the most memory a run's results may take [bytes], estimated before
#: anything is solved (:func:`results_bytes`)
MAX_RESULTS_BYTES = 4 * 2 ** 30


def results_bytes(system: System, samples: float) -> float:
    """Estimated bytes of a run's results [B]: per output sample the state
    (twice: as solved and in the history) and what the results file holds
    per body (position, Euler parameters, velocities, accelerations,
    angles, energies: 24 numbers), per mount (deflection, rate, three
    forces, potential: 16) and per modal coordinate (3), 8 bytes each."""
    lay = system.layout
    columns = (2 * lay.ny + 24 * len(system.scene.bodies) + 16 * len(system.scene.mounts)
               + 3 * lay.n_modal + 8)
    return 8.0 * samples * columns


def check_results_size(system: System, settings: Settings) -> None:
    """InputError if the run's results would pass :data:`MAX_RESULTS_BYTES`."""
    n = output_samples(settings.t_end, settings.output_dt)
    size = results_bytes(system, n)
    if size > MAX_RESULTS_BYTES:
        raise InputError(f"{n:.3g} output samples (t_end = {settings.t_end:g} s, output_dt = "
                         f"{settings.output_dt:g} s) of this scene's state would take about "
                         f"{size / 2 ** 30:.3g} GiB; the limit is "
                         f"{MAX_RESULTS_BYTES / 2 ** 30:g} GiB (a larger output_dt, or a shorter "
                         f"t_end)")


def simulate_system(sf: SceneFile, system: System, settings: Settings, *, start: str,
                    model: str, linear_tol: float, eq: Equilibrium | None = None,
                    sag: bool | None = None, progress=None) -> Simulation:
    """Run the motion of a compiled scene.

    Parameters
    ----------
    sf : SceneFile
    system : System
    settings : Settings
    start : {"equilibrium", "initial"}
    model : {"nonlinear", "linear", "auto"}
    linear_tol : float
        [m] for ``model = "auto"``.
    eq : Equilibrium, optional
        The static equilibrium if already known (solved here when needed).
    sag : bool, optional
        Static sag of the bed (default the scene's).
    progress : callable(t), optional

    Returns
    -------
    Simulation
    """
    assert not sf.elastomers or system.scene.maxwell, \
        "a time run's system takes its elastomers' Maxwell terms (flexbed.files.elastomer)"
    check_results_size(system, settings)
    _check_steps(sf, system, settings)     # the linear path's pieces are as fine
    if model == "linear" and system.laws.stopped.size:
        mount = system.scene.mounts[int(system.laws.stopped[0]) // 3].name
        raise InputError(f"{sf.source.name}: model = 'linear' cannot follow a bump stop's "
                         f"contact (mount {mount!r} has one): use 'nonlinear' or 'auto'")
    if model == "linear" and system.scene.maxwell:
        raise InputError(f"{sf.source.name}: model = 'linear' does not take an elastomer "
                         f"mount's Maxwell states (mount {system.scene.maxwell[0].mount!r}): "
                         f"use 'nonlinear' or 'auto'")
    # a first run: the right-hand side compiles in a second process beside the stepper
    compile_in_parallel(likely_steppers(settings.method) if model != "linear" else (),
                        linear=model == "linear")
    if (start == "equilibrium" or model != "nonlinear") and eq is None:
        eq = equilibrium(sf, system, sag=sag)
    y0 = system.initial_state(eq.y if start == "equilibrium" else None)   # + the velocities
    y_eq = eq.y if eq is not None else None
    motion = solve_motion(system, y_eq, y0, settings, model=model, linear_tol=linear_tol,
                          progress=progress)
    return Simulation(motion, eq, start, y0)
