"""Random vibration (issue 25, part 3) against closed forms: a one-stage
isolator under band-limited white base acceleration, and bad PSD input.

The body of :mod:`test_modal` on four mounts moves vertically alone under a
vertical base acceleration of one-sided PSD W [(m/s²)²/Hz]: its absolute
acceleration has ``T = (k + iωc)/(k − mω² + iωc)`` and its displacement
relative to the base (each mount's third-axis deflection) ``−m/G``, so over
the band [f₁, f₂]

    σ_a² = W ∫ |T|² df,   σ_z² = W ∫ m²/|G|² df,

whose integrals over (0, ∞) are ``π fₙ (1 + 4ζ²)/(4ζ)`` and
``π fₙ/(4ζ ωₙ⁴)`` [Crandall & Mark, *Random Vibration in Mechanical
Systems*, 1963, §2.4]; over the band they are taken by adaptive quadrature
of the closed-form integrands (an independent reference).
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from scene_text import KZ, M1, load_text, one_stage

BETA = 2e-3
G0 = 9.80665


@pytest.fixture(scope="module")
def isolator(tmp_path_factory):
    return load_text(tmp_path_factory.mktemp("rnd"), one_stage(BETA))


def _band_integrals(f1, f2):
    kz, cz = 4 * KZ, 4 * BETA * KZ

    def G2(f):
        om = 2 * math.pi * f
        return (kz - M1 * om**2) ** 2 + (om * cz) ** 2

    def T2(f):
        return (kz**2 + (2 * math.pi * f * cz) ** 2) / G2(f)

    fn = math.sqrt(kz / M1) / (2 * math.pi)
    opts = dict(points=[fn], limit=500, epsabs=0.0, epsrel=1e-13)
    return (quad(T2, f1, f2, **opts)[0], quad(lambda f: M1**2 / G2(f), f1, f2, **opts)[0], fn,
            BETA * math.sqrt(kz / M1) / 2)


def test_white_noise_isolator_against_closed_forms(isolator):
    import flexbed
    w_g = 0.04                                         # g²/Hz
    f1, f2 = 1.0, 400.0
    r = flexbed.random_vibration(isolator, psd={"z": [[f1, w_g], [f2, w_g]]},
                                 points=[("c", "mass", [0, 0, 0])])
    W = w_g * G0**2
    Ia, Iz, fn, zeta = _band_integrals(f1, f2)
    a = r.column("c az")
    # 2,000 log-spaced frequencies and the resonance's own: 1.9e-8 relative (measured),
    # within the error stated (Simpson against the trapezoid: 5.5e-6, a bound)
    assert r.rms[a] == pytest.approx(math.sqrt(W * Ia), rel=1e-7)
    assert abs(r.rms[a] - math.sqrt(W * Ia)) <= r.rms_error[a] < 1e-4 * r.rms[a]
    for k in range(1, 5):
        d = r.column(f"M{k} d3")
        assert r.rms[d] == pytest.approx(math.sqrt(W * Iz), rel=1e-7)
        assert abs(r.rms[d] - math.sqrt(W * Iz)) <= r.rms_error[d]
    assert r.rms[r.column("c ax")] < 1e-9 * r.rms[a]
    # the infinite band's closed form less what lies outside [f1, f2]: |T|² ≈ 1
    # below f1, ≈ (2ζfₙ/f)² above f2 (both to O((f1/fₙ)²) and O((fₙ/f2)²) ~ 1e-3 of
    # themselves, 5e-5 of the whole)
    outside = f1 + (2 * zeta * fn) ** 2 / f2
    assert r.rms[a] ** 2 == pytest.approx(
        W * (math.pi * fn * (1 + 4 * zeta**2) / (4 * zeta) - outside), rel=1e-4)
    # Miles' equation beside the single-mode outputs: √(π ζ fₙ S_y(fₙ)), with the
    # closed form's S_y(fₙ) = W (1 + 4ζ²)/(4ζ²) exactly the infinite-band RMS
    assert r.miles.frequency[a] == pytest.approx(fn, rel=1e-10)
    assert r.miles.rms[a] == pytest.approx(
        math.sqrt(W * math.pi * fn * (1 + 4 * zeta**2) / (4 * zeta)), rel=1e-8)
    assert r.miles.share[a] == pytest.approx(0.5, abs=0.01)
    assert r.three_sigma[a] == 3 * r.rms[a]
    # the input's RMS over its band, exact: √(W (f2 − f1)) in g
    assert r.input_rms[2] == pytest.approx(math.sqrt(w_g * (f2 - f1)), rel=1e-13)
    # base force: the body's inertia, −m a
    assert r.rms[r.column("base FZ")] == pytest.approx(M1 * r.rms[a], rel=1e-9)


def test_loglog_interpolation_is_a_power_law():
    from flexbed.dynamics.frequency.random import loglog_interpolate
    fb = np.array([20.0, 80.0, 350.0, 2000.0])
    w = np.array([0.01, 0.04, 0.04, 0.007])
    f = np.array([10.0, 20.0, 40.0, 200.0, 1000.0, 2000.0, 3000.0])
    got = loglog_interpolate(fb, w, f)
    slope = math.log(0.007 / 0.04) / math.log(2000 / 350)
    np.testing.assert_allclose(got, [0.0, 0.01, 0.01 * 2.0, 0.04,
                                     0.04 * (1000 / 350) ** slope, 0.007, 0.0], rtol=1e-13)


@pytest.mark.parametrize("text, message", [
    ("[z]\ntable = [[20, 0.01], [20, 0.04]]\n",
     r"psd.toml: \[z\] table row 2: frequency 20 Hz must be above the previous row's 20 Hz"),
    ("[z]\ntable = [[20, 0.01], [80, -0.04]]\n",
     r"psd.toml: \[z\] table row 2: level -0.04 g²/Hz must be finite and >= 0"),
    ("[w]\ntable = [[20, 0.01], [80, 0.04]]\n", r"psd.toml: axis 'w' is not x, y or z"),
    ("[z]\ntable = [[20, 0.01], [80, 0.04]]\n[x]\ntable = [[20, 0.01], [80, 0.04]]\n"
     "[coherence]\nxz = 1.5\n", r"\[coherence\] xz = 1.5: \|γ\| must be <= 1"),
])
def test_bad_psd_is_one_line_exit_2(tmp_path, capsys, text, message):
    from flexbed.cli import main
    (tmp_path / "psd.toml").write_text(text)
    code = main(["random", "--psd", str(tmp_path / "psd.toml"), "-o", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1
    import re
    assert re.search(message, err), err
    assert not list(tmp_path.glob("r*"))


def test_csv_psd_is_read(tmp_path):
    from flexbed.files.psd import load_psd
    p = tmp_path / "p.csv"
    p.write_text("# MIL-STD-810-like\nfrequency_Hz,x,z\n20,0.01,0.02\n1000,0.01,0.02\n")
    s = load_psd(p)
    assert s.axes == [0, 2]
    np.testing.assert_allclose(s.level([100.0])[0], [0.01, 0.0, 0.02], rtol=1e-14)
    p.write_text("frequency_Hz,z\n20,0.01\n10,0.02\n")
    from flexbed.errors import InputError
    with pytest.raises(InputError, match=r"p.csv: \[z\] table row 2: frequency 10 Hz"):
        load_psd(p)


@pytest.mark.slow
def test_random_response_against_a_time_domain_monte_carlo(tmp_path):
    """Gaussian base accelerations synthesised from the PSD (random-phase
    sums of sinusoids on a 0.1 Hz grid, Rayleigh amplitudes: E[A²/2] = S Δf),
    run through the nonlinear model (flexbed.simulate, the base driven by curve
    data, from the static equilibrium), one 10 s period each after 3 s of
    transient (e^{-ζωₙ t} = 7e-6): each realisation's mean-square mount deflection
    matches its own spectral sum Σ |H(f_j)|² A_j²/2 to 2e-3 (the nonlinear model
    at small amplitude, the curve's cubic spline), and the ensemble's mean square
    matches the random response's within 3 of the ensemble's standard errors
    (Var of a realisation's mean square: Σ (|H_j|² S_j Δf)²)."""
    import flexbed
    w_g = 1e-4                                      # g²/Hz: deflections of ~0.1 mm
    f1, f2, df, period, settle, dt = 2.0, 40.0, 0.1, 10.0, 3.0, 0.002
    fj = np.arange(f1, f2 + df / 2, df)
    Sj = w_g * G0**2 * np.ones_like(fj)
    t = np.arange(0.0, settle + period + 0.5, dt)
    # the spectral model: the mount's third-axis deflection per unit base acceleration
    iso = load_text(tmp_path, one_stage(BETA), "iso.toml")
    Hj = flexbed.frf(iso, points=[("c", "mass", [0, 0, 0])], frequencies=fj,
                     deflections=True)
    Hd = Hj.H[:, Hj.column("M1 d3")]
    r = flexbed.random_vibration(iso, psd={"z": [[f1, w_g], [f2, w_g]]},
                                 points=[("c", "mass", [0, 0, 0])])
    ms_random = r.rms[r.column("M1 d3")] ** 2
    rng = np.random.default_rng(25)
    got, want = [], []
    for k in range(3):
        amp = np.sqrt(rng.exponential(2.0 * Sj * df))          # A²/2 ~ Exp(S Δf)
        phase = rng.uniform(0.0, 2.0 * np.pi, fj.size)
        a = (amp[None, :] * np.cos(2 * np.pi * fj[None, :] * t[:, None] + phase)).sum(axis=1)
        (tmp_path / "drive.csv").write_text("\n".join(f"{ti:.6f},{ai:.12e}"
                                                      for ti, ai in zip(t, a)))
        text = one_stage(BETA) + f"""
[base]
motion = "driven"

[[base.drive]]
direction = "z"
shape = "curve"
file = "drive.csv"

[solver]
t_end = {settle + period}
output_dt = {dt}
"""
        run = flexbed.simulate(load_text(tmp_path, text, f"mc{k}.toml"))
        keep = run.t >= settle - 1e-9
        x = run.mount_deflection[keep, 0, 2][:-1]             # one period, M1's third axis
        got.append(np.mean((x - x.mean()) ** 2))
        want.append(float(np.sum(np.abs(Hd) ** 2 * amp**2 / 2)))
        assert got[-1] == pytest.approx(want[-1], rel=2e-3)
    c = np.abs(Hd) ** 2 * Sj * df
    stderr = math.sqrt(np.sum(c**2) / len(got))
    assert abs(np.mean(got) - ms_random) < 3 * stderr
    # and the discrete spectrum's expected value is the random response's integral
    assert np.sum(c) == pytest.approx(ms_random, rel=1e-3)


def test_the_command_writes_its_files(tmp_path, capsys):
    import h5py

    from flexbed.cli import main
    (tmp_path / "iso.toml").write_text(one_stage(BETA))
    (tmp_path / "p.csv").write_text("frequency_Hz,z\n1,0.04\n400,0.04\n")
    code = main(["random", str(tmp_path / "iso.toml"), "--psd", str(tmp_path / "p.csv"),
                 "--point", "c=mass:0,0,0", "-o", str(tmp_path / "r"), "--peak-factor", "4.5"])
    out = capsys.readouterr().out
    assert code == 0, out
    assert "4.5 sigma" in out and "c az" in out
    for suffix in (".h5", "-rms.csv", "-psd.csv", "-acceleration.png", "-deflection.png"):
        assert (tmp_path / f"r{suffix}").stat().st_size > 0
    with h5py.File(tmp_path / "r.h5") as f:
        names = [n.decode() for n in f["outputs/names"][()]]
        j = names.index("c az")
        assert f["response/peak"][j] == pytest.approx(4.5 * f["response/rms"][j], rel=1e-15)
        assert list(f["miles/output"][()]).count(j) == 1
    rows = (tmp_path / "r-rms.csv").read_text().splitlines()
    assert rows[0].startswith("output,unit,rms,3sigma,peak_4.5sigma,rms_g")


def test_cross_spectra_of_fully_coherent_axes_add_the_amplitudes():
    """A rank-one input S = a aᴴ (axes fully coherent, complex coherence) is one
    input along a: S_y = |Σ_d H_d a_d|², what the coherence table builds."""
    from flexbed.files.psd import G0 as g0
    from flexbed.files.psd import psd_from_tables
    from flexbed.dynamics.frequency.random import response_psd
    rng = np.random.default_rng(3)
    H = rng.normal(size=(5, 3, 4)) + 1j * rng.normal(size=(5, 3, 4))
    gamma = np.exp(0.7j)
    spec = psd_from_tables({"x": [[1, 0.02], [100, 0.02]], "z": [[1, 0.05], [100, 0.05]]},
                           {"xz": [gamma.real, gamma.imag]}, "t")
    f = np.linspace(2, 90, 5)
    S = spec.matrix(f)
    a = g0 * np.array([math.sqrt(0.02), 0.0, math.sqrt(0.05) * np.conj(gamma)])
    exact = np.abs(np.einsum("kdo,d->ko", H, a)) ** 2
    np.testing.assert_allclose(response_psd(H, S), exact, rtol=1e-13)
    from flexbed.errors import InputError
    with pytest.raises(InputError, match=r"t: \[coherence\] xy: both axes need a table"):
        psd_from_tables({"x": [[1, 0.02], [100, 0.02]]}, {"xy": 0.5}, "t")
