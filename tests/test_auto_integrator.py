"""integrator = "auto" (the default): radau where dop853 would be
stability-bound (its stable step below half the output spacing, or more
steps than stiff_steps), else dop853; the results say which ran and why."""

from dataclasses import replace
from pathlib import Path

import numpy as np

from flexbed.cli import main as flexbed
from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.statics import solve_statics
from flexbed.dynamics.method_choice import AUTO_STEP_FRACTION
from flexbed.dynamics.stiffness import stable_step_at_start
from flexbed.files.results import read_results
from flexbed.files.scene import load_scene
from flexbed.stages.modes import ensure_modes
from flexbed.stages.system import compile_scene

SCENES = Path(__file__).parent / "scenes"


def test_the_default_is_auto():
    assert Settings().method == "auto"
    assert load_scene(None).solver.integrator == "auto"


def test_auto_runs_dop853_on_the_reference_scene(reference_scene, reference_system):
    """Rigid bed: dop853's stable step (0.05 s) is far above the output
    spacing; auto runs dop853 and gives its very numbers."""
    sf, s = reference_scene, reference_system
    y0 = solve_statics(s, tol=1e-6).y
    auto = integrate(s, y0, sf.solver.settings(t_end=0.5))
    ref = integrate(s, y0, sf.solver.settings(method="dop853", t_end=0.5))
    assert auto.stats.method == "dop853" and auto.stats.requested == "auto"
    assert auto.stats.reason.startswith("auto: dop853 is not stability-bound")
    assert ref.stats.requested == "dop853" and ref.stats.reason == "requested"
    assert auto.settings.method == "auto"
    np.testing.assert_array_equal(auto.y, ref.y)
    assert auto.stats.steps == ref.stats.steps


def test_auto_runs_radau_on_the_damped_modes(beta20):
    """20 modes with β = 0.01: dop853's stable step 1.8e-5 s is far below
    half the output spacing (0.5 ms): auto runs radau, with radau's numbers."""
    sf, _, system, y0 = beta20
    h, _ = stable_step_at_start(system, y0, 0.2, "dop853")
    assert h < AUTO_STEP_FRACTION * sf.solver.output_dt
    auto = integrate(system, y0, sf.solver.settings(method="auto", t_end=0.2))
    ref = integrate(system, y0, sf.solver.settings(method="radau", t_end=0.2))
    assert auto.stats.method == "radau" and auto.stats.requested == "auto"
    assert auto.stats.reason.startswith("auto: dop853 would be stability-bound (the fastest rate "
                                        "3.6e+05 1/s limits dop853 to steps below 1.8e-05 s")
    np.testing.assert_array_equal(auto.y, ref.y)


def test_auto_runs_radau_on_stiff_mounts():
    """1e9 N/m mounts under 10 kg (hard_stiff_soft.toml)."""
    sf = load_scene(SCENES / "hard_stiff_soft.toml")
    s = compile_scene(sf)
    y0 = solve_statics(s, tol=sf.solver.static_tol).y
    run = integrate(s, y0, sf.solver.settings(method="auto", t_end=0.2))
    assert run.complete and run.stats.method == "radau"


def test_auto_beyond_stiff_steps_runs_radau(reference_system):
    """A stable step above half the output spacing but more steps than
    stiff_steps (where dop853 would be refused): radau."""
    s = reference_system
    y0 = solve_statics(s, tol=1e-6).y
    run = integrate(s, y0, Settings("auto", t_end=0.2, stiff_steps=2))
    assert run.complete and run.stats.method == "radau"
    assert "more than stiff_steps = 2" in run.stats.reason


def test_static_correction_just_works_with_the_default(tmp_path):
    """The reference scene's flexible bed (β = 0.01) with its static
    correction: the default integrator used to refuse it (dop853 stiff);
    auto runs radau."""
    sf0 = load_scene(None)
    sf = replace(sf0, bed=replace(sf0.bed, model="flexible", static_correction=True))
    data, _ = ensure_modes(sf, tmp_path / "m.h5", log=lambda _: None)
    s = compile_scene(sf, data.path)
    y0 = solve_statics(s, tol=1e-6, sag=True).y
    old = integrate(s, y0, sf.solver.settings(method="dop853"))
    assert not old.complete and old.message.startswith("stiff scene")
    run = integrate(s, y0, sf.solver.settings())
    assert run.complete and run.stats.method == "radau"


def test_the_results_file_says_which_method_ran_and_why(beta20, tmp_path, capsys):
    sf, modes, _, _ = beta20
    out = tmp_path / "r.h5"
    code = flexbed(["simulate", str(SCENES / "hard_beta20.toml"), "--modes-file", str(modes),
                    "--integrator", "auto", "--t-end", "0.1", "-o", str(out), "--no-progress"])
    assert code == 0
    printed = capsys.readouterr().out
    assert "auto: dop853 would be stability-bound" in printed and "radau:" in printed
    solver = read_results(out).attrs["solver"]
    assert solver["method"] == "radau" and solver["method_requested"] == "auto"
    assert solver["method_reason"].startswith("auto: dop853 would be stability-bound")
    assert 0.0 < solver["wall_time"] and 0.0 < solver["load_time"]      # both measured
