"""Shock response spectra: Smallwood's ramp-invariant filter against the
closed-form half-sine spectrum and against each oscillator integrated
directly; the command and the API on a driven-base run."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from flexbed.dynamics.shock_spectrum import (acceleration_coefficients, frequency_grid,
                                             ramp_invariant_coefficients, shock_spectrum)


def _half_sine_srs(f, peak, tau):
    """Exact undamped SRS of a half-sine base pulse ÿ = peak·sin(πt/τ), 0 ≤ t ≤ τ.

    With Ω = π/τ, ρ = Ω/ω, the absolute acceleration during the pulse is
    ẍ = peak/(1 − ρ²)·(sin Ωt − ρ sin ωt); its extrema satisfy
    cos Ωt = cos ωt, i.e. t = 2πn/(ω ± Ω) (and the pulse's end). After it
    the free oscillation has the amplitude 2ρ|cos(ωτ/2)|/|1 − ρ²|·peak,
    reached with both signs. Returns (positive, negative) maximax.
    """
    pos, neg = [], []
    for fi in f:
        w = 2 * math.pi * fi
        W = math.pi / tau
        rho = W / w
        cand = [tau]
        for rate in (w + W, abs(w - W)):
            n = np.arange(1, int(rate * tau / (2 * math.pi)) + 1)
            cand.extend((2 * math.pi * n / rate).tolist())
        t = np.array(cand)
        x = peak / (1 - rho ** 2) * (np.sin(W * t) - rho * np.sin(w * t))
        res = peak * 2 * rho * abs(math.cos(w * tau / 2)) / abs(1 - rho ** 2)
        pos.append(max(x.max(), res))
        neg.append(max(-x.min(), res))
    return np.array(pos), np.array(neg)


def test_acceleration_filter_is_the_ramp_invariant_discretisation():
    """Smallwood's closed-form coefficients equal those derived from the
    exact piecewise-linear-input step (Van Loan exponential)."""
    omega = 2 * math.pi * frequency_grid(1.0, 2000.0, 6)
    for zeta in (0.0, 0.05, 0.3):
        c = np.column_stack([-omega ** 2, -2 * zeta * omega])
        b, a = ramp_invariant_coefficients(omega, zeta, 1e-4, c)
        bc, ac = acceleration_coefficients(omega, zeta, 1e-4)
        np.testing.assert_allclose(b, bc, rtol=0, atol=1e-12)
        np.testing.assert_allclose(a, ac, rtol=0, atol=1e-12)


def test_half_sine_against_its_closed_form():
    """Undamped SRS of a 10 ms, 100 m/s² half-sine sampled every 10 µs.

    Two sampling errors only: the input's straight lines between samples
    (relative (ΩT)²/8 = 1.2e-6) and the peak between two samples (relative
    at most 1 − cos(ωT/2) ≈ (ωT)²/8, 1.2e-4 at 500 Hz); the tolerance is
    their sum per frequency, plus 1e-6."""
    tau, peak, dt = 0.01, 100.0, 1e-5
    f = frequency_grid(5.0, 500.0, 6)
    t = np.arange(0.0, tau + 1.2 / f[0], dt)
    u = np.where(t <= tau, peak * np.sin(np.pi * np.minimum(t, tau) / tau), 0.0)
    s = shock_spectrum(u, dt, f, q=math.inf)
    pos, neg = _half_sine_srs(f, peak, tau)
    tol = (2 * np.pi * f * dt) ** 2 / 8 + (np.pi / tau * dt) ** 2 / 8 + 1e-6
    assert np.all(np.abs(s.positive / pos - 1) <= tol)
    assert np.all(np.abs(s.negative / neg - 1) <= tol)
    # undamped, ẍ = −ω²z: the pseudo-velocity is the maximax over ω (the two
    # filters' round-off, growing as 1/(ωT)² = 1e7 at 5 Hz, apart)
    np.testing.assert_allclose(s.pseudo_velocity, s.maximax / (2 * np.pi * f), rtol=1e-8)
    # the classical peak of the half-sine spectrum, 1.768 × the pulse's peak
    assert s.maximax.max() / peak == pytest.approx(1.768, abs=2e-3)


def test_half_sine_against_each_oscillator_integrated():
    """Q = 10: the filter's outputs at the samples equal each oscillator
    integrated directly (DOP853, rtol 1e-12) through the same straight-line
    input, piece by piece, to 1e-9 of the peak response."""
    tau, peak, dt, q = 0.01, 100.0, 2e-4, 10.0
    t = np.arange(0.0, 0.04, dt)
    u = np.where(t <= tau, peak * np.sin(np.pi * np.minimum(t, tau) / tau), 0.0)
    f = np.array([12.0, 80.0, 300.0])
    s = shock_spectrum(u, dt, f, q=q)
    zeta = 0.5 / q
    for i, fi in enumerate(f):
        w = 2 * math.pi * fi
        y = np.zeros(2)
        acc = [0.0]                       # ẍ at t = 0: at rest, ÿ(0) = 0
        z = [0.0]
        for k in range(t.size - 1):
            slope = (u[k + 1] - u[k]) / dt

            def rhs(tt, s_, k=k, slope=slope, w=w):
                return [s_[1], -w * w * s_[0] - 2 * zeta * w * s_[1] - (u[k] + slope * tt)]

            y = solve_ivp(rhs, (0.0, dt), y, method="DOP853", rtol=1e-12, atol=1e-15).y[:, -1]
            acc.append(-(w * w * y[0] + 2 * zeta * w * y[1]))
            z.append(y[0])
        acc, z = np.array(acc), np.array(z)
        assert s.positive[i] == pytest.approx(max(acc.max(), 0.0), rel=1e-9)
        assert s.negative[i] == pytest.approx(max(-acc.min(), 0.0), rel=1e-9)
        assert s.displacement[i] == pytest.approx(np.abs(z).max(), rel=1e-9)
        assert s.pseudo_velocity[i] == pytest.approx(w * np.abs(z).max(), rel=1e-9)


def test_frequency_grid():
    f = frequency_grid(10.0, 100.0, 3)
    np.testing.assert_allclose(f[:10], 10.0 * 2 ** (np.arange(10) / 3))
    assert f[-1] == 100.0 and f.size == 11


def test_srs_of_a_run_command_and_api(tmp_path):
    """linear_sdof.toml: 50 kg on mounts of 5e5 N/m vertically, undamped, a
    driven base. The mass is itself an oscillator of fn = √(k/m)/2π on that
    base, so the input's spectrum at fn with (almost) no damping is the
    mass's own peak acceleration — to 1e-4: the record's damping
    ζωt = 1.3e-5 (Q = 1e6) and the triangle's corners, off the 0.1 ms samples
    and cut by straight lines (input error ~ slope change × T²/8 against the
    impulse, 1e-5). The command writes the CSV, HDF5 and PNG files."""
    import flexbed
    from flexbed.cli import main
    from flexbed.files.store import read_file

    scene = flexbed.load_scene(Path(__file__).parent / "scenes" / "linear_sdof.toml")
    run = flexbed.simulate(scene, output_dt=1e-4, rtol=1e-11, atol=1e-13, integrator="dop853")
    fn = math.sqrt(5e5 / 50.0) / (2 * math.pi)
    s = flexbed.srs(run, point=("c", "mass", [0, 0, 0]), q=1e6, fmin=fn, fmax=fn)
    az = run.acceleration[:, 1, 2]
    assert s.input.positive[0, 2] == pytest.approx(az.max(), rel=1e-4)
    assert s.input.negative[0, 2] == pytest.approx(-az.min(), rel=1e-4)
    # the point's spectra are those of its absolute acceleration (the centre of mass)
    ref = shock_spectrum(az, 1e-4, s.frequency, q=1e6)
    np.testing.assert_array_equal(s.points[0].maximax[:, 2], ref.maximax)

    path = tmp_path / "r.h5"
    run.save(path)
    code = main(["srs", str(path), "--point", "mass top=mass:0,0,0.1", "--fmax", "200",
                 "--per-octave", "3", "--csv", str(tmp_path / "csv"), "--hdf5",
                 str(tmp_path / "srs.h5"), "--plot", str(tmp_path / "png")])
    assert code == 0
    f = read_file(tmp_path / "srs.h5", schema="flexbed.srs", major=1)
    n = f.datasets["frequency"].size
    assert f.datasets["frequency"][0] == 1.0 and f.datasets["frequency"][-1] == 200.0
    for g in ("mass top", "input"):
        for key in ("positive", "negative", "maximax", "pseudo_velocity"):
            assert f.datasets[f"{g}/{key}"].shape == (n, 3)
    assert f.units["input/pseudo_velocity"] == "m/s" and f.attrs[""]["q"] == 10.0
    rows = (tmp_path / "csv" / "srs-mass_top.csv").read_text().splitlines()
    assert rows[0].startswith("frequency_Hz,positive_x_m/s2") and len(rows) == n + 1
    assert (tmp_path / "csv" / "srs-input.csv").is_file()
    assert (tmp_path / "png" / "srs-mass_top.png").stat().st_size > 0


def test_srs_bad_band_is_one_line(tmp_path, capsys):
    from flexbed.cli import main
    import flexbed
    scene = flexbed.load_scene(Path(__file__).parent / "scenes" / "linear_sdof.toml")
    path = tmp_path / "r.h5"
    flexbed.simulate(scene, model="linear").save(path)
    assert main(["srs", str(path), "--point", "c=mass:0,0,0", "--fmax", "400"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--fmax 400 Hz" in err and "250" in err
