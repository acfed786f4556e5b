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

Builders of scenes, functions of what a test chooses, are plain modules
beside this file, not fixtures, since test modules call them at import time
too (module constants, parametrisations, Hypothesis strategies):
``scene_text`` (TOML text) and ``built_scenes`` (:mod:`flexbed.dynamics.scene`
objects). This folder is no package, so pytest's default import mode
(``prepend``) puts it on ``sys.path`` when it loads this file, and they
import by their plain names; no test edits ``sys.path`` and no test module
imports another.
"""

from pathlib import Path

import numpy as np
import pytest

SCENES = Path(__file__).parent / "scenes"


def _read_only(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


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
