"""The response-spectrum method (issue 24): a 1-DOF system's answer is the
spectrum's value, CQC against SRSS and its closed form for two modes, the
NRL grouping, the static limit of a flat spectrum on a scene; design
spectrum files and their faults (one line, exit 2, nothing written)."""

import math
from importlib import resources

import numpy as np
import pytest

from flexbed.cli import main
from flexbed.dynamics.design_spectrum import DesignSpectrum, tripartite
from flexbed.dynamics.frequency.response_spectrum import (combine, cqc_correlation, modal_peaks,
                                                          nrl_groups, participation)
from flexbed.dynamics.pulses import STANDARD_GRAVITY as G

SPEC = """name = "deck"
damping = 0.05
units = "g"
[z]
displacement = 0.05
velocity = 2.0
acceleration = 100.0
band = [1.0, 2000.0]
"""


# ------------------------------------------------------------------ spectra
def test_tripartite_is_the_minimum_of_its_three_lines():
    d, v, a = 0.05, 2.0, 100.0 * G
    s = tripartite(d, v, a, 1.0, 2000.0, 0.05)
    f = np.geomspace(1.0, 2000.0, 200)
    w = 2 * np.pi * f
    assert np.allclose(s(f), np.minimum(np.minimum(w * w * d, w * v), a), rtol=1e-12)
    assert np.allclose(s.frequency[1:3], [v / (2 * np.pi * d), a / (2 * np.pi * v)], rtol=1e-15)
    # outside: constant displacement below, constant acceleration above
    assert s(0.5) == pytest.approx((2 * np.pi * 0.5) ** 2 * d, rel=1e-12)
    assert s(5000.0) == pytest.approx(a, rel=1e-15)


def test_log_log_interpolation_is_a_power_law_between_breakpoints():
    s = DesignSpectrum([10.0, 100.0], [1.0, 100.0], 0.05)          # slope 2 in log-log
    assert s(31.622776601683793) == pytest.approx(10.0, rel=1e-12)


# ------------------------------------------------------------------ RSA core
def test_one_dof_answer_is_the_spectrum_value():
    m, k = 250.0, 3.0e6
    f0 = math.sqrt(k / m) / (2 * np.pi)
    s = tripartite(0.05, 2.0, 100.0 * G, 1.0, 2000.0, 0.05)
    phi = np.array([[1.0 / math.sqrt(m)]])                           # unit modal mass
    iota = np.ones((1, 3))
    gamma = participation(phi, iota)
    p = modal_peaks(phi, np.array([f0]), np.array([[m]]), iota[:, 2], gamma[:, 2], s([f0]))
    w2 = (2 * np.pi * f0) ** 2
    assert gamma[0, 2] == pytest.approx(math.sqrt(m), rel=1e-15)
    assert p.effective_mass[0] == pytest.approx(m, rel=1e-15)
    assert abs(p.acceleration[0, 0]) == pytest.approx(s(f0), rel=1e-14)        # S_a
    assert abs(p.displacement[0, 0]) == pytest.approx(s(f0) / w2, rel=1e-14)   # S_d
    for rule in ("nrl", "srss", "cqc", "abs"):                        # one mode: all agree
        force = combine(k * p.displacement, p.frequency, 0.05, rule)
        assert force[0] == pytest.approx(m * s(f0), rel=1e-13)


def test_cqc_is_srss_for_well_separated_modes():
    r = np.array([[3.0, -1.0], [2.0, 4.0]])
    f = np.array([5.0, 60.0])
    srss, cqc = combine(r, f, 0.05, "srss"), combine(r, f, 0.05, "cqc")
    rho = cqc_correlation(f, 0.05)[0, 1]
    assert rho < 1e-3
    assert np.allclose(cqc, srss, rtol=2e-3)
    assert not np.allclose(cqc, srss, rtol=1e-9)                      # but not the same rule


@pytest.mark.parametrize("beta", [1.0, 1.02, 1.1, 1.5])
def test_cqc_of_two_close_modes_follows_the_closed_form(beta):
    zeta = 0.05
    r1, r2 = 2.0, -1.5
    # Der Kiureghian (1981), equal damping, written out for this test
    rho = (8 * zeta ** 2 * (1 + beta) * beta ** 1.5
           / ((1 - beta ** 2) ** 2 + 4 * zeta ** 2 * beta * (1 + beta) ** 2))
    got = combine(np.array([[r1], [r2]]), np.array([10.0, 10.0 * beta]), zeta, "cqc")[0]
    assert got == pytest.approx(math.sqrt(r1 ** 2 + r2 ** 2 + 2 * rho * r1 * r2), rel=1e-13)
    if beta == 1.0:                                                   # fully correlated
        assert got == pytest.approx(abs(r1 + r2), rel=1e-13)
    srss = combine(np.array([[r1], [r2]]), np.array([10.0, 10.0 * beta]), zeta, "srss")[0]
    assert (got - srss) * np.sign(r1 * r2) >= 0.0                     # opposite signs: smaller


def test_nrl_sums_close_modes_first_then_max_plus_srss():
    f = np.array([10.0, 10.5, 10.9, 20.0, 40.0])
    assert nrl_groups(f).tolist() == [0, 0, 0, 1, 2]                  # 10.9 within 10 % of 10
    r = np.array([[1.0], [-2.0], [0.5], [4.0], [1.0]])
    # groups: |1|+|-2|+|0.5| = 3.5, 4, 1 → 4 + sqrt(3.5² + 1²)
    assert combine(r, f, 0.05, "nrl")[0] == pytest.approx(4.0 + math.sqrt(3.5 ** 2 + 1.0),
                                                          rel=1e-15)
    assert combine(r, f, 0.05, "abs")[0] == pytest.approx(8.5, rel=1e-15)


# ------------------------------------------------------------------ on a scene
def test_flat_spectrum_gives_the_static_load_of_the_moving_mass():
    """A spectrum flat at A for every mode: Σ_k φ_k Γ_k A/ω_k² = K⁻¹ M ι A, the
    static deflection under A, so the signed sum of the base force's modal
    peaks is the moving mass times A, and each point's acceleration is A."""
    import flexbed
    from flexbed.analyses.response_spectrum import response_spectrum
    from flexbed.files.spectrum import parse_spectrum
    from pathlib import Path

    scene = flexbed.load_scene(resources.files("flexbed") / "scenes" / "skid.toml")
    m = flexbed.modal(scene)
    flat = parse_spectrum('damping = 0.05\nunits = "g"\n[z]\nfrequency = [0.01, 1e5]\n'
                          'acceleration = [10.0, 10.0]\n', Path("flat.toml"))
    r = response_spectrum(scene, m.mounted, flat)
    a = r.axes[2]
    A = 10.0 * G
    assert a.mass_included == pytest.approx(1.0, abs=1e-9)
    fz = a.modal[:, a.column("base FZ")].sum()
    assert abs(fz) == pytest.approx(m.moving_mass * A, rel=1e-7)
    for name in a.names:
        if name.endswith(" az"):
            assert abs(a.modal[:, a.column(name)].sum()) == pytest.approx(A, rel=1e-7)
    assert np.all(a.combined["abs"] >= a.combined["nrl"] - 1e-12 * np.abs(a.combined["abs"]))
    assert np.all(a.combined["nrl"] >= a.combined["srss"] - 1e-12 * np.abs(a.combined["abs"]))


# ------------------------------------------------------------------ faults
def _run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("old, new, words", [
    ("[z]\ndisplacement = 0.05\nvelocity = 2.0\nacceleration = 100.0\nband = [1.0, 2000.0]\n",
     "[z]\nfrequency = [5.0, 50.0, 40.0]\nacceleration = [1.0, 2.0, 3.0]\n",
     "frequency[2] = 40.0 Hz is not above frequency[1] = 50.0 Hz"),
    ("[z]\ndisplacement = 0.05\nvelocity = 2.0\nacceleration = 100.0\nband = [1.0, 2000.0]\n",
     "[z]\nfrequency = [5.0, 50.0]\nacceleration = [1.0, -2.0]\n",
     "acceleration[1] = -2.0 g must be > 0"),
    ("velocity = 2.0", "velocity = -2.0", "velocity = -2.0 m/s must be > 0"),
    ('units = "g"', 'units = "G"', "units = 'G' must be one of"),
    ("damping = 0.05", "damping = 1.5", "damping = 1.5 must be in [0, 1)"),
])
def test_bad_spectrum_files(tmp_path, capsys, old, new, words):
    spec = tmp_path / "spec.toml"
    text = SPEC.replace(old, new)
    assert text != SPEC
    spec.write_text(text)
    code, out, err = _run(capsys, "rsa", "--spectrum", str(spec), "-o", str(tmp_path / "r"))
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "spec.toml" in lines[0] and words in lines[0], err
    assert "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.toml"]


@pytest.mark.parametrize("argv, words", [
    (["--damping", "0.02"], "damping = 0.02 asked, but the spectrum is given for damping = 0.05"),
    (["--rule", "sqrs"], "--rule 'sqrs' is not a combination rule (one of nrl, srss, cqc, abs)"),
    (["--max-frequency", "-1"], "--max-frequency -1.0 must be a frequency > 0"),
])
def test_bad_rsa_requests(tmp_path, capsys, argv, words):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)
    code, out, err = _run(capsys, "rsa", "--spectrum", str(spec), "-o", str(tmp_path / "r"),
                          *argv)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and words in lines[0], err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.toml"]


@pytest.mark.parametrize("argv, words", [
    (["--axis", "y"], "spec.toml: no spectrum for axis y (it gives z)"),
    (["--band", "50", "5"], "--band 50.0 5.0 Hz must satisfy 0 < LO < HI"),
    (["--band", "0.001", "2000"], "samples (over 5,000,000): narrow the band"),
])
def test_bad_synthesis_requests(tmp_path, capsys, argv, words):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)
    code, out, err = _run(capsys, "synthesise", str(spec), "-o", str(tmp_path / "m"), *argv)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and words in lines[0], err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.toml"]


def test_rsa_command_writes_its_files(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)
    skid = str(resources.files("flexbed") / "scenes" / "skid.toml")
    code, out, err = _run(capsys, "rsa", skid, "--spectrum", str(spec), "-o", str(tmp_path / "r"))
    assert code == 0, err
    assert "| output | NRL | SRSS | CQC | ABS |" in out and "base FZ" in out
    from flexbed.files.store import read_file
    from flexbed.files.response_spectrum import RSA_SCHEMA
    c = read_file(tmp_path / "r.h5", schema=RSA_SCHEMA, major=1)
    names = list(c.get("z/outputs/names"))
    fz = np.asarray(c.get("z/combined/srss"))[names.index("base FZ")]
    csv = (tmp_path / "r.csv").read_text().splitlines()
    row = next(line for line in csv if line.startswith("z,base FZ,N,"))
    assert float(row.split(",")[4]) == pytest.approx(fz, rel=1e-9)
