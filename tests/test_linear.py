"""The linear fast path: exact propagation, its error estimate, the model choice."""

from __future__ import annotations

import math
import subprocess
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.linear import run_linear
from flexbed.dynamics.linear.estimate import _largest_displacement, _point_map
from flexbed.dynamics.statics import solve_statics
from flexbed.stages.modes import ensure_modes
from flexbed.stages.system import compile_scene
from flexbed.files.results import read_results
from flexbed.files.scene import load_scene
from scene_text import base_and_body, four_mounts

SDOF = Path(__file__).parent / "scenes" / "linear_sdof.toml"


def _pulse_pieces(start, rise, flat, fall, peak):
    """(t_k, α, β) of a piecewise-linear acceleration a = α + β (t − t_k)."""
    pts = [(start, 0.0), (start + rise, peak)]
    if flat > 0:
        pts.append((start + rise + flat, peak))
    pts.append((pts[-1][0] + fall, 0.0))
    pieces = [(0.0, 0.0, 0.0)] if start > 0 else []
    for (ta, a0), (tb, a1) in zip(pts[:-1], pts[1:]):
        pieces.append((ta, a0, (a1 - a0) / (tb - ta)))
    pieces.append((pts[-1][0], 0.0, 0.0))
    return pieces


def _exact_sdof(t, omega2, pieces):
    """Absolute displacement d_base + u of an undamped oscillator
    ü + ω² u = −a(t) on a base with acceleration a(t), from rest; closed form
    piece by piece (particular solution −(α + βτ)/ω² plus free vibration)."""
    w = math.sqrt(omega2)
    out = np.empty_like(t)
    u = v = d = dv = 0.0
    bounds = [p[0] for p in pieces[1:]] + [np.inf]
    for (tk, al, be), tb in zip(pieces, bounds):
        C, D = u + al / omega2, (v + be / omega2) / w

        def state(tau, al=al, be=be, C=C, D=D, d=d, dv=dv):     # this piece's constants
            uu = -(al + be * tau) / omega2 + C * np.cos(w * tau) + D * np.sin(w * tau)
            dd = d + dv * tau + al * tau ** 2 / 2 + be * tau ** 3 / 6
            return uu, dd

        sel = (t >= tk) & (t < tb)
        uu, dd = state(t[sel] - tk)
        out[sel] = uu + dd
        if np.isfinite(tb):
            h = tb - tk
            u, d_new = state(h)
            v = -be / omega2 - C * w * math.sin(w * h) + D * w * math.cos(w * h)
            dv, d = dv + al * h + be * h * h / 2, d_new
    return out


def test_linear_path_is_exact_on_a_linear_scene():
    sf = load_scene(SDOF)
    system = compile_scene(sf)
    eq = solve_statics(system, tol=1e-12)
    lr = run_linear(system, eq.y, eq.y, Settings("rk4", t_end=0.25, output_dt=1e-3))
    t = lr.run.t
    r = system.layout.split(lr.run.y)["r"][:, 0, :] - eq.y[system.layout.q_rigid][:3]
    ex = _exact_sdof(t, 4 * 5.0e4 / 50.0, _pulse_pieces(0.0, 0.004, 0.01, 0.0065, -12.0))
    ez = _exact_sdof(t, 4 * 1.25e5 / 50.0, _pulse_pieces(0.0102, 0.0031, 0.0, 0.0057, 30.0))
    peak = max(np.max(np.abs(ex)), np.max(np.abs(ez)))
    assert peak > 1e-3
    # round-off only (measured 1.9e-14 m and 3.8e-13 m against a 0.043 m peak)
    assert np.max(np.abs(r[:, 0] - ex)) < 5e-11 * peak
    assert np.max(np.abs(r[:, 2] - ez)) < 5e-11 * peak
    assert np.max(np.abs(r[:, 1])) < 1e-15
    # the scene is linear: the estimated error is round-off too
    assert lr.estimate.position < 1e-10 * peak


def test_error_estimate_matches_the_nonlinear_model():
    """On the reference scene with a flexible bed (2 undamped modes), the
    estimate predicts the linear model's actual error against a converged
    nonlinear run, and linear + estimated correction is far closer still."""
    sf = load_scene(None)
    sf = replace(sf, bed=replace(sf.bed, model="flexible", modes=2, fmax=None,
                                 rayleigh=(0.0, 0.0)))
    with pytest.MonkeyPatch.context() as mp:
        import tempfile
        tmp = Path(tempfile.mkdtemp())
        mp.chdir(tmp)
        data, _ = ensure_modes(sf, tmp / "m.h5", log=lambda m: None)
        system = compile_scene(sf, data.path)
    eq = solve_statics(system, tol=1e-11)
    st = Settings("dop853", t_end=1.0, rtol=1e-11, atol=1e-13, output_dt=1e-3)
    lr = run_linear(system, eq.y, eq.y, st)
    ref = integrate(system, eq.y, st)
    assert ref.complete
    lay = system.layout
    R = lay.split(ref.y)["r"]
    est = lr.estimate
    c = lr.linearisation.coords
    # the actual error at the points the estimate measures: centres of mass
    # and mount ends, rotations and modes with their lever arms
    points = _point_map(system, c)
    actual = _largest_displacement(c.to_z(ref.y) - c.to_z(lr.run.y), c, points)
    assert 1e-9 < actual < 1e-5                      # a small but visible nonlinearity
    assert 0.9 < est.position / actual < 1.1
    assert est.reliable
    corrected = c.to_y(c.to_z(lr.run.y) + est.e)
    com = float(np.max(np.abs(lay.split(lr.run.y)["r"] - R)))
    assert float(np.max(np.abs(lay.split(corrected)["r"] - R))) < 0.05 * com
    # |p| = 1 on every sample of the linear solution
    p = lay.split(lr.run.y)["p"]
    assert np.max(np.abs(np.linalg.norm(p, axis=-1) - 1.0)) < 1e-14


def _simulate(tmp_path, env, *args):
    """``flexbed simulate`` of the SDOF scene in a process of its own, forked
    from the command server (``env``: conftest's ``forked_flexbed``)."""
    out = tmp_path / "r.h5"
    cp = subprocess.run(["flexbed", "simulate", str(SDOF), "-o", str(out), "--no-progress",
                         *args], capture_output=True, text=True, cwd=tmp_path, env=env)
    return cp, out


@pytest.mark.slow
def test_auto_picks_linear_below_the_tolerance(tmp_path, forked_flexbed):
    cp, out = _simulate(tmp_path, forked_flexbed, "--model", "auto")
    assert cp.returncode == 0, cp.stderr
    assert "model auto: linear" in cp.stdout
    attrs = read_results(out).attrs["solver"]
    assert attrs["model"] == "linear" and attrs["model_requested"] == "auto"
    assert attrs["linear_estimated_error"] < 1e-6


@pytest.mark.slow
def test_auto_falls_back_to_nonlinear_above_the_tolerance(tmp_path, forked_flexbed):
    cp, out = _simulate(tmp_path, forked_flexbed, "--model", "auto", "--linear-tol", "1e-20")
    assert cp.returncode == 0, cp.stderr
    assert "model auto: nonlinear" in cp.stdout
    attrs = read_results(out).attrs["solver"]
    assert attrs["model"] == "nonlinear" and attrs["method"] == "dop853"


@pytest.mark.slow
def test_bad_linear_tol_is_one_line(tmp_path, forked_flexbed):
    cp, out = _simulate(tmp_path, forked_flexbed, "--model", "auto", "--linear-tol", "-1")
    assert cp.returncode == 2
    assert cp.stderr.count("\n") == 1 and "linear-tol" in cp.stderr
    assert not out.exists()


def test_point_map_is_the_first_order_kinematics(tmp_path, monkeypatch):
    """The estimate's map from deviations z to the displacements of the mount
    ends is the derivative of the kernel's own end positions (flexible bed:
    rotations and modes with their lever arms)."""
    sf = load_scene(None)
    sf = replace(sf, bed=replace(sf.bed, model="flexible", modes=2, fmax=None))
    monkeypatch.chdir(tmp_path)
    data, _ = ensure_modes(sf, tmp_path / "m.h5", log=lambda m: None)
    system = compile_scene(sf, data.path)
    y_eq = solve_statics(system, tol=1e-11).y
    c = run_linear(system, y_eq, y_eq, Settings("dop853", t_end=1e-3, output_dt=1e-3)
                   ).linearisation.coords
    points = _point_map(system, c)
    ends = points[len(system.layout.rigid):]
    moving = np.isin(system.end_body, system.layout.rigid)
    dz = np.random.default_rng(1).standard_normal(c.nz)
    eps = 1e-7

    def end_positions(z):
        system.rhs(0.0, c.to_y(z))
        return np.array(system.data.w_P)[moving]

    exact = (end_positions(eps * dz) - end_positions(-eps * dz)) / (2 * eps)
    np.testing.assert_allclose(np.einsum("pij,j->pi", ends, dz), exact, rtol=0,
                               atol=1e-7 * np.abs(exact).max())


def test_a_spinning_body_is_not_taken_for_linear():
    """Equipment spinning on its mounts: the centres of mass hardly move, the
    attitude does; model = "auto" must see it and integrate the nonlinear
    model (the estimate counts rotations at the mount points)."""
    import flexbed
    scene = flexbed.vary(flexbed.load_scene(), {"body.equipment A.angular_velocity": [0, 20, 3],
                                                "solver.t_end": 0.3})
    run = flexbed.simulate(scene, model="auto")
    assert run.solver["model"] == "nonlinear"
    assert run.solver["linear_estimated_error"] > 1e-3


UNSTABLE = base_and_body("unstable", gravity=0.0, mass=10.0, inertia="[1.0, 1.0, 1.0]") + """

[solver]
t_end = 0.5
allow_unstable = true
""" + four_mounts("""
law = "polynomial"
stiffness = [[0.0, 1.0e4], [0.0, 1.0e4], [0.0, -1.0e4, 0.0, 1.0e8]]
""")


def test_an_unstable_equilibrium_is_reported_not_propagated(tmp_path):
    """Four mounts of negative vertical stiffness (−1e4 N/m each, hardening
    cubically) hold 10 kg at an equilibrium that is unstable (run from
    with allow_unstable = true; without, the run stops): the linear
    model reports the growing mode, sqrt(4k/m) = 63.2 1/s, and propagates
    nothing (no NaN); auto integrates the nonlinear model instead."""
    import flexbed
    path = tmp_path / "unstable.toml"
    path.write_text(UNSTABLE)
    scene = flexbed.load_scene(path)
    lin = flexbed.simulate(scene, model="linear")
    assert not lin.complete and "unstable equilibrium" in lin.message
    rate = float(lin.message.split("rate ")[1].split(" ")[0])
    assert rate == pytest.approx(math.sqrt(4 * 1e4 / 10.0), rel=1e-3)
    assert lin.t.shape == (1,) and np.all(np.isfinite(lin.position))
    auto = flexbed.simulate(scene, model="auto")
    assert auto.complete and auto.solver["model"] == "nonlinear"
    assert "unstable equilibrium" in auto.solver["model_reason"]


def test_the_time_numba_loads_or_compiles_is_told_apart_without_a_warm_up():
    """The linear run's timings leave out numba's loading and compiling,
    timed by numba's event API (its compiler lock) rather than by a
    warm-up run: a first call that compiles is counted, a call of code
    already loaded is not."""
    import numba

    from flexbed.dynamics.linear.run import _loading

    @numba.njit
    def add_one(x):
        return x + 1.0

    with _loading() as first:
        add_one(1.0)
    with _loading() as again:
        add_one(2.0)
    assert sum(first) > 0.0 and sum(again) == 0.0
