"""Fixtures shared by the test modules, and how to run the suite.

Running the tests
-----------------
The fast suite, for development: under 90 s on two cores once numba's
cache is warm (the first run compiles the kernels, minutes more)::

    pytest -m "not slow"

The whole suite, what CI runs (``.ci/run``)::

    pytest

``pytest -m slow`` runs the slow tests alone: the benchmark's report and
the README's commands (marked ``bench`` and ``readme`` too: ``-m bench``,
``-m readme``), fine FE meshes and 3-D solid references, the Dask studies,
the fuzzer, commands interrupted in child processes, and commands run
whole, stage after stage. The markers are registered in ``pyproject.toml``
with ``--strict-markers`` (a misspelt marker is an error). A test is slow
by its marker, never by a timing in the test; mark one slow when it takes
more than a second or two, and never shorten a physics test to leave it
unmarked.

Shared objects
--------------
What several modules build is a session fixture here, built once per run:
the built-in reference scene, its compiled system and its equilibrium, and
the 20-mode β-damped flexible bed of ``scenes/hard_beta20.toml``. They are
shared: a test must not change them (their state arrays are read-only;
copy one to perturb it).

Three commands are shared across the pytest-xdist workers too: ``flexbed run``
of the built-in scene (about 20 s of CPU), which the tour page's command
lines and ``tests/test_cli_modes.py`` both check, the tour's ``flexbed
compare`` (about 7 s), whose numbers ``tests/test_compare.py`` checks, and
the tour's ``flexbed sweep`` on the default local cluster (about 10 s),
whose table ``tests/test_sweep.py`` checks (:data:`SHARED_COMMANDS`, with
the files they read from their page, :data:`SHARED_FILES`). The first worker to ask
runs it, in a process of its own as the documentation's other command lines
(``forked_flexbed``), under a lock in the run's
common temporary folder; later ones read what it left (one that comes while
it runs runs its own rather than wait).
A test copies its folder before running more commands in it. The
command lines of the documentation, its code blocks and its example
scripts run forked from a server that has imported flexbed once
(``forked_flexbed``, ``forked_python``, :mod:`command_server`): the
shared commands too, each about 3 s of CPU less than in a fresh interpreter
(``flexbed compare``: 3.3-3.8 s against 6.5-8.3 s of CPU, the server's
start-up subtracted).

Builders of scenes, functions of what a test chooses, are plain modules
beside this file, not fixtures, since test modules call them at import time
too (module constants, parametrisations, Hypothesis strategies):
``scene_text`` (TOML text) and ``built_scenes`` (:mod:`flexbed.dynamics.scene`
objects). This folder is no package, so pytest's default import mode
(``prepend``) puts it on ``sys.path`` when it loads this file, and they
import by their plain names; no test edits ``sys.path`` and no test module
imports another.
"""

from __future__ import annotations

import fcntl
import json
import os
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path


def _one_thread_per_pool() -> None:
    """Start this process's BLAS and OpenMP pools, and its subprocesses',
    at one thread each (unless the environment already sizes them), as
    ``flexbed``'s command line does (:mod:`flexbed.threads`): set before
    NumPy is imported. Two pytest-xdist workers each with a pool of one
    thread per core put four threads on two cores; OpenBLAS's waiting
    threads spin, and the workers' FE solves and the benchmark's report
    spent their CPU waiting on each other (the bench's quick report in its
    test profile: 64 s of CPU with the default pools, 31 s with one thread,
    on the same loaded machine). The Python API holds the
    pools at ``FLEXBED_THREADS`` inside its calls anyway; this covers the
    library functions the tests call directly. Tests that need pools of
    another size set them themselves (threadpoolctl)."""
    for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS",
                 "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS"):
        os.environ.setdefault(name, "1")


_one_thread_per_pool()

import numpy as np  # noqa: E402  (after the pools' sizes are set)
import pytest  # noqa: E402

SCENES = Path(__file__).parent / "scenes"


def _keep_bytecode() -> None:
    """Let this process and its subprocesses keep the bytecode they compile
    (``__pycache__``, beside numba's cache, ignored by git), as Python does by
    default: with ``PYTHONDONTWRITEBYTECODE`` set, every ``flexbed`` command
    a test starts compiled flexbed's modules again (about 0.6 s of CPU each,
    a third of its start-up) and each pytest worker its test modules."""
    os.environ.pop("PYTHONDONTWRITEBYTECODE", None)
    sys.dont_write_bytecode = False


_keep_bytecode()


def _read_only(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


def _compile_jobs() -> list:
    """numba's compiled code in parts (name, function): the right-hand side,
    each compiled stepper with the batch evaluations, the linear path, the
    statics of rigid bodies, and the rest the suite reaches (:func:`_compile_the_rest`);
    all of flexbed's compiled functions (:data:`flexbed.dynamics.jitcache.COMPILED`)
    for the argument types the runs pass them."""
    from flexbed.dynamics import precompile
    from flexbed.dynamics.kernel import rhs_function

    return ([("rhs", rhs_function)]
            + [(m, lambda m=m: precompile.compile_callers((m,))) for m in precompile.STEPPERS]
            + [("linear", precompile.compile_linear_path),
               ("statics", precompile.compile_statics),
               ("rest", _compile_the_rest)])


def _compile_the_rest() -> None:
    """Compile (or load) the compiled functions the suite calls outside
    :mod:`flexbed.dynamics.precompile`'s parts, for the argument types it
    passes them (numba's ``Dispatcher.compile``, nothing called): a study's
    point paths and peaks (:mod:`flexbed.dynamics.sample_passes`, in every
    worker process of a local cluster), the linear estimate's modal rows and
    norm, and the linear maps' second layouts (a sliced output, read-only
    states). About 5 s of CPU on an empty cache, which each process that met
    them first paid again until one had written the cache: both pytest-xdist
    workers, and the local clusters' worker processes of the sweeps and
    optimisations started meanwhile (about 10 s more of CPU with the
    statics' parts, in a first run, than compiled once here). The list is
    the one a whole suite run leaves in numba's cache; a signature missing
    here is compiled on first use, as before, and one that no longer fits
    its function (after an edit of it) is a warning, not an error: the
    function is then compiled on first use too."""
    import warnings
    from numba import types

    from flexbed.dynamics import sample_passes
    from flexbed.dynamics.linear import defect, phi, sweep

    f8, i8, b1 = types.float64, types.int64, types.boolean

    def arr(dtype, ndim, layout="C", readonly=False):
        return types.Array(dtype, ndim, layout, readonly=readonly)

    F1, F2, F3, I1, I2r = arr(f8, 1), arr(f8, 2), arr(f8, 3), arr(i8, 1), arr(i8, 2, "C", True)
    FA2, FA3 = arr(f8, 2, "A"), arr(f8, 3, "A")
    for fn, argtypes in (
            (sample_passes.point_path, (FA2, FA2, F1, FA2, FA2, b1)),
            (sample_passes.point_path, (FA2, FA2, F1, FA2, F2, b1)),
            (sample_passes.peak_norms, (F3,)),
            (sample_passes.peak_norms, (FA3,)),
            (defect.modal_point_rows, (I1, I1, F2, F3, arr(i8, 1, "C", True), F3)),
            (phi.norm1, (F2,)),
            (sweep.poly_derivatives, (arr(f8, 2, "C", True), arr(f8, 1, "C", True), I1, F1, F1,
                                      FA2)),
            (sweep.states_to_deviations, (arr(f8, 2, "C", True), F1, I2r, I2r, I2r, I2r, F2,
                                          F2))):
        try:
            fn.compile(argtypes)
        except Exception as exc:        # noqa: BLE001 - a warm-up, never a test failure
            warnings.warn(f"conftest: {fn.__name__}{argtypes} not compiled ahead "
                          f"({type(exc).__name__}); compiled on first use", stacklevel=1)


@pytest.fixture(scope="session", autouse=True)
def compiled_once_across_workers(request, tmp_path_factory):
    """On an empty numba cache (a fresh install, as in CI), the pytest-xdist
    workers compile flexbed's kernels before their first test, each part
    once: a worker takes the parts in order, the other from the end, each
    part under a lock in the run's shared temporary folder; a part the other
    worker holds is left till last, then loaded from the cache it wrote.
    Without this, each worker compiled what its first tests used, both often
    the same functions at the same time (about 30 s of CPU for the
    right-hand side alone), each also in a compile child of its own
    (:mod:`flexbed.dynamics.precompile`): four compiling processes on two
    cores. Nothing is done with a warm cache, without xdist, or for a run
    of a few tests (``tests/test_jitcache.py`` checks the first-run
    compiling itself, in processes of its own with caches of their own)."""
    worker = os.environ.get("PYTEST_XDIST_WORKER")
    if worker is None or len(request.session.items) < 200:
        return
    from flexbed.dynamics.precompile import rhs_cached

    if rhs_cached():
        return
    jobs = _compile_jobs()
    if int(worker.removeprefix("gw") or 0) % 2:
        jobs.reverse()
    root = _shared_root(tmp_path_factory)
    later = []
    for name, job in jobs:
        with open(root / f"numba-{name}.lock", "w") as lock:
            try:
                fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                later.append((name, job))
                continue
            job()
    for name, job in later:        # the other worker's parts: loaded once it has written them
        with open(root / f"numba-{name}.lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            job()


@pytest.fixture(scope="session")
def reference_scene():
    """The built-in reference scene (rigid bed) as ``load_scene(None)``
    reads it: a frozen :class:`flexbed.files.scene.SceneFile`."""
    from flexbed.files.scene import load_scene

    return load_scene(None)


@pytest.fixture(scope="session")
def reference_system(reference_scene):
    """The reference scene compiled (rigid bed): a
    :class:`flexbed.dynamics.system.System`."""
    from flexbed.stages.system import compile_scene

    return compile_scene(reference_scene)


@pytest.fixture(scope="session")
def reference_equilibrium(reference_system):
    """The reference system's static equilibrium to ``tol = 1e-11``: the
    state (ny,), read-only."""
    from flexbed.dynamics.statics import solve_statics

    eq = solve_statics(reference_system, tol=1e-11)
    assert eq.success, eq.message
    return _read_only(eq.y)


@pytest.fixture(scope="session")
def beta20(tmp_path_factory):
    """``scenes/hard_beta20.toml``, a flexible bed with 20 modes and
    Rayleigh β = 0.01 (its fastest eigenvalue near −βω₂₀², 3.6e5 1/s):
    the scene file, the modes file's path, the compiled system and the
    equilibrium with the elastic sag (ny,), read-only."""
    from flexbed.dynamics.statics import solve_statics
    from flexbed.files.scene import load_scene
    from flexbed.stages.modes import ensure_modes
    from flexbed.stages.system import compile_scene

    sf = load_scene(SCENES / "hard_beta20.toml")
    modes = tmp_path_factory.mktemp("beta20") / "modes.h5"
    ensure_modes(sf, modes, log=lambda _: None)
    system = compile_scene(sf, modes)
    eq = solve_statics(system, tol=sf.solver.static_tol, sag=sf.bed.static_sag)
    assert eq.success, eq.message
    return sf, modes, system, _read_only(eq.y)


@dataclass(frozen=True)
class CommandRun:
    """A command line run once in a subprocess, in its own folder.

    Attributes
    ----------
    cwd : Path
        The folder it ran in (its outputs inside; do not write there).
    returncode : int
    stdout, stderr : str
    """

    cwd: Path
    returncode: int
    stdout: str
    stderr: str


def command_env() -> dict:
    """The environment the documentation's command lines run in: this
    interpreter's ``flexbed`` first on the PATH."""
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    return env


def _shared_root(tmp_path_factory) -> Path:
    """The temporary folder every worker of this pytest run shares (the
    parent of the workers' own under pytest-xdist; the run's own without)."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


def _run_in(folder: Path, cmd: str, env: dict) -> CommandRun:
    cp = subprocess.run(["bash", "-c", "set -o pipefail; " + cmd], cwd=folder,
                        env=env, capture_output=True, text=True, timeout=600)
    return CommandRun(folder, cp.returncode, cp.stdout, cp.stderr)


def run_once(tmp_path_factory, name: str, cmd: str, env: dict) -> CommandRun:
    """``cmd`` run by bash with the environment ``env`` in the folder
    ``name`` of the shared temporary
    folder, once per pytest run: the first caller runs it, later callers (in
    any worker) read its exit code and output. A caller that comes while
    another worker is running it runs its own rather than leave its worker
    idle, but for those of :data:`WAIT_FOR`, which it waits for."""
    folder = _shared_root(tmp_path_factory) / f"shared-{name}"
    record = folder.with_suffix(".json")
    with open(folder.with_suffix(".lock"), "w") as lock:
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)    # released when the file closes
        except BlockingIOError:
            if name not in WAIT_FOR:
                return _run_in(_with_its_files(tmp_path_factory.mktemp(name), name), cmd, env)
            fcntl.flock(lock, fcntl.LOCK_EX)
        if not record.exists():
            shutil.rmtree(folder, ignore_errors=True)     # an attempt that timed out
            folder.mkdir()
            run = _run_in(_with_its_files(folder, name), cmd, env)
            record.write_text(json.dumps([run.returncode, run.stdout, run.stderr]))
    code, out, err = json.loads(record.read_text())
    return CommandRun(folder, code, out, err)


#: command lines that several tests check, run once per pytest run
#: (:func:`shared_command`): the tour's ``flexbed run``, also checked by
#: tests/test_cli_modes.py, its ``flexbed compare``, whose results
#: tests/test_compare.py checks against the paper, and its ``flexbed sweep``
#: on the default local cluster, whose table tests/test_sweep.py checks
#: against single runs
SHARED_COMMANDS = {"flexbed run": "reference-run",
                   "flexbed compare -o compare-out": "reference-compare",
                   "flexbed sweep stiffness.toml -o stiffness --no-progress": "tour-sweep"}
#: shared commands that keep both cores busy themselves (a local cluster of
#: two worker processes): a worker that comes while another runs one waits
#: for it rather than run a second (in one suite run, the tour's sweep and
#: tests/test_sweep.py's came together, and each ran it)
WAIT_FOR = {"tour-sweep"}
#: the files a shared command reads, as its page shows them (a ```toml block
#: naming its file): written into its folder before it runs
SHARED_FILES = {"tour-sweep": ("docs/tour.md", ("stiffness.toml",))}


def _with_its_files(folder: Path, name: str) -> Path:
    """``folder`` with the files of :data:`SHARED_FILES` that the shared
    command ``name`` reads written into it, from its page."""
    from doc_pages import named_files

    page, names = SHARED_FILES.get(name, ("", ()))
    if names:
        files = named_files((Path(__file__).parents[1] / page).read_text())
        for file in names:
            (folder / file).write_text(files[file])
    return folder


@pytest.fixture(scope="session")
def shared_command(tmp_path_factory, forked_flexbed):
    """``shared_command(cmd)``: the :class:`CommandRun` of the command line
    ``cmd`` if it is one of :data:`SHARED_COMMANDS` (run on first use in
    this pytest run, its ``flexbed`` forked from the command server of
    ``forked_flexbed``), else None."""
    def get(cmd: str) -> CommandRun | None:
        name = SHARED_COMMANDS.get(cmd)
        return None if name is None else run_once(tmp_path_factory, name, cmd, forked_flexbed)
    return get


@pytest.fixture(scope="session")
def forked_flexbed():
    """The environment of :func:`command_env` with a ``flexbed`` first on
    the PATH that runs each command line forked from a server that has
    imported flexbed once (``command_server``): the documentation's many
    command lines skip the second of imports each would pay."""
    import tempfile

    import command_server

    folder = Path(tempfile.mkdtemp(prefix="flexbed-"))
    server = command_server.start(folder)
    env = command_env()
    env["PATH"] = f"{folder}{os.pathsep}{env['PATH']}"
    yield env
    server.terminate()
    server.wait()
    shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture(scope="session")
def forked_python(forked_flexbed):
    """The path of a ``python`` that runs ``python -c CODE [ARG ...]`` and
    ``python SCRIPT [ARG ...]`` as the interpreter does, in a process of its
    own forked from the server of ``forked_flexbed`` (use that environment):
    for the documentation's code blocks and scripts, whose checks do not
    depend on a fresh interpreter (about a second of CPU each)."""
    return str(Path(forked_flexbed["PATH"].split(os.pathsep)[0]) / "python")
