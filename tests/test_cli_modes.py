"""``flexbed modes`` and ``flexbed run`` through ``main([...])``: outputs,
caching, and one-line failures with exit code 2 and no file left behind.
The whole ``flexbed run`` of the built-in scene is the tour page's, run once
per pytest run in a subprocess (conftest's ``shared_command``)."""

import re
import shutil

import pytest

from flexbed.cli import main
from flexbed.files.modes import read_modes_file
from flexbed.files.scene import builtin_scene_path


def scene_with(tmp_path, old, new, name="s.toml"):
    text = builtin_scene_path().read_text()
    assert old in text
    path = tmp_path / name
    path.write_text(text.replace(old, new, 1))
    return path


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_one_mode_is_one_mode(tmp_path, capsys):
    code, out, err = run(capsys, "modes", "-o", str(tmp_path / "m.h5"), "--modes", "1")
    assert code == 0, err
    assert "(1 elastic mode, 1 asked;" in out and "modes," not in out


def test_modes_writes_the_file_and_prints_the_table(tmp_path, capsys):
    out_file = tmp_path / "m.h5"
    code, out, err = run(capsys, "modes", "-o", str(out_file), "--modes", "4")
    assert code == 0, err
    assert re.search(r"1\s+23\.168\d\s+bending about x\s+SS", out)
    assert re.search(r"3\s+83\.670\d\s+torsion\s+AA", out)
    assert "mass 2995.2 kg" in out and "5753.28, 162.24, 5910.53" in out
    assert read_modes_file(out_file).n_modes == 4


def test_cache_hit_and_miss(tmp_path, capsys):
    out_file = tmp_path / "m.h5"
    assert run(capsys, "modes", "-o", str(out_file))[0] == 0
    stamp = out_file.stat().st_mtime_ns
    code, out, _ = run(capsys, "modes", "-o", str(out_file))
    assert code == 0 and "reused" in out and out_file.stat().st_mtime_ns == stamp
    # fewer modes than held: still a hit
    assert "reused" in run(capsys, "modes", "-o", str(out_file), "--modes", "1")[1]
    # more modes than held: recomputed
    code, out, err = run(capsys, "modes", "-o", str(out_file), "--modes", "5")
    assert code == 0 and "wrote" in out and "fewer than asked" in err
    # --force: recomputed
    assert "wrote" in run(capsys, "modes", "-o", str(out_file), "--force")[1]
    # another plate: recomputed, and the new file says so
    thicker = scene_with(tmp_path, "thickness = 0.1", "thickness = 0.12")
    code, out, err = run(capsys, "modes", str(thicker), "-o", str(out_file))
    assert code == 0 and "other plate inputs" in err
    assert read_modes_file(out_file).plate.thickness == 0.12
    # a damaged cache is recomputed, not trusted
    out_file.write_bytes(b"garbage")
    code, out, err = run(capsys, "modes", "-o", str(out_file))
    assert code == 0 and "recomputing" in err and read_modes_file(out_file).n_modes == 2


def test_fmax_and_vtu(tmp_path, capsys):
    import meshio
    out_file = tmp_path / "m.h5"
    code, out, _ = run(capsys, "modes", "-o", str(out_file), "--fmax", "100",
                       "--vtu", str(tmp_path / "vtu"))
    assert code == 0
    data = read_modes_file(out_file)
    assert data.n_modes == 3 and data.frequency[-1] < 100 < data.next_frequency
    mesh = meshio.read(tmp_path / "vtu" / "lee1999-modes.vtu")
    assert mesh.points.shape == (121, 3)
    fields = sorted(k for k in mesh.point_data if k.startswith("mode"))
    assert fields == ["mode01_23.17Hz", "mode02_64.05Hz", "mode03_83.67Hz"]
    assert mesh.point_data["mode01_23.17Hz"].shape == (121, 3)


@pytest.mark.parametrize("old, new, words", [
    ("poisson = 0.3", "poisson = 0.5", "poisson = 0.5"),
    ("poisson = 0.3", "poisson = -1.0", "poisson = -1.0"),
    ("thickness = 0.1", "thickness = 0.0", "thickness = 0.0"),
    ("length_x = 0.8", "length_x = -0.8", "length_x = -0.8"),
    ("nx = 10", "nx = 0", "nx = 0"),
    ("modes = 2", "modes = 0", "modes = 0"),
    ("nx = 10", "nx = 10\nthicknes = 0.1", "unknown key 'thicknes'"),
])
def test_bad_scene_entries(tmp_path, capsys, old, new, words):
    scene = scene_with(tmp_path, old, new)
    out_file = tmp_path / "m.h5"
    code, out, err = run(capsys, "modes", str(scene), "-o", str(out_file))
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "s.toml" in lines[0] and words in lines[0], err
    assert "Traceback" not in err
    assert not out_file.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]


@pytest.mark.parametrize("argv, words", [
    (["--modes", "0"], "--modes 0"),
    (["--modes", "100000"], "has only 481 elastic modes"),
    (["--fmax", "-3"], "--fmax -3"),
])
def test_bad_requests(tmp_path, capsys, argv, words):
    out_file = tmp_path / "m.h5"
    code, _, err = run(capsys, "modes", "-o", str(out_file), *argv)
    assert code == 2 and len(err.strip().splitlines()) == 1 and words in err, err
    assert not out_file.exists() and list(tmp_path.iterdir()) == []


def test_show_refuses_damaged_and_foreign_files(tmp_path, capsys):
    good = tmp_path / "m.h5"
    assert run(capsys, "modes", "-o", str(good))[0] == 0
    cut = tmp_path / "cut.h5"
    cut.write_bytes(good.read_bytes()[:3000])
    code, _, err = run(capsys, "modes", "--show", str(cut))
    assert code == 2 and "cut.h5: not a readable HDF5 file" in err
    code, out, _ = run(capsys, "modes", "--show", str(good))
    assert code == 0 and "2 elastic modes" in out
    code, _, err = run(capsys, "modes", "--show", str(tmp_path / "missing.h5"))
    assert code == 2 and "missing.h5: no such file" in err


def test_missing_scene_file(tmp_path, capsys):
    code, _, err = run(capsys, "modes", str(tmp_path / "nope.toml"))
    assert code == 2 and "nope.toml" in err and len(err.strip().splitlines()) == 1


@pytest.mark.slow
def test_run_writes_every_stage_into_the_folder(tmp_path, capsys, shared_command):
    # the tour's `flexbed run` (docs/tour.md), run once per pytest run for both
    first = shared_command("flexbed run")
    code, out, err = first.returncode, first.stdout, first.stderr
    assert code == 0, err
    shutil.copytree(first.cwd / "flexbed-out", tmp_path / "out")
    for stage in ("[1/5] modes", "[2/5] static", "[3/5] simulations", "[4/5] points",
                  "[5/5] summary"):
        assert stage in out
    names = {p.name for p in (tmp_path / "out").iterdir()}
    for f in ("lee1999-modes.h5", "lee1999-modes.vtu", "lee1999-equilibrium.h5",
              "lee1999-rigid.h5", "lee1999-flexible.h5", "lee1999-damped.h5",
              "lee1999-compare.csv", "lee1999-summary.md", "lee1999-equipment_A-z.png",
              "lee1999-equipment_B-z.png", "lee1999-base-acceleration.png",
              "lee1999-damped-point-A_top-rel-bed.csv", "lee1999-rigid-point-bed_centre.csv",
              "lee1999-modes.csv", "lee1999-equilibrium.csv", "lee1999-damped-mounts.csv",
              "lee1999-damped-mount-forces.png", "lee1999-damped-bed.xdmf",
              "lee1999-damped-bed.h5", "lee1999-flexible-bed.xdmf"):
        assert f in names, f
    # the bed's motion: an XDMF over a self-describing HDF5 (units on every dataset)
    from flexbed.files.store import read_file
    from flexbed.files.xdmf import BED_MOTION_SCHEMA
    motion = read_file(tmp_path / "out" / "lee1999-damped-bed.h5", schema=BED_MOTION_SCHEMA,
                       major=1)
    assert all(motion.units.values()) and len(motion.units) == 3 + 2 * 301
    assert "1 elastic mode" not in out and "2 elastic modes" in out
    summary = (tmp_path / "out" / "lee1999-summary.md").read_text()
    assert "5.084327544" in summary and "5.331875044" in summary
    # the summary's numbers are the results files' numbers
    import numpy as np
    from flexbed.analyses.points import Point, Run, motion_table
    from flexbed.files.results import read_results
    for case in ("rigid", "flexible", "damped"):
        c = read_results(tmp_path / "out" / f"lee1999-{case}.h5")
        z = np.asarray(c.get("bodies/position"))[0, 2, 2]
        assert f"| equipment A | {case} | {z:.6f} |" in summary
        run_ = Run(tmp_path / "out" / f"lee1999-{case}.h5")
        table = motion_table([run_.absolute(Point("bed centre", "bed", np.array([0, 0, 0.05])))])
        assert table.splitlines()[-1] in summary
    # a second run reuses the modes file (its simulations cut short: the modes are the point)
    code, out, err = run(capsys, "run", "-o", str(tmp_path / "out"), "--t-end", "0.05")
    assert code == 0 and "[1/5] modes: reused" in out


def test_scene_prints_and_writes_the_reference(tmp_path, capsys):
    code, out, _ = run(capsys, "scene")
    assert code == 0 and out == builtin_scene_path().read_text()
    target = tmp_path / "mine.toml"
    assert run(capsys, "scene", "-o", str(target))[0] == 0
    assert target.read_text() == out.replace('name = "lee1999"', 'name = "mine"', 1)
    code, _, err = run(capsys, "scene", "-o", str(target))
    assert code == 2 and "already exists" in err
