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
from scipy.linalg import solve_banded   # loaded anyway by numba; scipy.interpolate is not

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
        # each interior piece's increase over its length (Horner, all at once)
        h = np.diff(self.breaks)
        rise = np.zeros(h.size)
        for j in range(d1, 0, -1):
            rise = (rise + out[1:n_pieces - 1, j]) * h
        out[1:, 0] = np.concatenate([[0.0], np.cumsum(rise)])
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
    if end not in END_CONDITIONS:
        raise ValueError(f"unknown end condition {end!r}")
    s = _spline_slopes(x, y, end, slopes)
    h = np.diff(x)
    m = np.diff(y) / h
    t = (s[:-1] + s[1:] - 2.0 * m) / h
    interior = np.column_stack([y[:-1], s[:-1], (m - s[:-1]) / h - t, t / h])   # (n - 1, 4)
    end_slope = (float(s[0]), float(s[-1]))

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


def _spline_slopes(x: np.ndarray, y: np.ndarray, end: str, slopes) -> np.ndarray:
    """The slopes s_i = f'(x_i), shape (n,), of the C² cubic spline through
    (x, y) with end conditions ``end`` (see :func:`spline_with_tails`).

    Continuity of f'' at the interior samples gives, with h_i = x_{i+1} − x_i
    and the secant slopes m_i = (y_{i+1} − y_i)/h_i, the tridiagonal rows
    h_i s_{i−1} + 2(h_{i−1} + h_i) s_i + h_{i−1} s_{i+1} = 3(h_i m_{i−1} + h_{i−1} m_i),
    i = 1 … n−2; the end rows are not-a-knot (f''' continuous at x_1 and
    x_{n−2}, in de Boor's form, which stays in the band), natural (f'' = 0
    at both ends) or clamped (s_0 and s_{n−1} given: the interior rows alone
    are solved).
    """
    n = x.size
    if n < 4 or y.shape != (n,):
        raise ValueError(f"a spline needs x and y of one length n >= 4, got {x.shape}, {y.shape}")
    h = np.diff(x)
    m = np.diff(y) / h
    ab = np.zeros((3, n))             # solve_banded's layout: ab[1 + i - j, j] = A[i, j]
    r = np.empty(n)
    ab[2, :-2] = h[1:]                # A[i, i-1] = h_i
    ab[1, 1:-1] = 2.0 * (h[:-1] + h[1:])
    ab[0, 2:] = h[:-1]                # A[i, i+1] = h_{i-1}
    r[1:-1] = 3.0 * (h[1:] * m[:-1] + h[:-1] * m[1:])
    if end == "clamped":
        s = np.empty(n)
        s[0], s[-1] = float(slopes[0]), float(slopes[1])
        r[1] -= h[1] * s[0]
        r[-2] -= h[-2] * s[-1]
        s[1:-1] = solve_banded((1, 1), ab[:, 1:-1], r[1:-1])
        return s
    if end == "natural":              # f''(x_0) = f''(x_{n-1}) = 0
        ab[1, 0], ab[0, 1], r[0] = 2.0, 1.0, 3.0 * m[0]
        ab[2, -2], ab[1, -1], r[-1] = 1.0, 2.0, 3.0 * m[-1]
    else:                             # not-a-knot
        d0, d1 = h[0] + h[1], x[-1] - x[-3]
        ab[1, 0], ab[0, 1] = h[1], d0
        r[0] = ((h[0] + 2.0 * d0) * h[1] * m[0] + h[0] ** 2 * m[1]) / d0
        ab[2, -2], ab[1, -1] = d1, h[-2]
        r[-1] = (h[-1] ** 2 * m[-2] + (2.0 * d1 + h[-1]) * h[-2] * m[-1]) / d1
    return solve_banded((1, 1), ab, r)
