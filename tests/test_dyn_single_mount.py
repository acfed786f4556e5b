"""One body on one mount: free vibration, damped decay, RK4's order, base-driven
steady response — all against closed forms."""

import math

import numpy as np
import pytest

from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.scene import Base, Drive
from flexbed.dynamics.time_functions import Sinusoid
from flexbed.dynamics.system import System
from built_scenes import K, M_BODY, Z0, free_vibration, one_mount


@pytest.mark.parametrize("zeta", [0.0, 0.05])
def test_free_vibration_and_decay_match_closed_form(zeta):
    c = 2 * zeta * math.sqrt(K * M_BODY)
    s = System(one_mount(c))
    y0 = s.initial_state()
    amp = 0.01
    y0[s.layout.q_rigid.start + 2] += amp          # body z displaced 1 cm
    run = integrate(s, y0, Settings("dop853", t_end=2.0, rtol=1e-12, atol=1e-14, output_dt=0.01))
    assert run.complete
    z = s.layout.split(run.y)["r"][:, 0, 2] - Z0
    exact = free_vibration(s, amp, zeta, run.t)
    assert np.max(np.abs(z - exact)) < 1e-10 * amp
    # the other directions and the rotation stay at rest
    assert np.max(np.abs(s.layout.split(run.y)["r"][:, 0, :2])) < 1e-15


def test_rk4_error_falls_at_fourth_order():
    zeta = 0.05
    c = 2 * zeta * math.sqrt(K * M_BODY)
    s = System(one_mount(c))
    y0 = s.initial_state()
    y0[s.layout.q_rigid.start + 2] += 0.01
    errs = []
    for dt in (4e-3, 2e-3, 1e-3):
        run = integrate(s, y0, Settings("rk4", t_end=1.0, dt=dt, output_dt=0.05))
        z = s.layout.split(run.y)["r"][:, 0, 2] - Z0
        errs.append(np.max(np.abs(z - free_vibration(s, 0.01, zeta, run.t))))
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(np.abs(orders - 4.0) < 0.15), (errs, orders)


def test_sinusoidal_base_drive_matches_exact_response_and_transmissibility():
    zeta = 0.2
    wn = math.sqrt(K / M_BODY)
    c = 2 * zeta * math.sqrt(K * M_BODY)
    amp, f = 3.0, 3.1                       # m/s², Hz
    W = 2 * math.pi * f
    base = Base("driven", drives=(Drive(2, Sinusoid(amp, f)),))
    s = System(one_mount(c, base))
    run = integrate(s, s.initial_state(), Settings("dop853", t_end=5.0, rtol=1e-12, atol=1e-14,
                                                   output_dt=0.002))
    assert run.complete
    t = run.t
    d = amp / W * t - amp / W ** 2 * np.sin(W * t)           # base displacement from rest
    x = s.layout.split(run.y)["r"][:, 0, 2] - Z0 - d          # relative motion
    # exact solution of m x'' + c x' + k x = -m a sin(W t), x(0) = x'(0) = 0
    den = (K - M_BODY * W ** 2) ** 2 + (c * W) ** 2
    P = -M_BODY * amp * (K - M_BODY * W ** 2) / den           # x_p = P sin + Q cos
    Q = M_BODY * amp * c * W / den
    wd = wn * math.sqrt(1 - zeta ** 2)
    C1 = -Q
    C2 = (zeta * wn * C1 - P * W) / wd
    exact = (P * np.sin(W * t) + Q * np.cos(W * t)
             + np.exp(-zeta * wn * t) * (C1 * np.cos(wd * t) + C2 * np.sin(wd * t)))
    assert np.max(np.abs(x - exact)) < 1e-9 * math.hypot(P, Q)
    # steady state: absolute acceleration amplitude / base amplitude = transmissibility
    from flexbed.dynamics.history import history
    late = t > 4.0          # transient down by exp(-16)
    h = history(s, t[late], run.y[late])
    acc = h["acceleration"][:, 1, 2]
    fit = np.linalg.lstsq(np.column_stack([np.sin(W * t[late]), np.cos(W * t[late])]), acc,
                          rcond=None)[0]
    tr = math.sqrt((K ** 2 + (c * W) ** 2) / den)
    assert abs(math.hypot(*fit) / amp - tr) < 1e-6 * tr
