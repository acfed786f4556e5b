"""Stresses by modal superposition against the direct static solve
(issue 26 part 3): the reference bed (Mindlin, coarse) on four stiff
supports under a point force at a mount. Truncated modes miss the local
stress at the load; the static correction's residual vectors at the mount
points (flexbed.stages.residual_modes) restore it — exactly when built
from every mode, and from the modes file's N modes up to what lies above
N."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as la

from flexbed.fem.modal_stress import modal_stress
from flexbed.fem.shell import assemble_shell
from flexbed.fem.spec import PlateSpec
from flexbed.fem.stresses import von_mises
from flexbed.stages.residual_modes import residual_basis


@pytest.fixture(scope="module")
def case():
    m = assemble_shell(PlateSpec(theory="mindlin", nx=4, ny=12))
    x, y = m.nodes.T
    d = m.node_dofs

    def node(px, py):
        return int(np.argmin((x - px) ** 2 + (y - py) ** 2))

    supports = [node(sx, sy) for sx in (-0.4, 0.4) for sy in (-2.0, 2.0)]
    load = node(0.2, 0.8)
    rows = np.concatenate([d[c][supports + [load]] for c in range(3)])
    springs = np.zeros(m.K.shape[0])
    springs[d[:3, supports].ravel()] = 1e8                          # N/m
    K = m.K.toarray() + np.diag(springs)
    f = np.zeros(m.K.shape[0])
    f[d[2, load]] = -1e4                                             # N
    lam, vec = la.eigh(m.K.toarray(), m.M.toarray())         # M-orthonormal
    assert np.all(np.abs(lam[:6]) < 1e-6 * lam[6])                 # six rigid motions
    Phi = vec[:, 6:]
    exact = _von_mises(modal_stress(m, la.solve(K, f, assume_a="pos")[:, None]), np.ones(1))
    return m, K, f, (np.sqrt(lam[6:]), Phi), rows, modal_stress(m, Phi), exact


def _von_mises(stress, q):
    return von_mises(stress.faces(q)).max(axis=-1)                   # (ne,)


def _errors(case, n, N=None):
    """Largest error of the element von Mises stresses over the field, and
    of the peak, relative to the direct solve's peak: n modes kept, with
    the correction from the first N modes (None: no correction)."""
    m, K, f, (omega, Phi), rows, stress, exact = case
    if N is None:
        T = np.eye(Phi.shape[1])[:, :n]
    else:
        t, _ = residual_basis(np.eye(N), np.diag(omega[:N] ** 2), Phi[rows, :N].T, n)
        T = np.zeros((Phi.shape[1], t.shape[1]))
        T[:N] = t
    V = np.column_stack([m.rigid_vectors(), Phi @ T])
    q = la.solve(V.T @ K @ V, V.T @ f, assume_a="pos")
    # stresses by superposition of the modal stresses (rigid motions carry none)
    got = _von_mises(stress.transformed(T), q[6:])
    scale = exact.max()
    return np.max(np.abs(got - exact)) / scale, abs(got.max() / scale - 1.0)


def test_correction_from_every_mode_is_exact(case):
    for n in (5, 20):
        field, peak = _errors(case, n, N=case[3][0].size)
        assert field < 1e-9 and peak < 1e-9, (n, field, peak)


def test_truncation_misses_the_local_stress_and_the_correction_restores_it(case):
    plain = [_errors(case, n)[0] for n in (5, 10, 20)]
    assert plain[0] > 0.08 and plain[-1] > 0.03, plain           # 11 %, 5.5 %, 4.3 %
    corrected = [_errors(case, n, N=60)[0] for n in (5, 10, 20)]
    # from 60 modes: 0.9 % whatever n, below the plain error of 20 modes
    assert max(corrected) < 0.25 * plain[-1], (plain, corrected)
    assert _errors(case, 5, N=120)[0] < max(corrected)
