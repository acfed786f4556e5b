"""The stiffness check's stable step (flexbed.dynamics.stiffness.stable_step)
gives the same answer as searching every eigenvalue's direction by the
grid-and-bisection it was first written as, at a fraction of the cost."""

import math

import numpy as np
import pytest

from flexbed.dynamics.stiffness import _RADIUS_BOUNDS, _STABILITY, stable_step


def _reference(method, eigenvalues):
    """Every eigenvalue searched: the first radius along its direction where
    |R| exceeds 1, on a grid of |hλ| up to 10, then 40 bisections; returns
    (h, rate) and the radii."""
    poly = _STABILITY[method]
    lam = np.asarray(eigenvalues, dtype=complex).ravel()
    lam = lam[np.isfinite(lam)]
    lam = np.minimum(lam.real, 0.0) + 1j * np.abs(lam.imag)
    mag = np.abs(lam)
    lam, mag = lam[mag > 0], mag[mag > 0]
    if lam.size == 0:
        return (math.inf, 0.0), np.zeros(0)
    d = lam / mag

    def unstable(r):
        z = r * (d if r.ndim == 1 else d[:, None])
        return np.abs(np.polyval(poly, z)) > 1.0 + 1e-12

    grid = np.linspace(0.0, 10.0, 1001)[1:]
    first = np.argmax(unstable(np.broadcast_to(grid, (d.size, grid.size))), axis=1)
    lo = np.where(first > 0, grid[first - 1], 0.0)
    hi = grid[first]
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        bad = unstable(mid)
        hi = np.where(bad, mid, hi)
        lo = np.where(bad, lo, mid)
    h = lo / mag
    k = int(np.argmin(h))
    return (float(h[k]), float(mag[k])), lo


def _same(got, ref):
    """The same step within the bisection's own resolution (1e-14 of |hλ|),
    set by the same eigenvalue."""
    assert got[1] == ref[1]
    assert got[0] == pytest.approx(ref[0], rel=1e-12)


@pytest.mark.parametrize("method", ["rk4", "dop853"])
def test_the_radius_bounds_hold_in_every_direction(method):
    theta = np.linspace(np.pi / 2, np.pi, 4001)
    _, radii = _reference(method, np.cos(theta) + 1j * np.sin(theta))
    lo, hi = _RADIUS_BOUNDS[method]
    assert radii.size == theta.size
    assert lo < radii.min() and radii.max() < hi
    # the margins are small: the bounds prune well
    assert radii.min() < 1.06 * lo and radii.max() > 0.95 * hi


@pytest.mark.parametrize("method", ["rk4", "dop853"])
@pytest.mark.parametrize("seed", range(6))
def test_same_answer_as_searching_every_eigenvalue(method, seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 120))
    scale = 10.0 ** rng.uniform(-1, 6, size=n)
    kind = seed % 3
    if kind == 0:       # lightly damped oscillators: pairs near the imaginary axis
        zeta = 10.0 ** rng.uniform(-4, -0.5, size=n)
        lam = scale * (-zeta + 1j * np.sqrt(1 - zeta ** 2))
        lam = np.concatenate([lam, lam.conj()])
    elif kind == 1:     # anywhere, growing ones included
        lam = scale * np.exp(1j * rng.uniform(0, 2 * np.pi, size=n))
    else:               # a cluster at the top (many candidates), zeros, nan
        lam = -1e4 * (1 + 0.1 * rng.random(n)) + 1e4j * rng.random(n)
        lam = np.concatenate([lam, [0.0, np.nan, 3.0]])
    _same(stable_step(method, lam), _reference(method, lam)[0])


def test_same_answer_on_a_damped_flexible_bed(beta20_eigenvalues):
    for method in ("rk4", "dop853"):
        _same(stable_step(method, beta20_eigenvalues), _reference(method, beta20_eigenvalues)[0])


@pytest.fixture(scope="module")
def beta20_eigenvalues(beta20):
    from flexbed.dynamics.stiffness import motion_eigenvalues

    _, _, system, y = beta20
    return motion_eigenvalues(system, y)
