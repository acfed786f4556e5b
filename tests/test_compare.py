"""The flexible bed through the command line: the paper's qualitative
findings on the reference scene, and one-line refusals of bad input."""

import csv

import pytest

from flexbed.cli import main
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


def test_reference_scene_rigid_flexible_damped(tmp_path, capsys):
    """Paper section 5.2: with the flexible bed the equipment sits lower and
    its vertical motion is slightly delayed; with beta = 0.01 its amplitude
    decays over time."""
    out = tmp_path / "cmp"
    code = main(["compare", "-o", str(out)])
    captured = capsys.readouterr()
    assert code == 0, captured.err
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
     "mount 'M1': point on the bed point (-0.5, -2.4, 0) m lies outside the plate"),
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
