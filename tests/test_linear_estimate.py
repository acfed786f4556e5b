"""The linear fast path's error estimate in compiled code: the scan of the
point displacements, the exact propagators of a linearly varying defect and
the sweep over the defect's nodes, each against the NumPy formulation it
replaced (to round-off)."""

from __future__ import annotations

import numpy as np
from scipy.linalg import expm

from flexbed.dynamics.linear import (_STRIDES, _DEFECT_SHARE, _defect_nodes,
                                     _error_on_every_sample, defect_propagators)
from flexbed.dynamics.steppers.propagate import defect_sweep


def _previous_nodes(t, d):
    """The NumPy stride choice the compiled scan replaced, and the largest |δP|."""
    k = t.size
    scale = float(np.max(np.abs(d - d[0])))
    motion = float(np.sqrt(np.max(np.sum(d.reshape(k, -1, 3) ** 2, axis=2))))
    for m in _STRIDES:
        nodes = np.arange(0, k, m)
        if nodes[-1] != k - 1:
            nodes = np.append(nodes, k - 1)
        if nodes.size < 3 or nodes.size == k:
            continue
        a, b = nodes[:-1], nodes[1:]
        mid = (a + b) // 2
        w = ((t[mid] - t[a]) / (t[b] - t[a]))[:, None]
        miss = d[mid] - (d[a] * (1.0 - w) + d[b] * w)
        if np.max(np.abs(miss)) <= _DEFECT_SHARE * scale:
            return nodes, motion
    return np.arange(k), motion


def _oscillators(n, rng):
    """A (2n, 2n): n coupled damped oscillators, ẍ = −K x − C ẋ (K, C
    symmetric positive definite, frequencies 3–90 rad/s)."""
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    K = Q @ np.diag(np.linspace(3.0, 90.0, n) ** 2) @ Q.T
    C = 0.02 * np.sqrt(np.diag(K)).mean() * np.eye(n) + 1e-3 * K
    return np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]])


def test_stride_choice_and_motion_as_numpy():
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 1.0, 403)                     # 402 intervals: a short last stride
    strides = set()
    for f in (0.2, 0.5, 1.0, 2.0, 10.0):               # strides 16, 8, 4, 2, every sample
        ph = rng.uniform(0, 2 * np.pi, 12)
        amp = rng.uniform(0.5, 2.0, 12)
        d = 1e-3 * amp * np.sin(2 * np.pi * f * t[:, None] * (1 + 0.02 * np.arange(12)) + ph)
        nodes, motion = _defect_nodes(t, d)
        ref_nodes, ref_motion = _previous_nodes(t, d)
        assert np.array_equal(nodes, ref_nodes)
        assert abs(motion - ref_motion) <= 1e-15 * ref_motion
        strides.add(int(nodes[1] - nodes[0]))
    assert strides == {16, 8, 4, 2, 1}


def test_defect_propagators_are_the_block_exponential():
    A = _oscillators(4, np.random.default_rng(5))
    nz = A.shape[0]
    lengths = np.array([1e-3, 4e-3, 0.0123, 0.2])
    Phis, P0s, P1s = defect_propagators(A, lengths)
    for L, Phi, P0, P1 in zip(lengths, Phis, P0s, P1s):
        M = np.zeros((3 * nz, 3 * nz))
        M[:nz, :nz] = L * A
        M[:nz, nz:2 * nz] = L * np.eye(nz)
        M[nz:2 * nz, 2 * nz:] = np.eye(nz)
        X = expm(M)
        for got, ref in ((Phi, X[:nz, :nz]), (P0, X[:nz, nz:2 * nz]), (P1, X[:nz, 2 * nz:])):
            assert np.max(np.abs(got - ref)) < 1e-12 * np.max(np.abs(ref))


def test_defect_sweep_on_the_nodes_equals_the_sweep_over_every_sample():
    """e propagated over the defect's nodes (the stride's step, the short
    last interval its own) equals e propagated sample by sample with the
    defect interpolated linearly, at the nodes; the largest point and
    rotation errors are those of the nodes."""
    rng = np.random.default_rng(7)
    A = _oscillators(4, rng)
    nz = A.shape[0]
    t = np.linspace(0.0, 0.5, 203)
    nodes = np.append(np.arange(0, t.size, 4), t.size - 1)
    Zn = 1e-3 * np.sin(2 * np.pi * 3.0 * t[nodes, None] + rng.uniform(0, 6, nz))
    R = Zn @ A.T + 1e-6 * np.cos(2 * np.pi * 7.0 * t[nodes, None] + rng.uniform(0, 6, nz))
    T = rng.standard_normal((9, nz))
    rot_index = np.array([1, 2], dtype=np.int64)
    tn = t[nodes]
    lengths = np.unique(np.round(np.diff(tn), 12))
    which = np.searchsorted(lengths, np.round(np.diff(tn), 12)).astype(np.int64)
    Phis, P0s, P1s = defect_propagators(A, lengths)
    D, E = np.empty_like(Zn), np.empty_like(Zn)
    pos, rot = defect_sweep(R, Zn, A, Phis, P0s, P1s, which, T, rot_index, D, E)
    assert np.max(np.abs(D - (R - Zn @ A.T))) < 1e-14 * np.max(np.abs(R))
    full = _error_on_every_sample(A, t, nodes, D)
    scale = np.max(np.abs(full))
    assert scale > 1e-9
    assert np.max(np.abs(E - full[nodes])) < 1e-10 * scale        # seen 6e-12
    dP = (E @ T.T).reshape(nodes.size, 3, 3)
    assert abs(pos - np.sqrt(np.max(np.sum(dP ** 2, axis=2)))) < 1e-13 * pos
    assert rot == np.max(np.abs(E[:, rot_index]))


def test_compiled_states_of_many_deviations_equal_the_numpy_map():
    from flexbed.dynamics.linear_model import Coordinates
    from flexbed.dynamics.statics import solve_statics
    from flexbed.files.scene import load_scene
    from flexbed.stages.system import compile_scene

    system = compile_scene(load_scene(None))
    y_eq = solve_statics(system, tol=1e-9).y
    c = Coordinates(system, y_eq)
    Z = 1e-2 * np.random.default_rng(11).standard_normal((40, c.nz))
    Y = c.to_y(Z)                                          # compiled: > 8 rows
    ref = np.concatenate([c.to_y(Z[i:i + 4]) for i in range(0, 40, 4)])   # NumPy
    assert np.max(np.abs(Y - ref)) < 1e-15 * np.max(np.abs(ref))
    assert np.max(np.abs(c.to_z(Y) - Z)) < 1e-13
