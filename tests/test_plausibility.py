"""Plausibility of the static equilibrium (issue 23, part 5) and the
mounts' static loads and deflections (part 4): a mass typed in grams is
refused in one line naming the body, the mount and the deflection (exit 2,
nothing written); the limits relax by scene keys; an unstable equilibrium
stops a run (exit 1) unless allowed; ``flexbed static`` prints each
mount's static force and deflection, which are m g / (4 k) here."""

import pytest

from flexbed.cli import main as flexbed
from flexbed.dynamics.statics import solve_statics
from flexbed.files.scene import load_scene
from flexbed.stages.plausibility import _rotation_deg, body_sizes, implausibility, mount_statics
from flexbed.stages.simulation import equilibrium
from flexbed.stages.system import compile_scene
from scene_text import base_and_body, body_on_four_mounts, four_mounts

K = 1.0e5                     # each mount's stiffness [N/m]


def _write(tmp_path, text, name="s.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_static_prints_the_mounts_loads_and_deflections(tmp_path, capsys):
    """50 kg on four mounts of 1e5 N/m: each carries m g / 4 = 122.625 N,
    compressed m g / (4 k) = 1.22625 mm, along its u3 (= z)."""
    p = _write(tmp_path, body_on_four_mounts())
    assert flexbed(["static", str(p), "-o", str(tmp_path / "eq.h5")]) == 0
    out = capsys.readouterr().out
    rows = [r for r in out.splitlines() if r.startswith("| M")]
    assert len(rows) == 4
    for r in rows:
        cells = [c.strip() for c in r.strip("|").split("|")]
        f = [float(v) for v in cells[2].split(",")]
        d = [float(v) for v in cells[3].split(",")]
        assert f[:2] == [0.0, 0.0] and f[2] == pytest.approx(-50 * 9.81 / 4, rel=1e-6)
        assert d[:2] == [0.0, 0.0] and d[2] == pytest.approx(-50 * 9.81 / 4 / K * 1e3, rel=1e-4)
    sf = load_scene(p)
    system = compile_scene(sf)
    ms = mount_statics(system, equilibrium(sf, system).y)
    assert ms.force[:, 2] == pytest.approx([-50 * 9.81 / 4] * 4, rel=1e-9)
    assert ms.deflection[:, 2] == pytest.approx([-50 * 9.81 / 4 / K] * 4, rel=1e-9)
    assert ms.body_i == ("base",) * 4 and ms.body_j == ("mass",) * 4


def test_a_mass_in_grams_is_refused(tmp_path, capsys):
    """50 kg typed as 50000: the mounts would deflect 1.23 m under a body of
    size 0.016 m (the box of that mass and its inertia): one line naming
    the body, the mount and the deflection; exit 2; nothing written."""
    p = _write(tmp_path, body_on_four_mounts(mass="50000.0"))
    out = tmp_path / "out" / "eq.h5"
    assert flexbed(["static", str(p), "-o", str(out)]) == 2
    err = [e for e in capsys.readouterr().err.strip().splitlines() if "warning" not in e]
    assert len(err) == 1, err
    line = err[0]
    for words in ("s.toml", "implausible static equilibrium", "mount 'M", "body 'mass'",
                  "deflects 1226 mm", "static_deflection_limit"):
        assert words in line, line
    assert not out.parent.exists() or not any(out.parent.iterdir())
    # a run stops the same way, before any simulation
    res = tmp_path / "r.h5"
    assert flexbed(["simulate", str(p), "-o", str(res), "--no-progress"]) == 2
    assert not res.exists()


def test_the_limit_relaxes_by_a_scene_key(tmp_path):
    """2000 kg on the same mounts sinks 49 mm, more than 0.25 of its size
    (0.082 m): refused; with [solver] static_deflection_limit = 1 it is
    accepted. (The 50000 kg of grams, let through with ``inf``, sinks past
    the mounts' ends into an unstable equilibrium, which then stops it.)"""
    p = _write(tmp_path, body_on_four_mounts(mass="2000.0"))
    assert flexbed(["static", str(p), "-o", str(tmp_path / "eq.h5")]) == 2
    p = _write(tmp_path, body_on_four_mounts(
        mass="2000.0", extra="\n[solver]\nstatic_deflection_limit = 1.0\n"), name="r.toml")
    assert flexbed(["static", str(p), "-o", str(tmp_path / "eq.h5")]) == 0
    p = _write(tmp_path, body_on_four_mounts(
        mass="50000.0", extra="\n[solver]\nstatic_deflection_limit = inf\n"), name="g.toml")
    assert flexbed(["static", str(p), "-o", str(tmp_path / "eq.h5")]) == 1


def test_deflection_criterion_is_the_stated_fraction(tmp_path):
    """The limit is 0.25 of the body's size: with the size s of body
    'mass', stiffness just above and just below m g / (4 · 0.25 s) passes
    and is refused."""
    sf = load_scene(_write(tmp_path, body_on_four_mounts()))
    size = body_sizes(sf, compile_scene(sf))[1]
    k_edge = 50 * 9.81 / (4 * 0.25 * float(size))
    for k, bad in ((1.01 * k_edge, False), (0.99 * k_edge, True)):
        sf = load_scene(_write(tmp_path, body_on_four_mounts(k=repr(k)), name=f"k{k:.0f}.toml"))
        system = compile_scene(sf)
        y = solve_statics(system, tol=1e-10).y
        assert bool(implausibility(sf, system, y)) is bad, k


def test_rotation_criterion(tmp_path):
    """A body on two stiff mounts on one side and two soft ones (400 N/m
    vertically) on the other tilts 13.2°: refused by the rotation limit
    (10° by default), naming the body and its most deflected mount (a soft
    one); static_rotation_limit_deg = 40 lets it be."""
    body = base_and_body("tilt", mass=20.0, inertia="[1.0, 1.0, 1.0]")
    soft = 'law = "linear"\nk = [1.0e4, 1.0e4, 400.0]'
    stiff = 'law = "linear"\nk = [1.0e4, 1.0e4, 1.0e6]'
    text = body + four_mounts(soft, corners=((-0.2, -0.2), (-0.2, 0.2)), prefix="S") \
        + four_mounts(stiff, corners=((0.2, -0.2), (0.2, 0.2)), prefix="H")
    p = _write(tmp_path, text + "\n[solver]\nstatic_deflection_limit = inf\n")
    sf = load_scene(p)
    system = compile_scene(sf)
    eq = solve_statics(system, tol=1e-10)
    assert eq.success
    turn = _rotation_deg(system.initial_p[1], system.poses(eq.y)[1][1])
    assert 10.0 < turn < 40.0
    why = implausibility(sf, system, eq.y, deflection_limit=float("inf"))
    assert "body 'mass' turns" in why and "mount 'S" in why and "static_rotation_limit_deg" in why
    assert implausibility(sf, system, eq.y, deflection_limit=float("inf"),
                          rotation_limit_deg=40.0) == ""


UNSTABLE = base_and_body("held", gravity=0.0, mass=10.0, inertia="[1.0, 1.0, 1.0]") + \
    four_mounts("""
law = "polynomial"
stiffness = [[0.0, 1.0e4], [0.0, 1.0e4], [0.0, -1.0e4, 0.0, 1.0e8]]
""")


def test_unstable_equilibrium_stops_a_run(tmp_path, capsys):
    """Negative vertical stiffness at rest: static and simulate stop with
    exit 1 and one line naming the body and the direction and the way to
    allow it; with [solver] allow_unstable = true the run goes on."""
    p = _write(tmp_path, UNSTABLE + "\n[solver]\nt_end = 0.01\n")
    assert flexbed(["static", str(p), "-o", str(tmp_path / "eq.h5")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "unstable equilibrium" in err[0] and "body 'mass' in z" in err[0] \
        and "allow_unstable = true" in err[0], err
    assert not (tmp_path / "eq.h5").exists()
    assert flexbed(["simulate", str(p), "-o", str(tmp_path / "r.h5"), "--no-progress"]) == 1
    capsys.readouterr()
    q = _write(tmp_path, UNSTABLE + "\n[solver]\nt_end = 0.01\nallow_unstable = true\n",
               name="allowed.toml")
    assert flexbed(["simulate", str(q), "-o", str(tmp_path / "r.h5"), "--no-progress"]) == 0
    assert "warning" in capsys.readouterr().err


@pytest.mark.parametrize("keys,words", [
    ("static_deflection_limit = -1", "static_deflection_limit = -1"),
    ("static_rotation_limit_deg = 0", "static_rotation_limit_deg = 0"),
    ('allow_unstable = "yes"', "allow_unstable = 'yes' must be true or false"),
])
def test_bad_keys_one_line(tmp_path, capsys, keys, words):
    p = _write(tmp_path, body_on_four_mounts(extra=f"\n[solver]\n{keys}\n"))
    assert flexbed(["static", str(p), "-o", str(tmp_path / "eq.h5")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "s.toml" in err[0] and "solver" in err[0] and words in err[0], err
