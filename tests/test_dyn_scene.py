"""Rotations and the scene's own checks (programmatic scenes, no file)."""

import math

import numpy as np
import pytest

from flexbed.dynamics.errors import SceneError
from flexbed.dynamics.laws import CurveLaw, LinearLaw, PolynomialLaw
from flexbed.dynamics.piecewise import spline_with_tails
from flexbed.dynamics.rotation import A, G, angles_from_p, p_from_A, p_from_angles, skew
from flexbed.dynamics.scene import Base, Body, Drive, Load, Mount, Scene
from flexbed.dynamics.time_functions import Curve, Sinusoid, Trapezoid, Triangle, sampled


def test_euler_parameters_roll_pitch_yaw_round_trip():
    rng = np.random.default_rng(7)
    for _ in range(200):
        ang = rng.uniform([-3, -1.5, -3], [3, 1.5, 3])
        p = p_from_angles(*ang)
        R = A(p)
        assert np.allclose(R.T @ R, np.eye(3), atol=1e-14) and abs(np.linalg.det(R) - 1) < 1e-14
        assert np.allclose(angles_from_p(p), ang, atol=1e-12)
        assert np.allclose(p_from_A(R), p, atol=1e-14)
        # X-Y-Z about body axes: A = Rx Ry Rz
        rx = A(p_from_angles(ang[0], 0, 0))
        ry = A(p_from_angles(0, ang[1], 0))
        rz = A(p_from_angles(0, 0, ang[2]))
        assert np.allclose(R, rx @ ry @ rz, atol=1e-14)
        # body angular velocity: w = 2 G pdot and dA/dt = A skew(w)
        w = rng.normal(size=3)
        pdot = 0.5 * G(p).T @ w
        assert np.allclose(2 * G(p) @ pdot, w, atol=1e-14)
        h = 1e-6
        dA = (A(p + h * pdot) - A(p - h * pdot)) / (2 * h)
        assert np.allclose(dA, R @ skew(w), atol=1e-8)
    assert np.allclose(A(p_from_angles(math.pi / 2, 0, 0)) @ [0, 1, 0], [0, 0, 1], atol=1e-15)


def test_rotation_matrix_entry_by_entry_is_the_matrix_sum_bit_for_bit():
    """A(p), written entry by entry, equals the sum of whole matrices
    (2e0² − 1) I + 2 e eᵀ + 2 e0 [e×] bit for bit (the sign of a zero
    aside: its terms of δij = 0 and of a zero of [e×] are not added), on
    Euler parameters of any scale and any leading shape, with zeros and the
    identity among them."""
    def summed(p):
        p = p / np.linalg.norm(p, axis=-1, keepdims=True)
        e0, e = p[..., 0, None, None], p[..., 1:]
        return ((2.0 * e0 * e0 - 1.0) * np.eye(3) + 2.0 * e[..., :, None] * e[..., None, :]
                + 2.0 * e0 * skew(e))

    rng = np.random.default_rng(1)
    for scale in (1.0, 1e-3, 1e3):
        p = rng.normal(size=(20000, 4)) * scale
        p[::7, 1] = 0.0
        p[::5, 0] = 0.0
        p[::11] = (1.0, 0.0, 0.0, 0.0)
        want = summed(p)
        for got in (A(p), A(p.reshape(2000, 10, 4)).reshape(20000, 3, 3),
                    np.array([A(q) for q in p[:50]])):
            assert got.shape[-2:] == (3, 3)
            assert np.array_equal(got, want[:got.shape[0]])


def test_exact_integrals_of_the_drive_shapes():
    from scipy.integrate import quad
    shapes = [Sinusoid(2.0, 3.0, 0.3, 0.1, 0.5), Triangle(5.0, 0.1, 0.2, 0.05),
              Trapezoid(5.0, 0.1, 0.1, 0.2, 0.05),
              Curve(np.linspace(0.1, 0.6, 7), np.cos(np.linspace(0, 2, 7)))]
    for sh in shapes:
        f = sh.compile()
        knots = sorted(set(f.breakpoints) | set(np.linspace(0.1, 0.6, 7)))
        for t in (0.05, 0.3, 0.55, 0.9):
            v = quad(f.value, 0, t, points=knots, epsabs=1e-14, epsrel=1e-13, limit=400)[0]
            d = quad(f.first, 0, t, points=knots, epsabs=1e-14, epsrel=1e-13, limit=400)[0]
            assert abs(f.first(t) - v) < 1e-12 and abs(f.second(t) - d) < 1e-12
    c = sampled(Sinusoid(1e6, 5.0, 0.0, 0.0, 1.0), 1e-3)
    assert c.time.size == 1001 and c.time[-1] == 1.0
    assert c.compile().value(2.0) == c.value[-1] and abs(c.value[-1]) < 1e-6


def test_curve_law_extrapolates_linearly_with_the_end_slopes():
    x = np.array([-0.1, -0.05, 0.0, 0.05, 0.1])
    f = spline_with_tails(x, x ** 3, left="linear", right="linear")
    d = f.derivative()
    assert abs(f(0.3) - (f(0.1) + d(0.1) * 0.2)) < 1e-15
    assert abs(f(-0.3) - (f(-0.1) - d(-0.1) * 0.2)) < 1e-15


BODY = dict(name="b", mass=1.0, inertia=(1, 2, 3), position=(0, 0, 0))


@pytest.mark.parametrize("change,message", [
    (dict(mass=-1.0), "body 'b': mass = -1.0 must be > 0"),
    (dict(inertia=[[1, 0, 0], [0, 1, 0], [0, 0.5, 1]]), "inertia is not symmetric"),
    (dict(inertia=[[1, 2, 0], [2, 1, 0], [0, 0, 1]]), "inertia is not positive definite"),
    (dict(position=(0, float("nan"), 0)), "position[1] = nan must be finite"),
])
def test_body_checks(change, message):
    with pytest.raises(SceneError, match=None) as err:
        Body(**{**BODY, **change})
    assert message in str(err.value)


def test_mount_and_scene_checks():
    bodies = (Body("g", 1, (1, 1, 1), (0, 0, 0)), Body(**BODY))
    lin = (LinearLaw(1.0),) * 3
    left = np.diag([1.0, 1.0, -1.0])
    cases = [
        (lambda: Mount("m", "g", "b", (0, 0, 0), (0, 0, 0), left, lin), "left-handed"),
        (lambda: Mount("m", "g", "b", (0, 0, 0), (0, 0, 0), np.eye(3) * 1.01, lin),
         "not orthonormal"),
        (lambda: Mount("m", "g", "g", (0, 0, 0), (0, 0, 0), np.eye(3), lin), "both 'g'"),
        (lambda: LinearLaw(-5.0), "k = -5.0 must be > 0"),
        (lambda: PolynomialLaw(tuple(range(10))), "degree 9"),
        (lambda: CurveLaw(([0, 1, 0.5, 2], [0, 1, 2, 3])), "strictly increasing"),
        (lambda: CurveLaw(([0, 1, 2], [0, 1, 2])), "at least 4"),
        (lambda: Triangle(1.0, -0.1, 0.1), "rise = -0.1 must be > 0"),
        (lambda: Trapezoid(1.0, 0.1, -0.1, 0.1), "flat = -0.1 must be >= 0"),
        (lambda: Sinusoid(1.0, 2.0, duration=-1.0), "duration = -1.0 must be > 0"),
        (lambda: Base("fixed", drives=(Drive(2, Triangle(1, 1, 1)),)), "motion = 'driven'"),
        (lambda: Base("driven", loads=(Load(2, Triangle(1, 1, 1)),)), "act only on a free base"),
        (lambda: Scene(bodies + (Body(**BODY),)), "name is used twice"),
        (lambda: Scene(bodies, mounts=(Mount("m", "g", "x", (0, 0, 0), (0, 0, 0), np.eye(3),
                                             lin),)),
         "body_j = 'x' is not a body"),
    ]
    for make, message in cases:
        with pytest.raises(SceneError) as err:
            make()
        assert message in str(err.value), (message, str(err.value))


def test_scene_arrays_are_read_only():
    b = Body(**BODY)
    with pytest.raises(ValueError):
        b.inertia[0, 0] = 5.0
    with pytest.raises(AttributeError):
        b.mass = 3.0
