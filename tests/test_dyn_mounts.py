"""Mount laws and geometry: tilted isotropic mounts, equivalent laws, equal and
opposite end forces, and a driven base that follows its prescribed motion."""

import math

import numpy as np
import pytest

from flexbed.dynamics.history import history
from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.laws import CurveLaw, LinearLaw, PolynomialLaw
from flexbed.dynamics.rotation import A, p_from_angles
from flexbed.dynamics.scene import Base, Body, Drive, Load, Scene
from flexbed.dynamics.time_functions import Curve, Sinusoid, Trapezoid, Triangle, sampled
from flexbed.dynamics.statics import solve_statics
from flexbed.dynamics.system import System
from built_scenes import C_EQ, K_EQ, bed_and_equipment


def perturbed_run(sc, t_end=0.6, dt=1e-3):
    """RK4 (fixed steps, so two runs differ only by round-off) from a tipped state."""
    s = System(sc)
    y0 = s.initial_state()
    parts = s.layout.split(y0)
    parts["w"][:] = [[0.05, -0.1, 0.02], [0.3, 0.2, -0.4]]
    parts["rd"][:] = [[0.01, 0.02, -0.03], [0.05, -0.02, 0.04]]
    run = integrate(s, y0, Settings("rk4", t_end=t_end, dt=dt, output_dt=0.01))
    assert run.complete
    return s, run


def motion(s, run):
    """Positions, Euler parameters and velocities (the energy quadratures left out)."""
    return run.y[:, :s.layout.nq + s.layout.nv]


def test_isotropic_undamped_mounts_make_the_tilt_irrelevant():
    """Paper section 5.2: with the same undamped stiffness in all three
    directions, equipment on 45°-tilted mounts (or on any other orientation
    of the axes) moves exactly as on upright mounts, to round-off — here in a
    fully three-dimensional motion."""
    laws = (LinearLaw(K_EQ),) * 3
    s, upright = perturbed_run(bed_and_equipment(laws))
    tilt45 = A(p_from_angles(math.radians(45), 0, 0)).T
    _, tilted = perturbed_run(bed_and_equipment(laws, axes=tilt45))
    odd = A(p_from_angles(0.4, -0.7, 1.2)).T
    _, skewed = perturbed_run(bed_and_equipment(laws, axes=odd))
    ref = motion(s, upright)
    assert np.max(np.abs(ref - ref[0])) > 1e-3                      # it does move
    assert np.max(np.abs(motion(s, tilted) - ref)) < 1e-12
    assert np.max(np.abs(motion(s, skewed) - ref)) < 1e-12


def test_tilt_matters_when_mounts_are_not_isotropic():
    laws = (LinearLaw(K_EQ), LinearLaw(2 * K_EQ), LinearLaw(K_EQ))
    s, upright = perturbed_run(bed_and_equipment(laws), t_end=0.2)
    tilt45 = A(p_from_angles(math.radians(45), 0, 0)).T
    _, tilted = perturbed_run(bed_and_equipment(laws, axes=tilt45), t_end=0.2)
    assert np.max(np.abs(motion(s, tilted) - motion(s, upright))) > 1e-4


def test_polynomial_and_curve_laws_reproduce_the_linear_law():
    """A polynomial holding only linear terms, and curve data along a straight
    line (the not-a-knot spline of a line is that line), reproduce the linear
    mount's run to round-off."""
    ks = (K_EQ, 2 * K_EQ, 3 * K_EQ)
    linear = tuple(LinearLaw(k, C_EQ) for k in ks)
    poly = tuple(PolynomialLaw((0.0, k), (0.0, C_EQ)) for k in ks)
    x = np.linspace(-0.2, 0.2, 9)
    v = np.linspace(-3.0, 3.0, 7)
    curve = tuple(CurveLaw((x, k * x), (v, C_EQ * v)) for k in ks)
    axes = A(p_from_angles(0.3, 0.2, -0.5)).T
    s, a = perturbed_run(bed_and_equipment(linear, axes=axes))
    _, b = perturbed_run(bed_and_equipment(poly, axes=axes))
    _, c = perturbed_run(bed_and_equipment(curve, axes=axes))
    assert np.max(np.abs(motion(s, b) - motion(s, a))) < 1e-12
    assert np.max(np.abs(motion(s, c) - motion(s, a))) < 1e-12


def test_mount_forces_are_equal_and_opposite_and_follow_eq_4():
    laws = (LinearLaw(K_EQ, C_EQ), LinearLaw(2 * K_EQ), LinearLaw(K_EQ, 2 * C_EQ))
    axes = A(p_from_angles(0.3, 0.2, -0.5)).T
    s, run = perturbed_run(bed_and_equipment(laws, axes=axes), t_end=0.3)
    h = history(s, run.t, run.y)
    assert np.array_equal(h["force_i"], -h["force_j"])
    # eq. 4 from the stored quantities: F_i = Σ_k f_k u_k, u_k = A(p_i) ū_k
    for k in range(0, run.t.size, 7):
        for m, mount in enumerate(s.scene.mounts):
            Ai = A(h["euler_parameters"][k, s.body_i[m]])
            F = (Ai @ mount.axes.T) @ h["force"][k, m]
            assert np.allclose(F, h["force_i"][k, m], rtol=0, atol=1e-9 * (1 + np.abs(F).max()))
            # and the law: f = k Δx + c Δẋ
            kk = np.array([law.k for law in mount.laws])
            cc = np.array([law.c for law in mount.laws])
            assert np.allclose(h["force"][k, m], kk * h["deflection"][k, m] + cc * h["rate"][k, m],
                               rtol=1e-12, atol=1e-9)


def test_driven_base_follows_its_prescribed_displacement():
    """Combined drives (a sinusoid along x, a triangle along z, a trapezoid and
    curve data along y); the base's stored position, velocity and acceleration
    equal the exact integrals written out here independently."""
    tri = Triangle(peak=20.0, rise=0.02, fall=0.03, start=0.05)
    sin = Sinusoid(amplitude=4.0, frequency=7.0, phase=0.3, start=0.01, duration=0.2)
    trap = Trapezoid(peak=-5.0, rise=0.01, flat=0.02, fall=0.04, start=0.0)
    tc = np.linspace(0.1, 0.2, 11)
    cur = Curve(tc, 3.0 * (tc - 0.1))          # straight line: spline is exact
    base = Base("driven", drives=(Drive(0, sin), Drive(2, tri), Drive(1, trap), Drive(1, cur)))
    s = System(bed_and_equipment((LinearLaw(K_EQ, C_EQ),) * 3, base=base))
    eq = solve_statics(s)
    run = integrate(s, eq.y, Settings("dop853", t_end=0.35, rtol=1e-8, atol=1e-10, output_dt=0.005))
    assert run.complete
    assert run.stats.segments == 1 + len([b for b in s.breakpoints if b < 0.35])
    h = history(s, run.t, run.y)
    t = run.t
    # x: sinusoid a = A sin(W u + ph), u = t - 0.01 on [0.01, 0.21]
    W, Am, ph, t0, T = 2 * math.pi * 7.0, 4.0, 0.3, 0.01, 0.2

    def sin_x(t):
        u = np.clip(t - t0, 0, T)
        v = Am / W * (math.cos(ph) - np.cos(W * u + ph))
        d = Am / W * math.cos(ph) * u - Am / W ** 2 * (np.sin(W * u + ph) - math.sin(ph))
        after = np.maximum(t - t0 - T, 0)
        return d + v * after, v, np.where((t >= t0) & (t <= t0 + T), Am * np.sin(W * u + ph), 0)

    # z: triangle, P = 20, rise 0.02, fall 0.03, start 0.05
    def tri_z(t):
        P, r, f, s0 = 20.0, 0.02, 0.03, 0.05
        out_d, out_v, out_a = np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
        for i, ti in enumerate(t):
            tau = ti - s0
            if tau <= 0:
                continue
            if tau <= r:
                out_a[i], out_v[i], out_d[i] = (P * tau / r, P * tau ** 2 / (2 * r),
                                                P * tau ** 3 / (6 * r))
                continue
            v1, d1 = P * r / 2, P * r ** 2 / 6
            u = min(tau - r, f)
            v = v1 + P * (u - u ** 2 / (2 * f))
            d = d1 + v1 * u + P * (u ** 2 / 2 - u ** 3 / (6 * f))
            after = max(tau - r - f, 0.0)
            out_a[i] = P * (1 - u / f) if tau - r <= f else 0.0
            out_v[i], out_d[i] = v, d + v * after
        return out_d, out_v, out_a

    dx_, vx_, ax_ = sin_x(t)
    dz_, vz_, az_ = tri_z(t)
    pos = h["position"][:, 0]
    assert np.max(np.abs(pos[:, 0] - dx_)) < 1e-15 + 1e-13 * np.max(np.abs(dx_))
    assert np.max(np.abs(pos[:, 2] - dz_)) < 1e-15 + 1e-13 * np.max(np.abs(dz_))
    assert np.max(np.abs(h["velocity"][:, 0, 0] - vx_)) < 1e-13 * np.max(np.abs(vx_))
    assert np.max(np.abs(h["velocity"][:, 0, 2] - vz_)) < 1e-13 * np.max(np.abs(vz_))
    assert np.max(np.abs(h["acceleration"][:, 0, 2] - az_)) < 1e-12 * 20
    # y: trapezoid + line; check the final displacement by a fine quadrature of the exact velocity
    from scipy.integrate import quad
    trap_f, cur_f = trap.compile(), cur.compile()

    def acc_y(u):
        return trap_f.value(u) + cur_f.value(u)

    def vel_y(u):
        return quad(acc_y, 0, u, points=[0.01, 0.03, 0.07, 0.1, 0.2], epsabs=1e-14, limit=200)[0]

    d_end = quad(vel_y, 0, 0.35, points=[0.01, 0.03, 0.07, 0.1, 0.2], epsabs=1e-13, limit=200)[0]
    assert abs(pos[-1, 1] - d_end) < 1e-10
    # the bodies feel it: the bed has moved with the base
    assert np.max(np.abs(h["position"][:, 1, 0] - h["position"][0, 1, 0])) > 1e-4
    # the base drive did work and the energy balance closes
    b = h["balance"]
    assert np.max(np.abs(b - b[0])) < 1e-9 * np.max(np.abs(h["work"][:, 2]))


@pytest.mark.parametrize("method", ["rk4", "dop853", "adams", "radau"])
def test_free_base_moves_with_the_double_integral_of_its_loads(method):
    """A free base alone under curve-data and pulse loads (no gravity, no
    mounts): r(t) = r0 + ∬F/m exactly; this checks that every integrator
    feels the load it was given, between and at the breakpoints."""
    load_z = sampled(Sinusoid(1e6, 5.0, 0.0, 0.0, 1.0), 1e-3)
    load_x = Triangle(2e5, 0.1, 0.15, 0.2)
    load_y = Curve(np.linspace(0.3, 0.5, 9), np.cos(np.linspace(0.3, 0.5, 9) * 20))
    base = Base("free", loads=(Load(2, load_z), Load(0, load_x), Load(1, load_y)))
    bodies = (Body("base", 1e6, (1e8, 1e8, 1e8), (1.0, 2.0, 3.0)),
              Body("dummy", 1.0, (1, 1, 1), (0, 0, 10.0)))
    s = System(Scene(bodies, base, (), (0.0, 0.0, 0.0), "loads"))
    st = (Settings("rk4", t_end=1.5, dt=5e-4, output_dt=0.025) if method == "rk4" else
          Settings(method, t_end=1.5, rtol=1e-10, atol=1e-12, output_dt=0.025))
    run = integrate(s, s.initial_state(), st)
    assert run.complete
    r = s.layout.split(run.y)["r_base"]
    funcs = [f.compile() for f in (load_x, load_y, load_z)]
    exact = np.array([[f.second(t) / 1e6 for f in funcs] for t in run.t]) + (1.0, 2.0, 3.0)
    assert np.max(np.abs(exact - (1.0, 2.0, 3.0))) > 1e-3
    tol = 1e-10 if method == "rk4" else 1e-8      # adaptive: rtol acts on |r| ~ 3 m
    assert np.max(np.abs(r - exact)) < tol
