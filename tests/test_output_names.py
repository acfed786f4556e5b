"""Default output names come from the scene file's stem
(``SceneFile.output_name``), so that scene files in one folder never share
a modes, equilibrium or results file; ``flexbed scene -o FILE`` names the
scene after FILE."""

import numpy as np
import pytest

from flexbed.cli import main as flexbed
from flexbed.files.modes import read_modes_file
from flexbed.files.results import read_results
from flexbed.files.scene import load_scene


@pytest.mark.slow
def test_two_scenes_from_flexbed_scene_in_one_folder_do_not_collide(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert flexbed(["scene", "-o", "a.toml"]) == 0
    assert flexbed(["scene", "-o", "b.toml"]) == 0
    for name, thickness in (("a", "0.1"), ("b", "0.12")):
        path = tmp_path / f"{name}.toml"
        text = path.read_text().replace('model = "rigid"', 'model = "flexible"')
        path.write_text(text.replace("thickness = 0.1", f"thickness = {thickness}"))
        sf = load_scene(path)
        assert sf.scene.name == name and sf.output_name == name
    # a hand copy keeps a's [scene] name but has its own outputs
    (tmp_path / "c.toml").write_text((tmp_path / "a.toml").read_text())
    assert load_scene(tmp_path / "c.toml").scene.name == "a"
    for name in ("a", "b", "c"):
        assert flexbed(["modes", f"{name}.toml"]) == 0
        assert flexbed(["static", f"{name}.toml"]) == 0
        assert flexbed(["simulate", f"{name}.toml", "--t-end", "0.02", "--no-progress"]) == 0
    masses = {}
    for name in ("a", "b", "c"):
        modes = read_modes_file(tmp_path / f"{name}-modes.h5")
        masses[name] = modes.invariants.mass
        assert (tmp_path / f"{name}-equilibrium.h5").exists()
        res = read_results(tmp_path / f"{name}-results.h5")
        assert res.attrs["scene"]["source"].endswith(f"{name}.toml")
        assert res.attrs["bed"]["modes_file"].endswith(f"{name}-modes.h5")
        assert res.attrs[""]["complete"] is True
    assert np.isclose(masses["b"], masses["a"] * 1.2, rtol=1e-14, atol=0)
    assert masses["c"] == masses["a"]
    # a second round reuses each scene's own modes file (none was overwritten)
    for name in ("a", "b"):
        assert flexbed(["simulate", f"{name}.toml", "--t-end", "0.01", "--no-progress"]) == 0


def test_builtin_scene_keeps_its_name():
    sf = load_scene()
    assert sf.output_name == "lee1999" and sf.scene.name == "lee1999"
