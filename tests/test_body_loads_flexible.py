"""A load at a point of the flexible bed (issue 25, part 1): it projects onto
the modes by the mode shapes at the point, so its generalized forces and
the power it feeds in (F · Ṗ, Ṗ with Φ ȧ) must agree: the run's energy
balance (kinetic + potential + strain − the works) stays constant while the
load works on the bed's bending."""

import numpy as np
import pytest

from flexbed.cli import main
from flexbed.files.results import read_results

from scene_text import FIXED_REFERENCE

LOAD = """
[[load]]
name = "shaker"
body = "bed"
point = [0.3, 1.8, 0.0]      # drawing frame, off the bed's centre lines
direction = "z"
shape = "sinusoid"
amplitude = 2000.0
frequency = 23.0             # near the bed's first bending mode
"""


@pytest.mark.slow
def test_a_load_on_the_flexible_bed_keeps_the_energy_balance(tmp_path):
    text = (FIXED_REFERENCE.replace('model = "rigid"', 'model = "flexible"')
            .replace("rayleigh = [0.0, 0.01]", "rayleigh = [0.0, 0.0]")
            .replace("t_end = 3.0", "t_end = 0.5") + LOAD)
    scene = tmp_path / "shaken.toml"
    scene.write_text(text)
    modes, results = tmp_path / "m.h5", tmp_path / "r.h5"
    assert main(["modes", str(scene), "-o", str(modes)]) == 0
    assert main(["simulate", str(scene), "--modes-file", str(modes), "-o", str(results),
                 "--no-progress"]) == 0
    c = read_results(results)
    work = np.asarray(c.get("energy/work_external"))
    strain = np.asarray(c.get("energy/strain"))
    balance = np.asarray(c.get("energy/balance"))
    assert np.max(np.abs(work)) > 1.0             # J: the load works
    assert np.ptp(strain[:, 1]) > 0.01               # J: and bends the bed (beyond its sag)
    # the energy balance moves with the integrator's error only
    assert np.max(np.abs(balance - balance[0])) < 1e-7 * np.max(np.abs(work))
