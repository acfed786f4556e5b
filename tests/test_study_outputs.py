"""A study point's run (issue 30, part 5): :class:`flexbed.study.outputs.PointRun`
evaluates only what the metrics read, and what it gives equals
:func:`flexbed.simulate`'s results bit for bit — the points on the
equipment (its own kinematics), a point on the bed (the whole results,
built on demand), the mounts' forces and deflections, any other attribute
— while a study of peaks never builds the whole results.

The reference scene (rigid bed) and a flexible variant, over 0.05 s."""

from __future__ import annotations

import numpy as np
import pytest

import flexbed
from flexbed.api.simulation import solved
from flexbed.study.analyses import ANALYSES
from flexbed.study.metrics import PeakMotion, PeakMount, peak_norm
from flexbed.study.outputs import PointRun
from flexbed.study.point import run_point

T_END = 0.05

POINTS = [("equipment A", (0.0, 0.0, 0.15), "bed"),         # the scene's "A top"
          ("equipment B", (0.1, -0.05, 0.2), None),
          ("equipment B", (0.0, 0.0, 0.0), "equipment A"),
          ("bed", (0.3, 1.0, 0.05), None),                    # on the bed: the whole results
          ("equipment A", (0.0, 0.0, 0.15), "base")]


def _pair(scene, **kw):
    st = flexbed.statics(scene, **kw)
    lazy = PointRun(*solved(scene, equilibrium=st, t_end=T_END, **kw))
    full = flexbed.simulate(scene, equilibrium=st, t_end=T_END, **kw)
    return lazy, full


def _same(a: np.ndarray, b: np.ndarray) -> None:
    assert a.shape == b.shape
    assert np.array_equal(a, b), float(np.max(np.abs(a - b)))


@pytest.fixture(scope="module")
def rigid():
    return _pair(flexbed.load_scene())


def _same_points_and_mounts(lazy, full):
    """Every point of POINTS and the mount forces, bit for bit."""
    for body, xyz, rel in POINTS:
        a = lazy.point(body, xyz, relative_to=rel)
        b = full.point(body, xyz, relative_to=rel)
        for key in ("position", "velocity", "acceleration"):
            _same(getattr(a, key), getattr(b, key))
        # the positions alone (a peak displacement's), from a run not asked before
        fresh = PointRun(lazy.scene, lazy.system, lazy.sim, lazy.modes)
        _same(fresh.point_position(body, xyz, relative_to=rel), b.position)
    _same(lazy.mount_force, full.mount_force)


def test_points_and_mounts_equal_the_results_bit_for_bit(rigid):
    lazy, full = rigid
    _same_points_and_mounts(lazy, full)
    _same(lazy.mount_deflection, full.mount_deflection)
    _same(lazy.t, full.t)
    # any other attribute: the whole results'
    _same(lazy.angular_velocity, full.angular_velocity)
    _same(lazy["energy/balance"], full["energy/balance"])
    assert lazy.complete and lazy.message == full.message


def test_the_mounts_alone_equal_the_whole_right_hand_side_s_bit_for_bit(rigid):
    """A run asked for its mount forces and deflections alone evaluates the
    right-hand side only as far as the mount forces (``mounts_only``): the
    same numbers as the results file's; the system's right-hand side after
    it is whole again (the flag is reset)."""
    lazy, full = rigid
    fresh = PointRun(lazy.scene, lazy.system, lazy.sim, lazy.modes)
    _same(fresh.mount_force, full.mount_force)
    _same(fresh.mount_deflection, full.mount_deflection)
    assert "_captured" not in vars(fresh)
    system, Y = fresh.system, fresh._Y
    dY, cap = system.rhs_batch(fresh.t, Y, ("w_f", "w_acc"))
    for i in (0, Y.shape[0] // 2, Y.shape[0] - 1):
        _same(dY[i], system.rhs(fresh.t[i], Y[i]))
    none, mounts = system.rhs_batch(fresh.t, Y, ("w_f",), mounts_only=True)
    assert none is None
    _same(mounts["w_f"], cap["w_f"])
    _same(system.rhs_batch(fresh.t, Y, ("w_f", "w_acc"))[0], dY)


def test_the_peaks_are_numpy_s_norms_bit_for_bit(rigid):
    """The metrics' peaks (:func:`peak_norm`: the squares summed, one root)
    equal the largest of ``np.linalg.norm`` bit for bit: on the run's
    mount forces and points, and on numbers spread over 300 decades."""
    lazy, full = rigid
    f = full.mount_force
    want = np.linalg.norm(f, axis=2).max(axis=0)
    _same(peak_norm(f), want)
    force = PeakMount("peak_mount_force", tuple(range(12)), tuple(f"M{i}" for i in range(1, 13)),
                      None, None)
    assert force.values({"simulate": lazy}) == tuple(float(x) for x in want)
    for body, xyz, rel in POINTS:
        x = full.point(body, xyz, relative_to=rel).position
        peak = PeakMotion("peak_displacement", "p", body, xyz, rel, None)
        assert peak.values({"simulate": lazy}) == \
            (float(np.linalg.norm(x - x[0], axis=1).max()),)
    rng = np.random.default_rng(5)
    v = rng.normal(size=(4000, 7, 3)) * 10.0 ** rng.uniform(-150, 150, size=(4000, 7, 1))
    _same(peak_norm(v), np.linalg.norm(v, axis=2).max(axis=0))


def test_a_study_of_peaks_on_the_equipment_builds_no_results():
    scene = flexbed.load_scene()
    st = flexbed.statics(scene)
    run = PointRun(*solved(scene, equilibrium=st, t_end=T_END))
    outcomes = {"simulate": run}
    peak = PeakMotion("peak_displacement", "A", "equipment A", (0.0, 0.0, 0.15), "bed", None)
    force = PeakMount("peak_mount_force", tuple(range(12)), tuple(f"M{i}" for i in range(1, 13)),
                      None, None)
    peak.values(outcomes)
    force.values(outcomes)
    assert "_results" not in vars(run)
    # a peak displacement reads the poses alone (no velocities, no accelerations)
    assert "_kinematics" not in vars(run)
    assert "_captured" not in vars(run)          # the right-hand side as far as the mounts
    run.point("bed", (0.0, 0.0, 0.05))
    assert "_results" in vars(run)


def test_the_kept_results_file_is_simulate_s(tmp_path):
    scene = flexbed.vary(flexbed.load_scene(), {"solver.t_end": T_END})
    res = run_point(scene, ("static", "simulate"), (), keep=True)
    assert res.status == "ok", res.message
    writer, args = res.files["results.h5"]
    full = flexbed.simulate(scene, equilibrium=flexbed.statics(scene))
    datasets, attrs = args
    want, want_attrs = full._datasets
    assert set(datasets) == set(want)
    for key in want:
        a, b = np.asarray(datasets[key].data), np.asarray(want[key].data)
        assert a.dtype == b.dtype and (np.array_equal(a, b) if a.dtype.kind in "fiub"
                                       else (a == b).all()), key
    assert ANALYSES["simulate"].files is not None


@pytest.mark.slow
def test_a_flexible_bed_s_points_equal_the_results_bit_for_bit():
    scene = flexbed.vary(flexbed.load_scene(), {"bed.model": "flexible"})
    lazy, full = _pair(scene, modes=flexbed.modes(scene))
    _same_points_and_mounts(lazy, full)


def test_a_point_asked_again_is_checked_as_the_api_checks_it(rigid):
    """A run keeps the points it was asked for, checked: asked again (a
    study's metric, every point) it answers the same; a value the API
    refuses is refused even where an equal-comparing one was kept (True
    == 1, 1 == 1.0)."""
    lazy, full = rigid
    body, xyz, rel = POINTS[0]
    first = lazy.point_position(body, xyz, relative_to=rel)
    _same(lazy.point_position(body, tuple(xyz), relative_to=rel), first)
    lazy.point_position(body, (1, 0, 0))
    with pytest.raises(flexbed.InputError, match="position"):
        lazy.point_position(body, (True, 0, 0))
    with pytest.raises(flexbed.InputError, match="position"):
        lazy.point_position(body, (float("nan"), 0.0, 0.0))
