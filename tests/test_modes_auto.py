"""``[bed] modes = "auto"``: the cut-off rule and its place in the scene file."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from flexbed.dynamics.scene import Base, Drive, Scene
from flexbed.dynamics.time_functions import Sinusoid, Triangle
from flexbed.dynamics.statics import solve_statics
from flexbed.dynamics.system import System
from flexbed.errors import InputError
from flexbed.stages.modes_auto import input_frequency, suspension_frequency
from flexbed.files.scene import load_scene

SDOF = Path(__file__).parent / "scenes" / "linear_sdof.toml"


def _driven(sf, *drives):
    base = Base("driven", drives=tuple(drives))
    return Scene(sf.scene.bodies, base, sf.scene.mounts, sf.scene.gravity, "s")


def test_input_frequency_of_a_sinusoid():
    """A 7 Hz drive over 10 whole periods: at least 7 Hz; the switch-on and
    switch-off corners spread 0.1 % of the energy to about twice that."""
    sf = load_scene(SDOF)
    f = input_frequency(_driven(sf, Drive(2, Sinusoid(3.0, 7.0, 0.0, 0.0, 10 / 7.0))), 10 / 7.0)
    assert 7.0 <= f <= 2.5 * 7.0


def test_input_frequency_scales_with_the_pulse():
    """Halving a pulse's duration (and the window with it) doubles the
    frequency the rule finds; the amplitude does not matter."""
    sf = load_scene(SDOF)
    f1 = input_frequency(_driven(sf, Drive(0, Triangle(20.0, 0.003, 0.003))), 0.06)
    f2 = input_frequency(_driven(sf, Drive(0, Triangle(-7.0, 0.0015, 0.0015))), 0.03)
    assert 100.0 < f1 < 1000.0
    assert f2 == pytest.approx(2.0 * f1, rel=0.02)


@pytest.mark.parametrize("periods", [0.14, 2.3, 6.6])
def test_the_end_of_the_run_is_not_a_switch_off(periods):
    """A 7 Hz drive still on when the run ends: the run never sees the input
    after t_end, so the rule must not read the end as a step. It finds a few
    times 7 Hz (a window of 0.14 periods resolves nothing finer than about
    1/t_end); a real step, the same drive switched off at 0.9 t_end, is
    still seen (a higher frequency). (Before, zeros after t_end made the end
    a step too: 4.8 kHz, 268 Hz and 41 Hz for the drive still on.)"""
    sf = load_scene(SDOF)
    t_end = periods / 7.0
    on = input_frequency(_driven(sf, Drive(2, Sinusoid(3.0, 7.0, 0.0, 0.0, 10.0))), t_end)
    off = input_frequency(_driven(sf, Drive(2, Sinusoid(3.0, 7.0, 0.0, 0.0, 0.9 * t_end))),
                          t_end)
    assert 7.0 <= on < max(5.0 * 7.0, 2.0 / t_end)
    assert off > on


def test_reference_scene_cut_short_keeps_few_modes(tmp_path):
    """The reference scene (a 5 Hz load for 1 s) run to t_end = 0.02 s, a
    tenth of a period: the load's frequency is resolved no finer than about
    1/t_end, so f_input lies between the full run's and 2/t_end (before:
    5.1 kHz, a 10 kHz cut-off, 280 modes of a 192-triangle Mindlin bed,
    read from the load still being on at t_end)."""
    sf = load_scene(_auto_scene(tmp_path, ""))
    f_in = sf.bed.auto[1]
    assert f_in < input_frequency(sf.scene, 0.02) < 2.0 / 0.02


def test_suspension_frequency_is_the_highest_natural_frequency():
    """50 kg on four mounts at (±0.2, ±0.3) m in the plane of its centre of
    mass: the decoupled modes are √(4k/m) per axis and, in roll,
    √(4 k_z y² / J_xx) = √(4 · 1.25e5 · 0.09 / 2) rad/s, the highest."""
    sf = load_scene(SDOF)
    system = System(sf.scene)
    eq = solve_statics(system, tol=1e-12)
    exact = math.sqrt(4 * 1.25e5 * 0.3 ** 2 / 2.0) / (2 * math.pi)
    assert suspension_frequency(system, eq.y) == pytest.approx(exact, rel=1e-7)


def _auto_scene(tmp_path, extra: str) -> Path:
    text = (Path(__file__).parents[1] / "pipeline" / "scenes" / "lee1999.toml").read_text()
    text = text.replace('model = "rigid"', 'model = "flexible"')
    text = text.replace("modes = 2\n", f"modes = \"auto\"\n{extra}")
    path = tmp_path / "auto.toml"
    path.write_text(text)
    return path


def test_reference_scene_auto_cut_off(tmp_path):
    sf = load_scene(_auto_scene(tmp_path, ""))
    f_cut, f_in, f_sus = sf.bed.auto
    assert sf.bed.fmax == f_cut == pytest.approx(2.0 * max(f_in, f_sus))
    # the load is a 5 Hz sinusoid switched off after 1 s; the equipment's
    # rocking on its mounts is the fastest suspension mode
    assert 5.0 < f_in < 20.0 and 10.0 < f_sus < 30.0
    sf3 = load_scene(_auto_scene(tmp_path, "auto_factor = 3.0\n"))
    assert sf3.bed.fmax == pytest.approx(1.5 * f_cut)


@pytest.mark.parametrize("extra, words", [("fmax = 40.0\n", "not both"),
                                          ("auto_factor = 0.5\n", "auto_factor = 0.5")])
def test_auto_bad_input(tmp_path, extra, words):
    with pytest.raises(InputError, match=words):
        load_scene(_auto_scene(tmp_path, extra))


def test_auto_keeps_at_least_one_mode(tmp_path):
    from flexbed.stages.modes import ensure_modes
    from flexbed.stages.flexible_bed import kept_modes
    sf = load_scene(_auto_scene(tmp_path, ""))
    data, _ = ensure_modes(sf, tmp_path / "m.h5", log=lambda m: None)
    n = kept_modes(sf, data)
    assert n >= 1
    assert np.all(data.frequency[:n] < sf.bed.fmax) or n == 1
