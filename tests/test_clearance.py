"""Clearances over a run (issue 23, part 3) against a motion known in
closed form: a free body, no gravity, no mounts, translating at 1 m/s
along x while it spins about its principal z axis (torque-free, so the
spin stays exact):

    r(t) = (x0 + v t, 0, 0.5),  A(t) = Rz(ω t).

- to a point Q = (0, b, 0.5) on the base: d = √((x0 + v t)² + b²), least
  b at t = −x0 / v;
- from the rim point (ρ, 0, 0) to the plane y = Y on the base, normal −y:
  d = Y − ρ sin ω t, least Y − ρ at ω t = π/2 (and a turn later);
- from the centre to the box [0.2, 0.4] × [0.1, 0.3] × [0.4, 0.6] on the
  base: 0.1 (the y gap) while x ∈ [0.2, 0.4].
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import flexbed
from flexbed.analyses.clearance import clearance, distance
from flexbed.analyses.extremes import extreme
from flexbed.files.limits import Clearance

X0, V, B, RHO, Y = -0.3337, 1.0, 0.05, 0.12, 0.2
OMEGA = 2 * math.pi * 1.3

SCENE = f"""
[scene]
name = "free"
gravity = [0.0, 0.0, 0.0]

[[body]]
name = "base"
mass = 1000.0
inertia = [100.0, 100.0, 100.0]
position = [0.0, 0.0, 0.0]

[[body]]
name = "mass"
mass = 50.0
inertia = [2.0, 3.0, 4.0]
position = [{X0}, 0.0, 0.5]
velocity = [{V}, 0.0, 0.0]
angular_velocity = [0.0, 0.0, {OMEGA!r}]

[[clearance]]
name = "pass"
body = "mass"
point = [0.0, 0.0, 0.0]
other = "base"
other_point = [0.0, {B}, 0.5]
minimum = 0.04

[[clearance]]
name = "wall"
body = "mass"
point = [{RHO}, 0.0, 0.0]
other = "base"
plane = {{point = [0.0, {Y}, 0.0], normal = [0.0, -1.0, 0.0]}}
minimum = 0.09

[[clearance]]
name = "shelf"
body = "mass"
point = [0.0, 0.0, 0.0]
other = "base"
box = {{min = [0.2, 0.1, 0.4], max = [0.4, 0.3, 0.6]}}
minimum = 0.12

[solver]
start = "initial"
t_end = 1.0
integrator = "dop853"
rtol = 1e-11
atol = 1e-13
"""


@pytest.fixture(scope="module")
def free(tmp_path_factory):
    path = tmp_path_factory.mktemp("free") / "free.toml"
    path.write_text(SCENE)
    sf = flexbed.load_scene(path)
    return sf, flexbed.simulate(sf)._run()


def test_the_distances_follow_the_closed_form_at_every_sample(free):
    sf, run = free
    t = run.t
    x = X0 + V * t
    exact = {"pass": np.hypot(x, B), "wall": Y - RHO * np.sin(OMEGA * t),
             "shelf": np.where((x >= 0.2) & (x <= 0.4), 0.1,
                               np.hypot(np.maximum(0.2 - x, 0) + np.maximum(x - 0.4, 0), 0.1))}
    for c in sf.limits.clearances:
        np.testing.assert_allclose(distance(run, c), exact[c.name], rtol=0, atol=1e-9,
                                   err_msg=c.name)


def test_minimum_time_and_margin_against_the_closed_form(free):
    sf, run = free
    got = {c.name: clearance(run, c) for c in sf.limits.clearances}
    p = got["pass"]             # between samples (t* = 0.3337 s, output every 1 ms)
    assert p.minimum == pytest.approx(B, rel=1e-7)
    assert p.time == pytest.approx(-X0 / V, abs=1e-6)
    assert p.margin == pytest.approx(B - 0.04, rel=1e-6) and p.passed
    w = got["wall"]
    assert w.minimum == pytest.approx(Y - RHO, rel=1e-9)
    turn = 2 * math.pi / OMEGA
    assert min(abs(w.time - (0.25 + k) * turn) for k in range(2)) < 1e-6
    assert w.margin == pytest.approx(Y - RHO - 0.09, rel=1e-8) and not w.passed
    s = got["shelf"]            # a flat bottom: the sample itself, no dip below it
    assert s.minimum == pytest.approx(0.1, abs=1e-12)
    assert 0.2 - X0 <= s.time + 1e-12 and s.time <= 0.4 - X0
    assert s.margin == pytest.approx(-0.02, abs=1e-12) and not s.passed


class _Still:
    """A run in which the point sits at fixed places in the other's frame."""

    def __init__(self, rho):
        self.rho = np.atleast_2d(rho)
        self.t = np.arange(len(self.rho), dtype=float)
        self.bed_body, self.bed_centre = None, np.zeros(3)

    def relative(self, point, body):
        return type("M", (), {"position": self.rho})


def test_inside_a_box_the_distance_is_minus_the_depth():
    box = Clearance("b", "mass", (0, 0, 0), "base", "box", ((0, 0, 0), (1, 2, 3)), 0.0)
    run = _Still([[0.5, 1.0, 0.2], [0.9, 1.9, 2.95], [1.5, 1.0, 1.0], [2.0, 3.0, 4.0]])
    np.testing.assert_allclose(distance(run, box), [-0.2, -0.05, 0.5, math.sqrt(3)])


def test_extremes_are_refined_between_samples_on_smooth_signals():
    t = np.linspace(0.0, 1.0, 101)
    f = np.cos(7.3 * t + 0.4)                   # minimum −1 at t = (π − 0.4) / 7.3
    low = extreme(t, f, "min")
    assert low.value == pytest.approx(-1.0, abs=1e-6)
    assert low.time == pytest.approx((math.pi - 0.4) / 7.3, abs=1e-6)
    assert f.min() + 1.0 > 5e-4                  # the samples alone miss it by 500 times more
    edge = extreme(t, t ** 2, "max")             # at the record's end: the sample itself
    assert tuple(edge) == (1.0, 1.0)
