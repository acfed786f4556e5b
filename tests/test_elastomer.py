"""Elastomer mounts (issue 25, part 4): the complex stiffness k(f)(1 + iη(f))
against the one-stage isolator's closed forms, and bad input.

The body of :mod:`test_modal` on four mounts moves vertically alone under a
vertical base acceleration; with the mounts' vertical complex stiffness
κ = 4 k(f)(1 + iη(f)) its absolute acceleration has ``T = κ/(κ − mω²)``, so
with a constant η, ``|T| = √((1 + η²)/((1 − r²)² + η²))``, r = f/fₙ
[Harris & Piersol, *Shock and Vibration Handbook*, 5th ed., §2.3 on
hysteretic damping].
"""

import math

import numpy as np
import pytest

from scene_text import KX, KY, KZ, M1, base_and_body, elastomer_stage, load_text, one_stage

ETA = 0.15


def _vertical(scene, f):
    import flexbed
    t = flexbed.frf(scene, input="base z", points=[("c", "mass", [0, 0, 0])], frequencies=f)
    return t.H[:, t.column("c az")], t


def test_constant_loss_factor_against_the_closed_form(tmp_path):
    scene = load_text(tmp_path, elastomer_stage(f"loss_factor = [{ETA}, {ETA}, {ETA}]"))
    fn = math.sqrt(4 * KZ / M1) / (2 * math.pi)
    f = fn * np.array([0.1, 0.5, 0.9, 0.999, 1.0, 1.001, 1.1, 2.0, 10.0])
    H, t = _vertical(scene, f)
    r = f / fn
    exact = np.sqrt((1 + ETA**2) / ((1 - r**2) ** 2 + ETA**2))
    np.testing.assert_allclose(np.abs(H), exact, rtol=1e-10)
    kap = 4 * KZ * (1 + 1j * ETA)
    om = 2 * math.pi * f
    np.testing.assert_allclose(H, kap / (kap - M1 * om**2), rtol=1e-10)
    # horizontal input stays apart from the vertical: no cross-talk
    assert np.all(np.abs(t.H[:, t.column("c ax")]) < 1e-9 * np.abs(H))
    # the force into the base is the body's inertia force, −m a, and the sum of the
    # mounts' complex forces κ/4 (relative deflection), with u = −m/(κ − mω²)
    np.testing.assert_allclose(t.H[:, t.column("base FZ")], -M1 * H, rtol=1e-10)
    u = -M1 / (kap - M1 * om**2)
    for k in range(1, 5):
        np.testing.assert_allclose(t.H[:, t.column(f"M{k} f3")], kap / 4 * u, rtol=1e-10)


def test_a_frequency_table_at_its_frequencies(tmp_path):
    f_tab = [2.0, 5.0, 10.0, 20.0, 50.0]
    kz = [KZ * s for s in (1.0, 1.1, 1.25, 1.4, 1.6)]
    eta = [0.05, 0.08, 0.12, 0.15, 0.2]
    rows_k = ", ".join(f"[{KX}, {KY}, {k}]" for k in kz)
    rows_e = ", ".join(f"[0.1, 0.1, {e}]" for e in eta)
    scene = load_text(tmp_path, elastomer_stage(
        f"elastomer = {{frequency = {f_tab}, stiffness = [{rows_k}], "
        f"loss_factor = [{rows_e}]}}"))
    f = np.array(f_tab)
    H, _ = _vertical(scene, f)
    kap = 4 * np.array(kz) * (1 + 1j * np.array(eta))
    om = 2 * math.pi * f
    np.testing.assert_allclose(H, kap / (kap - M1 * om**2), rtol=1e-10)
    # between the table's frequencies: log-log in the stiffness, held outside
    g = np.array([1.0, math.sqrt(10.0 * 20.0), 80.0])
    H, _ = _vertical(scene, g)
    k_mid = 4 * math.sqrt(kz[2] * kz[3])
    kap = np.array([4 * kz[0] * (1 + 1j * eta[0]), k_mid * (1 + 1j * 0.5 * (eta[2] + eta[3])),
                    4 * kz[-1] * (1 + 1j * eta[-1])])
    om = 2 * math.pi * g
    np.testing.assert_allclose(H, kap / (kap - M1 * om**2), rtol=1e-10)


def test_the_static_stiffness_is_the_laws(tmp_path):
    """The equilibrium with an elastomer is the plain linear mount's."""
    import flexbed
    plain = load_text(tmp_path, one_stage(0.0), "plain.toml")
    rubber = load_text(tmp_path, elastomer_stage(
        "elastomer = {frequency = [1.0, 100.0], stiffness = [[1e5, 1e5, 1e5], [2e5, 2e5, 2e5]]}"),
        "rubber.toml")
    np.testing.assert_array_equal(flexbed.statics(plain).position, flexbed.statics(rubber).position)
    assert plain.statics_digest == rubber.statics_digest      # one equilibrium file serves both


BAD = [
    ("loss_factor = [0.1, -0.2, 0.1]", "loss_factor[1] = -0.2 must be >= 0"),
    ("elastomer = {frequency = [1.0, 1.0], stiffness = [[1, 1, 1], [1, 1, 1]]}",
     "must increase strictly"),
    ("elastomer = {frequency = [1.0, 2.0], stiffness = [[1, 1, 1], [1, 0, 1]]}",
     "stiffness[1][1] = 0.0 must be > 0"),
    ("elastomer = {frequency = [1.0, 2.0], stiffness = [[1, 1, 1]]}",
     "stiffness must be 2 rows"),
    ("elastomer = {frequency = [1.0, 2.0], stiffness = [[1, 1, 1], [1, 1, 1]], "
     "loss_factor = [[0, 0, 0], [0, -1, 0]]}", "loss_factor[1][1] = -1.0 must be >= 0"),
    ("loss_factor = [0.1, 0.1, 0.1]\nelastomer = {frequency = [1.0], stiffness = [[1, 1, 1]]}",
     "not both"),
]


@pytest.mark.parametrize("extra, message", BAD)
def test_bad_elastomer_is_one_line_exit_2(tmp_path, capsys, extra, message):
    from flexbed.cli import main
    path = tmp_path / "bad.toml"
    path.write_text(elastomer_stage(extra))
    assert main(["static", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err and "mount 'M1'" in err, err


def test_loss_factor_on_a_nonlinear_law_is_refused(tmp_path, capsys):
    from flexbed.cli import main
    text = one_stage(0.0).replace('law = "linear"\n', 'law = "polynomial"\n', 1)
    text = text.replace(f"k = [{KX}, {KY}, {KZ}]\nc = [0.0, 0.0, 0.0]\n",
                        f"stiffness = [[0, {KX}], [0, {KY}], [0, {KZ}]]\n"
                        f"loss_factor = [0.1, 0.1, 0.1]\n", 1)
    path = tmp_path / "bad.toml"
    path.write_text(text)
    assert main(["static", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "applies to law = 'linear' only" in err, err


def _inclined(extra: str) -> str:
    """Zero gravity (no preload), the body turned, four mounts from the body
    (body i) to the base along inclined axes, ``extra`` keys on each."""
    text = base_and_body("inclined", gravity=0.0, body_extra="orientation_deg = [10, 20, 30]")
    return text + "".join(f"""
[[mount]]
name = "M{n}"
body_i = "mass"
body_j = "base"
point_i = [{x}, {y}, -0.3]
point_j = [{x}, {y}, 0.2]
axes_deg = [5, -15, 25]
law = "linear"
{extra}
""" for n, (x, y) in enumerate([(-0.2, -0.3), (0.25, -0.3), (0.2, 0.3), (-0.2, 0.35)], 1))


def test_a_table_of_one_stiffness_is_that_linear_mount(tmp_path):
    """An elastomer whose table holds k' with η = 0 is exactly the linear mount
    of stiffness k' (no preload, so no geometric stiffness): the D_vᵀ D blocks
    and the base force's axes, on inclined mounts of a turned body."""
    import flexbed
    k, k2 = (2e4, 3e4, 5e4), (3e4, 2.5e4, 8e4)
    plain = load_text(tmp_path, _inclined(f"k = {list(k2)}"), "plain.toml")
    rows = ", ".join([str(list(k2))] * 2)
    rubber = load_text(tmp_path, _inclined(
        f"k = {list(k)}\nelastomer = {{frequency = [1.0, 9.0], stiffness = [{rows}]}}"),
        "rubber.toml")
    f = np.array([0.5, 3.0, 5.0, 7.5, 12.0, 30.0])
    for inp in ("base x", "base z"):
        a = flexbed.frf(plain, input=inp, points=[("c", "mass", [0.1, 0, 0])], frequencies=f)
        b = flexbed.frf(rubber, input=inp, points=[("c", "mass", [0.1, 0, 0])], frequencies=f)
        assert a.names == b.names
        scale = np.abs(a.H).max(axis=0)
        assert np.max(np.abs(a.H - b.H) / scale) < 1e-8


def test_random_with_an_elastomer_against_the_closed_form(tmp_path):
    """The random response's vertical RMS with a constant loss factor: W ∫ |T|² df
    with |T|² = (1 + η²)/((1 − r²)² + η²), by adaptive quadrature."""
    import flexbed
    from scipy.integrate import quad
    scene = load_text(tmp_path, elastomer_stage(f"loss_factor = [{ETA}, {ETA}, {ETA}]"))
    w_g, f1, f2 = 0.01, 2.0, 200.0
    r = flexbed.random_vibration(scene, psd={"z": [[f1, w_g], [f2, w_g]]},
                                 points=[("c", "mass", [0, 0, 0])])
    fn = math.sqrt(4 * KZ / M1) / (2 * math.pi)
    T2 = quad(lambda f: (1 + ETA**2) / ((1 - (f / fn) ** 2) ** 2 + ETA**2), f1, f2,
              points=[fn], limit=500, epsabs=0.0, epsrel=1e-13)[0]
    a = r.column("c az")
    exact = math.sqrt(w_g * 9.80665**2 * T2)
    assert abs(r.rms[a] - exact) <= max(r.rms_error[a], 1e-7 * exact)
    assert r.rms[r.column("base FZ")] == pytest.approx(M1 * r.rms[a], rel=1e-9)


def test_maxwell_fit_recovers_a_maxwell_table():
    """A table made from a Maxwell series on the fit's own relaxation times is
    fitted back to round-off; the error stated is the error over the band."""
    import math
    from flexbed.dynamics.frequency.elastomer import ElastomerTable
    from flexbed.dynamics.frequency.maxwell import FIT_POINTS, MaxwellFit, fit_maxwell
    f = np.logspace(0, 2, FIT_POINTS)          # 1-100 Hz on the fit's own grid: exact rows
    tau = 1.0 / (2 * math.pi * np.logspace(-0.5, 2.5, 7))     # the fit's τ for this band
    k_inf = np.array([1e5, 2e5, 3e5])
    k = np.zeros((3, 7))
    k[:, 2], k[:, 4] = [3e4, 1e4, 5e4], [2e4, 6e4, 1e4]
    K = MaxwellFit((1.0, 100.0), tau, k_inf, k, np.zeros(3)).complex(f)
    table = ElastomerTable(k_inf, f, K.real, K.imag / K.real)
    fit = fit_maxwell(table)
    np.testing.assert_allclose(fit.tau, tau, rtol=1e-14)
    assert np.all(fit.error < 1e-9)
    np.testing.assert_allclose(fit.k_inf, k_inf, rtol=1e-8)
    np.testing.assert_allclose(fit.k, k, rtol=0, atol=1e-8 * k.max())
    # a table off the model: the error stated is the error over the band
    coarse = ElastomerTable(k_inf, f[::25], K.real[::25], (K.imag / K.real)[::25])
    fit = fit_maxwell(coarse)
    g = np.logspace(0, math.log10(f[::25][-1]), FIT_POINTS)
    err = np.max(np.abs(fit.complex(g) - coarse.complex(g)) / np.abs(coarse.complex(g)), axis=0)
    np.testing.assert_allclose(fit.error, err, rtol=1e-12)
    assert np.all(err > 1e-6)


def test_a_constant_loss_factor_fit_is_reported_when_read(tmp_path):
    from flexbed.errors import FlexbedWarning
    with pytest.warns(FlexbedWarning, match=r"mounts 'M1', 'M2', 'M3', 'M4': elastomer: a "
                                            r"generalised Maxwell series of \d+ terms matches "
                                            r".* over 1-1000 Hz") as got:
        load_text(tmp_path, elastomer_stage(f"loss_factor = [{ETA}, {ETA}, {ETA}]"))
    assert len([w for w in got if "Maxwell" in str(w.message)]) == 1


def test_modal_takes_each_mode_at_its_own_frequency(tmp_path):
    """The vertical mode of the isolator on a table: fₙ = √(4 k(fₙ)/m)/2π (the
    fixed point, by bisection on the table's log-log interpolation) and
    ζ = η(fₙ)/2; with a constant η, fₙ of the static k and ζ = η/2."""
    import flexbed
    from scipy.optimize import brentq
    scene = load_text(tmp_path, elastomer_stage(f"loss_factor = [{ETA}, {ETA}, {ETA}]"), "c.toml")
    m = flexbed.modal(scene)
    fn = math.sqrt(4 * KZ / M1) / (2 * math.pi)
    j = int(np.argmin(np.abs(m.frequency - fn)))
    assert m.frequency[j] == pytest.approx(fn, rel=1e-10)
    assert m.damping_ratio[j] == pytest.approx(ETA / 2, rel=1e-10)
    f_tab, s_tab, e_tab = [2.0, 5.0, 10.0, 20.0, 50.0], [1.0, 1.1, 1.25, 1.4, 1.6], \
        [0.05, 0.08, 0.12, 0.15, 0.2]
    rows_k = ", ".join(f"[{KX * s}, {KY * s}, {KZ * s}]" for s in s_tab)
    rows_e = ", ".join(f"[{e}, {e}, {e}]" for e in e_tab)
    scene = load_text(tmp_path, elastomer_stage(
        f"elastomer = {{frequency = {f_tab}, stiffness = [{rows_k}], "
        f"loss_factor = [{rows_e}]}}"), "t.toml")
    m = flexbed.modal(scene)
    lf, lt = np.log, np.log(f_tab)

    def k_of(f):
        return KZ * math.exp(np.interp(lf(f), lt, np.log(s_tab)))

    f_exact = brentq(lambda f: f - math.sqrt(4 * k_of(f) / M1) / (2 * math.pi), 1.0, 100.0,
                     xtol=1e-14, rtol=1e-15)
    j = int(np.argmin(np.abs(m.frequency - f_exact)))
    assert m.frequency[j] == pytest.approx(f_exact, rel=1e-10)
    assert m.damping_ratio[j] == pytest.approx(np.interp(lf(f_exact), lt, e_tab) / 2, rel=1e-10)
    assert m.energy[j].max() == pytest.approx(1.0, abs=1e-10)
