"""The frequency domain's searches end: round-off damping is no damping, and
the peak search stops at the spacing of doubles (issue 30: ``flexbed frf``
never finished on rigid rafts whose undamped modes came out with ζ = ±1e-16)."""

import numpy as np

from flexbed.dynamics.frequency.frf import PEAK_SEARCH_STEPS, peak_search
from flexbed.dynamics.frequency.modal import solve_modes
from flexbed.dynamics.frequency.mounted import MountedSystem


def two_masses(c: float) -> MountedSystem:
    """Two unit masses on springs of 4e4 and 9e4 N/m, only the first mode
    damped (modal damping c [N s/m]), in coordinates rotated by 0.3 rad so
    the eigensolver mixes the two and leaves round-off in the second."""
    th = 0.3
    R = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    z2 = np.zeros((0, 2))
    return MountedSystem(labels=("a x", "b x"), body=np.array([2, 3]), M=np.eye(2),
                         K=R @ np.diag([4e4, 9e4]) @ R.T, C=R @ np.diag([c, 0.0]) @ R.T,
                         K_elastic=np.zeros((2, 2)), D=z2, Dv=z2, Fq=z2, Fv=z2,
                         k_tangent=np.zeros(0), c_tangent=np.zeros(0), Bq=np.zeros((3, 2)),
                         Bv=np.zeros((3, 2)), iota=np.zeros((2, 3)), moving_mass=2.0,
                         y_eq=np.zeros(0), coords=None, evaluations=0)


def test_an_undamped_mode_beside_a_damped_one_has_zero_damping():
    m = solve_modes(two_masses(20.0))
    np.testing.assert_allclose(m.frequency, [200 / (2 * np.pi), 300 / (2 * np.pi)], rtol=1e-13)
    # the damped mode: ζ = c / (2 √(k m)) = 20 / 400, exactly as the eigenvalues give it
    assert abs(m.damping_ratio[0] - 0.05) < 1e-14
    # the undamped one: exactly zero, not ±1e-16 (which counted as damped, or growing)
    assert m.damping_ratio[1] == 0.0


def test_the_peak_search_stops_at_the_spacing_of_doubles():
    f0, width = 17.123456789, 1e-6
    calls = []

    def evaluate(x):
        calls.append(x.size)
        return (1.0 / ((x - f0) ** 2 + width ** 2))[:, None]

    # a tolerance of 2e-18 Hz, far below the spacing of doubles near 17 Hz (3.6e-15)
    fp = peak_search(evaluate, np.array([17.0]), np.array([17.3]), np.array([2e-18]),
                     np.array([0]))
    assert abs(fp[0] - f0) <= 8 * np.spacing(17.3)
    # 2 first evaluations and one a step: log(0.3 / (8 × 3.55e-15)) / log(1.618) = 62.3,
    # so 63 steps
    assert len(calls) == 2 + 63 < PEAK_SEARCH_STEPS


def test_the_peak_search_keeps_its_tolerance_where_it_is_coarse():
    f0 = 10.0

    def evaluate(x):
        return (-(x - f0) ** 2)[:, None]

    fp = peak_search(evaluate, np.array([9.0]), np.array([12.0]), np.array([1e-3]),
                     np.array([0]))
    assert abs(fp[0] - f0) <= 0.5e-3
