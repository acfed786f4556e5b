"""Post-processing from the results file: consistent with the run's own
kinematics, for rigid bodies and for points on the flexible bed."""

import subprocess
import sys

import h5py
import numpy as np
import pytest

from flexbed.cli import main
from flexbed.files.modes import read_modes_file
from flexbed.analyses.points import Point, Run
from flexbed.files.results import read_results
from flexbed.files.scene import builtin_scene_path


@pytest.fixture(scope="module")
def flexible_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("post")
    text = builtin_scene_path().read_text().replace('model = "rigid"', 'model = "flexible"')
    text += ('\n[[point]]\nname = "A roof"\nbody = "equipment A"\nposition = [0.0, 0.0, 0.15]\n'
             'relative_to = "bed"\n')
    scene = folder / "flex.toml"
    scene.write_text(text)
    modes = folder / "m.h5"
    assert main(["modes", str(scene), "-o", str(modes)]) == 0
    results = folder / "r.h5"
    assert main(["simulate", str(scene), "--modes-file", str(modes), "-o", str(results),
                 "--t-end", "0.3", "--no-progress"]) == 0
    return folder, scene, modes, results


def test_a_point_at_a_body_origin_is_the_body(flexible_run):
    _, _, _, results = flexible_run
    run = Run(results)
    c = read_results(results)
    for b, name in enumerate(run.names[2:], start=2):
        m = run.absolute(Point("o", name, np.zeros(3)))
        assert np.array_equal(m.position, np.asarray(c.get("bodies/position"))[:, b])
        assert np.array_equal(m.velocity, np.asarray(c.get("bodies/velocity"))[:, b])
        assert np.array_equal(m.acceleration, np.asarray(c.get("bodies/acceleration"))[:, b])


def test_a_body_relative_to_itself_is_still(flexible_run):
    _, _, _, results = flexible_run
    run = Run(results)
    m = run.relative(Point("o", "equipment B", np.array([0.1, -0.2, 0.3])), "equipment B")
    assert np.allclose(m.position, [0.1, -0.2, 0.3], rtol=0, atol=1e-14)
    assert np.abs(m.velocity).max() < 1e-14
    assert np.abs(m.acceleration).max() < 1e-12


def test_mount_points_from_post_give_the_runs_deflections(flexible_run):
    """M1 joins the base (never rotates, upright axes) to a corner of the
    flexible bed: Δx = P_j − P_i − l0 and Δẋ = Ṗ_j − Ṗ_i, with the points'
    motion from post (the bed's corner moved by the modes)."""
    _, _, _, results = flexible_run
    run = Run(results)
    Pi = run.absolute(Point("i", "base", np.array([-0.4, -2.4, 5.0])))
    Pj = run.absolute(Point("j", "bed", np.array([-0.4, -2.4, 0.0])))
    l0 = np.array([0.0, 0.0, 0.1])                     # unstrained, scene positions
    dx = Pj.position - Pi.position - l0
    dxd = Pj.velocity - Pi.velocity
    m = run.mount_names.index("M1")
    assert np.abs(dx - run.mounts["deflection"][:, m]).max() < 1e-12
    assert np.abs(dxd - run.mounts["rate"][:, m]).max() < 1e-11
    assert np.abs(run.a).max() > 1e-4                  # the bed did deform


def test_a_bed_node_moves_by_the_modal_reconstruction(flexible_run):
    _, _, modes, results = flexible_run
    run = Run(results)
    data = read_modes_file(modes)
    node = 17
    s = data.nodes[node]
    m = run.absolute(Point("n", "bed", s))
    n = run.a.shape[1]
    u = s + np.einsum("kn,nj->kj", run.a, data.translation[:n, node])
    expect = run.r[:, 1] + np.einsum("kij,kj->ki", run.A[:, 1], u)
    assert np.abs(m.position - expect).max() < 1e-13


@pytest.mark.slow
def test_post_command_outputs(flexible_run, capsys):
    folder, _, _, results = flexible_run
    code = main(["post", str(results), "--point", "P=bed:0.2,1.0,0.05", "--relative-to",
                 "base", "--mounts", "--csv", str(folder / "csv"), "--plot", str(folder / "png")])
    out = capsys.readouterr().out
    assert code == 0
    assert "| A roof | equipment A | inertial |" in out and "| A roof | equipment A | bed |" in out
    assert "| P | bed | base |" in out and "| M12 |" in out
    assert (folder / "csv" / "point-A_roof-rel-bed.csv").is_file()
    assert (folder / "csv" / "mounts.csv").is_file()
    assert (folder / "png" / "point-P.png").is_file()


@pytest.mark.parametrize("argv, words", [
    (["--point", "P=bed:1,2"], "expected NAME=BODY:x,y,z"),
    (["--point", "P=nobody:0,0,0"], "body 'nobody' is not a body"),
    (["--relative-to", "moon"], "--relative-to body 'moon' is not a body"),
    (["--point", "P=bed:0.5,0,0"], "lies outside the plate"),
])
def test_post_bad_input(flexible_run, capsys, argv, words):
    _, _, _, results = flexible_run
    code = main(["post", str(results)] + argv)
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and words in err, err


def test_post_refuses_missing_results_and_stale_modes(flexible_run, tmp_path, capsys):
    _, _, modes, results = flexible_run
    assert main(["post", str(tmp_path / "none.h5")]) == 2
    assert "none.h5: no such file" in capsys.readouterr().err
    stale = tmp_path / "r.h5"
    stale.write_bytes(results.read_bytes())
    with h5py.File(stale, "a") as f:
        f["bed"].attrs["plate_input_hash"] = "0" * 64
    assert main(["post", str(stale), "--mounts"]) == 2
    assert "made for another bed" in capsys.readouterr().err


@pytest.mark.slow
def test_post_works_from_a_moved_results_folder(tmp_path, capsys):
    """The modes file is found beside the results file by its name, wherever
    the folder goes; the recorded absolute path is gone after the move."""
    first = tmp_path / "first"
    assert main(["compare", "-o", str(first), "--t-end", "0.1"]) == 0
    moved = tmp_path / "elsewhere" / "moved"
    moved.parent.mkdir()
    first.rename(moved)
    capsys.readouterr()
    assert main(["post", str(moved / "lee1999-damped.h5"), "--mounts"]) == 0
    assert "| M12 |" in capsys.readouterr().out
    run = Run(moved / "lee1999-damped.h5")
    assert run.modes_path == moved / "lee1999-modes.h5"
    # the results file alone: refused, naming the places tried and the option
    alone = tmp_path / "alone"
    alone.mkdir()
    (alone / "r.h5").write_bytes((moved / "lee1999-damped.h5").read_bytes())
    assert main(["post", str(alone / "r.h5"), "--mounts"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert str(alone / "lee1999-modes.h5") in err and str(first / "lee1999-modes.h5") in err
    assert "--modes-file" in err
    # ... and read with --modes-file
    assert main(["post", str(alone / "r.h5"), "--mounts", "--modes-file",
                 str(moved / "lee1999-modes.h5")]) == 0
    assert "| M12 |" in capsys.readouterr().out


def test_post_modes_file_option_is_checked(flexible_run, tmp_path, capsys):
    _, _, _, results = flexible_run
    other = tmp_path / "thin.toml"
    other.write_text(builtin_scene_path().read_text().replace("thickness = 0.1",
                                                              "thickness = 0.08"))
    assert main(["modes", str(other), "-o", str(tmp_path / "thin.h5")]) == 0
    capsys.readouterr()
    assert main(["post", str(results), "--mounts", "--modes-file",
                 str(tmp_path / "thin.h5")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "made for another bed" in err
    assert main(["post", str(results), "--mounts", "--modes-file", str(tmp_path / "no.h5")]) == 2
    assert "no.h5 (missing)" in capsys.readouterr().err


def test_post_of_a_flexible_run_needs_no_compiled_dynamics(flexible_run):
    """post reads files and does array arithmetic: no numba, no scikit-fem,
    no matplotlib without --plot (checked in a fresh interpreter)."""
    _, _, _, results = flexible_run
    probe = ("import sys\nfrom flexbed.cli import main\ncode = main(sys.argv[1:])\n"
             "print('IMPORTED:' + ','.join(m for m in ('numba', 'skfem', 'matplotlib', "
             "'meshio') if m in sys.modules))\nsys.exit(code)\n")
    p = subprocess.run([sys.executable, "-c", probe, "post", str(results), "--mounts"],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert p.stdout.splitlines()[-1] == "IMPORTED:"


@pytest.mark.slow
def test_post_plots_the_mount_forces(flexible_run, tmp_path, capsys):
    _, _, _, results = flexible_run
    assert main(["post", str(results), "--mounts", "--plot", str(tmp_path)]) == 0
    assert (tmp_path / "mount-forces.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
