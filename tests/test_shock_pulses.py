"""Shock pulses as specifications state them (issue 23, part 1): the forms'
exact integrals against their closed forms, the jumps as breakpoints with
one-sided limits, compensation that brings the base back to rest, and the
scene file's keys (``units = "g"`` exact, bad values one line, exit 2)."""

import math

import numpy as np
import pytest

from flexbed.cli import main as flexbed
from flexbed.dynamics.errors import SceneError
from flexbed.dynamics.pulses import STANDARD_GRAVITY, ShockPulse
from flexbed.dynamics.time_functions import jumps
from flexbed.errors import InputError
from flexbed.files.scene import load_scene
from scene_text import body_on_four_mounts

P, D, S = 294.0, 0.011, 0.004            # peak [m/s²], duration [s], start [s]


def closed_form(form, t, rise=0.002, fall=0.003):
    """a, v, x of the uncompensated pulse from rest, by hand (τ = t − S)."""
    tau = np.clip(t - S, 0.0, D)
    on = (t >= S) & (t < S + D)
    after = np.clip(t - S - D, 0.0, None)
    if form == "half-sine":
        W = math.pi / D
        a = P * np.sin(W * tau)
        v = P / W * (1 - np.cos(W * tau))
        x = P / W * tau - P / W ** 2 * np.sin(W * tau)
    elif form == "haversine":
        W = 2 * math.pi / D
        a = P / 2 * (1 - np.cos(W * tau))
        v = P / 2 * (tau - np.sin(W * tau) / W)
        x = P / 2 * (tau ** 2 / 2 - (1 - np.cos(W * tau)) / W ** 2)
    elif form == "terminal-peak-sawtooth":
        a, v, x = P * tau / D, P * tau ** 2 / (2 * D), P * tau ** 3 / (6 * D)
    elif form == "initial-peak-sawtooth":
        a = P * (1 - tau / D)
        v = P * (tau - tau ** 2 / (2 * D))
        x = P * (tau ** 2 / 2 - tau ** 3 / (6 * D))
    elif form == "square":
        a, v, x = P + 0 * tau, P * tau, P * tau ** 2 / 2
    else:                                  # trapezoid: integrate the three pieces by hand
        r, f, h = rise, fall, D - rise - fall
        t1, t2 = np.minimum(tau, r), np.clip(tau - r, 0, h)
        t3 = np.clip(tau - r - h, 0, f)
        a = np.where(tau < r, P * tau / r, np.where(tau < r + h, P, P * (1 - t3 / f)))
        v1 = P * t1 ** 2 / (2 * r)
        v = v1 + P * t2 + P * (t3 - t3 ** 2 / (2 * f))
        x = (P * t1 ** 3 / (6 * r) + (P * r / 2) * (tau - t1) * (tau > r)
             + P * t2 ** 2 / 2 + P * h * (tau - r - h) * (tau > r + h)
             + P * (t3 ** 2 / 2 - t3 ** 3 / (6 * f)))
    a = np.where(on, a, 0.0)
    return a, v + 0 * t, x + v * after


FORMS = ["half-sine", "haversine", "terminal-peak-sawtooth", "initial-peak-sawtooth",
         "trapezoid", "square"]


def pulse(form, **kw):
    extra = dict(rise=0.002, fall=0.003) if form == "trapezoid" else {}
    return ShockPulse(form, P, D, S, **extra, **kw)


@pytest.mark.parametrize("form", FORMS)
def test_integrals_are_the_closed_forms(form):
    """Acceleration, velocity and displacement of each form against its
    closed form at 3001 times over 0 – 30 ms (the breakpoints among them):
    round-off (measured ≤ 1.6e-13 of peak·D, D², D³)."""
    f = pulse(form).compile()
    t = np.concatenate([np.linspace(0.0, 0.03, 3001), f.breakpoints])
    a, v, x = closed_form(form, t)
    assert np.abs(f.values(t) - a).max() < 1e-12 * P
    assert np.abs(f.firsts(t) - v).max() < 1e-13 * P * D
    assert np.abs(f.seconds(t) - x).max() < 1e-13 * P * D * D
    scalar = np.array([[f.value(u), f.first(u), f.second(u)] for u in t[::7]])
    assert np.abs(scalar - np.column_stack([a, v, x])[::7]).max() < 1e-12 * P
    assert f.breakpoints[0] == S and f.breakpoints[-1] == pytest.approx(S + D, rel=1e-15)


@pytest.mark.parametrize("form,expected", [
    ("half-sine", []), ("haversine", []), ("trapezoid", []),
    ("terminal-peak-sawtooth", [(S + D, -P)]), ("initial-peak-sawtooth", [(S, P)]),
    ("square", [(S, P), (S + D, -P)])])
def test_jumps_are_breakpoints_with_one_sided_limits(form, expected):
    """The jumps the integrators stop at: right minus left limit at each
    breakpoint; the haversine's two terms (square and sinusoid) jump at its
    ends but cancel to round-off."""
    found = [(b, d) for b, d in jumps(pulse(form).compile()) if abs(d) > 1e-12 * P]
    assert len(found) == len(expected)
    for (b, d), (b0, d0) in zip(found, expected):
        assert b == pytest.approx(b0, rel=1e-15) and d == pytest.approx(d0, rel=1e-14)


@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("how", ["half-sine", "rectangular"])
def test_compensated_pulse_ends_at_rest(form, how):
    """Pre- and post-pulses of 10 % of the peak: the base's velocity and
    displacement are zero at the end and after it, to round-off (measured
    ≤ 2e-15 m/s and 1.4e-16 m for peak·D = 3.2 m/s), and the main pulse is
    unchanged, only later by the pre-pulse. (The displacement's tolerance
    grows after the end as the velocity's round-off carries on: 10 s later
    3.6e-15 m.)"""
    p = pulse(form, compensation=how, ratio=0.1)
    f = p.compile()
    pre, *main, post = p.terms()
    assert pre.start == S and pre.end == pytest.approx(main[0].start, rel=1e-15)
    assert post.start == pytest.approx(main[0].start + D, rel=1e-14)
    for term in (pre, post):
        peak = term.amplitude if how == "half-sine" else term.peak
        assert peak == pytest.approx(-0.1 * P, rel=1e-15)
    end = p.end
    for t in (end, end + 0.5, end + 10.0):
        assert abs(f.first(t)) < 1e-14 * P * D
        # the velocity's round-off, carried on after the end, is the displacement's
        assert abs(f.second(t)) < 1e-14 * P * D * (D + t - end)
        assert abs(f.firsts(np.array([t]))[0]) < 1e-14 * P * D
    # the main pulse is the uncompensated one, shifted by the pre-pulse
    shift = main[0].start - S
    g = pulse(form).compile()
    t = np.linspace(S, S + D, 501)[:-1]          # the post-pulse starts at the end
    assert np.abs(f.values(t + shift) - g.values(t)).max() < 1e-12 * P
    # and the base really moved: the velocity change at the main pulse's end
    assert f.first(S + shift + D) - f.first(S + shift) == pytest.approx(g.first(S + D), rel=1e-12)


def test_shock_pulse_refuses_what_means_nothing():
    with pytest.raises(SceneError, match="peak = 0.0"):
        ShockPulse("half-sine", 0.0, D)
    with pytest.raises(SceneError, match="duration = -0.011 must be > 0"):
        ShockPulse("half-sine", P, -D)
    with pytest.raises(SceneError, match="rise \\+ fall"):
        ShockPulse("trapezoid", P, D, rise=0.006, fall=0.006)
    with pytest.raises(SceneError, match="compensation_ratio = 1.5"):
        ShockPulse("square", P, D, compensation="rectangular", ratio=1.5)
    with pytest.raises(SceneError, match="'bump'"):
        ShockPulse("square", P, D, compensation="bump", ratio=0.1)


DRIVE = """
[base]
motion = "driven"

[[base.drive]]
direction = "{axis}"
{keys}
"""


def _scene(tmp_path, keys, axis="z", name="s.toml"):
    p = tmp_path / name
    p.write_text(body_on_four_mounts(extra=DRIVE.format(axis=axis, keys=keys)))
    return p


def test_units_g_is_standard_gravity_exactly(tmp_path):
    """30 g is 30 × 9.80665 m/s²: the drive's terms are the same numbers."""
    g = load_scene(_scene(tmp_path, 'shape = "half-sine"\npeak = 30\nduration = 0.011\n'
                                    'units = "g"', name="g.toml")).scene.base.drives
    si = load_scene(_scene(tmp_path, f'shape = "half-sine"\npeak = {30 * 9.80665!r}\n'
                                     f'duration = 0.011\nunits = "m/s2"',
                           name="si.toml")).scene.base.drives
    assert g == si and g[0].shape.amplitude == 30 * STANDARD_GRAVITY
    # every acceleration key scales: a sinusoid's amplitude, a curve's values and slopes
    c = load_scene(_scene(tmp_path, 'shape = "curve"\ntime = [0, 0.1, 0.2, 0.3]\n'
                                    'value = [0, 1, 2, 1]\nend_condition = "clamped"\n'
                                    'end_slopes = [1, 2]\nunits = "g"', name="c.toml"))
    curve = c.scene.base.drives[0].shape
    assert list(curve.value) == [0.0, 9.80665, 2 * 9.80665, 9.80665]
    assert curve.ends.slopes == (9.80665, 2 * 9.80665)


def test_combined_axes_and_haversine_terms(tmp_path):
    """A haversine in z and a compensated half-sine in y: one drive per
    term, each on its axis (2 + 3)."""
    p = tmp_path / "two.toml"
    p.write_text(body_on_four_mounts(extra=DRIVE.format(
        axis="z", keys='shape = "haversine"\npeak = 30\nduration = 0.011\nunits = "g"')
        + '\n[[base.drive]]\ndirection = "y"\nshape = "half-sine"\npeak = 20\n'
          'duration = 0.011\nunits = "g"\ncompensation = "half-sine"\n'
          'compensation_ratio = 0.1\n'))
    drives = load_scene(p).scene.base.drives
    assert [d.direction for d in drives] == [2, 2, 1, 1, 1]


BAD = [
    ('shape = "half-sine"\npeak = 30\nduration = 0.011\nunits = "G"',
     "units = 'G' must be one of 'm/s2', 'g'"),
    ('shape = "half-sine"\npeak = 30\nduration = -0.011', "duration = -0.011"),
    ('shape = "square"\npeak = 0\nduration = 0.011', "peak = 0.0"),
    ('shape = "haversine"\npeak = 30', "'duration' is required"),
    ('shape = "half-sine"\npeak = 30\nduration = 0.011\ncompensation = "half-sine"',
     "needs compensation_ratio"),
    ('shape = "half-sine"\npeak = 30\nduration = 0.011\ncompensation = "half-sine"\n'
     'compensation_ratio = 0', "compensation_ratio = 0.0 must be in (0, 1]"),
    ('shape = "half-sine"\npeak = 30\nduration = 0.011\ncompensation_ratio = 0.1',
     "needs compensation = 'half-sine' or 'rectangular'"),
    ('shape = "half-sine"\npeak = 30\nduration = 0.011\nsample = 0.001',
     "sample does not apply"),
    ('shape = "half-sine"\npeak = 30\nduration = 0.011\nrise = 0.001',
     "key 'rise' does not apply"),
]


@pytest.mark.parametrize("keys,words", BAD)
def test_bad_drive_is_one_line_exit_2(tmp_path, capsys, keys, words):
    p = _scene(tmp_path, keys)
    out = tmp_path / "out" / "eq.h5"
    assert flexbed(["static", str(p), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert "s.toml" in err[0] and "base.drive 1" in err[0] and words in err[0], err[0]
    assert not out.parent.exists() or not any(out.parent.iterdir())


def test_units_on_a_force_is_refused(tmp_path):
    p = tmp_path / "f.toml"
    p.write_text(body_on_four_mounts(extra='[base]\nmotion = "free"\n[[base.force]]\n'
                                           'direction = "z"\nshape = "half-sine"\npeak = 100\n'
                                           'duration = 0.01\nunits = "g"\n'))
    with pytest.raises(InputError, match="base.force 1: units = 'g': a force is in N"):
        load_scene(p)
