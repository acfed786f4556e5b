"""The bed's stresses over a run and in the shock verdict (issue 26
part 3): ``allowable_stress`` read and refused in one line (exit 2);
``flexbed stress`` and the verdict's stress rows from the modes file's
modal stresses, checked against the superposition done here by hand."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from flexbed.cli import main
from flexbed.errors import InputError
from flexbed.files.builtin import builtin_scene_text
from flexbed.files.scene import parse_scene


def _scene(allowable: str | None, model: str = "flexible", body: str = "bed") -> str:
    text = builtin_scene_text().replace('model = "rigid"', f'model = "{model}"', 1)
    if allowable is not None:
        text = text.replace(f'name = "{body}"\n', f'name = "{body}"\n'
                                                  f'allowable_stress = {allowable}\n', 1)
    return text


def test_allowable_stress_is_read():
    sf = parse_scene(_scene("2.35e8"), Path("s.toml"))
    a = sf.limits.allowable
    assert (a.body, a.plate, a.stiffeners) == ("bed", 2.35e8, 2.35e8)
    two = _scene("{plate = 2.35e8, stiffeners = 3.55e8}")
    a = parse_scene(two, Path("s.toml")).limits.allowable
    assert (a.plate, a.stiffeners) == (2.35e8, 3.55e8)
    assert parse_scene(_scene(None), Path("s.toml")).limits.allowable is None


@pytest.mark.parametrize("allowable, model, body, match", [
    ("0.0", "flexible", "bed", r"s.toml: body 'bed': allowable_stress = 0.0 must be > 0"),
    ("-2.35e8", "flexible", "bed", r"allowable_stress = -235000000.0 must be > 0"),
    ('"235 MPa"', "flexible", "bed", r"allowable_stress = '235 MPa' must be a number"),
    ("{plate = -1.0}", "flexible", "bed", r"allowable_stress.plate = -1.0 must be > 0"),
    ("{stiffeners = 1.0}", "flexible", "bed", r"allowable_stress: 'plate' is required"),
    ("2.35e8", "rigid", "bed", r"needs \[bed\] model = \"flexible\""),
    ("2.35e8", "flexible", "equipment A", r"body 'equipment A': allowable_stress: only the "
                                          r"bed's body"),
])
def test_bad_allowable_stress_is_refused_in_one_line(allowable, model, body, match):
    with pytest.raises(InputError, match=match) as exc:
        parse_scene(_scene(allowable, model, body), Path("s.toml"))
    assert "\n" not in str(exc.value)


def test_allowable_stress_at_or_below_zero_exits_2(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(_scene("-1.0"))
    assert main(["qualify", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "allowable_stress = -1.0 must be > 0" in err
    assert "Traceback" not in err and not list(tmp_path.glob("bad-verdict*"))


def test_stress_of_a_rigid_run_or_a_bad_option_is_refused_in_one_line(tmp_path, capsys):
    path = tmp_path / "r.h5"
    assert main(["simulate", "-o", str(path), "--t-end", "0.01", "--no-progress"]) == 0
    capsys.readouterr()
    assert main(["stress", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "the run's bed is rigid" in err and "\n" not in err
    assert main(["stress", str(path), "--every", "0"]) == 2
    assert "--every 0: must be an integer >= 1" in capsys.readouterr().err
    (tmp_path / "file").write_text("")
    assert main(["stress", str(path), "--plot", str(tmp_path / "file")]) == 2
    assert "is not a folder" in capsys.readouterr().err


@pytest.mark.slow
def test_stress_command_and_verdict_against_hand_superposition(tmp_path, capsys, monkeypatch):
    """A short flexible run: the peak von Mises of ``flexbed stress`` and
    of the verdict is the one found by superposing the modes file's
    stresses with the run's modal coordinates here; an allowable below it
    fails (exit 3), above it passes."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text(_scene(None))
    assert main(["modes", "s.toml", "-o", "m.h5"]) == 0
    assert main(["simulate", "s.toml", "--modes-file", "m.h5", "-o", "r.h5", "--t-end", "0.15",
                 "--no-progress"]) == 0
    capsys.readouterr()
    assert main(["stress", "r.h5", "--modes-file", "m.h5", "--csv", "out", "--plot", "out",
                 "--xdmf", "out/series", "--every", "5"]) == 0
    printed = capsys.readouterr().out
    with h5py.File("m.h5") as f:
        mem, ben = f["stress/membrane"][...], f["stress/bending_top"][...]
    with h5py.File("r.h5") as f:
        a = f["modal/coordinates"][...]
    n = a.shape[1]
    m = np.einsum("kn,nec->kec", a, mem[:n])
    b = np.einsum("kn,nec->kec", a, ben[:n])
    faces = np.stack([m + b, m - b])
    vm = np.sqrt(faces[..., 0] ** 2 - faces[..., 0] * faces[..., 1] + faces[..., 1] ** 2
                 + 3 * faces[..., 2] ** 2)
    peak = vm.max()
    assert f"{peak / 1e6:12.4g}" in printed
    csv = (tmp_path / "out" / "bed-stress-peaks.csv").read_text().splitlines()
    assert max(float(r.split(",")[3]) for r in csv[1:]) == pytest.approx(peak, rel=1e-6)
    assert (tmp_path / "out" / "bed-stress-peak.png").stat().st_size > 10_000
    with h5py.File(tmp_path / "out" / "series.h5") as f:
        assert f.attrs["schema"] == "flexbed.bed_stress"
        assert f["frames/0001/von_mises_top"].attrs["units"] == "Pa"
        np.testing.assert_allclose(f["frames/0001/von_mises_top"][...], vm[0, 5], rtol=1e-12)
    assert "Center=\"Cell\"" in (tmp_path / "out" / "series.xdmf").read_text()

    for allowable, code in ((0.9 * peak, 3), (1.1 * peak, 0)):
        (tmp_path / "q.toml").write_text(_scene(repr(float(allowable))))
        assert main(["qualify", "q.toml", "--modes-file", "m.h5", "--t-end", "0.15",
                     "-o", "q"]) == code
        report = (tmp_path / "q.md").read_text()
        row = next(line for line in report.splitlines() if line.startswith("| plate |"))
        assert f"| {peak / 1e6:.4g} |" in row
        assert ("bed plate: stress: peak" in report) == (code == 3)
