"""A Mindlin bed through every stage (issue 14): the built-in scene with
``theory = "mindlin"``, modes = "auto" and the static correction, run end
to end in-process; the modes file's hash covers the theory; old Kirchhoff
files still load."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

import flexbed
from flexbed.analyses.points import Point, Run
from flexbed.cli import main
from flexbed.files.builtin import builtin_scene_path
from flexbed.files.modes import read_modes_file
from flexbed.files.store import read_file
from flexbed.files.xdmf import BED_MOTION_SCHEMA


def _scene(tmp_path, theory="mindlin", name="shell.toml"):
    text = builtin_scene_path().read_text()
    text = text.replace('model = "rigid"', f'model = "flexible"\ntheory = "{theory}"\n'
                        'static_correction = true\ncorrection_modes = 12', 1)
    text = text.replace("nx = 10\nny = 10\nmodes = 2\n", 'nx = 4\nny = 24\nmodes = "auto"\n')
    text = text.replace("t_end = 3.0", "t_end = 0.1")
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.slow
def test_mindlin_bed_runs_every_stage(tmp_path, capsys):
    scene = _scene(tmp_path)
    assert main(["run", str(scene), "-o", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert "in-plane" in out                       # the modes table shows the in-plane mode
    data = read_modes_file(tmp_path / "out" / "shell-modes.h5")
    assert data.plate.theory == "mindlin" and data.n_modes >= 12
    assert np.abs(data.translation[:, :, :2]).max() > 0       # in-plane translations stored
    assert data.rigid_omega.shape == (6,)
    with h5py.File(tmp_path / "out" / "shell-modes.h5", "r") as f:
        assert f["plate"].attrs["theory"] == "mindlin"
        assert f["invariants/mass"].attrs["source"].startswith("FE consistent mass")
    motion = read_file(tmp_path / "out" / "shell-damped-bed.h5", schema=BED_MOTION_SCHEMA,
                       major=1)
    assert all(motion.units.values())
    # post: a mount's deflection is the distance of its two points, the
    # bed's end moving with the shell's modes and residual vectors
    run = Run(tmp_path / "out" / "shell-damped.h5")
    assert run.a.shape[1] > 1
    Pi = run.absolute(Point("i", "base", np.array([-0.4, -2.4, 5.0])))
    Pj = run.absolute(Point("j", "bed", np.array([-0.4, -2.4, 0.0])))
    m = run.mount_names.index("M1")
    dx = Pj.position - Pi.position - np.array([0.0, 0.0, 0.1])
    assert np.abs(dx - run.mounts["deflection"][:, m]).max() < 1e-12
    with pytest.raises(flexbed.errors.InputError, match=r"\(0.5, 0, 0\) m lies off the bed"):
        run.absolute(Point("off", "bed", np.array([0.5, 0.0, 0.0])))


@pytest.mark.slow
def test_static_sag_mindlin_against_kirchhoff(tmp_path):
    """The bed's sag under its own weight and the equipment: the same
    within 1 % for both theories (the bed is slender along its length)."""
    z = {}
    for theory in ("kirchhoff", "mindlin"):
        sf = flexbed.load_scene(_scene(tmp_path, theory, f"{theory}.toml"))
        sf = flexbed.vary(sf, {"bed.nx": 8, "bed.ny": 48})
        rigid = flexbed.vary(sf, {"bed.model": "rigid"})
        z[theory] = (flexbed.statics(sf).position[2, 2] - flexbed.statics(rigid).position[2, 2])
    assert z["kirchhoff"] < -1e-3
    assert z["mindlin"] == pytest.approx(z["kirchhoff"], rel=0.01)


def test_modes_file_is_recomputed_when_the_theory_changes(tmp_path, capsys):
    kirchhoff, mindlin = _scene(tmp_path, "kirchhoff", "k.toml"), _scene(tmp_path)
    target = tmp_path / "m.h5"
    assert main(["modes", str(kirchhoff), "-o", str(target)]) == 0
    old = read_modes_file(target)
    assert old.plate.theory == "kirchhoff"
    assert main(["modes", str(mindlin), "-o", str(target)]) == 0
    said = capsys.readouterr()
    assert "made from other plate inputs" in said.out + said.err
    assert read_modes_file(target).input_hash != old.input_hash


def test_a_version_1_0_kirchhoff_file_still_loads(tmp_path):
    """Files written before ``theory`` existed have no such attribute."""
    path = tmp_path / "old.h5"
    assert main(["modes", "-o", str(path)]) == 0
    with h5py.File(path, "r+") as f:
        assert "theory" not in f["plate"].attrs
        f.attrs["schema_version"] = "1.0"
    data = read_modes_file(path)
    assert data.plate.theory == "kirchhoff" and data.plate == flexbed.load_scene().bed.plate
