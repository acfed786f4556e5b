"""The history of a run, evaluated in one compiled pass with array
operations (flexbed.dynamics.history), equals stacking System.observe at
every sample, to round-off: rigid and flexible beds, fixed, driven and free
bases, linear, polynomial and curve-data mounts."""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from flexbed.dynamics.history import history
from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.laws import CurveLaw, LinearLaw
from flexbed.dynamics.scene import Base, Drive
from flexbed.dynamics.time_functions import Curve, Triangle
from flexbed.dynamics.statics import solve_statics
from flexbed.dynamics.system import System
from flexbed.files.scene import load_scene
from flexbed.stages.modes import ensure_modes
from flexbed.stages.system import compile_scene
from built_scenes import bed_and_equipment

SCENES = Path(__file__).parent / "scenes"


def per_sample(system, t, y):
    """The history as it was first written: System.observe at every sample."""
    obs = [system.observe(float(tk), yk) for tk, yk in zip(t, y)]
    keys = {"position": "r", "euler_parameters": "p", "velocity": "rd",
            "angular_velocity": "w", "acceleration": "rdd", "angular_acceleration": "wd",
            "deflection": "dx", "rate": "dxd", "force": "f", "force_i": "force_i",
            "force_j": "force_j", "kinetic": "kinetic", "gravity_potential": "gravity_potential",
            "mount_potential": "mount_potential", "strain": "strain", "modal": "a",
            "modal_rate": "ad", "modal_acceleration": "add", "work": "work", "power": "power"}
    return {k: np.array([getattr(o, a) for o in obs]) for k, a in keys.items()}


def check(system, run):
    h = history(system, run.t, run.y)
    ref = per_sample(system, run.t, run.y)
    assert set(ref) < set(h)
    for key, want in ref.items():
        got = h[key]
        assert got.shape == want.shape, key
        scale = max(np.max(np.abs(want), initial=0.0), 1e-300)
        assert np.max(np.abs(got - want), initial=0.0) <= 1e-12 * scale, key
    assert np.all(np.isfinite(h["balance"])) and h["orientation"].shape == ref["velocity"].shape
    return h


def test_rigid_reference_scene(reference_system):
    s = reference_system
    eq = solve_statics(s, tol=1e-6)
    run = integrate(s, eq.y, Settings("dop853", t_end=0.3, output_dt=0.002))
    check(s, run)


@pytest.mark.parametrize("sag", [False, True])
def test_flexible_reference_scene(tmp_path, sag):
    sf0 = load_scene(None)
    sf = replace(sf0, bed=replace(sf0.bed, model="flexible", rayleigh=(0.0, 1e-4)))
    ensure_modes(sf, tmp_path / "modes.h5", log=lambda _: None)
    s = compile_scene(sf, tmp_path / "modes.h5")
    eq = solve_statics(s, tol=1e-6, sag=sag)
    run = integrate(s, eq.y, Settings("dop853", t_end=0.3, output_dt=0.002))
    h = check(s, run)
    assert np.max(np.abs(h["strain"])) > 0 and np.max(np.abs(h["modal"])) > 0


def test_driven_base_and_curve_mounts():
    x = np.linspace(-0.2, 0.2, 9)
    v = np.linspace(-3.0, 3.0, 7)
    laws = tuple(CurveLaw((x, k * x + 1e6 * x ** 3), (v, 300 * v)) for k in (1e5, 2e5, 3e5))
    tc = np.linspace(0.0, 0.2, 11)
    base = Base("driven", drives=(Drive(2, Triangle(20.0, 0.02, 0.03, 0.05)),
                                  Drive(1, Curve(tc, np.sin(10 * tc)))))
    s = System(bed_and_equipment(laws, base=base))
    eq = solve_statics(s)
    run = integrate(s, eq.y, Settings("dop853", t_end=0.25, output_dt=0.005))
    h = check(s, run)
    assert np.max(np.abs(h["acceleration"][:, 0])) > 1.0


def test_free_base_and_the_hard_polynomial_mounts():
    s = System(bed_and_equipment((LinearLaw(1e5, 300.0),) * 3))
    run = integrate(s, s.initial_state(), Settings("rk4", t_end=0.2, dt=1e-3, output_dt=0.01))
    check(s, run)
    sf = load_scene(SCENES / "hard_hardening_pulse.toml")
    s = compile_scene(sf)
    eq = solve_statics(s, tol=1e-8)
    run = integrate(s, eq.y, sf.solver.settings(t_end=0.05, output_dt=5e-4))
    check(s, run)
