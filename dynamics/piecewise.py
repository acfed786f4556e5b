"""Piecewise polynomials with polynomial tails and exact antiderivatives.

One representation serves every tabulated or piecewise-defined function of
the scene: pulse shapes of the base drive (piecewise linear accelerations),
cubic-spline curve data (drives, loads, mount curves) and their exact
integrals (velocity, displacement, mount potential).

A function with breaks ``b_0 < ... < b_n`` has ``n + 2`` pieces: the left
tail (``x < b_0``, local variable ``x - b_0``), the ``n`` interior pieces
(``b_k <= x < b_{k+1}``, local variable ``x - b_k``) and the right tail
(``x >= b_n``, local variable ``x - b_n``). Coefficients are ascending powers.
"""

from __future__ import annotations

from bisect import bisect_left, bisect_right

import numpy as np
from scipy.interpolate import CubicSpline

__all__ = ["PiecewisePolynomial", "spline_with_tails", "END_CONDITIONS"]

END_CONDITIONS = ("not-a-knot", "natural", "clamped")


class PiecewisePolynomial:
    """f(x) defined piecewise by polynomials.

    Parameters
    ----------
    breaks : array_like, shape (n + 1,)
        Strictly increasing break points.
    coeffs : array_like, shape (n + 2, d + 1)
        Ascending coefficients of each piece in its local variable (see the
        module docstring): row 0 the left tail, rows 1..n the interior
        pieces, row n + 1 the right tail.
    """

    __slots__ = ("breaks", "coeffs", "origins", "_b", "_c", "_o")

    def __init__(self, breaks, coeffs):
        b = np.array(breaks, dtype=float).reshape(-1)
        c = np.array(coeffs, dtype=float)
        if c.ndim != 2 or c.shape[0] != b.size + 1:
            raise ValueError(f"coeffs must have shape ({b.size + 1}, d + 1), got {c.shape}")
        if b.size < 1 or np.any(np.diff(b) <= 0):
            raise ValueError("breaks must be strictly increasing")
        self.breaks = b
        self.coeffs = c
        self.origins = np.concatenate([b[:1], b])
        for arr in (self.breaks, self.coeffs, self.origins):
            arr.setflags(write=False)
        # plain Python copies for the scalar hot path
        self._b = b.tolist()
        self._c = [tuple(row[::-1]) for row in c.tolist()]   # descending for Horner
        self._o = self.origins.tolist()

    @property
    def degree(self) -> int:
        return self.coeffs.shape[1] - 1

    def __call__(self, x: float, seg_end: float | None = None) -> float:
        """Value at a scalar x (pure Python: cheap on the hot path).

        Right-continuous at the breaks, except at or beyond ``seg_end`` (the
        end of the segment an integrator is stepping through), where the
        piece to the left is used: the limit from inside the segment.
        """
        if seg_end is not None and x >= seg_end:
            k = bisect_left(self._b, x)
        else:
            k = bisect_right(self._b, x)
        u = x - self._o[k]
        acc = 0.0
        for c in self._c[k]:
            acc = acc * u + c
        return acc

    def evaluate(self, x) -> np.ndarray:
        """Values at an array x (vectorised)."""
        x = np.asarray(x, dtype=float)
        k = np.searchsorted(self.breaks, x, side="right")
        u = x - self.origins[k]
        c = self.coeffs[k]
        acc = np.zeros_like(u)
        for j in range(self.coeffs.shape[1] - 1, -1, -1):
            acc = acc * u + c[..., j]
        return acc

    def derivative(self) -> "PiecewisePolynomial":
        d = self.coeffs.shape[1] - 1
        if d == 0:
            return PiecewisePolynomial(self.breaks, np.zeros((self.coeffs.shape[0], 1)))
        powers = np.arange(1, d + 1)
        return PiecewisePolynomial(self.breaks, self.coeffs[:, 1:] * powers)

    def antiderivative(self, x_ref: float | None = None) -> "PiecewisePolynomial":
        """The exact, continuous antiderivative F.

        F(b_0) = 0 (so a function that is zero left of b_0 has an integral that
        is zero there too), unless ``x_ref`` is given: then F(x_ref) = 0.
        """
        c = self.coeffs
        n_pieces, d1 = c.shape
        powers = np.arange(1, d1 + 1)
        out = np.zeros((n_pieces, d1 + 1))
        out[:, 1:] = c / powers
        # left tail: F(b0) = 0 -> constant 0 in its local variable (x - b0)
        # interior piece k (1-based row) starts at its origin with the running value
        running = 0.0
        b = self.breaks
        for row in range(1, n_pieces):
            out[row, 0] = running
            if row < n_pieces - 1:
                h = b[row] - b[row - 1]
                running = float(np.polyval(out[row, ::-1], h))
        f = PiecewisePolynomial(self.breaks, out)
        if x_ref is not None:
            shift = f(float(x_ref))
            out[:, 0] -= shift
            f = PiecewisePolynomial(self.breaks, out)
        return f


def spline_with_tails(x, y, *, left: str, right: str, end: str = "not-a-knot",
                      slopes=(0.0, 0.0)) -> PiecewisePolynomial:
    """Cubic spline through (x, y) with chosen end conditions and tails.

    Parameters
    ----------
    x, y : array_like, shape (n,)
        Samples, x strictly increasing, n >= 4.
    left, right : {"zero", "hold", "linear"}
        Tail rule: zero; the end value held; linear with the end slope.
    end : {"not-a-knot", "natural", "clamped"}
        The spline's end conditions: third derivative continuous at the
        second and last-but-one samples; zero second derivative at both
        ends; the first derivative at the ends given by ``slopes``.
    slopes : (float, float)
        End slopes (dy/dx at x[0] and x[-1]) of ``"clamped"`` [unit of y per
        unit of x]; ignored otherwise.
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if end == "clamped":
        bc = ((1, float(slopes[0])), (1, float(slopes[1])))
    elif end in END_CONDITIONS:
        bc = end
    else:
        raise ValueError(f"unknown end condition {end!r}")
    cs = CubicSpline(x, y, bc_type=bc)
    interior = cs.c[::-1].T                          # (n - 1, 4) ascending
    if end == "clamped":
        end_slope = (float(slopes[0]), float(slopes[1]))
    else:
        d1 = cs.derivative()
        end_slope = (float(d1(x[0])), float(d1(x[-1])))

    def tail(rule: str, slope: float, value: float) -> list[float]:
        if rule == "zero":
            return [0.0, 0.0, 0.0, 0.0]
        if rule == "hold":
            return [value, 0.0, 0.0, 0.0]
        if rule == "linear":
            return [value, slope, 0.0, 0.0]
        raise ValueError(f"unknown tail rule {rule!r}")

    coeffs = np.vstack([tail(left, end_slope[0], y[0]), interior,
                        tail(right, end_slope[1], y[-1])])
    return PiecewisePolynomial(x, coeffs)
