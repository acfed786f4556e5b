"""Transmitted force (issue 25, part 2) and the scene file's loads: the
force into the base against the momentum of the bodies above it, its
spectrum against the closed form of a tone, third-octave bands, insertion
loss, the command line, and bad loads in a scene file (one line, exit 2)."""

import math
from dataclasses import replace

import numpy as np
import pytest

from flexbed.analyses.transmitted import (db, insertion_loss, spectrum, third_octaves,
                                          transmitted_force)
from flexbed.cli import main
from flexbed.dynamics.rotation import A as rotation_matrix
from flexbed.files.results import read_results
from flexbed.files.scene import load_scene
from scene_text import FIXED_REFERENCE

# equipment A running with an unbalance, on the reference scene with its base held
UNBALANCE = """
[[unbalance]]
name = "pump"
body = "equipment A"
point = [0.1, 0.0, 0.05]
axis = "x"
mass_radius = 0.01
speed = 24.5

[[load]]
name = "gen"
body = "equipment B"
point = [0.0, 0.2, 0.0]
frame = "body"
direction = "z"
shape = "harmonic"
speed = 29.6
order = 2
amplitude = 40.0
"""


def _scene(tmp_path, extra=UNBALANCE, t_end=1.0):
    text = FIXED_REFERENCE.replace("t_end = 3.0", f"t_end = {t_end}") + extra
    path = tmp_path / "machinery.toml"
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def machinery_run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("machinery")
    scene = _scene(tmp)
    results = tmp / "machinery.h5"
    assert main(["simulate", str(scene), "-o", str(results), "--no-progress"]) == 0
    return scene, results


def test_transmitted_force_balances_the_momentum_of_the_bodies_above(machinery_run):
    scene, results = machinery_run
    c = read_results(results)
    tf = transmitted_force(c)
    assert len(tf.mounts) == 4                   # the bed's mounts stand on the base
    sc = load_scene(scene).scene
    m = np.array([b.mass for b in sc.bodies[1:]])
    acc = np.asarray(c.get("bodies/acceleration"))[:, 1:]
    p = np.asarray(c.get("bodies/euler_parameters"))
    t = tf.time
    loads = np.zeros((t.size, 3))
    for ld in sc.loads:
        f = ld.shape.compile().values(t)
        b = sc.body_index(ld.body)
        e = np.zeros((t.size, 3))
        e[:, ld.direction] = f
        if ld.frame == "body":
            e = np.einsum("kij,kj->ki", rotation_matrix(p[:, b]), e)
        loads += e
    g = np.asarray(sc.gravity)
    momentum = (m[None, :, None] * (g[None, None, :] - acc)).sum(axis=1) + loads
    scale = np.max(np.abs(tf.total - tf.total.mean(axis=0)))
    assert scale > 50.0                           # the machinery shakes the base
    assert np.max(np.abs(tf.total - momentum)) < 1e-6 * np.max(np.abs(tf.total))
    # and the sum is the mounts' own: each mount's base-side force, added up
    Fi = np.asarray(c.get("mounts/force_i"))
    assert np.array_equal(tf.total, Fi[:, :4].sum(axis=1))


def test_a_tone_reads_its_rms_and_its_third_octave_band():
    dt, n = 1e-3, 4000
    t = dt * np.arange(n)
    f0, A = 25.0, 3.0                              # on a line: Δf = 0.25 Hz
    x = 100.0 + A * np.sin(2 * np.pi * f0 * t)
    sp = spectrum(t, x)
    j = int(np.argmax(sp.rms[:, 0]))
    assert abs(sp.frequency[j] - f0) < 1e-9
    assert abs(sp.rms[j, 0] - A / math.sqrt(2)) < 1e-12 * A
    assert abs(sp.mean_square[:, 0].sum() - A ** 2 / 2) < 1e-9 * A ** 2
    bands = third_octaves(sp, 1.0, 400.0)
    k = int(np.argmax(bands.rms[:, 0]))
    assert bands.nominal[k] == 25.0
    assert abs(bands.rms[k, 0] - A / math.sqrt(2)) < 1e-9 * A
    assert abs(float(db(A / math.sqrt(2))) - 20 * math.log10(A / math.sqrt(2))) < 1e-12
    # the same tone 10 times weaker: 20 dB of insertion loss in its band
    weak = third_octaves(spectrum(t, 100.0 + 0.1 * A * np.sin(2 * np.pi * f0 * t)), 1.0, 400.0)
    assert abs(insertion_loss(bands, weak)[k, 0] - 20.0) < 1e-9


def test_transmitted_command_prints_bands_and_writes_csv_and_plot(machinery_run, tmp_path,
                                                                  capsys):
    _, results = machinery_run
    code = main(["transmitted", str(results), "--reference", str(results), "--from", "0.5",
                 "--csv", str(tmp_path / "csv"), "--plot", str(tmp_path / "t.png")])
    assert code == 0
    out = capsys.readouterr().out
    assert "third-octave bands" in out and "insertion loss" in out
    assert "25 Hz" in out
    bands = np.loadtxt(tmp_path / "csv" / "bands.csv", delimiter=",", skiprows=1)
    assert np.all(bands[:, -3:] == 0.0)          # a run against itself: no insertion loss
    assert (tmp_path / "t.png").stat().st_size > 10_000


@pytest.mark.parametrize("extra, message", [
    ("[[unbalance]]\nbody = \"equipment A\"\naxis = \"x\"\nmass_radius = 0.01\nspeed = 0.0\n",
     "unbalance 1: speed = 0.0 Hz must be > 0"),
    ("[[unbalance]]\nbody = \"base\"\naxis = \"x\"\nmass_radius = 0.01\nspeed = 20.0\n",
     "unbalance 1: body = 'base' is the base"),
    ("[[load]]\nname = \"f\"\nbody = \"pump\"\ndirection = \"z\"\nshape = \"sinusoid\"\n"
     "amplitude = 1.0\nfrequency = 10.0\n", "load 'f': body = 'pump' is not a body"),
    ("[[load]]\nname = \"f\"\nbody = \"equipment A\"\ndirection = \"z\"\nshape = \"harmonic\"\n"
     "amplitude = 1.0\nspeed = 0\norder = 1\n", "load 'f': speed = 0.0 Hz must be > 0"),
    ("[[load]]\nname = \"off\"\nbody = \"bed\"\npoint = [0.0, 3.0, 0.0]\ndirection = \"z\"\n"
     "shape = \"sinusoid\"\namplitude = 1.0\nfrequency = 10.0\n",
     "load 'off': point = [0.0, 3.0, 0.0] m is off the bed"),
])
def test_bad_loads_in_a_scene_file_are_one_line_and_exit_2(tmp_path, capsys, extra, message):
    scene = _scene(tmp_path, extra)
    scene.write_text(scene.read_text().replace('model = "rigid"', 'model = "flexible"'))
    assert main(["static", str(scene), "-o", str(tmp_path / "eq.h5")]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and "\n" not in err and "Traceback" not in err
    assert not (tmp_path / "eq.h5").exists()


def test_modes_auto_sees_the_loads_on_bodies(tmp_path):
    from flexbed.stages.modes_auto import input_frequency
    sc = load_scene(_scene(tmp_path)).scene          # base held: its inputs are none
    assert not sc.base.drives and not sc.base.loads
    assert input_frequency(replace(sc, loads=()), 1.0) == 0.0
    # at least the generator's order 2, 59.2 Hz (the pump's switch-on at t = 0, a step
    # of its cosine component, spreads to about 100 Hz, as the rule says)
    assert 59.2 <= input_frequency(sc, 1.0) < 150.0


def test_a_load_point_far_from_its_rigid_body_is_warned_about(tmp_path):
    from flexbed.errors import FlexbedWarning
    far = ("[[load]]\nname = \"far\"\nbody = \"equipment A\"\npoint = [0.0, 0.0, 150.0]\n"
           "direction = \"z\"\nshape = \"sinusoid\"\namplitude = 1.0\nfrequency = 10.0\n")
    with pytest.warns(FlexbedWarning, match="load 'far': point = .* from the centre of body "
                                            "'equipment A'"):
        load_scene(_scene(tmp_path, far))
