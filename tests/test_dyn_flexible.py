"""The flexible bed in the floating frame: zero modes is the rigid bed;
free-floating, it vibrates at the FE frequency and conserves energy and
momentum, spinning too; damped, a mode decays at α/2 + βω²/2."""

import math
from dataclasses import replace

import numpy as np
import pytest

from flexbed.dynamics.flexible import FlexibleBody, rayleigh_damping
from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.rotation import A as rotation_matrix
from flexbed.dynamics.scene import Base, Body, Scene
from flexbed.dynamics.system import System
from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.spec import PlateSpec
from flexbed.files.scene import load_scene


@pytest.fixture(scope="module")
def bed():
    return compute_bed_modes(PlateSpec(), n_modes=4)


def flexible(bed, n, *, C=None, points=None, shapes=None, full=True):
    points = np.zeros((0, 3)) if points is None else points
    inv = bed.invariants
    k = slice(0, n)
    K = inv.modal_stiffness[k, k]
    return FlexibleBody(
        mass=inv.mass, first_moment=inv.first_moment, inertia=inv.inertia,
        phi_integral=inv.phi_integral[:, k], u_cross_phi=inv.u_cross_phi[:, k],
        phi_cross_phi=inv.phi_cross_phi[k, :, k], modal_mass=inv.modal_mass[k, k],
        inertia_first_order=inv.inertia_first_order[k],
        inertia_second_order=inv.inertia_second_order[k, k], modal_stiffness=K,
        modal_damping=np.zeros((n, n)) if C is None else C, points=points,
        point_shapes=np.zeros((len(points), 3, n)) if shapes is None else shapes, full=full)


def floating(fb):
    """A lone flexible plate in space: no gravity, no mounts (body 1 is a
    fixed dummy base)."""
    bodies = (Body("ground", 1.0, [1.0, 1.0, 1.0], [0, 0, -10.0]),
              Body("bed", fb.mass, np.diag(fb.inertia), [0, 0, 0]))
    return System(Scene(bodies=bodies, base=Base(), gravity=[0, 0, 0],
                        flexible=(("bed", fb),)))


def run(system, y0, t_end, rtol=1e-11, atol=1e-13, output_dt=0.01, method="dop853"):
    s = Settings(method=method, t_end=t_end, rtol=rtol, atol=atol, output_dt=output_dt)
    result = integrate(system, y0, s)
    assert result.complete, result.message
    return result


def test_free_modal_vibration_at_the_fe_frequency(bed):
    fb = flexible(bed, 2)
    system = floating(fb)
    y0 = system.initial_state()
    lay = system.layout
    v0 = 1e-3
    y0[lay.v_modal.start] = v0
    res = run(system, y0, 1.0)
    omega = bed.modes.omega[0]
    a = res.y[:, lay.q_modal.start]
    assert np.abs(a - v0 / omega * np.sin(omega * res.t)).max() < 1e-8 * v0 / omega
    assert np.abs(res.y[:, lay.q_modal.start + 1]).max() < 1e-12 * v0 / omega


def momentum(system, y):
    """Linear and angular momentum (inertial, about the origin) of the bed."""
    fc = system.flex_compiled[0]
    parts = system.layout.split(y)
    r, p, rd, w = parts["r"][0], parts["p"][0], parts["rd"][0], parts["w"][0]
    a, ad = y[fc.qa], y[fc.va]
    A = rotation_matrix(p / np.linalg.norm(p))
    M = fc.eom.mass_matrix(A, a)
    v = np.concatenate([rd, w, ad])
    Mv = M @ v
    L = Mv[:3]                                  # = m ṙ - A S̃ ω + A I3 ȧ
    H = np.cross(r, L) + A @ Mv[3:6]            # body-frame part of the angular momentum
    return L, H


def energy(system, y):
    o = system.observe(0.0, y)
    return float(o.kinetic.sum() + o.strain.sum())


def test_spinning_vibrating_plate_conserves_energy_and_momentum(bed):
    """Spin about y (the plate's smallest inertia) with an off-axis rate,
    modal velocity in both modes: the configuration-dependent terms (I5,
    I8, I9) exchange energy between spin and vibration, the totals stay."""
    fb = flexible(bed, 4)
    system = floating(fb)
    lay = system.layout
    y0 = system.initial_state()
    parts = lay.split(y0)
    parts["rd"][0] = [0.1, -0.2, 0.05]
    parts["w"][0] = [0.3, 3.0, -0.2]
    y0[lay.v_modal] = [0.5, -0.3, 0.2, 0.1]       # sqrt(kg) m/s: mm-size vibration
    res = run(system, y0, 1.0, output_dt=0.02)
    E = np.array([energy(system, y) for y in res.y])
    LH = np.array([np.concatenate(momentum(system, y)) for y in res.y])
    assert np.abs(E - E[0]).max() < 1e-9 * E[0]
    assert np.abs(LH[:, :3] - LH[0, :3]).max() < 1e-10 * np.abs(LH[0, :3]).max()
    assert np.abs(LH[:, 3:] - LH[0, 3:]).max() < 1e-9 * np.abs(LH[0, 3:]).max()
    # the vibration and the spin do exchange energy (the coupling is exercised)
    strain = np.array([system.observe(0.0, y).strain.sum() for y in res.y])
    assert strain.max() > 0
    pn = np.linalg.norm(lay.split(res.y)["p"][:, 0], axis=1)
    assert np.abs(pn - 1).max() < 1e-12


def test_first_order_set_differs_only_at_second_order(bed):
    full = floating(flexible(bed, 4))
    first = floating(flexible(bed, 4, full=False))
    y = full.initial_state()
    parts = full.layout.split(y)
    parts["w"][0] = [0.3, 3.0, -0.2]
    y[full.layout.q_modal] = [1e-3, 2e-3, -1e-3, 5e-4]
    y[full.layout.v_modal] = [0.5, -0.3, 0.2, 0.1]
    d_full, d_first = full.rhs(0.0, y), first.rhs(0.0, y)
    assert not np.allclose(d_full, d_first, rtol=0, atol=0)
    assert np.abs(d_full - d_first).max() < 1e-3 * np.abs(d_full).max()


@pytest.mark.parametrize("alpha, beta", [(0.0, 0.01), (2.0, 0.0), (1.0, 1e-3)])
def test_damped_mode_decays_at_the_rayleigh_rate(bed, alpha, beta):
    fb0 = flexible(bed, 1)
    C = rayleigh_damping(fb0.modal_mass, fb0.modal_stiffness, alpha, beta)
    system = floating(replace(fb0, modal_damping=C))
    lay = system.layout
    y0 = system.initial_state()
    v0 = 1e-3
    y0[lay.v_modal.start] = v0
    res = run(system, y0, 0.5, output_dt=0.005)
    omega = bed.modes.omega[0]
    sigma = alpha / 2 + beta * omega ** 2 / 2
    zeta = sigma / omega
    assert zeta < 1
    wd = omega * math.sqrt(1 - zeta ** 2)
    exact = v0 / wd * np.exp(-sigma * res.t) * np.sin(wd * res.t)
    assert np.abs(res.y[:, lay.q_modal.start] - exact).max() < 1e-7 * v0 / omega
    # and the energy lost is the structural damping's work
    o0, o1 = system.observe(0.0, res.y[0]), system.observe(res.t[-1], res.y[-1])
    lost = (o0.kinetic.sum() + o0.strain.sum()) - (o1.kinetic.sum() + o1.strain.sum())
    assert lost == pytest.approx(-o1.work[3], rel=1e-6)


def test_zero_modes_reproduce_the_rigid_bed():
    """The reference scene with its bed through the flexible machinery and
    no modes (same mass properties) runs as the rigid bed, to round-off."""
    sf = load_scene(None)
    scene = sf.scene
    bed_body = scene.bodies[1]
    pts = np.unique(np.array([m.point_j for m in scene.mounts if m.body_j == "bed"]
                             + [m.point_i for m in scene.mounts if m.body_i == "bed"]), axis=0)
    fb = FlexibleBody(mass=bed_body.mass, first_moment=np.zeros(3), inertia=bed_body.inertia,
                      phi_integral=np.zeros((3, 0)), u_cross_phi=np.zeros((3, 0)),
                      phi_cross_phi=np.zeros((0, 3, 0)), modal_mass=np.zeros((0, 0)),
                      inertia_first_order=np.zeros((0, 3, 3)),
                      inertia_second_order=np.zeros((0, 0, 3, 3)),
                      modal_stiffness=np.zeros((0, 0)), modal_damping=np.zeros((0, 0)),
                      points=pts, point_shapes=np.zeros((len(pts), 3, 0)))
    rigid = System(scene)
    flex = System(replace(scene, flexible=(("bed", fb),)))
    assert rigid.ny == flex.ny
    from flexbed.dynamics.statics import solve_statics
    eq_r, eq_f = solve_statics(rigid), solve_statics(flex)
    assert np.abs(eq_r.y - eq_f.y).max() < 1e-12
    s = Settings(method="rk4", t_end=0.5, dt=1e-3, output_dt=0.01)
    yr = integrate(rigid, eq_r.y, s).y
    yf = integrate(flex, eq_f.y, s).y
    lay = rigid.layout
    assert np.abs(lay.split(yr)["r"] - lay.split(yf)["r"]).max() < 1e-12
    assert np.abs(lay.split(yr)["p"] - lay.split(yf)["p"]).max() < 1e-12


def test_modal_damping_ratio_gives_its_decay(bed):
    """Damping stated as a ratio per mode: c_kk = 2 ζ_k ω_k, decay ζω."""
    from flexbed.dynamics.flexible import modal_damping
    fb0 = flexible(bed, 2)
    zeta = [0.02, 0.05]
    system = floating(replace(fb0, modal_damping=modal_damping(bed.modes.omega[:2], zeta)))
    lay = system.layout
    y0 = system.initial_state()
    v0 = 1e-3
    y0[lay.v_modal] = v0
    res = run(system, y0, 0.3, output_dt=0.003)
    for k in range(2):
        omega = bed.modes.omega[k]
        wd = omega * math.sqrt(1 - zeta[k] ** 2)
        exact = v0 / wd * np.exp(-zeta[k] * omega * res.t) * np.sin(wd * res.t)
        assert np.abs(res.y[:, lay.q_modal.start + k] - exact).max() < 1e-7 * v0 / omega
