"""`flexbed simulate`: the results file, every integrator, restarts from a file,
interrupted runs, and bad input (one line, exit code 2, no output file)."""

import numpy as np
import pytest

from flexbed.cli import main
from flexbed.files.results import read_results
from flexbed.files.scene import load_scene


def flexbed(argv):
    """`flexbed ARGV` in-process; returns the exit code."""
    return main(argv)


REF = load_scene().text


def z(c, body):
    return c.get("bodies/position")[:, body, 2]


@pytest.mark.parametrize("method,opts", [("rk4", ["--dt", "1e-3"]), ("adams", []), ("bdf", []),
                                         ("radau", []), ("dop853", [])])
def test_every_integrator_writes_a_complete_results_file(tmp_path, method, opts):
    out = tmp_path / "r.h5"
    tol = [] if method == "rk4" else ["--rtol", "1e-9", "--atol", "1e-11"]
    code = flexbed(["simulate", "-o", str(out), "--integrator", method, "--t-end", "0.25",
                    "--output-dt", "0.005", "--no-progress"] + opts + tol)
    assert code == 0
    c = read_results(out)
    assert c.attrs[""]["complete"] is True and c.attrs[""]["start"] == "equilibrium"
    st = c.attrs["solver"]
    assert st["method"] == method and st["steps"] > 0 and st["rhs_evaluations"] >= st["steps"]
    assert st["wall_time"] > 0
    if method == "rk4":                 # fixed steps: none rejected
        assert st["rejected_steps"] == 0
    else:                               # the first step's trials rejected, then few
        assert 0 < st["rejected_steps"] < st["steps"] / 2
    assert c.units["bodies/position"] == "m" and c.units["mounts/force"] == "N"
    assert all(u is not None for u in c.units.values())
    t = c.get("time")
    assert np.allclose(t, np.arange(51) * 0.005, rtol=0, atol=1e-12)
    assert abs(z(c, 1)[0] - 5.084327544) < 1e-9           # started from Table 2
    assert c.attrs["scene"]["digest"] == load_scene().digest
    assert c.get("scene/toml") == REF
    # all methods agree on the motion of the equipment
    ref = np.load(_reference(tmp_path.parent))
    assert np.max(np.abs(c.get("bodies/position")[:, 1:] - ref)) < 2e-7
    # the energy balance closes
    b = c.get("energy/balance")
    assert np.max(np.abs(b - b[0])) < 1e-5 * np.max(np.abs(c.get("energy/work_external")))


def _reference(folder):
    path = folder / "reference_positions.npy"
    if not path.exists():
        out = folder / "reference.h5"
        assert flexbed(["simulate", "-o", str(out), "--integrator", "dop853", "--rtol", "1e-12",
                        "--atol", "1e-13", "--t-end", "0.25", "--output-dt", "0.005",
                        "--no-progress"]) == 0
        np.save(path, read_results(out).get("bodies/position")[:, 1:])
    return path


def test_undamped_tilted_and_upright_equipment_move_alike(tmp_path):
    """Paper 5.2: with M9–M12 undamped too, equipment A (45° mounts) and
    equipment B (upright) move identically in z (the scene is symmetric and
    the mounts isotropic), to round-off."""
    scene = tmp_path / "undamped.toml"
    scene.write_text(REF.replace("c = [500.0, 500.0, 500.0]", "c = [0.0, 0.0, 0.0]"))
    out = tmp_path / "r.h5"
    assert flexbed(["simulate", str(scene), "-o", str(out), "--integrator", "rk4", "--dt", "1e-3",
                    "--t-end", "1.0", "--output-dt", "0.01", "--no-progress"]) == 0
    c = read_results(out)
    zA, zB = z(c, 2), z(c, 3)
    assert np.ptp(zA) > 1e-3
    assert np.max(np.abs(zA - zB)) < 1e-12
    damped = tmp_path / "d.h5"
    assert flexbed(["simulate", "-o", str(damped), "--integrator", "rk4", "--dt", "1e-3",
                    "--t-end", "1.0", "--output-dt", "0.01", "--no-progress"]) == 0
    d = read_results(damped)
    assert np.max(np.abs(z(d, 2) - z(d, 3))) > 1e-5        # B's damping does show


def test_start_from_initial_and_from_an_equilibrium_file(tmp_path, capsys):
    eq = tmp_path / "eq.h5"
    assert flexbed(["static", "-o", str(eq)]) == 0
    out = tmp_path / "r.h5"
    assert flexbed(["simulate", "-o", str(out), "--equilibrium", str(eq), "--t-end", "0.05",
                    "--no-progress"]) == 0
    assert abs(z(read_results(out), 1)[0] - 5.084327544) < 1e-9
    assert flexbed(["simulate", "-o", str(out), "--from", "initial", "--t-end", "0.05",
                    "--no-progress"]) == 0
    c = read_results(out)
    assert z(c, 1)[0] == 5.1 and c.attrs[""]["start"] == "initial"
    # an equilibrium of another scene is refused
    other = tmp_path / "other.toml"
    other.write_text(REF.replace("mass = 100.0", "mass = 120.0", 1))
    capsys.readouterr()
    out2 = tmp_path / "r2.h5"
    assert flexbed(["simulate", str(other), "-o", str(out2), "--equilibrium", str(eq),
                    "--no-progress"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "equilibrium of another scene" in err[0]
    assert not out2.exists()


def test_an_interrupted_run_keeps_its_samples_marked_incomplete(tmp_path, monkeypatch, capsys):
    from flexbed.commands import simulate as cmd_simulate

    def ctrl_c(self, t):
        if t > 0.1:
            raise KeyboardInterrupt

    monkeypatch.setattr(cmd_simulate.Progress, "__call__", ctrl_c)
    out = tmp_path / "r.h5"
    assert flexbed(["simulate", "-o", str(out), "--t-end", "2.0"]) == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "interrupted (SIGINT) at t = " in err[0] and str(out) in err[0]
    c = read_results(out)
    assert c.attrs[""]["complete"] is False and "interrupted" in c.attrs[""]["message"]
    t = c.get("time")
    assert 0.09 < t[-1] < 2.0 and c.get("bodies/position").shape[0] == t.size


BAD = {
    "missing body": (('body_j = "equipment B"', 'body_j = "equipment C"'),
                     "mount 'M9': body_j = 'equipment C' is not a body"),
    "axes": (('axes_deg = [45.0, 0.0, 0.0]',
              'axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.1], [0.0, 0.0, 1.0]]'),
             "mount 'M5': axes = "),
    "non-monotone curve": (('sample = 1.0e-3',
                            'sample = 1.0e-3\n\n[[base.force]]\ndirection = "x"\n'
                            'shape = "curve"\ntime = [0.0, 0.2, 0.1, 0.3]\n'
                            'value = [0.0, 1.0, 2.0, 3.0]'),
                           "base.force 2: time must be strictly increasing: time[2] = 0.1"),
    "degree 9": (('k = [1.0e5, 1.0e5, 1.0e5]\nc = [500.0, 500.0, 500.0]',
                  'stiffness = [[0, 1e5, 0, 0, 0, 0, 0, 0, 0, 1.0], [0, 1e5], [0, 1e5]]'),
                 "mount 'M9': stiffness[0] has degree 9"),
    "negative mass": (('mass = 100.0', 'mass = -100.0'),
                      "body 'equipment A': mass = -100.0 must be > 0"),
    "indefinite inertia": (('inertia = [9.1, 2.8, 10.4]',
                            'inertia = [[9.1, 20.0, 0.0], [20.0, 2.8, 0.0], [0.0, 0.0, 10.4]]'),
                           "body 'equipment A': inertia is not positive definite"),
    "negative pulse": (('sample = 1.0e-3', 'sample = 1.0e-3\n\n[[base.force]]\ndirection = "y"\n'
                        'shape = "triangle"\npeak = 1.0e3\nrise = 0.01\nfall = -0.02'),
                       "base.force 2: fall = -0.02 must be > 0"),
    "unknown key": (('k = [5.0e5, 5.0e5, 5.0e5]', 'k = [5.0e5, 5.0e5, 5.0e5]\nstifness = 3.0'),
                    "mount 'M1': unknown key 'stifness'"),
}


@pytest.mark.parametrize("case", sorted(BAD))
@pytest.mark.parametrize("command", ["simulate", "static"])
def test_bad_input_is_one_line_exit_2_and_no_file(tmp_path, capsys, case, command):
    (old, new), expected = BAD[case]
    if case == "degree 9":
        text = REF.replace(old, new).replace('law = "linear"\nstiffness',
                                             'law = "polynomial"\nstiffness')
    else:
        text = REF.replace(old, new, 1)
    assert text != REF
    scene = tmp_path / "bad.toml"
    scene.write_text(text)
    out = tmp_path / "out.h5"
    assert flexbed([command, str(scene), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith(f"flexbed {command}: bad.toml: "), err[0]
    assert expected in err[0], err[0]
    assert "Traceback" not in err[0] and "ERROR" not in err[0]
    assert not out.exists()
    assert list(tmp_path.iterdir()) == [scene]


def test_bad_options_exit_2(tmp_path, capsys):
    out = tmp_path / "out.h5"
    assert flexbed(["simulate", "-o", str(out), "--integrator", "dop853", "--dt", "1e-3"]) == 2
    assert flexbed(["simulate", "-o", str(out), "--t-end", "-1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and "--dt applies to" in err[0] and "t_end = -1.0 must be > 0" in err[1]
    assert not out.exists()


def test_the_progress_line_ends_at_the_time_reached():
    """Drawn at most every 0.25 s, the line used to stop where the last
    redraw happened (17 %); closing draws the end: 100 % for a finished run."""
    import io
    from flexbed.commands.simulate import Progress

    stream = io.StringIO()
    progress = Progress(3.0, enabled=True, stream=stream)
    progress.t0 -= 2.0                       # a run that has taken 2 s so far
    progress(0.51)
    progress(0.9)                            # within 0.25 s of the last: not drawn
    progress.close(3.0)
    lines = stream.getvalue().split("\r")[1:]
    assert len(lines) == 2 and "( 17%)" in lines[0]
    assert "t = 3.0000 / 3 s (100%)" in lines[1] and "#" * 30 in lines[1]
    assert lines[1].endswith("\n")
    quiet = io.StringIO()
    short = Progress(3.0, enabled=True, stream=quiet)   # a run under 1 s: no line at all
    short(1.0)
    short.close(3.0)
    assert quiet.getvalue() == ""


def test_counts_are_singular_for_one():
    from flexbed.words import count
    assert count(1, "segment") == "1 segment" and count(2, "segment") == "2 segments"
    assert count(1, "elastic mode") == "1 elastic mode" and count(0, "Jacobian") == "0 Jacobians"
    assert count(1, "right-hand side") == "1 right-hand side"
