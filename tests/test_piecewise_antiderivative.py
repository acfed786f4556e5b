"""The vectorised antiderivative of a piecewise polynomial against its
definition, piece by piece: F at each interior break is F at the previous
break plus the integral of that piece over its width."""

import numpy as np
import pytest

from flexbed.dynamics.piecewise import PiecewisePolynomial, spline_with_tails


def _by_pieces(f: PiecewisePolynomial) -> np.ndarray:
    """The antiderivative's coefficients, one piece at a time (the definition)."""
    c = f.coeffs
    out = np.zeros((c.shape[0], c.shape[1] + 1))
    out[:, 1:] = c / np.arange(1, c.shape[1] + 1)
    running = 0.0
    for row in range(1, c.shape[0]):
        out[row, 0] = running
        if row < c.shape[0] - 1:
            running = float(np.polyval(out[row, ::-1], f.breaks[row] - f.breaks[row - 1]))
    return out


@pytest.mark.parametrize("seed", range(6))
def test_antiderivative_equals_the_piecewise_definition(seed):
    """Random splines (4 to 3000 samples, uneven spacing, every end
    condition): the coefficients of F and of its antiderivative agree with
    the piece-by-piece sums to round-off, F is continuous at every break to
    round-off, and F' = f."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(4, 3000))
    x = np.cumsum(rng.uniform(1e-3, 1.0, n)) - 0.3
    y = rng.normal(size=n)
    end = ("not-a-knot", "natural", "clamped")[seed % 3]
    f = spline_with_tails(x, y, left="zero", right=("hold", "linear")[seed % 2], end=end,
                          slopes=(0.7, -0.2))
    F = f.antiderivative()
    ref = _by_pieces(f)
    scale = np.abs(ref).max()
    assert np.max(np.abs(F.coeffs - ref)) <= 1e-13 * scale
    G = F.antiderivative()
    assert np.max(np.abs(G.coeffs - _by_pieces(F))) <= 1e-13 * np.abs(G.coeffs).max()
    # continuity at the interior breaks: the left piece's end value equals the right's start
    b = F.breaks
    left = np.array(
        [np.polyval(F.coeffs[k][::-1], b[k] - F.origins[k]) for k in range(1, b.size)])
    assert np.max(np.abs(left - F.coeffs[2:, 0])) <= 1e-12 * scale
    assert np.allclose(F.derivative().coeffs, f.coeffs, rtol=1e-14, atol=1e-14)


def test_antiderivative_reference_point():
    """With x_ref, F(x_ref) = 0 and F differs from the default by a constant."""
    x = np.linspace(0.0, 2.0, 40)
    f = spline_with_tails(x, np.cos(3 * x), left="zero", right="hold")
    F0, F1 = f.antiderivative(), f.antiderivative(x_ref=1.234)
    assert F1(1.234) == pytest.approx(0.0, abs=1e-15)
    xs = np.linspace(-1.0, 3.0, 101)
    d = F0.evaluate(xs) - F1.evaluate(xs)
    assert np.ptp(d) < 1e-14 and d[0] == pytest.approx(F0(1.234), abs=1e-15)
    # F(2) − F(0) is ∫ cos 3x = sin(6)/3, to the spline's accuracy
    assert F0(2.0) == pytest.approx(np.sin(6.0) / 3.0, abs=1e-5)
