"""``shape = "sawtooth"``: the terminal-peak sawtooth of shock standards
(linear rise to the peak, instantaneous drop). Its exact integrals, the
drop as a breakpoint with one-sided limits, a driven base's motion against
the closed form, a 1-DOF isolator against the closed-form (Duhamel)
response with rk4, dop853, radau and the linear fast path, and the scene
file's rules."""

import math

import numpy as np
import pytest

from flexbed.cli import main as flexbed
from flexbed.dynamics.errors import SceneError
from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.linear import run_linear
from flexbed.dynamics.time_functions import Sawtooth
from flexbed.dynamics.statics import solve_statics
from flexbed.errors import InputError
from flexbed.files.results import read_results
from flexbed.files.scene import load_scene
from flexbed.stages.system import compile_scene
from scene_text import base_and_body, driven_base, four_mounts

P, T, S = 200.0, 0.011, 0.0023        # peak [m/s²], rise [s], start [s]
M, K, C = 50.0, 1.25e5, 20.0          # body [kg]; per mount, z: [N/m], [N s/m]


def exact_drive(t):
    """Acceleration, velocity, displacement of the sawtooth (from rest):
    a = Pτ/T, v = Pτ²/(2T), x = Pτ³/(6T) on the rise (τ = t − start), then
    a = 0, v = PT/2, x = PT²/6 + PT/2 (t − start − T)."""
    t = np.asarray(t, dtype=float)
    tau = np.clip(t - S, 0.0, None)
    on = (t >= S) & (t < S + T)
    a = np.where(on, P * tau / T, 0.0)
    after = t >= S + T
    v = np.where(after, P * T / 2, P * tau ** 2 / (2 * T))
    x = np.where(after, P * T ** 2 / 6 + P * T / 2 * (t - S - T), P * tau ** 3 / (6 * T))
    return a, v, x


def exact_isolator(t, omega, zeta):
    """Relative displacement z of z'' + 2ζω z' + ω² z = −a_base(t) from rest:
    Duhamel's integral of the ramp in closed form (particular solution
    −c(τ/ω² − 2ζ/ω³), c = P/T, plus the free response that starts it at
    rest), then free damped vibration from the state at the drop."""
    c = P / T
    wd = omega * math.sqrt(1 - zeta ** 2)
    c1 = -2 * zeta * c / omega ** 3
    c2 = (c / omega ** 2 + zeta * omega * c1) / wd

    def ramp(tau):
        e = np.exp(-zeta * omega * tau)
        z = -c * (tau / omega ** 2 - 2 * zeta / omega ** 3) + e * (c1 * np.cos(wd * tau)
                                                                 + c2 * np.sin(wd * tau))
        dz = (-c / omega ** 2 + e * ((-zeta * omega * c1 + wd * c2) * np.cos(wd * tau)
                                     + (-zeta * omega * c2 - wd * c1) * np.sin(wd * tau)))
        return z, dz

    t = np.asarray(t, dtype=float)
    zT, dzT = ramp(T)
    u = t - S - T
    free = np.exp(-zeta * omega * u) * (zT * np.cos(wd * u)
                                        + (dzT + zeta * omega * zT) / wd * np.sin(wd * u))
    z_on, _ = ramp(np.clip(t - S, 0.0, T))
    return np.where(t < S, 0.0, np.where(t < S + T, z_on, free))


SCENE = base_and_body("sawtooth", mass=M) + driven_base("sawtooth", peak=P, start=S,
                                                        rise=T) + """
[solver]
t_end = 0.1
output_dt = 1.0e-4
""" + four_mounts(f"""
law = "linear"
k = [5.0e4, 7.5e4, {K}]
c = [{C}, {C}, {C}]
""", corners=[(-0.2, -0.3), (0.2, -0.3), (-0.2, 0.3), (0.2, 0.3)], prefix="S")


@pytest.fixture(scope="module")
def scene_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("sawtooth") / "sawtooth.toml"
    path.write_text(SCENE)
    return path


def test_sawtooth_integrals_are_exact_and_the_drop_is_a_breakpoint():
    f = Sawtooth(P, T, S).compile()
    assert f.breakpoints == (S, S + T)
    t = np.concatenate([np.linspace(0.0, 0.05, 2001), [S, S + T]])
    a, v, x = exact_drive(t)
    assert np.abs(f.values(t) - a).max() < 1e-12 * P
    assert np.abs(f.firsts(t) - v).max() < 1e-15 * P
    assert np.abs(f.seconds(t) - x).max() < 1e-16 * P
    # one-sided limits at the drop: the peak from inside the rise, 0 after it
    drop = S + T
    assert f.value(drop, drop) == pytest.approx(P, rel=1e-14)
    assert f.value(drop) == 0.0 and f.value(drop + 1e-9, 1.0) == 0.0
    assert f.first(drop, drop) == f.first(drop) == pytest.approx(P * T / 2, rel=1e-14)
    with pytest.raises(SceneError, match="rise = 0.0 must be > 0"):
        Sawtooth(P, 0.0)


def test_driven_base_follows_the_exact_integrals(scene_file):
    """The base's acceleration, velocity and displacement in the results
    file (every 0.1 ms over 0.1 s) equal the closed form to round-off."""
    out = scene_file.parent / "base.h5"
    assert flexbed(["simulate", str(scene_file), "-o", str(out), "--no-progress"]) == 0
    c = read_results(out)
    t = c.get("time")
    a, v, x = exact_drive(t)
    assert np.abs(c.get("bodies/velocity")[:, 0, 2] - v).max() < 1e-14
    assert np.abs(c.get("bodies/position")[:, 0, 2] - x).max() < 1e-15
    assert np.abs(c.get("bodies/acceleration")[:, 0, 2] - a).max() < 1e-11
    assert not np.any(c.get("bodies/position")[:, 0, :2])
    assert c.attrs["solver"]["segments"] == 3          # 0 → start → drop → t_end


MB = 1000.0                           # base [kg]


@pytest.fixture(scope="module")
def free_scene_file(scene_file):
    """The same isolator on a free base pushed by a sawtooth force of peak
    P·m_base (no gravity): the base's acceleration, and so the velocity's
    right-hand side, jumps at the drop."""
    text = SCENE.replace('motion = "driven"', 'motion = "free"').replace("[[base.drive]]",
                                                                        "[[base.force]]")
    text = text.replace("gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, 0.0]")
    path = scene_file.parent / "free.toml"
    path.write_text(text.replace(f"peak = {P}", f"peak = {P * MB}"))
    return path


@pytest.mark.parametrize("base", ["driven", "free"])
@pytest.mark.parametrize("method,options,tol", [
    ("rk4", dict(dt=1.3e-4), 2e-10),
    ("dop853", dict(rtol=1e-12, atol=1e-14), 5e-12),
    ("radau", dict(rtol=1e-10, atol=1e-13), 5e-11),
    ("linear", dict(rtol=1e-12, atol=1e-14), 1e-11),
])
def test_isolator_response_to_a_sawtooth_matches_duhamel(scene_file, free_scene_file, base,
                                                         method, options, tol):
    """1-DOF isolator, 4 mounts of k = 1.25e5 N/m and c = 20 N s/m on 50 kg,
    under the sawtooth: z'' + 2ζω z' + ω² z = −a(t) for the motion z of the
    mass relative to the base, against its closed form over 0.1 s (peak
    10 mm). Driven base: a = the drive, ω = 100 rad/s, ζ = 0.008. Free base
    (1000 kg) under a force P·m_base: a = force/m_base, ω² = 4k(1/m + 1/m_base).
    Every integrator stops on the drop (t = 13.3 ms; 3 segments) and sees
    the peak as the left limit there. Measured, max error (driven, free):
    rk4 (dt = 0.13 ms, not a divisor of the rise) 1.95e-11, 1.84e-11 m;
    dop853 (rtol 1e-12) 4.2e-13, 4.7e-13 m; radau (rtol 1e-10) 3.3e-12,
    4.2e-12 m; the linear fast path 1.0e-12, 4.4e-14 m. Without the drop as a
    breakpoint rk4 is off by 4.2e-5 m on the free base (its steps cross the
    jump of the base's acceleration)."""
    sf = load_scene(scene_file if base == "driven" else free_scene_file)
    system = compile_scene(sf)
    assert S + T in system.breakpoints
    if base == "driven":
        y_eq = solve_statics(system, tol=1e-12).y
        inv_m = 1.0 / M
    else:
        y_eq = system.initial_state()          # no gravity: unstrained is the equilibrium
        inv_m = 1.0 / M + 1.0 / MB
    y0 = system.initial_state(y_eq)
    st = Settings("dop853" if method == "linear" else method, t_end=0.1, output_dt=1e-4,
                  **options)
    run = run_linear(system, y_eq, y0, st).run if method == "linear" else integrate(system, y0, st)
    assert run.complete
    if method != "linear":
        assert run.stats.segments == 3
    parts = system.layout.split(run.y)
    r = parts["r"][:, 0, 2]
    r_base = exact_drive(run.t)[2] if base == "driven" else parts["r_base"][:, 2]
    rel = r - r_base - (r[0] - r_base[0])
    omega = math.sqrt(4 * K * inv_m)
    zeta = 4 * C * inv_m / (2 * omega)
    z = exact_isolator(run.t, omega, zeta)
    err = np.abs(rel - z).max()
    print(f"{base} {method}: max |z − Duhamel| {err:.2e} m (peak {np.abs(z).max():.3g} m)")
    assert np.abs(z).max() > 0.01
    assert err < tol
    if base == "free":       # momentum: the force's impulse, P m_base T / 2
        v = np.array([M, MB]) @ np.array([parts["rd"][-1, 0, 2], parts["rd_base"][-1, 2]])
        assert v == pytest.approx(P * MB * T / 2, rel=1e-9)


def write(tmp_path, text):
    path = tmp_path / "s.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("change,says", [
    ("rise = 0.011\n", "'rise' is required for shape = 'sawtooth'"),
    ("rise = 0.011\nfall = 0.001\n", "key 'fall' does not apply to shape = 'sawtooth'"),
    ("rise = -0.011\n", "rise = -0.011 must be > 0"),
    ("rise = 0.011\nsample = 0.001\n", "sample does not apply to shape = 'sawtooth'"),
])
def test_sawtooth_keys_checked_when_the_scene_is_read(tmp_path, change, says):
    text = SCENE.replace(f"rise = {T}\n", change if "required" not in says else "")
    with pytest.raises(InputError) as exc:
        load_scene(write(tmp_path, text))
    msg = str(exc.value)
    assert msg.startswith("s.toml: base.drive 1: ") and says in msg, msg
