"""Initial velocities from the scene file (``[[body]] velocity`` and
``angular_velocity``): a torque-free symmetric top against its closed form,
a body launched on linear mounts against x(t) = v0/ω sin ωt (nonlinear
integrator and linear fast path, from the static equilibrium), a free base
drifting, the flexible bed's frame, and the refusals."""


import numpy as np
import pytest

from flexbed.cli import main as flexbed
from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.linear import run_linear
from flexbed.dynamics.rotation import A as rotation_matrix
from flexbed.dynamics.statics import solve_statics
from flexbed.errors import InputError
from flexbed.files.results import read_results
from flexbed.files.scene import builtin_scene_path, load_scene
from flexbed.stages.modes import ensure_modes
from flexbed.stages.system import compile_scene
from scene_text import base_and_body, four_mounts

TOP = """
[scene]
name = "top"
gravity = [0.0, 0.0, 0.0]

[[body]]
name = "ground"
mass = 1.0
inertia = [1.0, 1.0, 1.0]
position = [0.0, 0.0, 0.0]

[[body]]
name = "top"
mass = 3.0
inertia = [2.0, 2.0, 3.5]
position = [0.1, 0.2, 1.0]
orientation_deg = [10.0, -20.0, 30.0]
velocity = [0.3, -0.2, 0.1]
angular_velocity = [1.0, 0.5, 10.0]

[solver]
t_end = 10.0
integrator = "dop853"
rtol = 1.0e-12
atol = 1.0e-12
output_dt = 0.01
start = "initial"
"""


def test_symmetric_top_from_a_scene_file_spins_as_the_closed_form(tmp_path):
    """J = diag(A, A, C), A = 2, C = 3.5 kg m², ω̄0 = (1, 0.5, 10) rad/s, no
    torque: ω̄3 constant, (ω̄1, ω̄2) turning at Ω = (C − A)/A ω̄3 = 7.5 rad/s in
    the body frame; the centre of mass moves at the given velocity; kinetic
    energy and the inertial angular momentum constant. Measured over 10 s
    with dop853 at rtol 1e-12 through `flexbed simulate`: ω̄ within 3.3e-11
    rad/s, positions within 1.8e-15 m, energy and |ΔL| within 1.4e-13 and
    2.5e-12 relative."""
    scene = tmp_path / "top.toml"
    scene.write_text(TOP)
    out = tmp_path / "top.h5"
    assert flexbed(["simulate", str(scene), "-o", str(out), "--no-progress"]) == 0
    c = read_results(out)
    t = c.get("time")
    w = c.get("bodies/angular_velocity")[:, 1]
    A, C = 2.0, 3.5
    w0 = np.array([1.0, 0.5, 10.0])
    Om = (C - A) / A * w0[2]
    exact = np.column_stack([w0[0] * np.cos(Om * t) - w0[1] * np.sin(Om * t),
                             w0[0] * np.sin(Om * t) + w0[1] * np.cos(Om * t),
                             np.full_like(t, w0[2])])
    err_w = np.abs(w - exact).max()
    r = c.get("bodies/position")[:, 1]
    err_r = np.abs(r - (np.array([0.1, 0.2, 1.0]) + np.outer(t, [0.3, -0.2, 0.1]))).max()
    Jw = w * np.array([A, A, C])
    L = np.einsum("kij,kj->ki", rotation_matrix(c.get("bodies/euler_parameters")[:, 1]), Jw)
    T = c.get("energy/kinetic")[:, 1]
    err_L = np.abs(L - L[0]).max() / np.linalg.norm(L[0])
    err_T = np.abs(T - T[0]).max() / T[0]
    print(f"top: |ω − exact| {err_w:.2e} rad/s, |r − exact| {err_r:.2e} m, "
          f"ΔT/T {err_T:.2e}, |ΔL|/|L| {err_L:.2e}")
    assert T[0] == pytest.approx(0.5 * 3.0 * 0.14 + 0.5 * (A * 1.25 + C * 100.0), rel=1e-14)
    assert err_w < 5e-10 and err_r < 1e-13 and err_T < 2e-12 and err_L < 3e-11


LAUNCH = base_and_body("launch", body_extra="velocity = [0.2, -0.1, -0.5]\n") + """

[solver]
t_end = 0.3
integrator = "dop853"
rtol = 1.0e-11
atol = 1.0e-13
output_dt = 1.0e-3
""" + four_mounts("""
law = "linear"
k = [5.0e4, 7.5e4, 1.25e5]
""", corners=[(-0.2, -0.3), (0.2, -0.3), (-0.2, 0.3), (0.2, 0.3)], prefix="S")

K_LAUNCH = np.array([5.0e4, 7.5e4, 1.25e5])
V_LAUNCH = np.array([0.2, -0.1, -0.5])


@pytest.fixture(scope="module")
def launched(tmp_path_factory):
    path = tmp_path_factory.mktemp("launch") / "launch.toml"
    path.write_text(LAUNCH)
    return path


@pytest.mark.parametrize("model", ["nonlinear", "linear"])
def test_body_launched_on_linear_mounts_oscillates_as_the_closed_form(launched, model):
    """Four linear mounts in the plane of the centre of mass (no rotation):
    from the static equilibrium with the scene's velocity v0, each axis
    moves as x(t) = v0/ω sin ωt, ω = √(4k/m) (63, 77 and 100 rad/s).
    Through `flexbed simulate` (start = "equilibrium", the default): the
    nonlinear integrator (dop853, rtol 1e-11) within 7.2e-13 m, the linear
    fast path within 1.9e-12 m (its Jacobian by central differences),
    measured, of an amplitude of 3.2 mm."""
    out = launched.parent / f"{model}.h5"
    assert flexbed(["simulate", str(launched), "-o", str(out), "--model", model,
                    "--no-progress"]) == 0
    c = read_results(out)
    assert c.attrs["solver"]["model"] == model
    t = c.get("time")
    r = c.get("bodies/position")[:, 1]
    omega = np.sqrt(4 * K_LAUNCH / 50.0)
    exact = r[0] + np.sin(np.outer(t, omega)) * (V_LAUNCH / omega)
    err = np.abs(r - exact).max()
    print(f"{model}: max |x − v0/ω sin ωt| {err:.2e} m "
          f"(amplitude {np.max(V_LAUNCH / omega):.3g} m)")
    assert np.allclose(c.get("bodies/velocity")[0, 1], V_LAUNCH, rtol=0, atol=1e-15)
    assert abs(r[0, 2] - (0.5 - 9.81 * 50.0 / (4 * 1.25e5))) < 1e-12     # the equilibrium
    assert err < 2e-11


def test_linear_fast_path_starts_from_the_initial_velocities(launched):
    """run_linear (the linear fast path) takes y0 with the velocities and
    gives the same motion as the nonlinear integrator, within 1e-12 m."""
    sf = load_scene(launched)
    system = compile_scene(sf)
    eq = solve_statics(system, tol=1e-10)
    y0 = system.initial_state(eq.y)
    assert np.array_equal(y0[:system.layout.nq], eq.y[:system.layout.nq])
    st = Settings("dop853", t_end=0.1, rtol=1e-11, atol=1e-13, output_dt=1e-3)
    lin = run_linear(system, eq.y, y0, st).run
    ref = integrate(system, y0, st)
    lay = system.layout
    assert np.abs(lin.y[:, lay.q_rigid] - ref.y[:, lay.q_rigid]).max() < 1e-12
    assert np.abs(lin.y[:, lay.v_rigid] - ref.y[:, lay.v_rigid]).max() < 1e-10


def _write(tmp_path, text, name="s.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_free_base_drifts_at_its_velocity(tmp_path):
    """A free base and its body given the same velocity, no gravity and no
    loads: everything translates at that velocity, the mounts stay
    unstrained (exactly: the motion is a uniform translation)."""
    text = LAUNCH.replace('gravity = [0.0, 0.0, -9.81]', 'gravity = [0.0, 0.0, 0.0]')
    text = text.replace('position = [0.0, 0.0, 0.0]\n',
                        'position = [0.0, 0.0, 0.0]\nvelocity = [0.2, -0.1, -0.5]\n', 1)
    text += '\n[base]\nmotion = "free"\n'
    sf = load_scene(_write(tmp_path, text))
    system = compile_scene(sf)
    y0 = system.initial_state()
    run = integrate(system, y0, Settings("dop853", t_end=2.0, rtol=1e-10, atol=1e-12,
                                         output_dt=0.01))
    parts = system.layout.split(run.y)
    drift = np.outer(run.t, V_LAUNCH)
    assert np.abs(parts["r_base"] - drift).max() < 1e-13
    assert np.abs(parts["r"][:, 0] - (np.array([0.0, 0.0, 0.5]) + drift)).max() < 1e-13


@pytest.mark.parametrize("motion,key,value,says", [
    ("fixed", "velocity", "[0.0, 0.0, 1.0]", "needs base motion = 'free'"),
    ("driven", "velocity", "[1.0, 0.0, 0.0]", "needs base motion = 'free'"),
    ("free", "angular_velocity", "[0.0, 0.0, 1.0]", "orientation is locked"),
])
def test_base_velocity_refused_unless_free(tmp_path, motion, key, value, says):
    text = LAUNCH.replace('position = [0.0, 0.0, 0.0]\n',
                          f'position = [0.0, 0.0, 0.0]\n{key} = {value}\n', 1)
    text += f'\n[base]\nmotion = "{motion}"\n'
    with pytest.raises(InputError) as exc:
        load_scene(_write(tmp_path, text))
    msg = str(exc.value)
    assert msg.startswith("s.toml: body 'base': ") and key in msg and says in msg
    assert value.replace(".0", "") in msg.replace(".0", "")


@pytest.mark.parametrize("value,says", [("[1.0, 2.0]", "must have 3 numbers"),
                                        ("[1.0, \"a\", 2.0]", "must be a number"),
                                        ("3.0", "must be a list of numbers")])
def test_bad_velocity_refused_with_file_entry_and_value(tmp_path, value, says):
    text = LAUNCH.replace("velocity = [0.2, -0.1, -0.5]", f"velocity = {value}")
    with pytest.raises(InputError) as exc:
        load_scene(_write(tmp_path, text))
    msg = str(exc.value)
    assert msg.startswith("s.toml: body 'mass': velocity") and says in msg


def test_flexible_bed_gets_its_frame_velocities_and_zero_modal_rates(tmp_path):
    """The bed's velocity and angular velocity go to its floating frame; the
    modal rates start at zero, from the scene's positions or from the
    equilibrium alike."""
    text = builtin_scene_path().read_text().replace('model = "rigid"', 'model = "flexible"')
    text = text.replace('name = "bed"', 'name = "bed"\nvelocity = [0.0, 0.01, -0.02]\n'
                                        'angular_velocity = [0.003, 0.0, 0.001]')
    sf = load_scene(_write(tmp_path, text, "flex.toml"))
    ensure_modes(sf, tmp_path / "flex-modes.h5", log=lambda m: None)
    system = compile_scene(sf, tmp_path / "flex-modes.h5")
    lay = system.layout
    eq = solve_statics(system, tol=1e-6)
    assert eq.success
    for y in (system.initial_state(), system.initial_state(eq.y)):
        parts = lay.split(y)
        assert np.array_equal(parts["rd"][0], [0.0, 0.01, -0.02])
        assert np.array_equal(parts["w"][0], [0.003, 0.0, 0.001])
        assert not np.any(parts["rd"][1:]) and not np.any(parts["w"][1:])
        assert parts["ad"].size == 2 and not np.any(parts["ad"])
        assert not np.any(y[lay.work])
    assert np.any(lay.split(eq.y)["a"])        # the sag is kept
    assert np.array_equal(lay.split(system.initial_state(eq.y))["a"], lay.split(eq.y)["a"])


def test_python_api_starts_with_the_scenes_velocities(launched):
    """flexbed.simulate (the shared simulation stage) from the equilibrium
    and from the initial positions, and a variant's velocity by vary."""
    import flexbed
    sf = flexbed.load_scene(launched)
    omega = np.sqrt(4 * K_LAUNCH / 50.0)
    for start in ("equilibrium", "initial"):
        res = flexbed.simulate(sf, start=start, t_end=0.05, output_dt=1e-3)
        assert np.array_equal(res.velocity[0, 1], V_LAUNCH)
    fast = flexbed.vary(sf, {"body.mass.velocity": [0.0, 0.0, 1.0]})
    res = flexbed.simulate(fast, t_end=0.05, output_dt=1e-3)
    z = res.position[:, 1, 2] - res.position[0, 1, 2]
    assert np.abs(z - np.sin(omega[2] * res.t) / omega[2]).max() < 1e-10
