"""The linear fast path's propagation: analytic sinusoids propagated
exactly through a state augmented with them, sampled inputs through
precomputed propagators in compiled code."""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import expm

from flexbed.dynamics.integrate import output_grid
from flexbed.dynamics.linear.propagation import _pieces, propagate
from flexbed.dynamics.linear.model import linearise
from flexbed.dynamics.statics import solve_statics
from flexbed.files.scene import load_scene
from flexbed.stages.system import compile_scene
from scene_text import base_and_body, four_mounts, sine_drive

K, C, M = 1.25e5, 200.0, 50.0              # per mount, vertical [N/m, N s/m]; mass [kg]
AMP, FREQ = 3.0, 13.0                      # base acceleration [m/s²], [Hz]

SINE_SDOF = base_and_body("sine-sdof") + sine_drive(AMP, FREQ) + four_mounts(f"""
law = "linear"
k = [5.0e4, 7.5e4, {K}]
c = [0.0, 0.0, {C}]
""", corners=[(-0.2, -0.3), (0.2, -0.3), (-0.2, 0.3), (0.2, 0.3)], prefix="S")


def _closed_form(t, w2, c):
    """Absolute vertical displacement of the mass from rest at its
    equilibrium, base acceleration a = AMP sin Ωt from t = 0: the base's
    d = AMP/Ω t − AMP/Ω² sin Ωt plus the relative u of
    ü + 2ζω u̇ + ω² u = −a (ω² = w2, 2ζω = c), steady state and transient."""
    w, W = math.sqrt(w2), 2 * math.pi * FREQ
    zeta = c / (2 * w)
    wd = w * math.sqrt(1 - zeta ** 2)
    den = (w * w - W * W) ** 2 + (2 * zeta * w * W) ** 2
    # the steady state u_p = a_s sin Ωt + a_c cos Ωt
    a_s, a_c = -AMP * (w * w - W * W) / den, AMP * 2 * zeta * w * W / den
    c1 = -a_c
    c2 = (zeta * w * c1 - a_s * W) / wd
    u = (a_s * np.sin(W * t) + a_c * np.cos(W * t)
         + np.exp(-zeta * w * t) * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t)))
    return AMP / W * t - AMP / W ** 2 * np.sin(W * t) + u


def test_sinusoid_propagated_exactly(tmp_path):
    """The analytic sinusoid in the augmented state: one piece length (no
    extra cuts), and the 1-DOF's closed form to 1e-12 of its motion (ω² and
    2ζω as the linearisation's central differences found them: 4k/m and
    4c/m to 1e-9)."""
    path = tmp_path / "sine.toml"
    path.write_text(SINE_SDOF)
    system = compile_scene(load_scene(path))
    lin = linearise(system, solve_statics(system, tol=1e-12).y)
    grid = output_grid(0.6, 1e-3)
    assert np.array_equal(_pieces(lin, grid), grid)
    t, Z, pieces = propagate(lin, np.zeros(lin.coords.nz), 0.6, 1e-3)
    c = lin.coords
    iz, vz = c.r_index[0, 2], c.v_index[0, 2]
    w2, damp = -lin.A[vz, iz], -lin.A[vz, vz]
    assert abs(w2 / (4 * K / M) - 1) < 1e-9 and abs(damp / (4 * C / M) - 1) < 1e-9
    z = Z[:, iz]
    exact = _closed_form(t, w2, damp)
    assert pieces == 600
    assert np.max(np.abs(z - exact)) < 1e-12 * np.max(np.abs(exact))


def _previous(lin, z0, t_end, output_dt):
    """The propagation as it was before the compiled one (git 0b25ded):
    each input a degree-5 polynomial on each piece, b0 a constant channel,
    one Van Loan exponential per distinct length, the recursion in NumPy."""
    deg = 5
    nodes = 0.5 - 0.5 * np.cos((2 * np.arange(deg + 1) + 1) * np.pi / (2 * (deg + 1)))
    vinv = np.linalg.inv(nodes[:, None] ** np.arange(deg + 1)[None, :])
    fact = np.array([math.factorial(m) for m in range(deg + 1)], dtype=float)
    grid = output_grid(t_end, output_dt)
    t = _pieces(lin, grid)
    h = np.diff(t)
    nu = len(lin.channels)
    G = np.column_stack([lin.B, lin.b0])
    U = lin.inputs((t[:-1, None] + h[:, None] * nodes[None, :]).reshape(-1))
    Wu = np.einsum("mi,kiu->kum", vinv, U.reshape(h.size, deg + 1, nu)) * fact
    W1 = np.zeros((h.size, 1, deg + 1))
    W1[:, 0, 0] = 1.0
    W = np.concatenate([Wu, W1], axis=1).reshape(h.size, -1)
    nz = lin.A.shape[0]
    cache, z, Z = {}, np.array(z0, dtype=float), [np.array(z0, dtype=float)]
    for i, hi in enumerate(h):
        key = float(f"{hi:.12e}")
        if key not in cache:
            n = nz + (nu + 1) * (deg + 1)
            Mx = np.zeros((n, n))
            Mx[:nz, :nz] = key * lin.A
            for j in range(nu + 1):
                c0 = nz + j * (deg + 1)
                Mx[:nz, c0] = key * G[:, j]
                for m in range(deg):
                    Mx[c0 + m, c0 + m + 1] = 1.0
            E = expm(Mx)
            cache[key] = (E[:nz, :nz], E[:nz, nz:])
        Phi, Psi = cache[key]
        z = Phi @ z + Psi @ W[i]
        Z.append(z)
    return grid, np.array(Z)[np.searchsorted(t, grid)]


def test_sampled_input_as_before(reference_system, reference_equilibrium):
    """The reference scene (its load sampled every 1 ms, a spline): the
    compiled propagation equals the previous implementation to round-off,
    from a displaced start so that every mode moves."""
    lin = linearise(reference_system, reference_equilibrium)
    z0 = 1e-4 * np.random.default_rng(3).standard_normal(lin.coords.nz)
    t, Z, _ = propagate(lin, z0, 1.5, 1e-3)
    t_old, Z_old = _previous(lin, z0, 1.5, 1e-3)
    assert np.array_equal(t, t_old)
    scale = np.max(np.abs(Z_old), axis=0)
    assert np.max(np.abs(Z - Z_old) / scale) < 1e-11


def test_inputs_from_the_splines_own_coefficients_equal_the_chebyshev_fit(reference_system):
    """The reference scene's sampled load (a cubic spline, its knots on the
    output grid): the pieces are the grid itself, and the inputs' σ-derivatives
    taken from the spline's coefficients equal those fitted at six Chebyshev
    points per piece (the channel without its polynomials) to the fit's
    round-off."""
    from dataclasses import replace

    from flexbed.dynamics.linear.propagation import _inputs_on_pieces

    lin = linearise(reference_system, solve_statics(reference_system, tol=1e-9).y)
    assert lin.channels and all(c.polys for c in lin.channels)
    grid = output_grid(1.5, 1e-3)
    t = _pieces(lin, grid)
    assert np.array_equal(t, grid)
    exact = _inputs_on_pieces(lin, t, [])
    fitted = _inputs_on_pieces(replace(lin, channels=tuple(replace(c, polys=())
                                                          for c in lin.channels)), t, [])
    # the fit's round-off, against the load's size (seen 8e-11): every column
    # is a σ-derivative of a value of that size
    scale = np.max(np.abs(fitted[:, 0]))
    assert scale > 1e5
    assert np.max(np.abs(exact - fitted)) < 1e-9 * scale
    assert np.all(exact[:, 4:6] == 0.0)                 # a cubic has no 4th, 5th derivatives


def test_compiled_sweep_equals_the_recursion():
    """linear_sweep (four rows at a time, the rest one by one) equals the
    recursion X[i + 1] = Φ_j X[i] + P[i] in NumPy to round-off, for sizes
    with and without a remainder and two alternating propagators."""
    from flexbed.dynamics.linear.sweep import linear_sweep

    rng = np.random.default_rng(5)
    for n in (3, 7, 42):
        Phis = 0.9 * rng.standard_normal((2, n, n)) / math.sqrt(n)
        which = rng.integers(0, 2, 200).astype(np.int64)
        P = rng.standard_normal((200, n))
        x0 = rng.standard_normal(n)
        X = np.empty((201, n))
        linear_sweep(Phis, which, P, x0, X)
        ref = np.empty_like(X)
        ref[0] = x0
        for i in range(200):
            ref[i + 1] = Phis[which[i]] @ ref[i] + P[i]
        assert np.max(np.abs(X - ref)) < 1e-13 * np.max(np.abs(ref))
        # in place: P held in X[1:] itself (as propagate does) gives the same bits
        Y = np.empty((201, n))
        Y[1:] = P
        linear_sweep(Phis, which, Y[1:], x0, Y)
        assert np.array_equal(Y, X)


def test_compiled_poly_derivatives_are_the_exact_derivatives():
    """poly_derivatives adds h^m f^(m)(t0) of a piecewise quintic (two pieces,
    each with its own origin) to what out holds: against NumPy's exact
    derivatives of the same polynomials."""
    from numpy.polynomial import polynomial as npp

    from flexbed.dynamics.piecewise import PiecewisePolynomial
    from flexbed.dynamics.linear.sweep import poly_derivatives

    rng = np.random.default_rng(6)
    coeffs = rng.standard_normal((3, 6))
    f = PiecewisePolynomial([0.0, 1.0], coeffs)       # origins: 0 (left tail), 0, 1
    t0 = np.array([-0.3, 0.2, 0.55, 1.4])
    h = np.array([0.1, 0.3, 0.25, 0.5])
    idx = np.searchsorted(f.breaks, t0 + 0.5 * h, side="right")
    out = np.ones((t0.size, 6))
    poly_derivatives(f.coeffs, f.origins, idx, t0, h, out)
    for i in range(t0.size):
        c = coeffs[idx[i]]
        u = t0[i] - f.origins[idx[i]]
        for m in range(6):
            exact = npp.polyval(u, npp.polyder(c, m)) * h[i] ** m if m else npp.polyval(u, c)
            assert abs(out[i, m] - 1.0 - exact) < 1e-13 * (1.0 + abs(exact))


def test_pieces_merge_knots_into_the_grid():
    """The pieces' ends: every grid time exactly, a knot within 1e-9 of the
    spacing of a grid time or of the cut before it left out, the others kept
    in order; the piece lengths grouped without sorting when few."""
    from flexbed.dynamics.linear.propagation import _lengths
    from flexbed.dynamics.linear.sweep import merge_cuts

    grid = np.linspace(0.0, 0.1, 11)
    tol = 1e-9 * 0.01
    extra = np.array([0.005, 0.02 + 0.4 * tol, 0.0349, 0.0349 + 0.5 * tol, 0.06 - 0.3 * tol, 0.095])
    out = np.empty(grid.size + extra.size)
    n = merge_cuts(grid, extra, tol, out)
    expected = np.sort(np.concatenate([grid, [0.005, 0.0349, 0.095]]))
    assert n == expected.size and np.array_equal(out[:n], expected)
    assert np.array_equal(out[:n][np.isin(out[:n], grid)], grid)
    lengths, which = _lengths(np.diff(out[:n]))
    assert np.allclose(lengths[which], np.diff(out[:n]), rtol=1e-11, atol=0.0)
    assert np.all(np.diff(lengths) > 0)


def test_a_multiple_of_the_shortest_piece_is_its_power(reference_system, reference_equilibrium):
    """The propagators of a piece k times the shortest (binary powers of the
    shortest's exponential in t-derivatives) equal the exponential of its own
    augmented matrix to round-off (the reference scene: a sampled load)."""
    from flexbed.dynamics.linear.propagation import _propagators, _sine_terms

    lin = linearise(reference_system, reference_equilibrium)
    terms = _sine_terms(lin)
    Phis, Psis = _propagators(lin, np.array([1e-3, 1e-2, 3e-3]), terms)
    for i, h in ((1, 1e-2), (2, 3e-3)):
        Phi, Psi = _propagators(lin, np.array([h]), terms)
        assert np.max(np.abs(Phis[i] - Phi[0])) < 1e-13 * np.max(np.abs(Phi[0]))
        for col in range(Psi.shape[2]):
            ref = Psi[0][:, col]
            assert np.max(np.abs(Psis[i][:, col] - ref)) <= 1e-12 * np.max(np.abs(ref)) + 1e-300


def test_polynomial_inputs_exponential_by_series_is_scipys(reference_system, reference_equilibrium):
    """Without sinusoids the augmented exponential is built from Φ = e^{hA}
    and the columns h φ_{m+1}(hA) [B b0] by their series on the balanced A
    (halved and doubled back where ‖hA'‖₁ > 2: 0.01 and 0.1 s here): it
    equals SciPy's expm of the whole augmented matrix to 1e-12 of each
    block's largest entry (the reference scene, rigid bed)."""
    from flexbed.dynamics.linear.propagation import _Exponential

    lin = linearise(reference_system, reference_equilibrium)
    exponential = _Exponential(lin, [])
    nz = lin.A.shape[0]
    for h in (1e-3, 1e-2, 1e-1):
        E, ref = exponential(h), expm(exponential._matrix(h))
        assert E.shape == ref.shape
        for block in (np.s_[:nz, :nz], np.s_[:nz, nz:], np.s_[nz:, :]):
            assert np.max(np.abs(E[block] - ref[block])) <= 1e-12 * np.max(np.abs(ref[block]))
