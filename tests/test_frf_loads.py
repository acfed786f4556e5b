"""A scene's loads as inputs of ``flexbed frf`` and ``flexbed.frf``
(issue 25, part 1), against the closed forms of the body on four mounts of
:mod:`test_modal` (mounts in its centre-of-mass plane, so its bounce, roll
and pitch are single-degree-of-freedom systems):

- a vertical ``[[load]]`` at an off-centre point (p, q): the force into the
  base per newton is ``(k + iωc)/G_z``, ``G = k − mω² + iωc`` (the mounts'
  sums), and the load point's acceleration ``−ω² (1/G_z + q²/G_rx +
  p²/G_ry)`` with the roll and pitch stiffnesses 4 k_z B², 4 k_z A²;
- a moment about x per N m: the roll ``1/G_rx``;
- an ``[[unbalance]]`` spinning about x, per newton of rotating force
  ``cos ωt e_y + sin ωt e_z``: base force ``(k_y + iωc_y)/G_y`` along y and
  ``−i (k_z + iωc_z)/G_z`` along z.
"""

import math

import numpy as np
import pytest

from scene_text import A, B, J1, KY, KZ, M1, one_stage

BETA = 2e-3
P, Q = 0.15, -0.1                     # the load's point [m]
LOADS = f"""
[[load]]
name = "push"
body = "mass"
point = [{P}, {Q}, 0.0]
direction = "z"
shape = "sinusoid"
amplitude = 5.0
frequency = 3.0
start = 1.0

[[load]]
name = "twist"
body = "mass"
quantity = "moment"
direction = "x"
shape = "sinusoid"
amplitude = 1.0
frequency = 3.0
start = 1.0

[[unbalance]]
name = "rotor"
body = "mass"
axis = "x"
mass_radius = 1e-3
speed = 7.0
start = 1.0

[[unbalance]]
name = "spin-up"
body = "mass"
axis = "z"
mass_radius = 1e-3
speed = [0.0, 7.0]
runup = 2.0
start = 1.0
"""


@pytest.fixture(scope="module")
def scene_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("loads") / "loaded.toml"
    path.write_text(one_stage(BETA) + LOADS)
    return path


@pytest.fixture(scope="module")
def scene(scene_path):
    import flexbed
    return flexbed.load_scene(scene_path)


def _G(om, k, inertia):
    return k * (1 + 1j * om * BETA) - inertia * om**2


def _closed_forms(f):
    om = 2 * math.pi * np.asarray(f, dtype=float)
    return om, _G(om, 4 * KZ, M1), _G(om, 4 * KZ * B**2, J1[0]), _G(om, 4 * KZ * A**2, J1[1])


FREQ = np.array([0.5, 3.0, 5.03, 5.04, 8.0, 25.0])     # Hz, through the 5.03 Hz bounce


def test_a_load_at_an_off_centre_point_against_the_closed_form(scene):
    import flexbed
    t = flexbed.frf(scene, input="load push", points=[("at load", "mass", [P, Q, 0.0]),
                                                      ("c", "mass", [0, 0, 0])],
                    frequencies=FREQ)
    om, Gz, Grx, Gry = _closed_forms(FREQ)
    kz = 4 * KZ * (1 + 1j * om * BETA)
    np.testing.assert_allclose(t.H[:, t.column("base FZ")], kz / Gz, rtol=1e-9)
    assert np.max(np.abs(t.H[:, [t.column("base FX"), t.column("base FY")]])) < 1e-9
    np.testing.assert_allclose(t.H[:, t.column("c az")], -om**2 / Gz, rtol=1e-9)
    np.testing.assert_allclose(t.H[:, t.column("at load az")],
                               -om**2 * (1 / Gz + Q**2 / Grx + P**2 / Gry), rtol=1e-9)
    assert t.units[t.column("base FZ")] == "1"
    assert t.units[t.column("c az")] == "m/s^2/N"
    assert "load 'push'" in t.input


def test_a_moment_load_is_per_newton_metre(scene):
    import flexbed
    y0 = 0.2
    t = flexbed.frf(scene, input="load twist", points=[("edge", "mass", [0, y0, 0])],
                    frequencies=FREQ, quantity="displacement")
    _, _, Grx, _ = _closed_forms(FREQ)
    np.testing.assert_allclose(t.H[:, t.column("edge dz")], y0 / Grx, rtol=1e-9)
    assert t.units[t.column("edge dz")] == "m/(N m)"
    assert t.units[t.column("base FZ")] == "N/(N m)"


def test_an_unbalance_is_per_newton_of_its_rotating_force(scene):
    import flexbed
    t = flexbed.frf(scene, input="load rotor", points=[("c", "mass", [0, 0, 0])], frequencies=FREQ)
    om, Gz, _, _ = _closed_forms(FREQ)
    Gy = _G(om, 4 * KY, M1)
    np.testing.assert_allclose(t.H[:, t.column("base FY")],
                               4 * KY * (1 + 1j * om * BETA) / Gy, rtol=1e-9)
    np.testing.assert_allclose(t.H[:, t.column("base FZ")],
                               -1j * 4 * KZ * (1 + 1j * om * BETA) / Gz, rtol=1e-9)
    assert np.max(np.abs(t.H[:, t.column("base FX")])) < 1e-9


def test_the_command_writes_the_load_frf_and_the_force_at_the_running_speed(scene_path,
                                                                            tmp_path, capsys):
    from flexbed.cli import main
    prefix = tmp_path / "push"
    assert main(["frf", str(scene_path), "--input", "load rotor", "-o", str(prefix),
                 "--band", "1,40", "-n", "40", "--no-plots"]) == 0
    out = capsys.readouterr().out
    # at 7 Hz: m e Ω² = 1.934 N, and the base force along z is |k_z + iωc_z|/|G_z| of it
    om, Gz, _, _ = _closed_forms([7.0])
    F = 1e-3 * om[0]**2
    Fz = F * abs(4 * KZ * (1 + 1j * om[0] * BETA) / Gz[0])
    assert f"FZ {Fz:.4g} N" in out
    assert f"({20 * math.log10(Fz / math.sqrt(2)):.1f} dB re 1 N RMS)" in out
    lines = (tmp_path / "push.csv").read_text().splitlines()
    head = lines[0].split(",")
    data = np.array([[float(v) for v in row.split(",")] for row in lines[1:]])
    f = data[:, 0]
    om, Gz, _, _ = _closed_forms(f)
    j = head.index("base FZ |H| [1]")
    # the CSV's 10 digits of frequency, times |H|'s slope (~1/ζ) at a ζ = 3 % resonance
    np.testing.assert_allclose(data[:, j], np.abs(4 * KZ * (1 + 1j * om * BETA) / Gz),
                               rtol=1e-8)
    assert (tmp_path / "push.h5").exists()


@pytest.mark.parametrize("argv_tail, message", [
    (["--input", "load pump"], "has no [[load]] or [[unbalance]] named 'pump' (loads: push, "
                               "twist; unbalances: rotor, spin-up)"),
    (["--input", "load spin-up"], "unbalance 'spin-up' runs up"),
    (["--input", "load"], "expected 'load NAME'"),
    (["--input", "load push", "--force-at", "mass:0,0,0"], "applies to --input force only"),
])
def test_bad_load_inputs_are_one_line_exit_2_nothing_written(scene_path, tmp_path, capsys,
                                                             argv_tail, message):
    from flexbed.cli import main
    assert main(["frf", str(scene_path), "-o", str(tmp_path / "bad")] + argv_tail) == 2
    err = capsys.readouterr().err
    assert message in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert not list(tmp_path.iterdir())


def test_the_api_refuses_an_unknown_load_in_one_line(scene):
    import flexbed
    from flexbed.errors import InputError
    with pytest.raises(InputError, match=r"flexbed.frf: input = 'load pump': loaded.toml has "
                                         r"no \[\[load\]\]") as exc:
        flexbed.frf(scene, input="load pump")
    assert "\n" not in str(exc.value)
    with pytest.raises(InputError, match="force_at"):
        flexbed.frf(scene, input="load push", force_at=("mass", [0, 0, 0]))


def test_a_load_and_the_same_force_input_agree(scene):
    """The load's generalized force from the right-hand side and a force
    input's from the point's Jacobian are the same column (measured: 2e-9
    of each output's largest, the load's column being a difference of two
    right-hand sides at the loaded equilibrium)."""
    import flexbed
    a = flexbed.frf(scene, input="load push", frequencies=FREQ)
    b = flexbed.frf(scene, input="force z", force_at=("mass", [P, Q, 0.0]), frequencies=FREQ)
    assert a.names == b.names
    top = np.abs(b.H).max(axis=0)
    assert np.all(np.abs(a.H - b.H) <= 1e-8 * top)
