"""Loads on any body (issue 25, part 1): a constant force's static
deflection, a rotating unbalance's response and the linear model's, all
against closed forms; the run's energy balance with the loads' work."""

import math

import numpy as np
import pytest

from flexbed.dynamics.body_loads import BodyLoad, unbalance
from flexbed.dynamics.errors import SceneError
from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.laws import LinearLaw
from flexbed.dynamics.scene import Base, Body, Mount, Scene
from flexbed.dynamics.statics import solve_statics
from flexbed.dynamics.system import System
from flexbed.dynamics.time_functions import Curve

M, K, A, B = 50.0, 2.0e4, 0.3, 0.2          # kg, N/m per mount and direction, m, m
Z0 = 1.0


def box(c=0.0, loads=()):
    """A 50 kg box on four mounts at (±A, ±B) in its centre-of-mass plane,
    k = K and c in every direction, no gravity: its translations are
    single-degree-of-freedom systems of stiffness 4K, its roll and pitch
    have stiffnesses 4 K B² and 4 K A²."""
    bodies = (Body("ground", 1e3, (1.0, 1.0, 1.0), (0, 0, 0)),
              Body("box", M, (2.0, 3.0, 4.0), (0, 0, Z0)))
    mounts = tuple(Mount(f"m{i}", "ground", "box", (sx * A, sy * B, Z0), (sx * A, sy * B, 0),
                         np.eye(3), (LinearLaw(K, c),) * 3)
                   for i, (sx, sy) in enumerate([(-1, -1), (-1, 1), (1, -1), (1, 1)]))
    return Scene(bodies, Base("fixed"), mounts, (0.0, 0.0, 0.0), "box", loads=loads)


def constant(value):
    return Curve(np.arange(4.0), np.full(4, value))


def test_constant_force_at_a_point_gives_the_closed_form_static_deflection():
    F, p, q = 20.0, 0.1, -0.05                 # N (small: rotations of 1e-4 rad), point [m]
    s = System(box(loads=(BodyLoad("box", (p, q, 0.0), 2, constant(F)),)))
    eq = solve_statics(s, tol=1e-9)
    assert eq.success, eq.message
    parts = s.layout.split(eq.y[None])
    dz = parts["r"][0, 0, 2] - Z0
    assert abs(dz - F / (4 * K)) < 1e-9 * F / (4 * K)
    # roll and pitch: the moment (q F, −p F) over 4 K B², 4 K A² (second order: 1e-4)
    p_eq = parts["p"][0, 0]
    theta = 2 * p_eq[1:] / p_eq[0]
    exact = np.array([q * F / (4 * K * B ** 2), -p * F / (4 * K * A ** 2)])
    assert np.max(np.abs(theta[:2] - exact)) < 2e-4 * np.max(np.abs(exact))


def test_a_moment_in_the_body_frame_turns_the_body_as_the_closed_form_says():
    Mz = 3.0                                     # N m about the box's z
    s = System(box(loads=(BodyLoad("box", (0, 0, 0), 2, constant(Mz), "body", "moment"),)))
    eq = solve_statics(s, tol=1e-9)
    assert eq.success, eq.message
    p_eq = s.layout.split(eq.y[None])["p"][0, 0]
    yaw = 2 * math.atan2(p_eq[3], p_eq[0])
    k_yaw = 4 * K * (A ** 2 + B ** 2)           # each mount's horizontal springs at radius r
    assert abs(yaw - Mz / k_yaw) < 1e-6 * Mz / k_yaw


def _exact_forced(t, m, k, c, F, W, phase):
    """x(t) of m x'' + c x' + k x = F sin(W t + phase), x(0) = x'(0) = 0."""
    wn = math.sqrt(k / m)
    zeta = c / (2 * math.sqrt(k * m))
    wd = wn * math.sqrt(1 - zeta ** 2)
    den = (k - m * W ** 2) ** 2 + (c * W) ** 2
    # F sin(Wt + φ) = F cos φ sin Wt + F sin φ cos Wt: particular P sin + Q cos
    Fs, Fc = F * math.cos(phase), F * math.sin(phase)
    P = (Fs * (k - m * W ** 2) + Fc * c * W) / den
    Q = (Fc * (k - m * W ** 2) - Fs * c * W) / den
    C1 = -Q
    C2 = (zeta * wn * C1 - P * W) / wd
    return (P * np.sin(W * t) + Q * np.cos(W * t)
            + np.exp(-zeta * wn * t) * (C1 * np.cos(wd * t) + C2 * np.sin(wd * t)))


def test_rotating_unbalance_matches_the_closed_form_response():
    zeta = 0.1
    c = 2 * zeta * math.sqrt(K * M)              # each mount: the box's ζ is the same
    me, f = 2.0e-3, 7.3                          # kg m, Hz (above the 6.4 Hz resonance)
    loads = unbalance("rotor", "box", (0, 0, 0), 0, me, f)      # spin axis x: force in y, z
    s = System(box(c, loads))
    run = integrate(s, s.initial_state(), Settings("dop853", t_end=2.0, rtol=1e-11, atol=1e-13,
                                                   output_dt=0.004))
    assert run.complete
    r = s.layout.split(run.y)["r"][:, 0]
    W = 2 * math.pi * f
    F = me * W ** 2
    y_exact = _exact_forced(run.t, M, 4 * K, 4 * c, F, W, math.pi / 2)   # F cos Wt along y
    z_exact = _exact_forced(run.t, M, 4 * K, 4 * c, F, W, 0.0)           # F sin Wt along z
    amp = F / math.hypot(4 * K - M * W ** 2, 4 * c * W)   # the steady amplitude
    assert np.max(np.abs(r[:, 1] - y_exact)) < 1e-7 * amp
    assert np.max(np.abs(r[:, 2] - Z0 - z_exact)) < 1e-7 * amp
    # steady state: a circle of radius m e Ω² / |k − m Ω² + i c Ω| (Den Hartog §3.3)
    late = run.t > 1.5
    radius = np.hypot(r[late, 1], r[late, 2] - Z0)
    assert np.max(np.abs(radius - amp)) < 1e-5 * amp


def test_the_loads_work_closes_the_energy_balance():
    zeta = 0.05
    c = 2 * zeta * math.sqrt(K * M)
    loads = unbalance("rotor", "box", (0.1, 0.05, 0.0), 2, 1e-3, 5.0) + (
        BodyLoad("box", (0.2, 0, 0), 1, constant(4.0), "body", "force"),)
    s = System(box(c, loads))
    run = integrate(s, s.initial_state(), Settings("dop853", t_end=1.0, rtol=1e-11, atol=1e-13,
                                                   output_dt=0.01))
    assert run.complete
    # no gravity: the kinetic energy is the work of the mounts plus the loads' work
    parts = s.layout.split(run.y)
    v, w = parts["rd"][:, 0], parts["w"][:, 0]
    ke = 0.5 * M * np.sum(v ** 2, axis=1) + 0.5 * np.einsum("ti,ij,tj->t", w,
                                                            np.diag([2.0, 3.0, 4.0]), w)
    work = run.y[:, s.layout.work.start] + run.y[:, s.layout.work.start + 1]
    assert np.max(ke) > 1e-4
    assert np.max(np.abs(ke - work)) < 1e-8 * np.max(ke)
    assert np.max(np.abs(run.y[:, s.layout.work.start + 1])) > 0.1 * np.max(ke)


def test_the_linear_model_sees_a_load_on_a_body():
    from flexbed.dynamics.linear.model import linearise
    c = 2 * 0.1 * math.sqrt(K * M)
    s = System(box(c, (BodyLoad("box", (0.1, 0, 0), 2, constant(1.0)),)))
    eq = solve_statics(System(box(c)), tol=1e-9)
    lin = linearise(s, eq.y)
    assert lin.B.shape[1] == 1
    col = lin.B[:, 0]
    co = lin.coords
    # a unit force along z at x = 0.1: r̈_z = 1/M, ω̇_y = −0.1 / J_yy
    assert abs(col[co.v_index[0, 2]] - 1 / M) < 1e-12
    assert abs(col[co.w_index[0, 1]] + 0.1 / 3.0) < 1e-12


@pytest.mark.parametrize("make, message", [
    (lambda: box(loads=(BodyLoad("nobody", (0, 0, 0), 2, constant(1.0)),)),
     "body = 'nobody' is not a body"),
    (lambda: box(loads=(BodyLoad("ground", (0, 0, 0), 2, constant(1.0)),)), "is the base"),
    (lambda: unbalance("u", "box", (0, 0, 0), 0, 1e-3, 0.0), "speed = 0.0 Hz must be > 0"),
    (lambda: unbalance("u", "box", (0, 0, 0), 0, 0.0, 5.0), "mass_radius = 0.0"),
])
def test_bad_loads_are_refused_with_one_line(make, message):
    with pytest.raises(SceneError, match=message) as exc:
        make()
    assert "\n" not in str(exc.value)


def test_a_run_up_is_phase_continuous_and_reaches_the_closed_form_force():
    from flexbed.dynamics.body_loads import unbalance as ub
    me, f0, f1, T = 1e-3, 2.0, 10.0, 1.5
    loads = ub("r", "box", (0, 0, 0), 2, me, (f0, f1), runup=T)
    fs = [ld.shape.compile() for ld in loads]
    t = np.linspace(0.0, 3.0, 3001)
    Fx = sum(fn.values(t) for ld, fn in zip(loads, fs) if ld.direction == 0)
    Fy = sum(fn.values(t) for ld, fn in zip(loads, fs) if ld.direction == 1)
    u = np.minimum(t, T)
    theta = 2 * math.pi * (f0 * u + 0.5 * (f1 - f0) * u ** 2 / T) + 2 * math.pi * f1 * (t - u)
    f = np.where(t < T, f0 + (f1 - f0) * t / T, f1)
    F = me * (2 * math.pi * f) ** 2
    top = me * (2 * math.pi * f1) ** 2
    assert np.max(np.abs(Fx - F * np.cos(theta))) < 1e-5 * top
    assert np.max(np.abs(Fy - F * np.sin(theta))) < 1e-5 * top


def test_a_load_as_a_frequency_response_input_gives_the_closed_form_transmissibility():
    from flexbed.dynamics.frequency.frf import Outputs, responses
    from flexbed.dynamics.frequency.load_inputs import load_input
    from flexbed.dynamics.frequency.mounted import mounted_system
    c = 2 * 0.05 * math.sqrt(K * M)
    s = System(box(c, (BodyLoad("box", (0, 0, 0), 2, constant(0.0)),)))
    eq = solve_statics(s, tol=1e-9)
    ms = mounted_system(s, eq.y)
    inp = load_input(ms, s, 0)
    out = Outputs(np.zeros((0, 3 + ms.n)), ms.Bq, ms.Bv)
    f = np.array([1.0, 6.366, 24.5, 100.0])           # Hz, through the 6.37 Hz bounce
    w = 2 * np.pi * f
    _, force = responses(ms, w, inp, out)
    # force into the base per unit force on the box: (k + icω) / (k − mω² + icω)
    k, cc = 4 * K, 4 * c
    exact = (k + 1j * cc * w) / (k - M * w ** 2 + 1j * cc * w)
    assert np.max(np.abs(force[:, 2] - exact) / np.abs(exact)) < 1e-8
    assert np.max(np.abs(force[:, :2])) < 1e-8
