"""The linear fast path's error estimate: the local cubics of the defect
and of the powers, the exact propagators of a cubic defect, e over the
nodes against e sample by sample and against the block exponential, the
largest point error between the nodes, and the estimate on the reference
scene against the one with the defect on every sample."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

import flexbed.dynamics.linear as linear
import flexbed.dynamics.linear.estimate as linear_estimate
from flexbed.dynamics.linear.defect import (hermite_peak, largest_motion,
                                            pieces_at, pieces_integral_at)
from flexbed.dynamics.linear.estimate import (_cubics, _error_on_every_sample,
                                              _propagate_defect, defect_propagators)


def _system_matrix(rng):
    """A (12, 12): three coupled damped oscillators from 3 to 90 rad/s, one
    stiff (3e3 rad/s, heavily damped: ‖A‖₁ far above the spectral radius)
    and a free mass's Jordan block (ẋ = v, v̇ = 0)."""
    n = 4
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    K = Q @ np.diag([9.0, 900.0, 8100.0, 9e6]) @ Q.T
    C = 0.05 * np.sqrt(np.diag(K)).mean() * np.eye(n) + 1e-4 * K
    A = np.zeros((12, 12))
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n], A[n:2 * n, n:2 * n] = -K, -C
    A[8:10, 10:12] = np.eye(2)
    A[10:12, :2] = 0.3 * K[:2, :2]          # the free mass pulled by two of the others
    return A


def _van_loan(A, L, degree=3):
    """Φ and P_0 … P_degree of ė = A e + d, d a polynomial in σ = t/L, by
    SciPy's exponential of the block matrix."""
    nz = A.shape[0]
    q = degree + 1
    M = np.zeros(((q + 1) * nz, (q + 1) * nz))
    M[:nz, :nz] = L * A
    M[:nz, nz:2 * nz] = L * np.eye(nz)
    for p in range(1, q):
        M[p * nz:(p + 1) * nz, (p + 1) * nz:(p + 2) * nz] = np.eye(nz)
    X = expm(M)
    return X[:nz, :nz], [X[:nz, (p + 1) * nz:(p + 2) * nz] for p in range(q)]


def test_defect_propagators_are_the_block_exponential():
    A = _system_matrix(np.random.default_rng(5))
    lengths = np.array([1e-3, 4e-3, 8e-3, 0.0123, 0.2])      # 4e-3: 8e-3's half
    Phis, Ps = defect_propagators(A, lengths)
    for L, Phi, P in zip(lengths, Phis, Ps):
        # the two squarings' round-off, growing with ‖Φ‖ (seen 3e-14 at 1 ms,
        # 1.8e-12 at 0.2 s where the free mass has drifted: ‖Φ‖ ≈ 7e4)
        ref_phi, ref_p = _van_loan(A, L)
        assert np.max(np.abs(Phi - ref_phi)) < 1e-11 * np.max(np.abs(ref_phi))
        for got, ref in zip(P.transpose(1, 0, 2), ref_p):
            assert np.max(np.abs(got - ref)) < 1e-11 * np.max(np.abs(ref))


def test_balancing_is_exact_and_reports_non_finite_entries():
    """The balancing the propagators work on (linear.model.balanced, once
    per linearisation): A' = S⁻¹ A S exactly (every entry times a power
    of 2), C-contiguous for the compiled series, with ‖A'‖₁ far below ‖A‖₁
    on a mounted system's matrix (stiffness over mass far above the
    spectral radius: it falls 2300-fold) and below it on a badly scaled
    random one; NaN or infinite entries raise LinAlgError."""
    from flexbed.dynamics.linear.model import balanced

    rng = np.random.default_rng(7)
    bad = rng.standard_normal((30, 30)) * np.exp2(rng.integers(-20, 20, 30))[:, None]
    for A, fall in ((_system_matrix(np.random.default_rng(5)), 300.0), (bad, 1.0)):
        Ab, scale = balanced(A)
        assert Ab.flags.c_contiguous and scale.shape == (A.shape[0],)
        assert np.all(np.log2(scale) == np.round(np.log2(scale)))
        assert np.array_equal(Ab, A / scale[:, None] * scale[None, :])
        assert np.linalg.norm(Ab, 1) * fall < np.linalg.norm(A, 1)
    for entry in (np.nan, np.inf):                         # reported, not balanced
        with pytest.raises(np.linalg.LinAlgError, match="NaN or infinite"):
            balanced(np.array([[1.0, entry], [1.0, 2.0]]))


def test_local_cubics_reproduce_cubics_and_integrate_them_exactly():
    rng = np.random.default_rng(2)
    tn = np.cumsum(rng.uniform(0.5, 1.5, 11))
    coeff = rng.standard_normal((4, 3))

    def poly(t):
        return np.stack([np.polyval(coeff[::-1, j], t) for j in range(3)], axis=1)

    def prim(t):
        return np.stack([np.polyval(np.polyint(coeff[::-1, j]), t) for j in range(3)], axis=1)

    tq = np.sort(rng.uniform(tn[0], tn[-1], 50))
    tq[0], tq[-1] = tn[0], tn[-1]
    C = _cubics(tn, poly(tn))
    got, integral = np.empty((tq.size, 3)), np.empty((tq.size, 3))
    pieces_at(tq, tn, C, got)
    pieces_integral_at(tq, tn, C, integral)
    scale = np.max(np.abs(poly(tq)))
    assert np.max(np.abs(got - poly(tq))) < 1e-12 * scale
    assert np.max(np.abs(integral - (prim(tq) - prim(tn[:1])))) < 1e-12 * scale * (tn[-1] - tn[0])
    # two and three nodes: the line and the parabola through them
    for n in (2, 3):
        V = np.stack([np.polyval(coeff[:n][::-1, j], tn[:n]) for j in range(3)], axis=1)
        out = np.empty((5, 3))
        ts = np.linspace(tn[0], tn[n - 1], 5)
        pieces_at(ts, tn[:n], _cubics(tn[:n], V), out)
        ref = np.stack([np.polyval(coeff[:n][::-1, j], ts) for j in range(3)], axis=1)
        assert np.max(np.abs(out - ref)) < 1e-12 * np.max(np.abs(ref))


def test_e_over_the_nodes_is_exact_and_equals_e_sample_by_sample():
    """A defect that is one cubic in t: the local cubics reproduce it, so e
    over the nodes (stride 4, a short last interval) is the exact solution
    of ė = A e + d (the block exponential of e and d's derivatives), and e
    propagated sample by sample (ErrorEstimate.e) equals it at the nodes."""
    rng = np.random.default_rng(7)
    A = _system_matrix(rng)
    nz = A.shape[0]
    t = np.linspace(0.0, 0.5, 203)
    nodes = np.append(np.arange(0, t.size, 4), t.size - 1)
    tn = t[nodes]
    a = 1e-3 * rng.standard_normal((4, nz)) * np.array([1.0, 10.0, 100.0, 1000.0])[:, None]
    D = a[0] + tn[:, None] * a[1] + tn[:, None] ** 2 * a[2] + tn[:, None] ** 3 * a[3]
    C = _cubics(tn, D)
    E = _propagate_defect(A, tn, C)
    # x = (e, d, ḋ, d̈, d⃛): ẋ = M x
    M = np.zeros((5 * nz, 5 * nz))
    M[:nz, :nz] = A
    for p in range(4):
        M[p * nz:(p + 1) * nz, (p + 1) * nz:(p + 2) * nz] = np.eye(nz)
    x0 = np.concatenate([np.zeros(nz), a[0], a[1], 2.0 * a[2], 6.0 * a[3]])
    ref = np.array([(expm(M * s) @ x0)[:nz] for s in tn[[10, 25, -2, -1]]])
    scale = np.max(np.abs(ref))
    assert scale > 1e-6
    assert np.max(np.abs(E[[10, 25, -2, -1]] - ref)) < 1e-9 * scale
    full = _error_on_every_sample(A, t, nodes, C)
    assert np.max(np.abs(full[nodes] - E)) < 1e-10 * scale


def test_hermite_peak_and_largest_motion():
    """Points moving on cubics in t: the Hermite interpolant through their
    values and rates at the nodes is the motion itself, so its largest
    length over the samples is the motion's; largest_motion is NumPy's."""
    rng = np.random.default_rng(4)
    t = np.linspace(0.0, 1.0, 97)
    nodes = np.append(np.arange(0, t.size, 8), t.size - 1)
    a, b = rng.standard_normal(12), 0.1 * rng.standard_normal(12)
    # largest near t = 0.53, between the nodes 0.5 and 0.583

    def V(s):
        return np.outer(1.0 - 4.0 * (s - 0.53) ** 2, a) + np.outer((s - 0.53) ** 3, b)

    def Vd(s):
        return np.outer(-8.0 * (s - 0.53), a) + np.outer(3.0 * (s - 0.53) ** 2, b)

    every = V(t)
    ref = np.sqrt(np.max(np.sum(every.reshape(t.size, 4, 3) ** 2, axis=2)))
    got = hermite_peak(t, nodes, V(t[nodes]), Vd(t[nodes]))
    assert abs(got - ref) < 1e-12 * ref
    assert abs(largest_motion(every, np.arange(t.size), np.eye(12)) - ref) < 1e-14 * ref
    assert got > 1.001 * np.sqrt(np.max(np.sum(V(t[nodes]).reshape(-1, 4, 3) ** 2, axis=2)))
    # the motion over some rows, each point on its non-zero columns only:
    # NumPy's dense product's
    Zp, T = rng.standard_normal((300, 7)), rng.standard_normal((12, 5))
    T[3:6, [0, 2]] = 0.0
    T[6:9, 1] = 0.0
    rows = np.arange(0, 300, 3)
    full = np.sqrt(np.max(np.sum((Zp[rows, :5] @ T.T).reshape(-1, 4, 3) ** 2, axis=2)))
    assert abs(largest_motion(Zp, rows, T) - full) < 1e-14 * full
    assert largest_motion(Zp, rows[:0], T) == 0.0                     # no rows


def test_estimate_within_its_tolerance_of_the_defect_on_every_sample(
        reference_system, reference_equilibrium, monkeypatch):
    """The reference scene (rigid bed, 0–1.5 s: the load stops at 1 s; 1 ms
    samples): the defect on every 16th sample, halved to 8 where the local
    cubics need it, gives the estimate, e and the works of the estimate
    with the defect on every sample (the cubics then reproduce it at
    every sample) to 0.5 %, 3 % and 2e-3 of their largest; the states are
    the same. With 10 ms samples (the same knots while the load lasts, 10 ms
    pieces after it) the first nodes are every 20 ms throughout (one length
    of node intervals and its halves), fewer, and the estimate and e those
    of the defect on every sample to 0.5 % and 4 %."""
    from flexbed.dynamics.integrate import Settings

    system, y = reference_system, reference_equilibrium
    st = Settings("rk4", t_end=1.5, output_dt=1e-3)
    lr = linear.run_linear(system, y, y, st)
    est = lr.estimate
    assert np.all(np.isin(np.arange(0, 1501, 16), est.nodes))
    steps = np.diff(est.nodes)
    assert np.sum(steps == 8) > 50 and np.sum(steps == 16) > 20 and np.all(steps <= 16)
    assert est.evaluations == est.nodes.size < 0.75 * 1501 / 8     # 133 against 188
    monkeypatch.setattr(linear_estimate, "_START", 1)
    ref = linear.run_linear(system, y, y, st)
    assert ref.estimate.nodes.size == 1501
    assert abs(est.position / ref.estimate.position - 1.0) < 5e-3            # seen +3.0e-3
    assert np.max(np.abs(est.e - ref.estimate.e)) < 3e-2 * np.max(np.abs(ref.estimate.e))  # 1.6e-2
    assert np.max(np.abs(est.e[est.nodes] - est.e_nodes)) < 1e-10 * np.max(np.abs(est.e))
    work = system.layout.work
    w, w_ref = lr.run.y[:, work], ref.run.y[:, work]
    scale = np.maximum(np.max(np.abs(w_ref - y[work]), axis=0), 1e-300)
    assert np.max(np.abs(w - w_ref) / scale) < 2e-3                      # seen 8.1e-4
    assert np.array_equal(lr.run.y[:, :work.start], ref.run.y[:, :work.start])
    monkeypatch.setattr(linear_estimate, "_START", 16)
    coarse = linear.run_linear(system, y, y, Settings("rk4", t_end=1.5, output_dt=1e-2))
    assert coarse.pieces == 1050 and coarse.run.t.size == 151
    nodes = coarse.estimate.nodes
    assert np.all(np.isin(np.arange(0, 1000, 20), nodes))      # 1 ms pieces to 1 s
    assert np.all(np.isin(np.arange(1000, 1050, 2), nodes))    # then 10 ms pieces
    assert nodes.size < est.nodes.size                                         # 116 against 133
    assert abs(coarse.estimate.position / ref.estimate.position - 1.0) < 5e-3  # seen −3.3e-4
    assert (np.max(np.abs(coarse.estimate.e - ref.estimate.e[::10]))
            < 4e-2 * np.max(np.abs(ref.estimate.e)))                          # seen 2.7e-2


def test_compiled_states_and_rates_of_many_rows_equal_the_numpy_maps(reference_system,
                                                                     reference_equilibrium):
    from flexbed.dynamics.linear.model import Coordinates

    system, y_eq = reference_system, reference_equilibrium
    c = Coordinates(system, y_eq)
    Z = 1e-2 * np.random.default_rng(11).standard_normal((40, c.nz))
    Y = c.to_y(Z)                                          # compiled: > 8 rows
    ref = np.concatenate([c.to_y(Z[i:i + 4]) for i in range(0, 40, 4)])   # NumPy
    assert np.max(np.abs(Y - ref)) < 1e-15 * np.max(np.abs(ref))
    assert np.max(np.abs(c.to_z(Y) - Z)) < 1e-13
    # to_z compiled (one or many rows) as the NumPy map (three axes), also
    # with Euler parameters of the other sign (the same rotations)
    Yf = Y.copy()
    Yf[::2, c.y_p[0]] *= -1.0
    ref = c.to_z(Yf.reshape(4, 10, -1)).reshape(40, -1)                 # NumPy
    assert np.max(np.abs(c.to_z(Yf) - ref)) < 1e-15
    assert np.max(np.abs(c.to_z(Yf[3]) - ref[3])) < 1e-15
    # and the rates of many state derivatives (compiled) as the NumPy map's
    dY = np.random.default_rng(12).standard_normal((40, Y.shape[1]))
    Zd = c.rate(dY)
    ref = np.concatenate([c.rate(dY[i:i + 4]) for i in range(0, 40, 4)])
    assert np.max(np.abs(Zd - ref)) < 1e-15 * np.max(np.abs(ref))


def test_knots_between_the_samples_keep_few_nodes(reference_system, reference_equilibrium):
    """Output samples every 1.3 ms against the load's 1 ms knots (0–0.5 s):
    the pieces change length at nearly every end, form no long runs, and
    the first nodes stay every 16th end, as on a uniform grid (not every
    end); the estimate is the 1 ms run's."""
    from flexbed.dynamics.integrate import Settings

    system, y = reference_system, reference_equilibrium
    ref = linear.run_linear(system, y, y, Settings("rk4", t_end=0.5, output_dt=1e-3))
    lr = linear.run_linear(system, y, y, Settings("rk4", t_end=0.5, output_dt=1.3e-3))
    assert lr.pieces > 800
    assert lr.estimate.evaluations < 2 * ref.estimate.evaluations              # 54 against 51
    assert abs(lr.estimate.position / ref.estimate.position - 1.0) < 5e-3     # seen −2e-3
