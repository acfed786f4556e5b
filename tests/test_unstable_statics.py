"""An unstable equilibrium is found, but not reported as a plain success:
allowed (``--allow-unstable``), a warning names the body and the direction
of the stiffness matrix's negative eigenvalue, and the equilibrium file
records it (without, the run stops: tests/test_plausibility.py)."""

import math

import pytest

from flexbed.cli import main as flexbed
from flexbed.files.store import read_file
from scene_text import base_and_body, four_mounts


def _scene(k_z: float) -> str:
    """10 kg without gravity on four mounts of vertical stiffness k_z (plus
    a hardening cubic), stiff sideways: the equilibrium at zero deflection
    has vertical stiffness 4 k_z."""
    held = base_and_body("held", gravity=0.0, mass=10.0, inertia="[1.0, 1.0, 1.0]")
    return held + four_mounts(f"""
law = "polynomial"
stiffness = [[0.0, 1.0e4], [0.0, 1.0e4], [0.0, {k_z}, 0.0, 1.0e8]]
""")


def test_negative_stiffness_is_warned_and_recorded(tmp_path, capsys):
    """k_z = −1e4 N/m: M⁻¹K has the eigenvalue 4 k_z / m = −4000 1/s² in z."""
    path = tmp_path / "unstable.toml"
    path.write_text(_scene(-1.0e4))
    out = tmp_path / "eq.h5"
    assert flexbed(["static", str(path), "-o", str(out), "--allow-unstable"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("flexbed static: warning: unstable.toml: unstable equilibrium")
    assert "mostly body 'mass' in z" in err[0]
    lam = float(err[0].split("negative eigenvalue (")[1].split(" ")[0])
    assert lam == pytest.approx(-4000.0, rel=1e-4)
    root = read_file(out, schema="flexbed.equilibrium", major=1).attrs[""]
    assert root["success"] is True and root["stability"] == "unstable"
    assert "body 'mass' in z" in root["instability"]
    rate = float(root["instability"].split("exp(")[1].split(" ")[0])
    assert rate == pytest.approx(math.sqrt(4000.0), rel=1e-3)


def test_a_stable_equilibrium_says_nothing(tmp_path, capsys):
    path = tmp_path / "stable.toml"
    path.write_text(_scene(1.0e4))
    out = tmp_path / "eq.h5"
    assert flexbed(["static", str(path), "-o", str(out)]) == 0
    assert capsys.readouterr().err == ""
    root = read_file(out, schema="flexbed.equilibrium", major=1).attrs[""]
    assert root["stability"] == "stable" and root["instability"] == ""
