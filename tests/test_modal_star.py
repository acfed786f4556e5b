"""Issue 30, part 3: the modes of large systems by their hub-and-leaves
structure (dynamics/frequency/star.py, star_modes.py) and the batched
isolation crossings equal the dense solutions.

1. star_eig against an exact solution: g identical oscillators (k, m) on a
   hub mass on a spring: ω² = k/m exactly g − 1 times (the leaves moving
   against each other, the hub at rest), the other two roots of the
   2-degree-of-freedom system with the leaves' total mass.
2. The built-in scene tiled 2 × 2 (8 pieces of equipment) and 4 × 4 (32):
   the structured solution against today's dense one (``sparse=None``:
   np.linalg.eig of M⁻¹K and of the first-order matrix). Frequencies,
   damping ratios and undamped frequencies to 1e-9 relative (eigenvalues
   matched one to one); per cluster of close frequencies (identical pieces
   of equipment; a basis within a cluster is arbitrary in both solutions,
   see :data:`CLUSTER`) the effective masses' sums and the spectral
   projector's diagonal ``Σ_k φ_k ⊙ (M ψ_k)`` to 1e-9, the damped shapes'
   span to 1e-6; the energy and strain tables of the modes at least 1e-4
   apart from their neighbours (whose shapes are well defined) to 1e-9.
3. The energy tables the structured solution writes from its structure
   (a mode with the hub at rest: a vector per leaf times a coefficient)
   equal the general products on the same shapes, every mode (repeated
   frequencies included), to 1e-13 of the largest entry.
4. The isolation crossings found for all outputs at once equal Brent's,
   and the exact r = √2 of a base-excited oscillator.
"""

from dataclasses import replace

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.optimize import linear_sum_assignment

from flexbed.bench.tiling import tiled_scene
from flexbed.dynamics.frequency import frf as dfrf
from flexbed.dynamics.frequency import modal, shares, star_modes
from flexbed.dynamics.frequency.modal import solve_modes
from flexbed.dynamics.frequency.mounted import mounted_system
from flexbed.dynamics.frequency.star import Star, star_eig
from flexbed.dynamics.statics import solve_statics
from flexbed.stages.system import compile_scene


def _mounted(c):
    sf = tiled_scene(c, bed_model="rigid")
    system = compile_scene(sf)
    eq = solve_statics(system, tol=sf.solver.static_tol)
    assert eq.success, eq.message
    return mounted_system(system, eq.y)


@pytest.fixture(scope="module")
def tiled8():
    return _mounted(2)


def test_identical_oscillators_on_a_hub_exact():
    g, k, m, K, Mh = 40, 3.0e4, 12.0, 5.0e5, 300.0
    # undamped standard form M⁻¹K, states x_1..x_g, then the hub x_h
    star = Star(np.full((g, 1, 1), k / m), np.full((g, 1, 1), -k / m),
                np.full((g, 1, 1), -k / Mh), np.array([[(K + g * k) / Mh]]))
    got = star_eig(star, left=True)
    assert got.eliminated == g - 1 and got.reduced == 2
    lam = np.sort(got.values.real)
    # the two others: det([[k − λm, −k], [−g k, K + g k − λ Mh]]) with the total mass
    a, b, c = m * Mh, -(m * (K + g * k) + k * Mh), k * K
    roots = np.sort(np.roots([a, b, c]).real)
    exact = np.sort(np.concatenate([np.full(g - 1, k / m), roots]))
    assert lam == pytest.approx(exact, rel=1e-13)
    assert np.abs(got.left @ got.right - np.eye(g + 1)).max() < 1e-12
    # the eliminated modes hold the hub at rest
    at_rest = np.abs(got.values - k / m) < 1e-9 * k / m
    assert np.abs(got.right[-1, at_rest]).max() == 0.0


def _matched(a, b):
    """Largest relative distance between eigenvalue sets a, b matched one to one."""
    d = np.abs(a[:, None] - b[None, :])
    i, j = linear_sum_assignment(d)
    return float((d[i, j] / np.abs(b[j])).max())


#: frequencies closer than this (relative) are one cluster in the comparisons
#: of vectors: a mode's shape moves by the matrices' perturbation over its gap
#: to the next, and the structured solution perturbs them by the spread of
#: identical pieces' eigenvalues, up to ~1e-11 relative (a differenced
#: stiffness's round-off, which the dense solution carries as much): 1e-8
#: over a gap of 1e-4, below 1e-9 for clusters 1e-3 apart
CLUSTER = 1e-3


def _clusters(f, rel):
    return np.concatenate([[0], np.cumsum(np.diff(f) > rel * f[1:])])


def _compare(ms):
    structured, dense = solve_modes(ms), solve_modes(replace(ms, sparse=None))
    for md in (structured, dense):
        assert md.frequency.size == ms.n

    def lam(md):
        return md.frequency * (-md.damping_ratio + 1j * np.sqrt(1 - md.damping_ratio ** 2))

    assert _matched(lam(structured), lam(dense)) < 1e-9
    assert structured.undamped_frequency == pytest.approx(dense.undamped_frequency, rel=1e-9)
    # undamped clusters: effective masses' sums and the projector's diagonal
    _, phi_s, psi_s, _ = modal._undamped(ms, star_modes.plan_of(ms))
    _, phi_d, psi_d, _ = modal._undamped(replace(ms, sparse=None))
    f = dense.undamped_frequency
    cl = _clusters(f, CLUSTER)
    for k in np.unique(cl):
        i = np.flatnonzero(cl == k)
        a, b = structured.effective_mass[i].sum(0), dense.effective_mass[i].sum(0)
        assert np.abs(a - b).max() <= 1e-9 * ms.moving_mass
        pa = (phi_s[i] * (psi_s[i].conj() @ ms.M)).sum(0).real
        pb = (phi_d[i] * (psi_d[i].conj() @ ms.M)).sum(0).real
        assert np.abs(pa - pb).max() <= 1e-9
    # damped: shapes' span per cluster; tables of the well separated modes
    fd = dense.frequency
    cl = _clusters(fd, CLUSTER)
    for k in np.unique(cl):
        i = np.flatnonzero(cl == k)
        q, _ = np.linalg.qr(structured.shapes[i].T)
        B = dense.shapes[i].T
        assert np.linalg.norm(B - q @ (q.conj().T @ B)) <= 1e-6 * np.linalg.norm(B)
    gap = np.diff(fd) / fd[1:]
    alone = np.flatnonzero(np.minimum(np.r_[np.inf, gap], np.r_[gap, np.inf]) > 1e-4)
    assert alone.size >= 10
    for name in ("energy", "strain_mounts", "strain_elastic"):
        a, b = getattr(structured, name)[alone], getattr(dense, name)[alone]
        assert np.abs(a - b).max() <= 1e-9, name
    return structured


def test_structured_modes_equal_the_dense_ones_8(tiled8, monkeypatch):
    monkeypatch.setattr(modal, "DENSE_LIMIT", 0)       # 54 coordinates: onto the large path
    _compare(tiled8)
    plan = star_modes.plan_of(tiled8)
    assert plan is not None and plan.leaf_index.shape == (8, 6)


@pytest.mark.slow
def test_structured_modes_equal_the_dense_ones_32():
    ms = _mounted(4)
    assert ms.n > modal.DENSE_LIMIT
    _compare(ms)


def test_lowest_modes_of_pieces_on_a_bed_are_the_structured_ones_cut(tiled8, monkeypatch):
    """``count`` on a hub with leaves: every mode by the structured solution,
    then the lowest ``count``: the same numbers as the whole solution's
    first ``count``, repeated frequencies of identical pieces included."""
    monkeypatch.setattr(modal, "DENSE_LIMIT", 0)
    full = solve_modes(tiled8)
    low = solve_modes(tiled8, count=13)
    np.testing.assert_array_equal(low.frequency, full.frequency[:13])
    np.testing.assert_array_equal(low.undamped_frequency, full.undamped_frequency[:13])
    np.testing.assert_array_equal(low.effective_mass, full.effective_mass[:13])


def test_structured_left_and_right_vectors_biorthogonal(tiled8):
    ms = tiled8
    lam, vl, vr, mu, _ = star_modes.undamped(ms, star_modes.plan_of(ms))
    assert np.abs(vl.conj().T @ ms.M @ vr - np.eye(ms.n)).max() < 1e-9
    assert np.abs(mu - np.einsum("ik,ij,jk->k", vl.conj(), ms.M, vr)).max() < 1e-12
    residual = ms.K @ vr - (ms.M @ vr) * lam[None, :]
    assert np.abs(residual).max() <= 1e-9 * np.abs(ms.K @ vr).max()
    lam_d, V, _ = star_modes.damped(ms, star_modes.plan_of(ms))
    assert lam_d.size == ms.n                            # one of each conjugate pair
    residual = ms.K @ V + (ms.C @ V) * lam_d + (ms.M @ V) * lam_d ** 2
    assert np.abs(residual).max() <= 1e-9 * np.abs(ms.K @ V).max()


def _tables_agree(ms, structured, picked):
    raw = structured.energies(ms, picked)
    assert raw is not None and structured.got.eliminated > 0
    phi = structured.rows[picked]
    general = (shares.kinetic(ms, phi), *shares.strain(ms, phi))
    for a, b in zip(raw, general):
        assert a.shape == b.shape
        assert np.abs(a - b).max() <= 1e-13 * np.abs(b).max()


def test_structured_energy_tables_equal_the_general_products(tiled8):
    ms = tiled8
    plan = star_modes.plan_of(ms)
    lam, V, structured = star_modes.damped(ms, plan)
    picked = modal._damped_from(lam, V, ms.n)[5]
    assert picked.size == ms.n                           # every mode, oscillating
    _tables_agree(ms, structured, picked)
    lam, _, _, _, structured = star_modes.undamped(ms, plan)
    _tables_agree(ms, structured, np.argsort(lam.real)[::-1])     # any order of the pairs


def test_undamped_system_tables_from_the_structure(tiled8, monkeypatch):
    """Without damping the tables come from the undamped structured solution."""
    monkeypatch.setattr(modal, "DENSE_LIMIT", 0)
    Ms, Ks, _ = tiled8.sparse
    ms = replace(tiled8, C=np.zeros_like(tiled8.C), sparse=(Ms, Ks, sp.csr_matrix(Ks.shape)))
    plan = star_modes.plan_of(ms)
    assert not ms.damped and plan is not None
    assert modal._undamped(ms, plan, tables=True)[3] is not None
    md = solve_modes(ms)
    energy, mounts, elastic = shares.shares(shares.kinetic(ms, md.shapes),
                                            *shares.strain(ms, md.shapes))
    assert np.abs(md.energy - energy).max() < 1e-13
    assert np.abs(md.strain_mounts - mounts).max() < 1e-13
    assert np.abs(md.strain_elastic - elastic).max() < 1e-13


def test_no_leaves_no_plan(tiled8):
    assert star_modes.plan_of(replace(tiled8, sparse=None)) is None


def test_batched_crossings_exact_and_equal_to_brent():
    """|T| of a base-excited oscillator crosses 1 at r = √2 for every ζ."""
    f0 = np.array([2.0, 3.5, 7.0, 11.0, 13.0])
    zeta = np.array([0.01, 0.05, 0.1, 0.3, 0.6])

    def evaluate(f):
        r = f[:, None] / f0[None, :]
        return np.abs((1 + 2j * zeta * r) / (1 - r * r + 2j * zeta * r))

    grid = np.geomspace(0.5, 100.0, 300)
    mag = evaluate(grid)
    batched = dfrf.unit_crossings(evaluate, grid, mag, batched=True)
    brent = dfrf.unit_crossings(evaluate, grid, mag)
    assert batched == pytest.approx(np.sqrt(2.0) * f0, rel=1e-12)
    assert batched == pytest.approx(brent, rel=1e-12)
    never = dfrf.unit_crossings(lambda f: 0.5 * evaluate(f) / evaluate(f), grid,
                                np.full_like(mag, 0.5), batched=True)
    assert np.all(np.isnan(never))


def test_frf_isolation_crossings_batched_equal_brent(monkeypatch):
    """The 2 × 2 tiling's FRF (54 coordinates: the large systems' path): the
    crossings of every body's vertical transmissibility found together
    equal Brent's method's, output by output, to 1e-11 relative."""
    from flexbed.analyses.frf import frequency_response
    from flexbed.analyses.modal import mounted

    sf = tiled_scene(2, bed_model="rigid")
    system = compile_scene(sf)
    eq = solve_statics(system, tol=sf.solver.static_tol)
    mt = mounted(sf, system, y_eq=eq.y)
    assert mt.ms.n > dfrf.DENSE_LIMIT
    grid = np.geomspace(1.0, 40.0, 300)
    batched = frequency_response(sf, mt, frequencies=grid).isolation_from
    brent = dfrf.unit_crossings
    monkeypatch.setattr(dfrf, "unit_crossings",
                        lambda *a, batched=False, **k: brent(*a, **k))
    one_by_one = frequency_response(sf, mt, frequencies=grid).isolation_from
    found = np.isfinite(one_by_one)
    assert found.sum() >= 9
    assert np.array_equal(found, np.isfinite(batched))
    assert batched[found] == pytest.approx(one_by_one[found], rel=1e-11)


def test_no_plan_when_the_sparse_matrices_are_not_the_dense_ones(tiled8):
    assert star_modes.plan_of(replace(tiled8, K=2.0 * tiled8.K)) is None
