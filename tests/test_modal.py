"""The mounted system's modes and transmissibility against closed forms.

A body on four mounts at its centre of mass's height, symmetric about its
principal axes, has its elastic centre at the centre of mass: six
uncoupled modes with K = diag(4kx, 4ky, 4kz, 4kz b², 4kz a², 4(kx b² + ky a²))
(the mounts' axes fixed in the base: the preload adds no stiffness), and
with dampers c = β k each mode has ζ = β ω / 2 exactly. Two such stages
stacked give the 2-DOF vertical isolator.
"""

import math

import numpy as np
import pytest

from scene_text import (A, B, J1, KX, KY, KZ, M1, base_and_body, isolator_mounts, load_text,
                        one_stage)

M2 = 20.0                           # the second stage's mass [kg]


def _two_stage(beta):
    top = f"""
[[body]]
name = "top"
mass = {M2}
inertia = [0.5, 0.6, 0.7]
position = [0.0, 0.0, 1.0]
"""
    return (base_and_body("two stages", mass=M1, inertia=f"[{J1[0]}, {J1[1]}, {J1[2]}]")
            + top + isolator_mounts("L", "base", "mass", 0.5, (KX, KY, KZ), beta)
            + isolator_mounts("U", "mass", "top", 0.5, (0.5 * KX, 0.5 * KY, 0.4 * KZ), beta))


def _diagonal(energy):
    """Each mode's largest kinetic-energy share and the coordinate it is in."""
    return energy.max(axis=1), energy.argmax(axis=1)


def test_one_stage_isolator_against_closed_forms(tmp_path):
    """Frequencies, damping ratios, a decoupled energy table (100 % on the
    diagonal to 1e-10), effective masses, the vertical transmissibility
    T = (k + iωc)/(k − mω² + iωc) and, under a force on the body, the
    accelerance −ω²/(k − mω² + iωc) and the force transmitted to the base,
    to 1e-10."""
    import flexbed
    beta = 2e-3
    scene = load_text(tmp_path, one_stage(beta))
    m = flexbed.modal(scene)
    k = np.array([4 * KX, 4 * KY, 4 * KZ, 4 * KZ * B**2, 4 * KZ * A**2,
                  4 * (KX * B**2 + KY * A**2)])
    inertia = np.array([M1, M1, M1, *J1])
    w = np.sqrt(k / inertia)
    share, where = _diagonal(m.energy)
    assert np.all(share > 1 - 1e-10)
    assert sorted(where) == list(range(6))
    order = np.argsort(w)
    assert list(where) == list(order)
    # translations exactly; the rotations' columns carry central differences' O(1e-12)
    np.testing.assert_allclose(m.frequency[where < 3], w[where[where < 3]] / (2 * math.pi),
                               rtol=1e-10)
    np.testing.assert_allclose(m.frequency, w[where] / (2 * math.pi), rtol=1e-8)
    np.testing.assert_allclose(m.damping_ratio[where < 3], beta * w[where[where < 3]] / 2,
                               rtol=1e-10)
    np.testing.assert_allclose(m.damping_ratio, beta * w[where] / 2, rtol=1e-8)
    # effective mass: each translation mode carries the whole mass along its axis
    np.testing.assert_allclose(m.effective_mass.sum(axis=0), M1, rtol=1e-12)
    assert m.moving_mass == pytest.approx(M1, rel=1e-14)
    for axis in range(3):
        mode = int(np.flatnonzero(np.argmax(m.energy, axis=1) == axis)[0])
        undamped = int(np.argmin(np.abs(m.undamped_frequency - m.frequency[mode])))
        assert m.effective_mass[undamped, axis] == pytest.approx(M1, rel=1e-10)
    # transmissibility, magnitude and phase, around and at the resonance
    f = np.array([1.0, 0.5 * w[2], 0.99 * w[2], w[2], 1.01 * w[2], 3.0 * w[2]]) / (2 * math.pi)
    t = flexbed.frf(scene, input="base z", points=[("c", "mass", [0, 0, 0])], frequencies=f)
    om = 2 * math.pi * f
    kz, cz = 4 * KZ, 4 * beta * KZ
    exact = (kz + 1j * om * cz) / (kz - M1 * om**2 + 1j * om * cz)
    H = t.H[:, t.column("c az")]
    np.testing.assert_allclose(np.abs(H), np.abs(exact), rtol=1e-10)
    np.testing.assert_allclose(np.angle(H), np.angle(exact), rtol=1e-10, atol=1e-12)
    assert np.all(np.abs(t.H[:, t.column("c ax")]) < 1e-9 * np.abs(H))
    # the force on the base is the body's inertia force: −m a, per unit base acceleration
    np.testing.assert_allclose(t.H[:, t.column("base FZ")], -M1 * H, rtol=1e-10)
    iso = t.isolation[:, t.column("c az")]
    assert np.isnan(iso[0]) and iso[-1] == pytest.approx(1 - abs(exact[-1]), rel=1e-10)
    # the vertical mode strains the four mounts' third axes alone, equally
    vert = int(np.flatnonzero(where == 2)[0])
    np.testing.assert_allclose(m.strain_mounts[vert][:, 2], 0.25, rtol=1e-10)
    assert m.strain_mounts[vert][:, :2].max() < 1e-12 and m.strain_elastic[vert] == 0.0
    # the grid finds the peak of |T|, ωₚ = ωₙ √(√(1 + 8ζ²) − 1) / (2ζ), to 0.1 % of 2ζfₙ
    z = beta * w[2] / 2
    fp = w[2] * math.sqrt(math.sqrt(1 + 8 * z**2) - 1) / (2 * z) / (2 * math.pi)
    t = flexbed.frf(scene, points=[("c", "mass", [0, 0, 0])], band=(1.0, 40.0), n=60)
    peaks = t.peaks[t.peaks[:, 0] == t.column("c az")]
    assert peaks.shape[0] == 1
    assert abs(peaks[0, 1] - fp) <= 0.5e-3 * 2 * z * w[2] / (2 * math.pi)
    # a unit force on the body: accelerance −ω²/G and force transmissibility (k + iωc)/G
    t = flexbed.frf(scene, input="force z", force_at=("mass", [0.0, 0.0, 0.0]),
                    points=[("c", "mass", [0, 0, 0])], frequencies=f)
    G = kz - M1 * om**2 + 1j * om * cz
    np.testing.assert_allclose(t.H[:, t.column("c az")], -om**2 / G, rtol=1e-10)
    np.testing.assert_allclose(t.H[:, t.column("base FZ")], (kz + 1j * om * cz) / G, rtol=1e-10)


def test_two_stage_isolator_against_closed_forms(tmp_path):
    """The vertical modes of two stacked stages: ω² from det(K − ω²M) = 0,
    ζ = βω/2, and the top's transmissibility from the 2×2 solve, to 1e-10."""
    import flexbed
    beta = 1e-3
    scene = load_text(tmp_path, _two_stage(beta))
    m = flexbed.modal(scene)
    k1, k2 = 4 * KZ, 4 * 0.4 * KZ
    K = np.array([[k1 + k2, -k2], [-k2, k2]])
    Mm = np.diag([M1, M2])
    w2 = np.linalg.eigvalsh(np.linalg.solve(np.sqrt(Mm), np.linalg.solve(np.sqrt(Mm), K).T))
    w = np.sqrt(w2)
    iz = [m.labels.index("mass z"), m.labels.index("top z")]
    vertical = np.flatnonzero(m.energy[:, iz].sum(axis=1) > 1 - 1e-10)
    assert vertical.size == 2
    np.testing.assert_allclose(m.frequency[vertical], w / (2 * math.pi), rtol=1e-10)
    np.testing.assert_allclose(m.damping_ratio[vertical], beta * w / 2, rtol=1e-10)
    f = np.array([0.5, 0.9, 1.0, 1.1, 2.0, 4.0]) * w[0] / (2 * math.pi)
    f = np.concatenate([f, [w[1] / (2 * math.pi)]])
    t = flexbed.frf(scene, points=[("t", "top", [0, 0, 0])], frequencies=f)
    om = 2 * math.pi * f
    c1, c2 = beta * k1, beta * k2
    z1, z2 = k1 + 1j * om * c1, k2 + 1j * om * c2
    exact = z1 * z2 / ((z1 + z2 - M1 * om**2) * (z2 - M2 * om**2) - z2**2)
    H = t.H[:, t.column("t az")]
    np.testing.assert_allclose(np.abs(H), np.abs(exact), rtol=1e-10)
    np.testing.assert_allclose(np.angle(H), np.angle(exact), rtol=1e-10, atol=1e-12)
    assert m.effective_mass.sum(axis=0) == pytest.approx([M1 + M2] * 3, rel=1e-12)


def test_reference_scene_couples_and_effective_masses_sum():
    """The reference scene (rigid bed): the equipment's mounts (45° on A,
    upright on B) sit 0.15 m below their centres of mass, so x couples with
    pitch and y with roll (two modes each share ≥ 5 % of both); the bed's
    own translations stay above 89 %; the effective masses add up to the
    moving mass, 2995.2 + 2 × 100 kg."""
    import flexbed
    m = flexbed.modal(flexbed.load_scene())
    lab = m.labels
    for body in ("equipment A", "equipment B"):
        for a, b in (("x", "pitch"), ("y", "roll")):
            both = (m.energy[:, lab.index(f"{body} {a}")] > 0.05) & \
                (m.energy[:, lab.index(f"{body} {b}")] > 0.05)
            assert both.sum() >= (2 if a == "x" else 1), (body, a, b)
    assert np.sum(m.energy.max(axis=1) < 0.9) >= 6
    for d in ("x", "y", "z"):
        assert m.energy[:, lab.index(f"bed {d}")].max() > 0.89
    np.testing.assert_allclose(m.effective_mass.sum(axis=0), 3195.2, rtol=1e-10)
    np.testing.assert_allclose(m.energy.sum(axis=1), 1.0, rtol=1e-12)
    assert m.cumulative_mass[-1] == pytest.approx([1.0, 1.0, 1.0], rel=1e-10)


def _fit(t, a, omega):
    """α + iβ of a(t) ≈ α sin ωt + β cos ωt + γ + δ t (least squares; the
    drift: the base's velocity has a mean)."""
    X = np.column_stack([np.sin(omega * t), np.cos(omega * t), np.ones_like(t), t])
    c = np.linalg.lstsq(X, a, rcond=None)[0]
    return c[0] + 1j * c[1]


def test_frf_is_the_steady_state_of_the_time_paths(tmp_path):
    """Under a base acceleration A sin ωt (8 Hz) the steady state of the
    linear time path equals Im(H A e^{iωt}) (positions: −H A/ω²) (all modes damped, ζ ≥ 0.2, so
    the samples after 2 s keep e^-19 of the transient), and the nonlinear run's tends to it
    as the amplitude falls (mounts 0.1 m below the centre of mass: the
    rotations' geometry makes the difference, O(A²) relative: 3e-5 at
    50 m/s², 3e-7 at 5 m/s²)."""
    import flexbed
    beta, f = 1.2e-2, 8.0
    omega = 2 * math.pi * f
    text = one_stage(beta, axes="axes_deg = [30.0, 0.0, 0.0]\n", z_j=-0.1)
    solver = """
[base]
motion = "driven"

[[base.drive]]
direction = "z"
shape = "sinusoid"
amplitude = AMP
frequency = 8.0

[solver]
t_end = 3.0
output_dt = 0.001
rtol = 1e-11
atol = 1e-13
"""
    t = None
    errors = []
    for amp in (50.0, 5.0):
        scene = load_text(tmp_path, text + solver.replace("AMP", str(amp)), f"a{amp}.toml")
        if t is None:
            m = flexbed.modal(scene)
            assert np.all(m.damping_ratio > 0.2)
            tr = flexbed.frf(scene, points=[("c", "mass", [0, 0, 0])], frequencies=[f])
            H = tr.H[0, [tr.column(f"c a{c}") for c in "xyz"]]
            assert abs(H[1]) > 0.05 * abs(H[2])          # y and z coupled by the 30° axes
            lin = flexbed.simulate(scene, model="linear")
            t = lin.t
            tail = t >= 2.0
            # positions: the linear path's own (its accelerations are the
            # nonlinear right-hand side's at its states)
            got = np.array([_fit(t[tail], lin.position[tail, 1, k], omega) for k in range(3)])
            np.testing.assert_allclose(got, -amp * H / omega**2, rtol=1e-7,
                                       atol=1e-9 * amp / omega**2)
        run = flexbed.simulate(scene, model="nonlinear", integrator="dop853")
        tail = run.t >= 2.0
        got = np.array([_fit(run.t[tail], run.acceleration[tail, 1, k], omega)
                        for k in range(3)])
        errors.append(np.abs(got - amp * H).max() / (amp * np.abs(H).max()))
    assert errors[1] < 1e-6
    assert errors[1] < 0.02 * errors[0]                  # O(A²): 1/100 for A/10


def test_flexible_bed_tends_to_the_rigid_bed_as_its_stiffness_grows():
    """The reference scene with a 6-mode flexible bed whose modal stiffness
    is scaled by s (E → sE: the plate's K is linear in E, its M is not):
    the 18 mounted-system frequencies tend to the rigid bed's as 1/s, and
    the effective masses still add up to the moving mass."""
    import dataclasses

    import flexbed
    from flexbed.analyses.modal import mounted
    from flexbed.dynamics.system import System
    from flexbed.stages.system import compile_scene
    scene = flexbed.load_scene()
    rigid = flexbed.modal(scene).undamped_frequency
    flex = flexbed.vary(scene, {"bed.model": "flexible", "bed.modes": 6,
                                "bed.rayleigh": [0.0, 0.0]})
    data = flexbed.modes(flex)
    base = compile_scene(flex, modes=data).scene
    bed = base.bodies[1].name
    errors = []
    for s in (1e2, 1e3, 1e4):
        bodies = tuple((k, dataclasses.replace(v, modal_stiffness=s * v.modal_stiffness)
                        if k == bed else v) for k, v in base.flexible)
        mt = mounted(flex, System(dataclasses.replace(base, flexible=bodies)), bed_modes=data)
        md = mt.modes
        errors.append(np.abs(md.undamped_frequency[:18] / rigid - 1.0).max())
        np.testing.assert_allclose(md.effective_mass.sum(axis=0), 3195.2, rtol=1e-10)
        assert np.all(md.undamped_frequency[18:] > 100 * rigid[-1] / 10)
    assert errors[-1] < 1e-5
    assert 9.0 < errors[1] / errors[2] < 11.0                 # first order in 1/s
    # the mode shapes for ParaView: the bed's mesh deforms in its own modes
    from flexbed.analyses.mode_shapes import mode_shape_meshes
    bed_mesh = mode_shape_meshes(flex, mt)[0]
    assert bed_mesh.name == bed and bed_mesh.nodes.shape == data.nodes.shape
    x = np.column_stack([np.ones(len(bed_mesh.nodes)), bed_mesh.nodes[:, :2]])
    for k in (0, 18):
        w = bed_mesh.displacement[k, :, 2]
        rest = w - x @ np.linalg.lstsq(x, w, rcond=None)[0]      # all but a rigid tilt
        assert (np.abs(rest).max() > 0.1) == (k == 18), k


@pytest.mark.slow
def test_modal_and_frf_commands_write_their_files(tmp_path):
    """``flexbed static``, ``modal --equilibrium`` and ``frf`` on the
    one-stage isolator: the files, their schemas, the CSV columns, a
    relative point; bad options are one-line input errors (exit 2)."""
    from flexbed.cli import main
    from flexbed.files.store import read_file
    scene = tmp_path / "iso.toml"
    scene.write_text(one_stage(2e-3))
    eq = tmp_path / "eq.h5"
    assert main(["static", str(scene), "-o", str(eq)]) == 0
    assert main(["modal", str(scene), "--equilibrium", str(eq), "-o",
                 str(tmp_path / "m"), "--no-plots"]) == 0
    c = read_file(tmp_path / "m.h5", schema="flexbed.modal", major=1)
    assert c.get("energy/kinetic").shape == (6, 6)
    assert c.attrs[""]["equilibrium_source"] == str(eq)
    import xml.etree.ElementTree as ET
    shapes = read_file(tmp_path / "m-shapes.h5", schema="flexbed.mode_shapes", major=1)
    fields = [e.text.split(":/")[1] for e in ET.parse(tmp_path / "m-shapes.xdmf").iter("DataItem")]
    assert len(fields) == 2 + 6 and all(f in shapes.datasets for f in fields)
    assert shapes.get("bodies/0/cells").shape == (1, 8)          # the body as its box
    rows = (tmp_path / "m-effective-mass.csv").read_text().splitlines()
    assert rows[0].startswith("mode,frequency_Hz,mass_X_kg") and len(rows) == 7
    assert main(["frf", str(scene), "-o", str(tmp_path / "f"), "--band", "1,40", "-n", "50",
                 "--point", "edge=mass:0.2,0.3,0", "--relative-to", "base"]) == 0
    c = read_file(tmp_path / "f.h5", schema="flexbed.frf", major=1)
    names = [str(n) for n in c.get("outputs/names")]
    assert names[:3] == ["edge@base ax", "edge@base ay", "edge@base az"]
    assert "base FZ" in names and "M4 f3" in names
    f = np.asarray(c.get("frequency"))
    assert f[0] == pytest.approx(1.0) and f[-1] == pytest.approx(40.0) and f.size > 50
    assert (tmp_path / "f-bode.png").stat().st_size > 0
    header = (tmp_path / "f.csv").read_text().splitlines()[0]
    assert header.startswith("frequency_Hz,edge@base ax |H| [1],edge@base ax phase [deg]")
    assert main(["frf", str(scene), "--input", "force z", "-o", str(tmp_path / "g")]) == 2
    assert main(["frf", str(scene), "--band", "5,1", "-o", str(tmp_path / "g")]) == 2


def test_table_rows_are_the_values_formatted_one_by_one():
    """The modal tables' rows (one ``%`` over a row) are exactly each value's
    ``format(v, fmt)``: signs of zero, infinities, NaN, subnormals, every
    magnitude."""
    from flexbed.analyses.modal import _row
    rng = np.random.default_rng(1)
    v = np.concatenate([rng.normal(size=500) * 10.0 ** rng.integers(-30, 30, 500),
                        [0.0, -0.0, np.inf, -np.inf, np.nan, 1e300, 5e-324, 123456789012.5]])
    for fmt in (".8f", ".10g", ".12g", ".6f"):
        assert _row(v, fmt) == ",".join(format(float(x), fmt) for x in v), fmt
    assert _row([], ".8f") == ""
