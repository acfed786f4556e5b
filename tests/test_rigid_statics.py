"""The compiled pieces of the statics' Newton–Raphson for rigid scenes
(:mod:`flexbed.dynamics.rigid_statics`, issue 30, part 5) against the NumPy
code they stand for: the tangent stiffness against
:func:`flexbed.dynamics.tangent.tangent` to 1e-14 of its largest entry (the
same formulas; NumPy's stacked 3 × 3 products may sum in another order),
the state update against :func:`flexbed.dynamics.jacobian.perturbed_positions`
bit for bit; and that the statics take them where they apply."""

from __future__ import annotations

import numpy as np
import flexbed
from flexbed.api.bed_modes import compiled
from flexbed.dynamics import statics as statics_module
from flexbed.dynamics.jacobian import perturbed_positions
from flexbed.dynamics.rigid_statics import step_state
from flexbed.dynamics.statics import _rigid_jacobian, _rigid_only, solve_statics
from flexbed.dynamics.tangent import tangent

from scene_text import base_and_body, four_mounts

#: a tilted, off-centre body on polynomial mounts with bump stops in contact at rest
POLY_STOPS = base_and_body("poly", mass=80.0, inertia="[3.0, 4.0, 5.0]") + four_mounts(
    'law = "polynomial"\n'
    'stiffness = [[0.0, 2.0e4, 0.0, 1.0e8], [0.0, 3.0e4], [0.0, 5.0e4, 4.0e5]]\n'
    'bump_stop = {direction = 3, gap_compression = 0.002, stiffness = 1.0e6}',
    corners=((-0.25, -0.15), (0.3, -0.2), (0.2, 0.25), (-0.2, 0.1)))


def _scenes(tmp_path):
    path = tmp_path / "poly.toml"
    path.write_text(POLY_STOPS)
    return [flexbed.load_scene(), flexbed.load_scene(path)]


def _states(system):
    """The start, a state with every body moved and turned, the equilibrium."""
    y = system.initial_state()
    y[system.layout.nq:] = 0.0
    step = 0.01 * np.cos(np.arange(6 * system.n_rigid) + 0.3)
    moved = perturbed_positions(system, y, step[None, :])[0]
    eq = solve_statics(system)
    assert eq.success, eq.message
    return [y, moved, eq.y]


def test_the_compiled_tangent_is_the_numpy_one(tmp_path):
    for scene in _scenes(tmp_path):
        system = compiled(scene, None)
        assert _rigid_only(system)
        for y in _states(system):
            want = tangent(system, y, dense=True, rates=False).Kq
            system.rhs(0.0, y)           # the tangent is taken at the last evaluation's state
            got = _rigid_jacobian(system)
            assert got.shape == want.shape
            assert np.max(np.abs(got - want)) <= 1e-14 * np.max(np.abs(want))


def test_the_compiled_state_update_is_perturbed_positions_bit_for_bit(tmp_path):
    rng = np.random.default_rng(7)
    for scene in _scenes(tmp_path):
        system = compiled(scene, None)
        n = system.n_rigid
        for y in _states(system):
            for scale in (1e-12, 1e-4, 0.3):
                dx = scale * rng.standard_normal(6 * n)
                dx[3:6] = 0.0                          # a body not turned: p(0) = 1
                got = np.empty_like(y)
                step_state(y, system.layout.q_rigid.start, n, dx, got)
                assert np.array_equal(got, perturbed_positions(system, y, dx[None, :])[0])


def test_the_statics_take_the_compiled_pieces_where_they_apply(monkeypatch):
    """A rigid scene: no NumPy tangent and no perturbed_positions called, the
    same equilibrium as the NumPy path's to round-off (1e-12 m, rad)."""
    system = compiled(flexbed.load_scene(), None)
    with monkeypatch.context() as mp:
        mp.setattr(statics_module, "_rigid_only", lambda s: False)
        numpy_path = solve_statics(system)
    assert solve_statics(system).history == numpy_path.history
    with monkeypatch.context() as mp:
        def refuse(*a, **k):
            raise AssertionError("the NumPy path was taken")
        mp.setattr(statics_module, "tangent", refuse)
        mp.setattr(statics_module, "perturbed_positions", refuse)
        fast = solve_statics(system)
    assert fast.success and fast.jacobian is not None
    pa, qa = system.poses(fast.y)
    pb, qb = system.poses(numpy_path.y)
    assert np.max(np.abs(pa - pb)) < 1e-12 and np.max(np.abs(qa - qb)) < 1e-12
    assert fast.iterations == numpy_path.iterations


def test_a_load_on_a_body_keeps_the_numpy_tangent():
    """The tangent's own terms of a loaded body are not compiled: such a
    scene takes the NumPy path (:func:`_rigid_only` is False)."""
    from flexbed.dynamics.body_loads import BodyLoad
    from flexbed.dynamics.laws import LinearLaw
    from flexbed.dynamics.scene import Base, Body, Mount, Scene
    from flexbed.dynamics.system import System
    from flexbed.dynamics.time_functions import Curve
    bodies = (Body("ground", 1e3, (1.0, 1.0, 1.0), (0, 0, 0)),
              Body("box", 50.0, (2.0, 3.0, 4.0), (0, 0, 1.0)))
    mounts = tuple(Mount(f"m{i}", "ground", "box", (x, y, 1.0), (x, y, 0), np.eye(3),
                         (LinearLaw(2e4, 0.0),) * 3)
                   for i, (x, y) in enumerate([(-0.3, -0.2), (-0.3, 0.2), (0.3, -0.2),
                                               (0.3, 0.2)]))
    plain = Scene(bodies, Base("fixed"), mounts, (0.0, 0.0, -9.81), "box")
    assert _rigid_only(System(plain))
    load = BodyLoad("box", (0.1, 0.0, 0.0), 2, Curve(np.arange(4.0), np.full(4, 5.0)))
    loaded = Scene(bodies, Base("fixed"), mounts, (0.0, 0.0, -9.81), "box", loads=(load,))
    assert not _rigid_only(System(loaded))


def test_the_equilibrium_keeps_the_mounts_at_rest_as_observed(tmp_path):
    """``Equilibrium.mounts`` (the deflections and forces the plausibility
    check and a study's static metrics read) are observe's at the
    equilibrium bit for bit; a failed solve keeps none."""
    for scene in _scenes(tmp_path):
        system = compiled(scene, None)
        eq = solve_statics(system)
        obs = system.observe(0.0, eq.y)
        dx, f = eq.mounts
        assert np.array_equal(dx, obs.dx) and np.array_equal(f, obs.f)
        failed = solve_statics(system, max_iter=1)
        assert not failed.success and failed.mounts is None
