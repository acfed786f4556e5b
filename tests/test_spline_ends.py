"""Spline end conditions of curve data (``end_condition`` = "not-a-knot" |
"natural" | "clamped", ``end_slopes``): the end conditions hold, each
reproduces a function that satisfies them exactly, each is SciPy's
CubicSpline with that bc_type to round-off, the tails keep their rules, the scene file checks the
keys, and a run with each works end to end."""

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from flexbed.cli import main as flexbed
from flexbed.dynamics.errors import SceneError
from flexbed.dynamics.laws import CurveLaw, LawBank
from flexbed.dynamics.time_functions import Curve, SplineEnds
from flexbed.errors import InputError
from flexbed.files.results import read_results
from flexbed.files.scene import load_scene
from scene_text import base_and_body, four_mounts

RNG = np.random.default_rng(11)
X = np.sort(RNG.uniform(0.0, 1.0, 9)) * 0.04 + np.linspace(0.0, 0.2, 9)   # uneven spacing


def left(f, x):
    """Limit from the left of a piecewise polynomial at x."""
    return f(x, seg_end=x)


def natural_test_function():
    """A C² piecewise cubic with knots at the interior samples and zero
    second derivative at both ends: g = α + βx + Σ c_k (x − x_k)₊³ with
    Σ c_k (x_n − x_k) = 0. The natural spline through its samples is g."""
    knots = X[1:-1]
    c = RNG.normal(size=knots.size) * 1e4
    c[-1] = -np.sum(c[:-1] * (X[-1] - knots[:-1])) / (X[-1] - knots[-1])

    def g(x, d=0):
        u = np.clip(np.subtract.outer(np.asarray(x, dtype=float), knots), 0.0, None)
        if d == 0:
            return 3.0 - 2.0 * x + u ** 3 @ c
        if d == 1:
            return -2.0 + 3 * u ** 2 @ c
        return 6 * u @ c
    return g


def test_natural_has_zero_curvature_at_both_ends_and_reproduces_such_data():
    g = natural_test_function()
    assert abs(g(X[-1], 2)) < 1e-9 * np.abs(g(X, 2)).max()
    f = SplineEnds("natural").spline(X, g(X), left="linear", right="linear")
    f2 = f.derivative().derivative()
    scale = np.abs(g(X)).max()
    assert abs(f2(X[0])) < 1e-9 * np.abs(g(X, 2)).max()
    assert abs(left(f2, X[-1])) < 1e-9 * np.abs(g(X, 2)).max()
    xs = np.linspace(X[0], X[-1], 2001)
    assert np.abs(f.evaluate(xs) - g(xs)).max() < 1e-13 * scale
    # not-a-knot through the same samples is another curve
    other = SplineEnds().spline(X, g(X), left="linear", right="linear")
    assert np.abs(other.evaluate(xs) - g(xs)).max() > 1e-6 * scale
    # the linear tails continue with the end slopes: C² at the ends
    for x0, s in ((X[0] - 0.05, g(X[0], 1)), (X[-1] + 0.05, g(X[-1], 1))):
        end = X[0] if x0 < X[0] else X[-1]
        assert f(x0) == pytest.approx(g(end) + s * (x0 - end), rel=1e-12)


@pytest.mark.parametrize("slopes", [(0.0, 0.0), (-3.0e4, 2.5e5)])
def test_clamped_has_the_given_slopes_and_reproduces_a_cubic_with_them(slopes):
    """A cubic p with p'(x_0), p'(x_n) = slopes: the clamped spline through
    its samples is p (and its slopes are the given ones)."""
    x0, x1 = X[0], X[-1]
    # p(x) = a + s0 (x − x0) + b (x − x0)² + c (x − x0)³ with p'(x1) = s1
    c = 7.0e5
    h = x1 - x0
    b = (slopes[1] - slopes[0] - 3 * c * h * h) / (2 * h)
    p = np.polynomial.Polynomial([1.5, slopes[0], b, c])

    def P(x):
        return p(np.asarray(x) - x0)
    ends = SplineEnds("clamped", slopes)
    f = ends.spline(X, P(X), left="linear", right="linear")
    d = f.derivative()
    assert d(X[0]) == pytest.approx(slopes[0], abs=1e-9 * max(1.0, abs(slopes[0])))
    assert left(d, X[-1]) == pytest.approx(slopes[1], abs=1e-9 * max(1.0, abs(slopes[1])))
    xs = np.linspace(X[0], X[-1], 2001)
    assert np.abs(f.evaluate(xs) - P(xs)).max() < 1e-13 * np.abs(P(xs)).max()
    # outside the data: linear with the given slopes exactly (C¹)
    assert f(X[-1] + 0.1) - f(X[-1]) == pytest.approx(0.1 * slopes[1], abs=1e-9)
    assert f(X[0] - 0.1) - f(X[0]) == pytest.approx(-0.1 * slopes[0], abs=1e-9)


def scipy_close(coeffs, cs):
    """Interior coefficients (n − 1, 4) equal to SciPy's CubicSpline ``cs``
    to 1e-13 of each power's largest coefficient (our own tridiagonal
    solve, not SciPy's: equal up to round-off, not bit for bit)."""
    ref = cs.c[::-1].T
    scale = np.abs(ref).max(axis=0)
    return np.all(np.abs(coeffs - ref) <= 1e-13 * scale)


def test_not_a_knot_is_the_default_and_scipys():
    """The default is SciPy's not-a-knot spline, coefficient for coefficient
    to round-off, and reproduces a cubic."""
    y = RNG.normal(size=X.size)
    f = Curve(X, y).compile().value
    cs = CubicSpline(X, y, bc_type="not-a-knot")
    assert scipy_close(f.coeffs[1:-1], cs)
    assert np.array_equal(f.coeffs[-1], [y[-1], 0, 0, 0]) and not np.any(f.coeffs[0])
    law = LawBank([CurveLaw((X, y))])
    d1 = cs.derivative()
    tail = law.curve_springs[0].coeffs[0]
    assert tail[0] == y[0] and np.array_equal(tail[2:], [0, 0])
    assert tail[1] == pytest.approx(d1(X[0]), rel=1e-13)
    # the tail's slope is the first piece's slope at X[0]: C¹ exactly
    assert tail[1] == law.curve_springs[0].coeffs[1, 1]
    p = np.polynomial.Polynomial([0.3, -2.0, 40.0, -90.0])
    g = SplineEnds().spline(X, p(X), left="zero", right="hold")
    xs = np.linspace(X[0], X[-1], 501)
    assert np.abs(g.evaluate(xs) - p(xs)).max() < 1e-13


@pytest.mark.parametrize("n", [4, 5, 9])
@pytest.mark.parametrize("ends,bc_type", [
    (SplineEnds(), "not-a-knot"),
    (SplineEnds("natural"), "natural"),
    (SplineEnds("clamped", (0.0, 0.0)), ((1, 0.0), (1, 0.0))),
    (SplineEnds("clamped", (-3.0e4, 2.5e5)), ((1, -3.0e4), (1, 2.5e5))),
])
def test_each_end_condition_is_scipys_cubic_spline(ends, bc_type, n):
    """Each end condition against SciPy's CubicSpline with the matching
    bc_type, on uneven samples (n = 4 is the fewest a scene allows)."""
    x = np.sort(RNG.uniform(0.0, 1.0, n)) * 0.04 + np.linspace(0.0, 0.2, n)
    y = RNG.normal(size=n) * 1e3
    f = ends.spline(x, y, left="linear", right="linear")
    cs = CubicSpline(x, y, bc_type=bc_type)
    assert scipy_close(f.coeffs[1:-1], cs)
    d1 = cs.derivative()
    assert f.coeffs[0, 1] == pytest.approx(d1(x[0]), rel=1e-12, abs=1e-9)
    assert f.coeffs[-1, 1] == pytest.approx(d1(x[-1]), rel=1e-12, abs=1e-9)


@pytest.mark.parametrize("ends", [SplineEnds(), SplineEnds("natural"),
                                  SplineEnds("clamped", (0.0, 0.0))])
def test_input_curves_keep_zero_before_and_hold_after(ends):
    """Drive and force curves: zero before the first sample and the last
    value held after the last, whatever the end condition; clamped with
    slopes (0, 0) through a curve starting at 0 is C¹ at both ends."""
    t = np.array([0.01, 0.02, 0.03, 0.05, 0.06])
    v = np.array([0.0, 40.0, 100.0, 30.0, 20.0])
    f = Curve(t, v, ends).compile()
    assert f.breakpoints == (0.01, 0.06)
    assert f.value(0.0099) == 0.0 and f.value(0.07) == 20.0 and f.value(1.0) == 20.0
    assert np.allclose(f.values(t), v, rtol=0, atol=1e-12)
    d = f.value.derivative()
    if ends.condition == "clamped":
        assert abs(d(0.01)) < 1e-9 and abs(left(d, 0.06)) < 1e-9
    # the integrals stay exact: velocity after the curve = its integral
    assert f.first(0.07) == pytest.approx(f.first(0.06) + 20.0 * 0.01, rel=1e-13)


def test_spline_ends_checked_in_the_dataclass():
    with pytest.raises(SceneError, match="end_condition = 'periodic' must be one of"):
        SplineEnds("periodic")
    with pytest.raises(SceneError, match=r"end_slopes = \[1.0, 0.0\] apply to end_condition "
                                         r"= 'clamped', not 'natural'"):
        SplineEnds("natural", (1.0, 0.0))
    with pytest.raises(SceneError, match=r"end_slopes\[1\] = inf must be finite"):
        SplineEnds("clamped", (0.0, float("inf")))
    with pytest.raises(SceneError, match="must be two numbers"):
        SplineEnds("clamped", (0.0, 1.0, 2.0))


SCENE = base_and_body("ends") + """

[base]
motion = "driven"

[[base.drive]]
direction = "z"
shape = "curve"
time = [0.0, 0.01, 0.02, 0.03, 0.04, 0.05]
value = [0.0, 60.0, 150.0, 80.0, 10.0, 0.0]
DRIVE_ENDS

[solver]
t_end = 0.15
integrator = "dop853"
rtol = 1.0e-10
atol = 1.0e-12
output_dt = 1.0e-3
""" + four_mounts("""
law = "curve"
spring_curve = [SPRING, SPRING, SPRING]
damper_curve = [DAMPER, DAMPER, DAMPER]
""", corners=[(-0.2, -0.3), (0.2, -0.3), (-0.2, 0.3), (0.2, 0.3)], prefix="S")

SPRING = ("{deflection = [-0.02, -0.01, -0.004, 0.0, 0.004, 0.01, 0.02], "
          "force = [-3300.0, -1350.0, -506.4, 0.0, 506.4, 1350.0, 3300.0]SPRING_ENDS}")
DAMPER = "{rate = [-1.0, -0.3, 0.0, 0.3, 1.0], force = [-60.0, -15.0, 0.0, 15.0, 60.0]}"
ENDS = {"not-a-knot": ("", ""),
        "natural": ('end_condition = "natural"', ', end_condition = "natural"'),
        "clamped": ('end_condition = "clamped"\nend_slopes = [6000.0, -1000.0]',
                    ', end_condition = "clamped", end_slopes = [1.25e5, 1.25e5]')}


def scene_text(condition):
    drive, spring = ENDS[condition]
    return (SCENE.replace("SPRING", SPRING).replace("DAMPER", DAMPER)
            .replace("DRIVE_ENDS", drive).replace("SPRING_ENDS", spring))


def test_scene_file_reads_the_end_conditions(tmp_path):
    path = tmp_path / "ends.toml"
    path.write_text(scene_text("clamped"))
    sc = load_scene(path).scene
    assert sc.base.drives[0].shape.ends == SplineEnds("clamped", (6000.0, -1000.0))
    law = sc.mounts[0].laws[2]
    assert law.spring_ends == SplineEnds("clamped", (1.25e5, 1.25e5))
    assert law.damper_ends == SplineEnds()
    path.write_text(scene_text("natural"))
    assert load_scene(path).scene.mounts[3].laws[0].spring_ends.condition == "natural"


@pytest.mark.parametrize("old,new,says", [
    ('end_condition = "natural"', 'end_condition = "periodic"',
     "base.drive 1: end_condition = 'periodic' must be one of 'not-a-knot', 'natural', "
     "'clamped'"),
    ('end_condition = "natural"', 'end_condition = "natural"\nend_slopes = [0.0, 1.0]',
     "base.drive 1: end_slopes = [0.0, 1.0] applies to end_condition = 'clamped' only "
     "(end_condition is 'natural')"),
    (', end_condition = "natural"}', ', end_condition = "clamped", end_slopes = [1.0]}',
     "mount 'S1': spring_curve[0]: end_slopes = [1.0] must have 2 numbers, has 1"),
    (', end_condition = "natural"}', ', end_condition = 3}',
     "mount 'S1': spring_curve[0]: end_condition = 3 must be a string"),
    (', end_condition = "natural"}', ', end_slope = [1.0, 2.0]}',
     "mount 'S1': spring_curve[0]: unknown key 'end_slope'"),
])
def test_bad_end_conditions_refused_naming_file_entry_and_value(tmp_path, old, new, says):
    path = tmp_path / "ends.toml"
    text = scene_text("natural")
    assert old in text
    path.write_text(text.replace(old, new, 1))
    with pytest.raises(InputError) as exc:
        load_scene(path)
    assert str(exc.value).startswith(f"ends.toml: {says}"), str(exc.value)


def test_a_run_with_each_end_condition_works_end_to_end(tmp_path):
    """`flexbed simulate` of a driven base (curve data) on four curve-law
    mounts (spring and damper curves) with each end condition: complete,
    the energy balance closes (to 5e-7 of the drive's work of 9 kJ;
    measured 1.6e-8, 4.5e-8 and 3.3e-8 for not-a-knot, natural and
    clamped), and the end conditions change the motion."""
    z = {}
    for condition in ENDS:
        path = tmp_path / f"{condition}.toml"
        path.write_text(scene_text(condition))
        out = tmp_path / f"{condition}.h5"
        assert flexbed(["simulate", str(path), "-o", str(out), "--no-progress"]) == 0
        c = read_results(out)
        assert c.attrs[""]["complete"] is True
        b = c.get("energy/balance")
        work = np.abs(c.get("energy/work_drive")).max()
        drift = np.abs(b - b[0]).max() / work
        print(f"{condition}: energy balance drift {drift:.1e} of the drive's work {work:.3g} J")
        assert work > 1.0 and drift < 5e-7
        z[condition] = c.get("bodies/position")[:, 1, 2] - c.get("bodies/position")[:, 0, 2]
    assert np.abs(z["natural"] - z["not-a-knot"]).max() > 1e-6
    assert np.abs(z["clamped"] - z["not-a-knot"]).max() > 1e-6
