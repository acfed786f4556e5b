"""Energy bookkeeping: conservation in an exactly conservative scene, and a
closed balance in a scene where the paper's mount is not conservative."""

import numpy as np

from flexbed.dynamics.history import history
from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.laws import LinearLaw
from flexbed.dynamics.scene import Base, Body, Mount, Scene
from flexbed.dynamics.system import System

SIGNS = [(-1, -1), (-1, 1), (1, -1), (1, 1)]


def bed_and_box(*, l0_zero: bool, isotropic: bool):
    """Fixed base, a bed on 4 mounts from the base, a box on 4 mounts from the bed."""
    bodies = (Body("base", 1e5, (1e5, 1e5, 1e5), (0, 0, 0)),
              Body("bed", 300.0, (60.0, 20.0, 75.0), (0, 0, 1.0)),
              Body("box", 40.0, ([3.0, 0.2, 0.0], [0.2, 2.0, 0.1], [0.0, 0.1, 4.0]),
                   (0.1, 0.2, 1.3)))
    mounts = []
    for n, (sx, sy) in enumerate(SIGNS):
        mounts.append(Mount(f"b{n}", "base", "bed", (0.6 * sx, 0.9 * sy, 0.5),
                            (0.6 * sx, 0.9 * sy, -0.05),
                            np.eye(3), (LinearLaw(4e4), LinearLaw(5e4), LinearLaw(9e4))))
    k_box = (LinearLaw(2e4),) * 3 if isotropic else (LinearLaw(1e4), LinearLaw(2e4), LinearLaw(3e4))
    tilt = np.array([[1, 0, 0], [0, 0.8, 0.6], [0, -0.6, 0.8]])
    for n, (sx, sy) in enumerate(SIGNS):
        pj = np.array([0.2 * sx, 0.25 * sy, -0.15])
        pi = pj + (0.1, 0.2, 1.3) - np.array([0, 0, 1.0])          # same point in space: l0 = 0
        if not l0_zero:
            pi = pi - (0.0, 0.0, 0.05)
        mounts.append(Mount(f"e{n}", "bed", "box", pi, pj, tilt, k_box))
    return System(Scene(bodies, Base("fixed"), tuple(mounts), (0.0, 0.0, -9.81), "energy"))


def kicked(s):
    y0 = s.initial_state()
    parts = s.layout.split(y0)
    parts["rd"][:] = [[0.05, -0.03, 0.1], [-0.1, 0.2, -0.05]]
    parts["w"][:] = [[0.2, -0.1, 0.15], [0.5, 0.3, -0.4]]
    return y0


def test_undamped_unloaded_scene_conserves_total_energy():
    """Exactly conservative: the bed's mounts hang from the base, which never
    rotates, and the box's mounts have l0 = 0 and isotropic stiffness, so the
    force Σ f_k u_k = k l is a gradient even though the bed rotates. Total
    energy T + V_gravity + V_mount drifts by less than 1e-9 of the largest
    kinetic energy over 10 s (the gravity potential's constant offset is not
    allowed to hide a drift)."""
    s = bed_and_box(l0_zero=True, isotropic=True)
    run = integrate(s, kicked(s), Settings("dop853", t_end=10.0, rtol=1e-12, atol=1e-13,
                                           output_dt=0.01))
    assert run.complete
    h = history(s, run.t, run.y)
    T = h["kinetic"].sum(axis=1)
    E = T + h["gravity_potential"].sum(axis=1) + h["mount_potential"].sum(axis=1)
    assert np.max(np.abs(E - E[0])) < 1e-9 * T.max()
    # mount work is minus the change of mount potential
    Vm = h["mount_potential"].sum(axis=1)
    assert np.max(np.abs(h["work"][:, 0] + Vm - Vm[0])) < 1e-9 * T.max()
    assert np.max(np.abs(np.linalg.norm(h["euler_parameters"], axis=2) - 1)) < 1e-12


def test_paper_mount_is_not_conservative_but_the_balance_closes():
    """With l0 ≠ 0 held fixed in a rotating body i and anisotropic stiffness
    (paper eq. 2–4 as stated), Σ f_k u_k is not a gradient: the mount
    potential does not balance the mount work. The recorded balance
    T + V_gravity − W_mount (with W_mount the integrated power of the mount
    forces) stays constant all the same."""
    s = bed_and_box(l0_zero=False, isotropic=False)
    run = integrate(s, kicked(s), Settings("dop853", t_end=3.0, rtol=1e-12, atol=1e-13,
                                           output_dt=0.01))
    h = history(s, run.t, run.y)
    T = h["kinetic"].sum(axis=1)
    b = h["balance"]
    assert np.max(np.abs(b - b[0])) < 1e-9 * T.max()
    Vm = h["mount_potential"].sum(axis=1)
    assert np.max(np.abs(h["work"][:, 0] + Vm - Vm[0])) > 1e-5 * T.max()
