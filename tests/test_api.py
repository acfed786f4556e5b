"""The Python API and the one import namespace (issue 11): the API's objects
hold exactly what the commands write; variants are checked as scene files;
the thread pools are held; the example under docs/ runs."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import flexbed
from flexbed.cli import main
from flexbed.files.results import read_results
from flexbed.files.toml_text import dumps

ROOT = Path(__file__).resolve().parents[1]


def _python(code: str, cwd: Path, **env) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], cwd=cwd, capture_output=True, text=True,
                          env={**os.environ, **env})


def test_one_namespace(tmp_path):
    """fem, dynamics and pipeline are not top-level packages; flexbed.* are."""
    for name in ("fem", "dynamics", "pipeline"):
        cp = _python(f"import {name}", tmp_path)
        assert cp.returncode != 0 and "ModuleNotFoundError" in cp.stderr, name
    cp = _python("import flexbed.fem.bed, flexbed.dynamics.system, flexbed.commands.simulate, "
                 "flexbed.files.scene, flexbed.stages.modes, flexbed.analyses.points, "
                 "flexbed.bench.report; print(flexbed.__version__)", tmp_path)
    assert cp.returncode == 0, cp.stderr
    assert cp.stdout.strip() == flexbed.__version__


def test_import_flexbed_is_light(tmp_path):
    """``import flexbed`` loads the API on first use, not NumPy and numba."""
    cp = _python("import sys, flexbed; print(sorted(m for m in ('numpy', 'numba', 'scipy', "
                 "'h5py', 'skfem', 'matplotlib') if m in sys.modules))", tmp_path)
    assert cp.returncode == 0, cp.stderr
    assert cp.stdout.strip() == "[]"


def test_statics_equals_the_command(tmp_path, capsys):
    eq = flexbed.statics(flexbed.load_scene())
    assert main(["static", "-o", str(tmp_path / "eq.h5")]) == 0
    from flexbed.files.store import read_file
    c = read_file(tmp_path / "eq.h5", schema="flexbed.equilibrium", major=1)
    np.testing.assert_array_equal(eq.position, c.get("bodies/position"))
    np.testing.assert_array_equal(eq.equilibrium.y, c.get("state/y"))
    assert eq.body_names == ("base", "bed", "equipment A", "equipment B")
    # the paper's Table 2 as the README shows it
    assert eq.position[1, 2] == pytest.approx(5.084327544, abs=1e-9)
    assert eq.position[2, 2] == pytest.approx(5.331875044, abs=1e-9)
    eq.save(tmp_path / "api-eq.h5")
    c2 = read_file(tmp_path / "api-eq.h5", schema="flexbed.equilibrium", major=1)
    np.testing.assert_array_equal(c2.get("state/y"), c.get("state/y"))


@pytest.fixture(scope="module")
def flexible_scene():
    return flexbed.vary(flexbed.load_scene(), {"bed.model": "flexible", "solver.t_end": 0.4})


def test_simulate_equals_the_command(tmp_path, flexible_scene, monkeypatch):
    """Same scene, same settings: the API's arrays are the results file's, bit for bit."""
    scene_file = tmp_path / "flex.toml"
    scene_file.write_text(flexible_scene.text)
    monkeypatch.chdir(tmp_path)
    assert main(["modes", str(scene_file)]) == 0
    assert main(["simulate", str(scene_file), "-o", "cli.h5", "--no-progress"]) == 0
    sf = flexbed.load_scene(scene_file)
    run = flexbed.simulate(sf, modes=flexbed.modes(sf, file=tmp_path / "flex-modes.h5"))
    c = read_results(tmp_path / "cli.h5")
    for name in ("time", "bodies/position", "bodies/euler_parameters", "mounts/force",
                 "modal/coordinates", "energy/balance"):
        np.testing.assert_array_equal(run[name], c.get(name), err_msg=name)
    assert run.complete and run.solver["method"] == c.attrs["solver"]["method"]
    # a point on the flexible bed from memory, and from the saved file
    top = run.point("bed", [0.4, 2.4, 0.05])
    run.save(tmp_path / "api.h5")
    again = flexbed.open_results(tmp_path / "api.h5")
    np.testing.assert_array_equal(again.point("bed", [0.4, 2.4, 0.05]).position, top.position)
    # the motion differs from the bed's rigid motion: the modes are in it
    rigid_part = flexbed.simulate(dataclasses.replace(
        sf, bed=dataclasses.replace(sf.bed, model="rigid"))).point("bed", [0.4, 2.4, 0.05])
    assert np.abs(top.position - rigid_part.position).max() > 1e-5


def test_in_memory_modes_equal_the_file(tmp_path, flexible_scene):
    mem = flexbed.modes(flexible_scene)
    disk = flexbed.modes(flexible_scene, file=tmp_path / "m.h5")
    assert mem.path is None and disk.path == tmp_path / "m.h5"
    assert mem.input_hash == disk.input_hash
    for key in ("frequency", "translation", "rotation", "twist"):
        np.testing.assert_array_equal(getattr(mem, key), getattr(disk, key))
    assert flexbed.modes(flexible_scene) is mem          # once per plate in a process


def test_points_of_the_scene(flexible_scene):
    run = flexbed.simulate(flexible_scene)
    pts = run.points()
    assert set(pts) == {"A top", "A top@bed", "B top", "B top@bed", "bed centre"}
    # relative to the bed, in its frame: the top of A stands 0.15 m above A's
    # centre of mass, 0.2475 m above the bed's frame origin at equilibrium
    assert pts["A top@bed"].position[0, 2] == pytest.approx(0.2475 + 0.15, abs=2e-3)


def test_vary_is_a_scene_file():
    scene = flexbed.load_scene()
    same = flexbed.vary(scene, {})
    assert same.digest == scene.digest and same.statics_digest == scene.statics_digest
    data = tomllib.loads(scene.text)
    assert tomllib.loads(dumps(data)) == data
    v = flexbed.vary(scene, {"mount.M5.k": [1e6, 1e6, 2e6], "solver.t_end": 1.0,
                             "body.equipment A.mass": 120.0, "base.force[0].amplitude": 5e5})
    m5 = next(m for m in v.scene.mounts if m.name == "M5")
    assert m5.laws[2].k == 2e6 and v.solver.t_end == 1.0
    assert v.scene.bodies[2].mass == 120.0
    assert v.statics_digest != scene.statics_digest
    assert tomllib.loads(v.text)["base"]["force"][0]["amplitude"] == 5e5


@pytest.mark.parametrize("changes, words", [
    ({"mount.M13.k": [1, 1, 1]}, ["'mount.M13.k'", "M12"]),
    ({"bed.thickness": -0.1}, ["thickness", "-0.1"]),
    ({"bed.thicknes": 0.1}, ["thicknes"]),
    ({"base.force[3].amplitude": 1.0}, ["[3]", "1 entries"]),
    ({"solver.t_end.x": 1.0}, ["t_end", "value"]),
    ({"mount.M1.axes_deg[0]": 10.0}, ["no 'axes_deg' to index", "(mount.M1.axes_deg = [...])"]),
])
def test_vary_refuses_with_the_path(changes, words):
    with pytest.raises(flexbed.InputError) as err:
        flexbed.vary(flexbed.load_scene(), changes)
    for w in words:
        assert w in str(err.value)


def test_unknown_setting_is_refused():
    with pytest.raises(flexbed.InputError, match="t_ned"):
        flexbed.simulate(flexbed.load_scene(), t_ned=1.0)


def test_api_holds_the_thread_pools(monkeypatch):
    """Inside an API call every loaded BLAS/OpenMP pool has FLEXBED_THREADS threads."""
    from threadpoolctl import threadpool_info
    seen = []
    monkeypatch.setenv("FLEXBED_THREADS", "1")
    flexbed.simulate(flexbed.load_scene(), t_end=0.05,
                     progress=lambda t: seen.append(max(p["num_threads"]
                                                        for p in threadpool_info())))
    assert seen and set(seen) == {1}


@pytest.mark.parametrize("setting, expected", [(None, "1"), ("2", "2"), ("zero", "1")])
def test_command_line_pins_the_pools(tmp_path, setting, expected):
    env = {k: v for k, v in os.environ.items() if k != "FLEXBED_THREADS"}
    if setting is not None:
        env["FLEXBED_THREADS"] = setting
    env["OPENBLAS_NUM_THREADS"] = "64"
    cp = subprocess.run([sys.executable, "-c", "import os; from flexbed.threads import "
                         "pin_environment; pin_environment(); print(os.environ["
                         "'OPENBLAS_NUM_THREADS'], os.environ['OMP_NUM_THREADS'])"],
                        cwd=tmp_path, capture_output=True, text=True, env=env)
    assert cp.stdout.split() == [expected, expected], cp.stderr


def test_compare_rows(flexible_scene):
    c = flexbed.compare(flexbed.vary(flexible_scene, {"bed.model": "rigid"}), t_end=0.4)
    assert [(r["equipment"], r["case"]) for r in c.rows][:3] == [
        ("equipment A", "rigid"), ("equipment A", "flexible"), ("equipment A", "damped")]
    rows = {(r["equipment"], r["case"]): r for r in c.rows}
    # the flexible bed sags: the equipment sits lower (README: 2.4 mm)
    sag = rows[("equipment A", "rigid")]["static_z"] - rows[("equipment A", "flexible")]["static_z"]
    assert sag == pytest.approx(2.42e-3, rel=0.01)
    assert "| equipment A | damped |" in c.table()


@pytest.mark.slow
def test_the_example_runs(tmp_path, forked_flexbed, forked_python):
    """The script run whole, forked from a server that has imported flexbed
    (conftest's ``forked_python``)."""
    cp = subprocess.run([forked_python, str(ROOT / "docs" / "api_example.py")], cwd=tmp_path,
                        capture_output=True, text=True, timeout=600, env=forked_flexbed)
    assert cp.returncode == 0, cp.stderr
    lines = [ln for ln in cp.stdout.splitlines() if "peak |dz|" in ln]
    assert len(lines) == 4
