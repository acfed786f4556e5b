"""A free body without gravity: momentum, energy and the intermediate-axis flip."""

import numpy as np

from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.rotation import A, p_from_angles
from flexbed.dynamics.scene import Base, Body, Scene
from flexbed.dynamics.system import System


def spinning(J, w0, p0=(1.0, 0.0, 0.0, 0.0), v0=(0.0, 0.0, 0.0)):
    bodies = (Body("ground", 1.0, (1, 1, 1), (0, 0, 0)),
              Body("spinner", 7.0, J, (0.3, -0.2, 1.0), np.array(p0)))
    s = System(Scene(bodies, Base("fixed"), (), (0.0, 0.0, 0.0), "free"))
    y0 = s.initial_state()
    parts = s.layout.split(y0)
    parts["w"][0] = w0
    parts["rd"][0] = v0
    return s, y0


def momenta(s, y):
    parts = s.layout.split(y)
    J = s.J[0]
    w = parts["w"][:, 0]
    Aw = A(parts["p"][:, 0])
    L = np.einsum("kij,jl,kl->ki", Aw, J, w)                 # world angular momentum
    energy = 0.5 * np.einsum("ki,ij,kj->k", w, J, w)
    P = s.mass[1] * parts["rd"][:, 0]
    return L, energy, P, parts


def test_intermediate_axis_flips_and_conserves_energy_and_momentum():
    """J = diag(1, 2, 3), ω̄0 = (0.01, 5, 0.01) rad/s, 20 s: the spin about the
    intermediate axis turns over; energy and |L| stay to 1e-8 relative and the
    Euler parameters stay on |p| = 1 to 1e-12 (projection after every step)."""
    s, y0 = spinning((1.0, 2.0, 3.0), (0.01, 5.0, 0.01))
    run = integrate(s, y0, Settings("dop853", t_end=20.0, rtol=1e-12, atol=1e-12, output_dt=0.01))
    assert run.complete
    L, energy, P, parts = momenta(s, run.y)
    wy = parts["w"][:, 0, 1]
    assert wy.min() < -4.9 and wy.max() > 4.9                # it flipped (and came back)
    assert np.max(np.abs(energy / energy[0] - 1)) < 1e-8
    Lmag = np.linalg.norm(L, axis=1)
    assert np.max(np.abs(Lmag / Lmag[0] - 1)) < 1e-8
    assert np.max(np.linalg.norm(L - L[0], axis=1)) < 1e-8 * Lmag[0]   # the vector, too
    assert np.max(np.abs(np.linalg.norm(parts["p"][:, 0], axis=1) - 1)) < 1e-12


def test_free_body_conserves_linear_and_angular_momentum():
    J = np.array([[2.0, 0.3, -0.1], [0.3, 3.0, 0.2], [-0.1, 0.2, 4.0]])
    s, y0 = spinning(J, (1.5, -2.0, 0.7), p_from_angles(0.3, -0.5, 1.1), v0=(0.4, -1.0, 2.0))
    run = integrate(s, y0, Settings("rk4", t_end=5.0, dt=1e-3, output_dt=0.01))
    L, energy, P, parts = momenta(s, run.y)
    assert np.max(np.abs(P - P[0])) < 1e-14 * np.linalg.norm(P[0])
    # uniform straight motion of the centre of mass, exactly
    r_exact = np.array([0.3, -0.2, 1.0]) + np.outer(run.t, [0.4, -1.0, 2.0])
    assert np.max(np.abs(parts["r"][:, 0] - r_exact)) < 1e-12
    assert np.max(np.linalg.norm(L - L[0], axis=1)) < 1e-9 * np.linalg.norm(L[0])
    assert np.max(np.abs(energy / energy[0] - 1)) < 1e-9
    assert np.max(np.abs(np.linalg.norm(parts["p"][:, 0], axis=1) - 1)) < 1e-12
