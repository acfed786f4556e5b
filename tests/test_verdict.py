"""The shock verdict (issue 23, part 4): its figures against the closed
form of an undamped oscillator under a half-sine, its PASS/FAIL logic on
each limit kind, and ``flexbed qualify``'s files and exit status.

The scene: a 50 kg body on four identical mounts in the plane of its
centre of mass (no rocking), the base driven by a 30 g / 11 ms half-sine
in z. The relative motion u = Δx3 − Δx3_static obeys ü + ω² u = −a(t),
ω² = 4 k_z / m, from rest:

    u(t) = −A / (ω² − Ω²) (sin Ω t − (Ω/ω) sin ω t),   t ≤ T, Ω = π / T,

then free vibration from u(T), u̇(T). The body's absolute acceleration is
−ω² u, each mount's force k_z (Δx3_static + u).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import flexbed
from flexbed.analyses.verdict import G, judge
from flexbed.analyses.verdict_tables import csv, markdown
from flexbed.cli import main
from flexbed.errors import EXIT_FAIL
from flexbed.files.limits import Clearance, Fragility, Limits, MountLimits

from scene_text import base_and_body, four_mounts

M, KZ, A, T = 50.0, 1.25e5, 30 * G, 0.011
OMEGA, BIG_OMEGA = math.sqrt(4 * KZ / M), math.pi / T
STATIC = -M * 9.81 / (4 * KZ)                           # Δx3 at rest [m]

DRIVE = f"""
[base]
motion = "driven"

[[base.drive]]
direction = "z"
shape = "sinusoid"
amplitude = {A!r}
frequency = {1 / (2 * T)!r}
duration = {T}

[solver]
t_end = 0.2
output_dt = 1.0e-4
integrator = "dop853"
rtol = 1e-10
atol = 1e-12
"""

LAW = 'law = "linear"\nk = [5.0e4, 7.5e4, 1.25e5]'


def text(limits: str = "", body: str = "", extra: str = "") -> str:
    return (base_and_body("verdict", body_extra=body)
            + four_mounts(LAW + "\n" + limits) + DRIVE + extra)


def exact_u(t: np.ndarray) -> np.ndarray:
    """u(t) of the module docstring [m]."""
    w, W = OMEGA, BIG_OMEGA
    c = -A / (w * w - W * W)
    u = c * (np.sin(W * t) - W / w * np.sin(w * t))
    uT = c * (math.sin(W * T) - W / w * math.sin(w * T))
    vT = c * (W * math.cos(W * T) - W * math.cos(w * T))
    after = uT * np.cos(w * (t - T)) + vT / w * np.sin(w * (t - T))
    return np.where(t <= T, u, after)


@pytest.fixture(scope="module")
def qualified(tmp_path_factory):
    path = tmp_path_factory.mktemp("verdict") / "oscillator.toml"
    path.write_text(text(extra="""
[[point]]
name = "top"
body = "mass"
position = [0.0, 0.0, 0.1]
relative_to = "base"
"""))
    return flexbed.qualify(flexbed.load_scene(path))


def test_the_figures_follow_the_closed_form(qualified):
    v = qualified.verdict
    t = np.linspace(0.0, 0.2, 2_000_001)
    u = exact_u(t)
    for m in v.mounts:
        assert m.static_deflection[2] == pytest.approx(STATIC, rel=1e-9)
        assert m.static_load == pytest.approx(-KZ * STATIC, rel=1e-9)
        assert m.dynamic_compression[2] == pytest.approx(-u.min(), rel=1e-7)
        period = 2 * math.pi / OMEGA    # undamped: the residual minimum comes back each period
        late = (m.dynamic_compression_time[2] - t[np.argmin(u)]) / period
        assert abs(late - round(late)) * period < 1e-5
        assert m.dynamic_extension[2] == pytest.approx(u.max(), rel=1e-7)
        assert m.compression[2] == pytest.approx(-(STATIC + u).min(), rel=1e-7)
        assert m.extension[2] == pytest.approx(max(0.0, (STATIC + u).max()), rel=1e-7)
        assert m.peak_force == pytest.approx(KZ * np.abs(STATIC + u).max(), rel=1e-7)
        assert np.all(np.isnan(m.stroke_used))            # no limits given
        assert m.compression[0] < 1e-12 and m.extension[1] < 1e-12   # nothing sideways
    (body,) = v.bodies
    assert body.peak_acceleration == pytest.approx(OMEGA ** 2 * np.abs(u).max(), rel=1e-7)
    (top,) = v.points                   # moves with the body: the same as its centre
    assert top.peak_acceleration == pytest.approx(body.peak_acceleration, rel=1e-9)
    assert top.peak_relative_displacement == pytest.approx(np.abs(u).max(), rel=1e-7)
    assert v.passed and v.reasons == ()                    # nothing to fail against


def _with(q, **limits) -> object:
    return judge(q.results._run(), Limits(**limits), *_static(q))


def _static(q):
    from flexbed.api.qualification import static_mounts
    return static_mounts(q.statics)


def _mounts(**kw):
    return tuple(MountLimits(f"M{i}", **kw) for i in range(1, 5))


def test_each_limit_kind_passes_just_above_and_fails_just_below_its_figure(qualified):
    v = qualified.verdict
    m = v.mounts[0]
    c3, e3 = m.compression[2], m.extension[2]
    load, peak, acc = m.static_load, m.peak_force, v.bodies[0].peak_acceleration
    top = (0.0, 0.0, 0.1)
    # the body's top and a plane 5 cm above its initial height on the base
    plane = Clearance("roof", "mass", top, "base", "plane", ((0.0, 0.0, 0.65), (0.0, 0.0, -1.0)),
                      0.0)
    lowest = _with(qualified, clearances=(plane,)).clearances[0].minimum
    cases = {
        "compression": lambda s: dict(mounts=_mounts(compression=(1, 1, c3 * s))),
        "extension": lambda s: dict(mounts=_mounts(extension=(1, 1, e3 * s))),
        "rated_load": lambda s: dict(mounts=_mounts(rated_load=load * s)),
        "max_force": lambda s: dict(mounts=_mounts(max_force=peak * s)),
        "fragility": lambda s: dict(fragility=(Fragility("mass", acc * s, "m/s2"),)),
        "clearance": lambda s: dict(clearances=(dataclasses.replace(plane,
                                                                    minimum=lowest / s),)),
    }
    words = {"compression": "stroke: direction 3 compression", "extension":
             "stroke: direction 3 extension", "rated_load": "load: static",
             "max_force": "force: peak", "fragility": "fragility: peak", "clearance": "minimum"}
    assert c3 > 0 and e3 > 0 and lowest > 0
    for kind, limits in cases.items():
        above = _with(qualified, **limits(1 + 1e-6))
        below = _with(qualified, **limits(1 - 1e-6))
        assert above.passed, (kind, above.reasons)
        assert not below.passed and all(words[kind] in r for r in below.reasons), kind
        n = 4 if kind in ("compression", "extension", "rated_load", "max_force") else 1
        assert len(below.reasons) == n, (kind, below.reasons)
    used = _with(qualified, **cases["compression"](2.0)).mounts[0].stroke_used
    assert used[2] == pytest.approx(0.5, rel=1e-12) and used[0] == pytest.approx(0.0, abs=1e-9)


def test_the_tables_say_the_same(qualified):
    v = _with(qualified, mounts=_mounts(rated_load=1.0))        # every mount fails its load
    md, table = markdown(v), csv(v)
    assert md.startswith("# Verdict: FAIL") and md.count("**FAIL**") == 4
    rows = [r.split(",") for r in table.splitlines()]
    assert rows[0] == "item,name,direction,quantity,value,unit,limit,time_s,pass".split(",")
    assert rows[1][:5] == ["verdict", "", "", "pass", "0"]
    loads = [r for r in rows if r[3] == "static_load"]
    assert len(loads) == 4 and all(float(r[4]) == pytest.approx(-KZ * STATIC) for r in loads)


def _cli(tmp_path, scene_text: str, *more):
    (tmp_path / "s.toml").write_text(scene_text)
    return main(["qualify", str(tmp_path / "s.toml"), "-o", str(tmp_path / "out" / "v"), *more])


@pytest.mark.slow
def test_qualify_exits_0_on_pass_and_3_on_fail_with_its_three_files(tmp_path, capsys):
    assert _cli(tmp_path, text("stroke_compression = [0.05, 0.05, 0.05]")) == 0
    out = capsys.readouterr().out
    assert "# Verdict: PASS" in out
    written = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert written == ["v.csv", "v.h5", "v.md"]
    from flexbed.files.store import read_file
    c = read_file(tmp_path / "out" / "v.h5", schema="flexbed.verdict", major=1)
    assert c.attrs[""]["passed"] is True or c.attrs[""]["passed"] == 1
    assert c.units["mounts/stroke_used"] == "1"
    assert EXIT_FAIL == 3
    for p in (tmp_path / "out").iterdir():
        p.unlink()
    assert _cli(tmp_path, text("stroke_compression = [0.05, 0.05, 0.005]")) == 3
    assert "# Verdict: FAIL" in capsys.readouterr().out
    assert len(list((tmp_path / "out").iterdir())) == 3


BAD = [
    ("stroke below static", text("stroke_compression = [0.05, 0.05, 0.0009]"),
     "s.toml: mount 'M1': stroke_compression[2] = 0.0009 m is smaller than the static "
     "deflection in direction 3, 0.000981 m of compression"),
    ("units", text(body='fragility = {peak = 20, units = "G"}'),
     "s.toml: body 'mass': fragility.units = 'G' must be one of 'm/s2', 'g'"),
    ("gap of 0", text("bump_stop = {direction = 3, gap_compression = 0.0, stiffness = 1e7}"),
     "s.toml: mount 'M1': bump_stop.gap_compression = 0.0 must be > 0"),
    ("negative contact stiffness",
     text("bump_stop = {direction = 3, gap_compression = 0.01, stiffness = -1e7}"),
     "s.toml: mount 'M1': bump_stop.stiffness = -10000000.0 must be > 0"),
    ("linear model with stops", text("bump_stop = {direction = 3, gap_compression = 0.01, "
                                     "stiffness = 1e7}").replace('integrator = "dop853"',
                                                                 'model = "linear"'),
     "s.toml: model = 'linear' cannot follow a bump stop's contact (mount 'M1' has one)"),
    ("self clearance", text(extra='\n[[clearance]]\nname = "c"\nbody = "mass"\n'
                                  'point = [0, 0, 0]\nother = "mass"\n'
                                  'other_point = [0, 0, 1]\nminimum = 0.01\n'),
     "s.toml: clearance 'c': other = 'mass' is the body itself"),
]


@pytest.mark.parametrize("scene_text, words", [(t, w) for _, t, w in BAD],
                         ids=[n for n, _, _ in BAD])
def test_bad_input_is_one_line_exit_2_and_nothing_written(tmp_path, capsys, scene_text, words):
    assert _cli(tmp_path, scene_text) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"flexbed qualify: {words}" in err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


WRONG_CALLS = [
    (lambda sc: flexbed.qualify("skid.toml"), "flexbed.qualify: scene = 'skid.toml' must be a "
                                              "scene: read the file with flexbed.load_scene"),
    (lambda sc: flexbed.qualify(sc, t_end="1"), "flexbed.qualify: t_end = '1' must be a number"),
    (lambda sc: flexbed.qualify(sc, progress=5), "flexbed.qualify: progress = 5 must be a "
                                                 "function"),
    (lambda sc: flexbed.qualify(sc, speed=2), "flexbed.qualify: unknown setting(s) speed"),
    (lambda sc: flexbed.qualify(sc, modes="m.h5"), "flexbed.qualify: modes = 'm.h5' must be"),
]


@pytest.mark.parametrize("call, words", WRONG_CALLS)
def test_wrong_api_calls_are_one_line_naming_the_argument(tmp_path, call, words):
    path = tmp_path / "s.toml"
    path.write_text(text())
    with pytest.raises(flexbed.InputError) as exc:
        call(flexbed.load_scene(path))
    assert str(exc.value).startswith(words) and "\n" not in str(exc.value)


def test_a_qualification_saves_only_to_a_file_name(qualified):
    with pytest.raises(flexbed.InputError, match=r"^flexbed.Qualification.save: path = 3 must "
                                                 r"be a file name"):
        qualified.save(3)
