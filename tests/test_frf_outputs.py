"""FRF outputs besides acceleration (velocity, displacement, relative
displacement, mount deflection) and the isolation crossing, against the
closed forms of a one-stage isolator (issue 25, part 5).

The body on four mounts of :mod:`test_modal` moves vertically alone under a
vertical base acceleration: with ``G = k − mω² + iωc`` (k, c the four
mounts' sums), the body's acceleration is ``T = (k + iωc)/G`` per unit
base acceleration, its displacement ``−T/ω²``, its velocity ``T/(iω)``,
its displacement relative to the base (and each mount's deflection along
its third axis, the mount's body j moving against body i)
``(T − 1)(−1/ω²) = −m/G``; |T| = 1 at ω = √2 ωₙ whatever the damping.
"""

import math

import numpy as np
import pytest

from scene_text import KZ, M1, load_text, one_stage


@pytest.fixture(scope="module")
def isolator(tmp_path_factory):
    return load_text(tmp_path_factory.mktemp("iso"), one_stage(2e-3))


def _exact(f, beta=2e-3):
    om = 2 * math.pi * np.asarray(f)
    kz, cz = 4 * KZ, 4 * beta * KZ
    G = kz - M1 * om**2 + 1j * om * cz
    return om, (kz + 1j * om * cz) / G, G


def test_velocity_displacement_relative_and_deflection(isolator):
    import flexbed
    fn = math.sqrt(4 * KZ / M1) / (2 * math.pi)
    f = fn * np.array([0.1, 0.7, 0.999, 1.0, 1.3, 4.0])
    om, T, G = _exact(f)
    pts = [("c", "mass", [0, 0, 0])]
    v = flexbed.frf(isolator, points=pts, frequencies=f, quantity="velocity")
    np.testing.assert_allclose(v.H[:, v.column("c vz")], T / (1j * om), rtol=1e-10)
    assert v.units[v.column("c vz")] == "s"
    d = flexbed.frf(isolator, points=pts, frequencies=f, quantity="displacement",
                    deflections=True)
    np.testing.assert_allclose(d.H[:, d.column("c dz")], -T / om**2, rtol=1e-10)
    # each mount's third-axis deflection: l = body point − base point grows as the
    # body rises against the base, by (T − 1)(−1/ω²) = −m/G per unit base acceleration
    for k in range(1, 5):
        np.testing.assert_allclose(d.H[:, d.column(f"M{k} d3")], -M1 / G, rtol=1e-9)
        assert np.all(np.abs(d.H[:, d.column(f"M{k} d1")]) < 1e-9 * np.abs(M1 / G))
    r = flexbed.frf(isolator, points=[("c", "mass", [0, 0, 0], "base")], frequencies=f,
                    quantity="displacement")
    np.testing.assert_allclose(r.H[:, r.column("c@base dz")], -M1 / G, rtol=1e-9)


def test_isolation_crossing_is_located_between_grid_points(isolator):
    import flexbed
    fn = math.sqrt(4 * KZ / M1) / (2 * math.pi)
    t = flexbed.frf(isolator, points=[("c", "mass", [0, 0, 0])], band=(1.0, 40.0), n=60)
    j = t.column("c az")
    cross = t.result.isolation_from[j]
    assert cross == pytest.approx(math.sqrt(2) * fn, rel=1e-11)
    assert not np.any(np.isclose(t.frequency, cross, rtol=1e-6))     # not a grid point
    assert np.isnan(t.result.isolation_from[t.column("c ax")])


def test_bad_quantity_is_one_line():
    import flexbed
    from flexbed.errors import InputError
    with pytest.raises(InputError, match="quantity = 'jerk'"):
        flexbed.frf(flexbed.load_scene(), quantity="jerk")


def test_the_frf_file_stores_the_crossing(isolator, tmp_path):
    import h5py

    import flexbed
    t = flexbed.frf(isolator, points=[("c", "mass", [0, 0, 0])], band=(1.0, 40.0), n=60)
    path, _ = t.save(tmp_path / "iso")
    with h5py.File(path) as f:
        assert list(f["isolation/output"][()]) == [t.column("c az")]
        assert f["isolation/frequency"][0] == t.result.isolation_from[t.column("c az")]
        assert f["isolation/frequency"].attrs["units"] == "Hz"


def test_stacked_states_and_poses_are_each_row_s():
    """The point Jacobians' perturbed states made in one pass
    (``MountedSystem.states``, ``System.poses`` of a stack) are, row by
    row, the single state's numbers bit for bit (rotations included, with
    the compiled pass above 8 rows)."""
    from flexbed.analyses.modal import mounted
    from flexbed.dynamics.statics import solve_statics
    from flexbed.files.scene import load_scene
    from flexbed.stages.system import compile_scene
    sf = load_scene()
    system = compile_scene(sf)
    ms = mounted(sf, system, y_eq=solve_statics(system, tol=sf.solver.static_tol).y).ms
    rng = np.random.default_rng(3)
    for k in (3, 12):                                    # NumPy's path, the compiled one
        Q = rng.normal(scale=1e-3, size=(k, ms.n))
        Y = ms.states(Q)
        pos, p = system.poses(Y)
        for i in range(k):
            y = ms.state(Q[i])
            assert Y[i].tobytes() == y.tobytes()
            r1, p1 = system.poses(y)
            assert pos[i].tobytes() == r1.tobytes() and p[i].tobytes() == p1.tobytes()
