"""The flexible bed through the command line: the paper's qualitative
findings on the reference scene, and one-line refusals of bad input."""

import csv
import io
import math

import numpy as np
import pytest

from flexbed.analyses.compare import csv_table, delay, markdown_table
from flexbed.cli import build_parser, main
from flexbed.dynamics.integrate import METHODS
from flexbed.files.results import read_results
from flexbed.files.scene import builtin_scene_path

FLEX = ('model = "rigid"', 'model = "flexible"')


def scene(tmp_path, *edits, name="s.toml"):
    text = builtin_scene_path().read_text()
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new, 1)
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.slow
def test_reference_scene_rigid_flexible_damped(shared_command):
    """Paper section 5.2: with the flexible bed the equipment sits lower and
    its vertical motion is slightly delayed; with beta = 0.01 its amplitude
    decays over time. Checked on the tour page's ``flexbed compare -o
    compare-out`` (the same command on the same built-in scene), run once
    per pytest run for both (conftest's ``shared_command``)."""
    cp = shared_command("flexbed compare -o compare-out")
    assert cp.returncode == 0, cp.stderr
    out = cp.cwd / "compare-out"
    with open(out / "lee1999-compare.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 6
    by = {(r["equipment"], r["case"]): r for r in rows}
    for eq in ("equipment A", "equipment B"):
        rigid, flex, damped = (by[(eq, c)] for c in ("rigid", "flexible", "damped"))
        assert float(rigid["static_z_m"]) == pytest.approx(5.331875044, abs=1e-9)
        assert float(flex["static_z_m"]) < float(rigid["static_z_m"]) - 1e-3
        assert 0 < float(flex["delay_s"]) < 0.05
        assert 0 < float(damped["delay_s"]) < 0.05
        assert float(damped["decay_ratio"]) < float(flex["decay_ratio"]) - 0.2
        assert float(flex["decay_ratio"]) > 0.95              # undamped bed: no decay
    for f in ("lee1999-equipment_A-z.png", "lee1999-equipment_B-z.png",
              "lee1999-base-acceleration.png", "lee1999-rigid.h5", "lee1999-flexible.h5",
              "lee1999-damped.h5", "lee1999-modes.h5"):
        assert (out / f).is_file(), f


@pytest.fixture(scope="module")
def modes_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("modes") / "m.h5"
    assert main(["modes", "-o", str(path)]) == 0
    return path


@pytest.mark.parametrize("edits, words", [
    ([FLEX, ("thickness = 0.1", "thickness = 0.12")], "made for another bed"),
    ([FLEX, ("modes = 2", "modes = 5")], "holds only 2"),
    ([FLEX, ("rayleigh = [0.0, 0.01]", "rayleigh = [0.0, -0.01]")], "beta = -0.01"),
    ([FLEX, ("rayleigh = [0.0, 0.01]", "rayleigh = [-1.0, 0.01]")], "alpha = -1.0"),
    ([FLEX, ("point_j = [-0.40, -2.40, 0.00]", "point_j = [-0.50, -2.40, 0.00]")],
     "mount 'M1': point_j = [-0.5, -2.4, 0.0] m is off the bed (outside its outline"),
])
def test_bad_flexible_input(tmp_path, capsys, modes_file, edits, words):
    path = scene(tmp_path, *edits)
    out = tmp_path / "eq.h5"
    code = main(["static", str(path), "--modes-file", str(modes_file), "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1 and words in err, err
    assert not out.exists()


def test_missing_modes_file_says_which_stage_to_run(tmp_path, capsys):
    path = scene(tmp_path, FLEX)
    code = main(["static", str(path), "--modes-file", str(tmp_path / "none.h5")])
    err = capsys.readouterr().err
    assert code == 2 and "run 'flexbed modes" in err


def test_flexible_static_lowers_the_equipment(tmp_path, capsys, modes_file):
    path = scene(tmp_path, FLEX)
    code = main(["static", str(path), "--modes-file", str(modes_file),
                 "-o", str(tmp_path / "eq.h5")])
    out = capsys.readouterr().out
    assert code == 0
    z = {line.split()[1]: float(line.split()[-4]) for line in out.splitlines()
         if line.strip()[:1].isdigit()}
    assert z["bed"] < 5.084327544 - 1e-3


# ---------------------------------------------------------------- the delay

def pulse_response(t, shift=0.0):
    """A decaying 3 Hz oscillation that starts at 0.2 s + shift [s]."""
    s = np.clip(t - 0.2 - shift, 0.0, None)
    return np.where(t >= 0.2 + shift, np.exp(-1.5 * s) * np.sin(2 * np.pi * 3.0 * s), 0.0)


@pytest.mark.parametrize("shift", [-0.09, -0.012, 0.0, 0.024, 0.08, 0.15])
def test_delay_is_measured_inside_half_a_period(shift):
    """The window is half the reference's period (167 ms at 3 Hz): any shift
    inside it is found to a small fraction of the sample spacing, 80 and
    150 ms included (the old search stopped at 50 ms and reported 50)."""
    t = np.arange(0.0, 3.0 + 5e-4, 1e-3)
    ref = pulse_response(t)
    d = delay(t, pulse_response(t, shift), ref)
    assert d.window == pytest.approx(0.5 / 3.0, abs=2e-3)
    assert d.beyond == 0 and d.value == pytest.approx(shift, abs=1e-4)
    assert d.text() == f"{1e3 * d.value:.3f}"


@pytest.mark.parametrize("shift, side", [(0.08, 1), (-0.08, -1)])
def test_a_delay_beyond_the_window_is_said_so(shift, side):
    t = np.arange(0.0, 3.0 + 5e-4, 1e-3)
    d = delay(t, pulse_response(t, shift), pulse_response(t), max_lag=0.05)
    assert d.beyond == side and math.isnan(d.value) and d.window == pytest.approx(0.05)
    assert d.text() == f"beyond {side * 50:g} ms"
    row = {"equipment": "A", "case": "flexible", "static_z": 5.3, "peak": 1e-3, "rms": 1e-4,
           "frequency": 3.0, "delay": d, "decay": 1.0}
    assert f"| beyond {side * 50:g} ms |" in markdown_table([row])
    fields = next(csv.DictReader(io.StringIO(csv_table([row]))))
    assert fields["delay_s"] == "nan" and float(fields["delay_window_s"]) == pytest.approx(0.05)
    assert int(fields["delay_beyond"]) == side


# ---------------------------------------------------- integrator and end time

@pytest.mark.slow
@pytest.mark.parametrize("command", ["compare", "run"])
def test_integrator_and_t_end_options(tmp_path, capsys, command):
    out = tmp_path / command
    code = main([command, "-o", str(out), "--integrator", "rk4", "--t-end", "0.2"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    for case in ("rigid", "flexible", "damped"):
        c = read_results(out / f"lee1999-{case}.h5")
        solver = c.attrs["solver"]
        assert solver["method"] == "rk4" and solver["t_end"] == 0.2
        assert c.get("time")[-1] == pytest.approx(0.2)
    assert "0-0.2 s, rk4" in captured.out


def test_integrator_choices_are_the_dynamics_methods():
    parser = build_parser(["compare", "run", "simulate"])
    for name in ("compare", "run", "simulate"):
        sub = parser._subparsers._group_actions[0].choices[name]
        action = next(a for a in sub._actions if "--integrator" in a.option_strings)
        assert tuple(action.choices) == tuple(METHODS)


@pytest.mark.parametrize("argv, words", [
    (["--t-end", "-1"], "--t-end = -1.0 must be > 0"),
    (["--t-end", "nan"], "--t-end = nan must be > 0"),
])
def test_bad_solver_options(tmp_path, capsys, argv, words):
    code = main(["compare", "-o", str(tmp_path / "c")] + argv)
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and words in err, err
    assert not (tmp_path / "c").exists()
