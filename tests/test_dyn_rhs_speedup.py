"""The compiled body-frame maps of FlexibleEOM against the straightforward
formulas of the floating frame (dynamics/flexible.py docstring), term by
term, with random invariants: the restructuring for speed must not change
the physics beyond round-off."""

from dataclasses import replace

import numpy as np
import pytest

from flexbed.dynamics.flexible import FlexibleBody, FlexibleEOM
from flexbed.dynamics.rotation import A as rotation_matrix


def skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def random_body(n, rng, full=True):
    J = rng.standard_normal((3, 3))
    I6 = rng.standard_normal((n, n))
    return FlexibleBody(
        mass=3.0, first_moment=0.1 * rng.standard_normal(3), inertia=J @ J.T + 3 * np.eye(3),
        phi_integral=rng.standard_normal((3, n)), u_cross_phi=rng.standard_normal((3, n)),
        phi_cross_phi=rng.standard_normal((n, 3, n)), modal_mass=I6 @ I6.T + n * np.eye(n),
        inertia_first_order=rng.standard_normal((n, 3, 3)),
        inertia_second_order=rng.standard_normal((n, n, 3, 3)),
        modal_stiffness=rng.standard_normal((n, n)), modal_damping=rng.standard_normal((n, n)),
        points=np.zeros((0, 3)), point_shapes=np.zeros((0, 3, n)), full=full)


def straightforward(b, A, w, a, ad, g):
    """M (6+n, 6+n) and Q_v + Q_g + Q_e (6+n,) written out term by term."""
    n = b.n_modes
    I5 = b.phi_cross_phi if b.full else 0 * b.phi_cross_phi
    I9 = b.inertia_second_order if b.full else 0 * b.inertia_second_order
    I3, I8 = b.phi_integral, b.inertia_first_order
    S = b.first_moment + I3 @ a
    J = b.inertia + sum(a[k] * (I8[k] + I8[k].T) for k in range(n)) \
        + sum(a[k] * a[l] * I9[k, l] for k in range(n) for l in range(n))
    C = b.u_cross_phi + sum(a[k] * I5[k] for k in range(n))
    M = np.zeros((6 + n, 6 + n))
    M[:3, :3] = b.mass * np.eye(3)
    M[:3, 3:6] = -A @ skew(S)
    M[3:6, :3] = skew(S) @ A.T
    M[3:6, 3:6] = J
    M[:3, 6:] = A @ I3
    M[6:, :3] = (A @ I3).T
    M[3:6, 6:] = C
    M[6:, 3:6] = C.T
    M[6:, 6:] = b.modal_mass
    T = [I8[k] + sum(a[l] * I9[k, l] for l in range(n)) for k in range(n)]
    B = sum(ad[k] * T[k] for k in range(n))
    gb = A.T @ g
    Q = np.zeros(6 + n)
    Q[:3] = -A @ (np.cross(w, np.cross(w, S)) + 2 * np.cross(w, I3 @ ad)) + b.mass * g
    Q[3:6] = -np.cross(w, J @ w) - 2 * B @ w + np.cross(S, gb)
    for k in range(n):
        Q[6 + k] = (w @ T[k] @ w + 2 * w @ I5[k] @ ad + I3[:, k] @ gb
                    - b.modal_stiffness[k] @ a - b.modal_damping[k] @ ad)
    return M, Q


@pytest.mark.parametrize("n", [1, 2, 6])
@pytest.mark.parametrize("full", [True, False])
def test_body_frame_maps_match_the_formulas(n, full):
    rng = np.random.default_rng(n + 10 * full)
    body = random_body(n, rng, full)
    eom = FlexibleEOM(body)
    for _ in range(3):
        A = rotation_matrix(rng.standard_normal(4))
        w, a, ad = rng.standard_normal(3), rng.standard_normal(n), rng.standard_normal(n)
        g = np.array([0.3, -1.0, -9.81])
        M0, Q0 = straightforward(body, A, w, a, ad, g)
        M1 = eom.mass_matrix(A, a).copy()
        Q1 = eom.forces(A, w, a, ad, g).copy()
        assert np.abs(M1 - M0).max() <= 1e-13 * np.abs(M0).max()
        assert np.abs(Q1 - Q0).max() <= 1e-13 * np.abs(Q0).max()
        # body frame: M = T M̄ Tᵀ, Q = T Q̄ with T = diag(A, I, I); C ȧ after Q̄
        Mb = eom.mass_matrix_body(a)
        Qb = eom.forces_body(w, a, ad, A.T @ g, Mb[3:6, 3:6])
        T = np.eye(6 + n)
        T[:3, :3] = A
        assert np.abs(T @ Mb @ T.T - M0).max() <= 1e-13 * np.abs(M0).max()
        assert np.abs(T @ Qb[:6 + n] - Q0).max() <= 1e-13 * np.abs(Q0).max()
        assert np.allclose(Qb[6 + n:], body.modal_damping @ ad, rtol=1e-13, atol=0)


def test_first_order_set_drops_the_quadratic_terms():
    rng = np.random.default_rng(3)
    body = random_body(3, rng)
    lin = FlexibleEOM(replace(body, full=False))
    a = rng.standard_normal(3)
    J = lin.inertia(a)
    I8 = body.inertia_first_order
    assert np.allclose(J, body.inertia + np.einsum("k,kij->ij", a, I8 + I8.transpose(0, 2, 1)),
                       rtol=1e-14, atol=0)
