"""Runs that cannot end well are stopped early and say why: a motion that
grows without bound, a motion that blows up in finite time, and a load
whose frequency would force trillions of steps."""

import math

import numpy as np

from flexbed.cli import main as flexbed
from flexbed.files.results import read_results
from scene_text import base_and_body, four_mounts


def _scene(z_law: str, t_end: float = 3.0) -> str:
    """10 kg held by four mounts, stiff sideways, with the vertical law
    ``z_law``, run from the scene's positions under gravity."""
    return base_and_body("diverging", mass=10.0, inertia="[1.0, 1.0, 1.0]") + f"""
[solver]
t_end = {t_end}
start = "initial"
""" + four_mounts(f"""
law = "polynomial"
stiffness = [[0.0, 1.0e4], [0.0, 1.0e4], {z_law}]
""")


def test_exponential_growth_is_stopped_as_divergence(tmp_path, capsys):
    """Negative vertical stiffness (−1e4 N/m per mount): from rest at zero
    deflection, z(t) − z(0) = −(g/λ)(cosh(√λ t) − 1) with λ = 4k/m = 4000
    1/s². The run stops as soon as the body is 1 km away (t ≈ 0.22 s;
    checked every 50 steps), exit 1, one line naming the body, and the
    samples so far — which follow the exact solution — kept, marked
    incomplete."""
    path = tmp_path / "neg.toml"
    path.write_text(_scene("[0.0, -1.0e4]"))
    out = tmp_path / "r.h5"
    assert flexbed(["simulate", str(path), "-o", str(out), "--no-progress"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("flexbed simulate: diverged at t = ")
    assert "body 'mass'" in err[0] and "grows without bound" in err[0]
    assert "(marked incomplete)" in err[0]
    c = read_results(out)
    assert c.attrs[""]["complete"] is False and c.attrs[""]["message"].startswith("diverged")
    t_reached = c.attrs["solver"]["t_reached"]
    lam = 4 * 1e4 / 10.0
    assert math.cosh(math.sqrt(lam) * t_reached) - 1 > 1e3 * lam / 9.81     # really 1 km away
    assert t_reached < 1.0                                                    # and soon after
    t = c.get("time")
    z = c.get("bodies/position")[:, 1, 2]
    exact = -(9.81 / lam) * (np.cosh(math.sqrt(lam) * t) - 1.0)
    assert np.max(np.abs(z - z[0] - exact) / np.maximum(np.abs(exact), 1e-6)) < 1e-5


def test_finite_time_blow_up_is_stopped_as_divergence(tmp_path, capsys):
    """A softening cubic (−1e8 N/m³) on top of the negative stiffness: the
    deflection reaches infinity in finite time (about 0.055 s); the run
    stops there naming the body, exit 1, in a few hundred steps."""
    path = tmp_path / "blow.toml"
    path.write_text(_scene("[0.0, -1.0e4, 0.0, -1.0e8]"))
    out = tmp_path / "r.h5"
    assert flexbed(["simulate", str(path), "-o", str(out), "--no-progress"]) == 1
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("flexbed simulate: diverged at t = ")
    assert "body 'mass'" in err[0]
    c = read_results(out)
    assert c.attrs[""]["complete"] is False
    assert 0.03 < c.attrs["solver"]["t_reached"] < 0.1
    assert c.attrs["solver"]["steps"] < 10_000


def test_a_load_at_1e12_hz_is_refused_before_integrating(tmp_path, capsys):
    """A sinusoid at 1e12 Hz would need steps of 2.5e-13 s: 4e12 of them over
    1 s. Refused at once (exit 2), with the number, before any work."""
    text = _scene("[0.0, 1.0e4]", t_end=1.0).replace('[solver]', '''[base]
motion = "free"

[[base.force]]
direction = "z"
shape = "sinusoid"
amplitude = 1.0
frequency = 1.0e12

[solver]''')
    path = tmp_path / "fast.toml"
    path.write_text(text)
    out = tmp_path / "r.h5"
    for model in ("nonlinear", "linear"):
        assert flexbed(["simulate", str(path), "-o", str(out), "--model", model,
                        "--no-progress"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "would take 4e+12 steps" in err[0]
        assert "2.5e-13 s" in err[0] and "max_steps = 10000000" in err[0]
        assert not out.exists()
