"""flexbed as a Python library: the stages as functions returning objects
with NumPy arrays; files only when asked.

>>> import flexbed
>>> scene = flexbed.load_scene()                          # the built-in scene
>>> thick = flexbed.vary(scene, {"bed.thickness": 0.12})  # a variant, checked
>>> eq = flexbed.statics(thick)                           # doctest: +SKIP
>>> run = flexbed.simulate(thick, t_end=1.0)              # doctest: +SKIP
>>> top = run.point("equipment A", [0, 0, 0.15], relative_to="bed")  # doctest: +SKIP
>>> run.save("thick.h5")                                  # doctest: +SKIP

Every function takes a :class:`~flexbed.files.scene.SceneFile` (from
:func:`load_scene`, :func:`vary`, or ``dataclasses.replace`` of its
sections). A flexible bed's modes are computed in memory when none are
given, once per plate in a process (or pass ``modes=flexbed.modes(scene)``,
or ``modes=flexbed.modes(scene, file=...)`` to keep them in a modes file).
Errors are :class:`flexbed.errors.InputError` (bad input) and
:class:`flexbed.errors.NumericalError` (no equilibrium); a run that stops
early comes back with ``complete = False`` and the samples it reached.
BLAS and OpenMP pools are held to ``FLEXBED_THREADS`` threads (default 1)
inside each call (:mod:`flexbed.threads`).
"""

from __future__ import annotations

import dataclasses
import functools
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from flexbed.analyses.compare import CASES, LABELS, case_run, comparison_rows, markdown_table, \
    solve_case
from flexbed.analyses.points import Point, PointMotion, Run
from flexbed.dynamics.rotation import angles_from_p
from flexbed.dynamics.statics import Equilibrium
from flexbed.dynamics.system import System
from flexbed.errors import InputError, NumericalError
from flexbed.files.modes import ModesData, modes_data
from flexbed.files.results import read_results, results_contents, write_equilibrium, \
    write_results_contents
from flexbed.files.scene import SceneFile, load_scene
from flexbed.files.store import Contents, in_memory
from flexbed.files.variants import vary
from flexbed.stages.modes import compute_modes, ensure_modes
from flexbed.stages.simulation import equilibrium, simulate_system
from flexbed.stages.system import compile_scene
from flexbed.threads import limited

__all__ = ["load_scene", "vary", "modes", "statics", "simulate", "compare", "open_results",
           "modal", "frf", "srs", "sweep", "Statics", "Results", "Comparison", "Modal", "Transmissibility"]


def _pinned(fn):
    """Run ``fn`` with the thread pools limited (:func:`flexbed.threads.limited`)."""
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        with limited():
            return fn(*args, **kwargs)
    return wrapper


# ---------------------------------------------------------------------- modes
_MODES: dict[tuple, ModesData] = {}      # modes computed in memory, by plate and request


def _modes_in_memory(sf: SceneFile) -> ModesData:
    key = modes_request(sf)
    if key not in _MODES:
        if len(_MODES) >= 8:
            _MODES.pop(next(iter(_MODES)))
        _MODES[key] = modes_data(compute_modes(sf))
    return _MODES[key]


def modes_request(sf: SceneFile) -> tuple:
    """What a bed's modes depend on: (plate hash, modes, fmax, correction
    modes) — the key under which they are computed once and shared."""
    bed = sf.bed
    return (bed.plate.digest(), bed.modes, bed.fmax,
            bed.correction_modes if bed.static_correction else 0)


@_pinned
def modes(scene: SceneFile, *, file: str | Path | None = None, force: bool = False) -> ModesData:
    """Free–free modes and modal invariants of the scene's bed.

    Parameters
    ----------
    scene : SceneFile
    file : path, optional
        Keep them in this modes file: reused when it was made from the same
        plate inputs and holds the modes asked for, else computed and
        written (as ``flexbed modes -o FILE``).
    force : bool
        With ``file``: recompute whatever it holds.

    Returns
    -------
    ModesData
        Frequencies [Hz], nodal shapes, invariants (``path`` is None when
        computed in memory).
    """
    if file is not None:
        data, _ = ensure_modes(scene, Path(file), force=force, log=lambda m: None)
        return data
    return _modes_in_memory(scene)


def _system(scene: SceneFile, modes_given: ModesData | None, **flex) -> System:
    if scene.bed.flexible and modes_given is None:
        modes_given = modes(scene)
    return compile_scene(scene, modes=modes_given, **flex)


# -------------------------------------------------------------------- statics
@dataclasses.dataclass(frozen=True)
class Statics:
    """The static equilibrium of a scene (the paper's Table 2).

    Attributes
    ----------
    scene : SceneFile
    body_names : tuple of str
    position : ndarray (nb, 3)
        Centres of mass [m], inertial frame.
    euler_parameters : ndarray (nb, 4)
        Scalar first [1].
    orientation_deg : ndarray (nb, 3)
        Roll, pitch, yaw [deg] (X-Y-Z about body axes).
    equilibrium : Equilibrium
        Newton–Raphson's result: ``iterations``, ``residual``, ``y`` (the
        state at rest, layout :mod:`flexbed.dynamics.layout`), ….
    system : System
        The compiled scene it belongs to.
    """

    scene: SceneFile
    body_names: tuple
    position: np.ndarray
    euler_parameters: np.ndarray
    orientation_deg: np.ndarray
    equilibrium: Equilibrium
    system: System

    def save(self, path: str | Path) -> Path:
        """Write the equilibrium file (as ``flexbed static -o``)."""
        return write_equilibrium(Path(path), self.scene, self.system, self.equilibrium)


def _statics_of(scene: SceneFile, system: System, eq: Equilibrium) -> Statics:
    pos, p = system.poses(eq.y)
    return Statics(scene, tuple(b.name for b in system.scene.bodies), pos, p,
                   np.degrees(angles_from_p(p)), eq, system)


@_pinned
def statics(scene: SceneFile, *, modes: ModesData | None = None, tol: float | None = None,
            sag: bool | None = None) -> Statics:
    """The static equilibrium, base held (Newton–Raphson).

    Parameters
    ----------
    scene : SceneFile
    modes : ModesData, optional
        A flexible bed's modes (default: computed in memory).
    tol : float, optional
        Tolerance (default the scene's ``static_tol``).
    sag : bool, optional
        Include the bed's elastic sag (default the scene's ``static_sag``).

    Raises NumericalError when no equilibrium is found.
    """
    system = _system(scene, modes)
    return _statics_of(scene, system, equilibrium(scene, system, tol=tol, sag=sag))


# -------------------------------------------------------------------- results
class Results:
    """A run: the datasets of its results file, in memory.

    Arrays (k samples, nb bodies, M mounts): ``t`` (k,) [s]; ``position``,
    ``velocity``, ``acceleration`` (k, nb, 3) of the centres of mass
    [m, m/s, m/s²], inertial; ``euler_parameters`` (k, nb, 4);
    ``orientation_deg`` (k, nb, 3); ``angular_velocity``,
    ``angular_acceleration`` (k, nb, 3) body frame [rad/s, rad/s²];
    ``mount_deflection``, ``mount_rate``, ``mount_force`` (k, M, 3) along
    the mount axes [m, m/s, N]; ``modal_coordinates`` (k, n). Every dataset
    of the file by its path: ``results["energy/balance"]``.
    ``complete`` / ``message`` say whether the run reached its end.
    """

    def __init__(self, contents: Contents, *, modes: ModesData | None = None,
                 modes_file: str | Path | None = None, datasets: tuple | None = None):
        self.contents = contents
        self._modes = modes
        self._modes_file = modes_file
        self._datasets = datasets
        self._post: Run | None = None

    # the file's datasets
    def __getitem__(self, name: str) -> Any:
        return self.contents.get(name)

    def _array(self, name: str) -> np.ndarray:
        return np.asarray(self.contents.get(name))

    t = property(lambda self: self._array("time"))
    position = property(lambda self: self._array("bodies/position"))
    velocity = property(lambda self: self._array("bodies/velocity"))
    acceleration = property(lambda self: self._array("bodies/acceleration"))
    euler_parameters = property(lambda self: self._array("bodies/euler_parameters"))
    orientation_deg = property(lambda self: self._array("bodies/orientation_deg"))
    angular_velocity = property(lambda self: self._array("bodies/angular_velocity"))
    angular_acceleration = property(lambda self: self._array("bodies/angular_acceleration"))
    mount_deflection = property(lambda self: self._array("mounts/deflection"))
    mount_rate = property(lambda self: self._array("mounts/rate"))
    mount_force = property(lambda self: self._array("mounts/force"))
    modal_coordinates = property(lambda self: self._array("modal/coordinates"))

    @property
    def body_names(self) -> tuple[str, ...]:
        return tuple(str(n) for n in self.contents.get("bodies/names"))

    @property
    def mount_names(self) -> tuple[str, ...]:
        return tuple(str(n) for n in np.atleast_1d(self.contents.datasets.get("mounts/names",
                                                                               [])))

    @property
    def complete(self) -> bool:
        return bool(self.contents.attrs.get("", {}).get("complete", True))

    @property
    def message(self) -> str:
        return str(self.contents.attrs.get("", {}).get("message", ""))

    @property
    def solver(self) -> dict:
        """Method, settings and statistics (the results file's ``solver`` group)."""
        return dict(self.contents.attrs.get("solver", {}))

    def body(self, name: str) -> int:
        """Index of a body by name (InputError naming the bodies if unknown)."""
        names = self.body_names
        if name not in names:
            raise InputError(f"body {name!r} is not a body of this run (bodies: "
                             f"{', '.join(names)})")
        return names.index(name)

    # points of interest
    def _run(self) -> Run:
        if self._post is None:
            self._post = Run(self.contents, modes=self._modes, modes_file=self._modes_file)
        return self._post

    def point(self, body: str, position: Sequence[float], *, relative_to: str | None = None,
              name: str = "point") -> PointMotion:
        """Motion of a point fixed in a body (on a flexible bed: moving with
        the modes; ``position[2]`` is then the offset from the mid-surface).

        Parameters
        ----------
        body : str
        position : 3 floats
            In the body's frame [m].
        relative_to : str, optional
            Give the motion relative to this body, in its frame.

        Returns
        -------
        PointMotion
            ``position``, ``velocity``, ``acceleration`` (k, 3) [m, m/s, m/s²],
            inertial or in ``relative_to``'s frame.
        """
        xyz = np.asarray(position, dtype=float)
        if xyz.shape != (3,) or not np.all(np.isfinite(xyz)):
            raise InputError(f"point {name!r}: position {position!r} must be 3 finite numbers [m]")
        run = self._run()
        pt = Point(name=name, body=body, position=xyz)
        return run.relative(pt, relative_to) if relative_to else run.absolute(pt)

    def points(self) -> dict[str, PointMotion]:
        """The scene's ``[[point]]`` tables: name → absolute motion, and
        ``name@body`` → the motion relative to its ``relative_to`` body."""
        run = self._run()
        out = {}
        for pt in run.scene_points:
            out[pt.name] = run.absolute(pt)
            if pt.relative_to:
                out[f"{pt.name}@{pt.relative_to}"] = run.relative(pt, pt.relative_to)
        return out

    def save(self, path: str | Path) -> Path:
        """Write the results file (as ``flexbed simulate -o``)."""
        if self._datasets is None:
            raise InputError("these results were read from a file: copy the file instead")
        return write_results_contents(Path(path), *self._datasets)


def open_results(path: str | Path, *, modes: ModesData | str | Path | None = None) -> Results:
    """A results file read back. ``modes``: a flexible bed's modes (data, or
    a modes file); default the modes file the run used, looked for beside
    the results file, then where the run recorded it (checked by the
    plate's hash)."""
    if isinstance(modes, (str, Path)):
        return Results(read_results(path), modes_file=modes)
    return Results(read_results(path), modes=modes)



def srs(results: Results | str | Path, *,
        point: str | Point | Sequence[str | Point] | None = None, q: float = 10.0,
        fmin: float = 1.0, fmax: float | None = None,
        per_octave: int = 12):
    """Shock response spectra of points' absolute accelerations (as ``flexbed srs``).

    Parameters
    ----------
    results : Results or path of a results file
    point : "NAME=BODY:x,y,z", a :class:`Point`, or a list of them;
        default the scene's ``[[point]]`` tables
    q : quality factor Q = 1/(2ζ) [1]
    fmin, fmax : band [Hz] (``fmax``: default a tenth of the sampling
        rate, at most a quarter)
    per_octave : frequencies per octave

    Returns
    -------
    flexbed.analyses.shock.Spectra
        ``frequency`` (n,) [Hz]; ``points``: for each point ``positive``,
        ``negative``, ``maximax`` (n, 3) [m/s²] and ``pseudo_velocity``
        (n, 3) [m/s], columns X, Y, Z; ``input``: the same for a driven
        base's acceleration, else None.
    """
    from flexbed.analyses.points import parse_point
    from flexbed.analyses.shock import spectra

    r = open_results(results) if isinstance(results, (str, Path)) else results
    run = r._run()
    given = [point] if isinstance(point, (str, Point)) else list(point or [])
    points = [parse_point(p) if isinstance(p, str) else p for p in given]
    if not points:
        points = list(run.scene_points)
    if not points:
        raise InputError("srs: give point=\"NAME=BODY:x,y,z\" (the scene has no [[point]] "
                         "tables)")
    return spectra(run, points, q=q, fmin=fmin, fmax=fmax, per_octave=per_octave)

_SETTINGS = ("integrator", "t_end", "dt", "rtol", "atol", "output_dt")


def _solver(scene: SceneFile, settings: Mapping[str, Any]):
    """The scene's ``[solver]`` with ``settings`` (names of :data:`_SETTINGS`)
    replaced, checked."""
    unknown = sorted(set(settings) - set(_SETTINGS))
    if unknown:
        raise InputError(f"unknown setting(s) {', '.join(unknown)} (known: "
                         f"{', '.join(_SETTINGS)})")
    try:
        solver = dataclasses.replace(scene.solver, **settings)
        solver.settings()
    except (TypeError, ValueError) as exc:
        raise InputError(f"settings {dict(settings)!r}: {exc}") from None
    return solver


@_pinned
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
        The scene's equilibrium from :func:`statics` (default: solved here).
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
    solver = _solver(scene, settings)
    if scene.bed.flexible and modes is None:
        modes = globals()["modes"](scene)
    system = equilibrium.system if equilibrium is not None else _system(scene, modes)
    sim = simulate_system(scene, system, solver.settings(), start=start or solver.start,
                          model=model or solver.model,
                          linear_tol=solver.linear_tol if linear_tol is None else linear_tol,
                          eq=equilibrium.equilibrium if equilibrium is not None else None,
                          progress=progress)
    contents = results_contents(scene, system, sim.motion.run, start=sim.start,
                                equilibrium=sim.equilibrium if sim.start == "equilibrium"
                                else None, modes_path=modes.path if modes else None,
                                model=sim.motion.attrs())
    return Results(in_memory(*contents), modes=modes if scene.bed.flexible else None,
                   datasets=contents)


# -------------------------------------------------------------------- compare
@dataclasses.dataclass(frozen=True)
class Comparison:
    """The scene with a rigid, a flexible (α = β = 0) and a damped flexible bed.

    rows : list of dict — per equipment and case: ``static_z`` [m], ``peak``
    and ``rms`` of d(t) [m], ``frequency`` [Hz], ``delay`` [s], ``decay``
    [–] (as ``flexbed compare`` reports them); runs : dict case → Results.
    """

    rows: list
    runs: dict

    def table(self) -> str:
        """The rows as a Markdown table (mm and ms, as ``flexbed compare``)."""
        return markdown_table(self.rows)


@_pinned
def compare(scene: SceneFile, *, modes: ModesData | None = None, **settings) -> Comparison:
    """Run the scene with its bed rigid, flexible undamped and flexible with
    its damping, each from its own static equilibrium (``**settings`` as in
    :func:`simulate`)."""
    if settings:
        scene = dataclasses.replace(scene, solver=_solver(scene, settings))
    if modes is None:
        flexible = dataclasses.replace(scene, bed=dataclasses.replace(scene.bed,
                                                                      model="flexible"))
        modes = globals()["modes"](flexible)
    runs, cases = {}, {}
    for case in CASES:
        sol = solve_case(scene, modes, case)
        if sol.interrupt is not None:      # Ctrl-C: stop here, as Python does
            raise sol.interrupt
        res = Results(in_memory(*sol.contents), modes=modes if case != "rigid" else None,
                      datasets=sol.contents)
        if not res.complete:
            raise NumericalError(f"{LABELS[case]}: {res.message}")
        runs[case] = res
        cases[case] = case_run(sol)
    names = [b.name for b in scene.scene.bodies]
    bed = scene.bed.body or names[1]
    equipment = [i for i in range(1, len(names)) if names[i] != bed]
    return Comparison(comparison_rows(cases, names, equipment), runs)


# ---------------------------------------------------- the frequency domain
from flexbed.frequency_api import Modal, Transmissibility  # noqa: E402
from flexbed.frequency_api import frf as _frf, modal as _modal  # noqa: E402

modal = _pinned(_modal)
frf = _pinned(_frf)


# ---------------------------------------------------------------------- sweep
def sweep(study, scheduler=None, *, output: str | Path | None = None, workers: int | None = None,
          keep_results: bool = False, retry_failed: bool = False, progress: bool = False,
          plots: bool = True, batch: int | None = None):
    """Run a design study on Dask (as ``flexbed sweep``).

    Parameters
    ----------
    study : path or flexbed.study.spec.Study
        The study file (TOML; see "Study file" in the README).
    scheduler : str or distributed.Client, optional
        ``"tcp://HOST:PORT"`` of a running Dask scheduler, or a Client;
        default: a local cluster of processes, one per core, for the call.
        (Started from a script, the local cluster's processes import the
        script again: keep its work under ``if __name__ == "__main__":``.)
    output : path, optional
        Folder for ``table.csv``, ``table.h5``, ``plots/`` and, with
        ``keep_results``, ``results/``; a re-run with the same folder
        skips the points done. Default: nothing written.
    workers : int, optional
        Size of the local cluster.
    keep_results, retry_failed, progress, plots : bool
        As the command's ``--keep-results``, ``--retry-failed``, progress
        bar (stderr) and ``--no-plots``.
    batch : int, optional
        Points per Dask task (``--batch``; default the study's ``batch``,
        else chosen from the numbers of points and workers, at most 16).

    Returns
    -------
    flexbed.study.table.StudyTable
        A row per point: ``table["peak_mount_force.M5"]``, ``table.ok``,
        ``table.rows()``; ``complete``.

    Raises
    ------
    InputError
        The study refused (unknown parameter path, metric, …) before
        anything runs.
    """
    from flexbed.study.plan import make_plan
    from flexbed.study.runner import run_plan
    from flexbed.study.spec import Study, read_study
    from flexbed.study.table import check_folder

    if batch is not None and (isinstance(batch, bool) or not isinstance(batch, int) or batch < 1):
        raise InputError(f"batch = {batch!r} must be an integer >= 1")
    plan = make_plan(study if isinstance(study, Study) else read_study(study))
    folder = check_folder(output) if output is not None else None
    return run_plan(plan, scheduler=scheduler, workers=workers, folder=folder,
                    keep_results=keep_results, retry_failed=retry_failed, progress=progress,
                    plots=plots, batch=batch)
