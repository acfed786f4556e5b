"""Force laws of one mount direction (paper eq. 1, 5, 6 and curve data).

Each law gives the force f = f_s(Δx) + f_d(Δẋ) along one mount axis [N]
from the deflection Δx [m] and the rate Δẋ [m/s]; a positive force on
body i at P_i acts along +u (a stretched mount pulls the points together).
The spring part has a potential ``V(Δx) = ∫_0^Δx f_s`` used in the energy
bookkeeping.

:class:`LawBank` compiles the laws of all (mount, direction) pairs of a
scene into stacked arrays, one group per kind, so that the forces of every
mount come from a few vectorised operations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import SceneError
from .piecewise import PiecewisePolynomial
from .time_functions import MIN_CURVE_POINTS, SplineEnds

__all__ = ["LinearLaw", "PolynomialLaw", "CurveLaw", "BumpStop", "LawBank", "MAX_DEGREE"]

MAX_DEGREE = 8


def _num(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise SceneError(f"{name} = {value!r} must be a number") from None
    if not math.isfinite(v):
        raise SceneError(f"{name} = {v!r} must be finite")
    return v


@dataclass(frozen=True, slots=True)
class LinearLaw:
    """f = k Δx + c Δẋ (paper eq. 5). k : float > 0 [N/m]; c : float >= 0 [N s/m]."""

    k: float
    c: float = 0.0

    def __post_init__(self):
        k, c = _num("k", self.k), _num("c", self.c)
        if not k > 0.0:
            raise SceneError(f"k = {k!r} must be > 0")
        if c < 0.0:
            raise SceneError(f"c = {c!r} must be >= 0")
        object.__setattr__(self, "k", k)
        object.__setattr__(self, "c", c)


@dataclass(frozen=True, slots=True)
class PolynomialLaw:
    """f = Σ_n k_n Δxⁿ + Σ_n c_n Δẋⁿ, n = 0…8 (paper eq. 6).

    stiffness : tuple of float, k_0 … k_d [N/mⁿ]; damping : tuple of float,
    c_0 … c_d [N sⁿ/mⁿ]. At most 9 coefficients each (degree 8).
    """

    stiffness: tuple[float, ...]
    damping: tuple[float, ...] = (0.0,)

    def __post_init__(self):
        for key in ("stiffness", "damping"):
            coeffs = getattr(self, key)
            try:
                coeffs = tuple(coeffs)
            except TypeError:
                raise SceneError(f"{key} = {coeffs!r} must be a list of numbers") from None
            if len(coeffs) == 0:
                raise SceneError(f"{key} is empty: give at least one coefficient")
            if len(coeffs) > MAX_DEGREE + 1:
                raise SceneError(f"{key} has degree {len(coeffs) - 1} "
                                 f"({len(coeffs)} coefficients), at most {MAX_DEGREE} allowed")
            coeffs = tuple(_num(f"{key}[{n}]", c) for n, c in enumerate(coeffs))
            object.__setattr__(self, key, coeffs)


@dataclass(frozen=True, slots=True)
class CurveLaw:
    """Force against deflection (and, optionally, against rate) as curve data.

    Cubic splines with the end conditions ``spring_ends`` and
    ``damper_ends`` (default not-a-knot; clamped slopes in N/m and N s/m);
    outside the data, linear extrapolation with the end slopes (for
    "clamped" the given ones, so the force is C¹ there; for "natural" the
    extrapolation also continues the zero curvature, C²). spring :
    (deflection [m], force [N]); damper : (rate [m/s], force [N]) or None
    for no damping force. At least 4 points, abscissae strictly
    increasing, everything finite.
    """

    spring: tuple[np.ndarray, np.ndarray]
    damper: tuple[np.ndarray, np.ndarray] | None = None
    spring_ends: SplineEnds = SplineEnds()
    damper_ends: SplineEnds = SplineEnds()

    def __post_init__(self):
        object.__setattr__(self, "spring",
                           _curve("spring_curve", ("deflection", "force"), self.spring))
        if self.damper is not None:
            object.__setattr__(self, "damper",
                               _curve("damper_curve", ("rate", "force"), self.damper))
        for key in ("spring_ends", "damper_ends"):
            if not isinstance(getattr(self, key), SplineEnds):
                raise SceneError(f"{key} = {getattr(self, key)!r} is not a SplineEnds")


@dataclass(frozen=True, slots=True)
class BumpStop:
    """A snubber (bump stop) on one mount direction: free travel up to a
    gap, then contact, f_c = k (Δx + g_c) + c Δẋ past the compression gap
    (Δx < −g_c) and f_c = k (Δx − g_e) + c Δẋ past the extension gap
    (Δx > g_e), added to the direction's own law.

    gap_compression, gap_extension : float > 0 [m], ``inf`` for no stop on
    that side (at least one finite); stiffness : float > 0 [N/m];
    damping : float >= 0 [N s/m]. Contact begins and ends where Δx
    crosses the gap (the integrators locate the instant and restart
    there, :mod:`flexbed.dynamics.contacts`); with damping, the force can
    pull briefly before the geometric release (a Kelvin–Voigt contact).
    """

    stiffness: float
    gap_compression: float = math.inf
    gap_extension: float = math.inf
    damping: float = 0.0

    def __post_init__(self):
        k, c = _num("stiffness", self.stiffness), _num("damping", self.damping)
        if not k > 0.0:
            raise SceneError(f"stiffness = {k!r} must be > 0")
        if c < 0.0:
            raise SceneError(f"damping = {c!r} must be >= 0")
        gaps = []
        for key in ("gap_compression", "gap_extension"):
            try:
                g = float(getattr(self, key))
            except (TypeError, ValueError):
                raise SceneError(f"{key} = {getattr(self, key)!r} must be a number") from None
            if not g > 0.0 or math.isnan(g):
                raise SceneError(f"{key} = {g!r} must be > 0 (a stop at zero deflection "
                                 f"would be in contact at rest)")
            gaps.append(g)
        if not any(math.isfinite(g) for g in gaps):
            raise SceneError("give gap_compression or gap_extension (or both)")
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "damping", c)
        object.__setattr__(self, "gap_compression", gaps[0])
        object.__setattr__(self, "gap_extension", gaps[1])

    def force(self, dx: np.ndarray, dxd: np.ndarray) -> np.ndarray:
        """The contact force [N] at deflections dx [m] and rates dxd [m/s]
        (zero where free), with the contact decided by dx."""
        dx = np.asarray(dx, dtype=float)
        f = np.zeros(np.broadcast(dx, dxd).shape)
        lo, hi = dx < -self.gap_compression, dx > self.gap_extension
        f = np.where(lo, self.stiffness * (dx + self.gap_compression) + self.damping * dxd, f)
        return np.where(hi, self.stiffness * (dx - self.gap_extension) + self.damping * dxd, f)


def _curve(name: str, keys: tuple[str, str], data) -> tuple[np.ndarray, np.ndarray]:
    try:
        x, f = data
    except (TypeError, ValueError):
        raise SceneError(f"{name} must be a pair ({keys[0]}, {keys[1]})") from None
    out = []
    for key, arr in zip(keys, (x, f)):
        try:
            a = np.array(arr, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise SceneError(f"{name}.{key} must be a list of numbers") from None
        if a.size < MIN_CURVE_POINTS:
            raise SceneError(f"{name}.{key} has {a.size} points, needs at least {MIN_CURVE_POINTS}")
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise SceneError(f"{name}.{key}[{bad[0]}] = {float(a[bad[0]])!r} must be finite")
        a.setflags(write=False)
        out.append(a)
    if out[0].size != out[1].size:
        raise SceneError(f"{name}: {keys[0]} has {out[0].size} points "
                         f"but {keys[1]} has {out[1].size}")
    bad = np.flatnonzero(np.diff(out[0]) <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise SceneError(f"{name}.{keys[0]} must be strictly increasing: "
                         f"{keys[0]}[{i}] = {float(out[0][i])!r} after "
                         f"{keys[0]}[{i - 1}] = {float(out[0][i - 1])!r}")
    return out[0], out[1]


class _CurveStack:
    """Many piecewise cubics evaluated at once (one point each)."""

    def __init__(self, funcs: list[PiecewisePolynomial]):
        n = max(f.breaks.size for f in funcs)
        m = len(funcs)
        deg = max(f.degree for f in funcs)
        self.breaks = np.full((m, n), np.inf)
        self.origins = np.zeros((m, n + 1))
        self.coeffs = np.zeros((m, n + 1, deg + 1))
        for i, f in enumerate(funcs):
            nb = f.breaks.size
            self.breaks[i, :nb] = f.breaks
            self.origins[i, :nb + 1] = f.origins
            self.coeffs[i, :nb + 1, :f.degree + 1] = f.coeffs
        self.rows = np.arange(m)
        self.deg = deg

    def __call__(self, x: np.ndarray) -> np.ndarray:
        k = np.count_nonzero(x[:, None] >= self.breaks, axis=1)
        u = x - self.origins[self.rows, k]
        c = self.coeffs[self.rows, k]
        acc = c[:, self.deg].copy()
        for j in range(self.deg - 1, -1, -1):
            acc *= u
            acc += c[:, j]
        return acc


class LawBank:
    """The laws of ``n`` (mount, direction) pairs compiled into stacked arrays.

    Parameters
    ----------
    laws : sequence of law, length n
        Entry ``3 m + k`` is direction k of mount m.

    stops : sequence of BumpStop or None, length n, optional
        Entry ``3 m + k``'s bump stop (``stop_gap``, ``stop_kc``,
        ``stopped``: the kernel adds the contact force to the law's).

    Per kind, the entries' indices (``lin``, ``poly``, ``curve``) and their
    tables: ``k``, ``c`` [N/m, N s/m]; ``pk``, ``pc`` ascending polynomial
    coefficients; ``curve_springs``, ``curve_dampers`` piecewise cubics. The
    right-hand side (:mod:`flexbed.dynamics.kernel`) evaluates the forces from these;
    ``spring_potential(dx)`` gives V(Δx) [J] per entry (vectorised over
    leading axes of dx).
    """

    def __init__(self, laws, stops=None):
        laws = list(laws)
        n = len(laws)
        self.n = n
        stops = [None] * n if stops is None else list(stops)
        if len(stops) != n:
            raise SceneError("one bump stop (or None) per law")
        #: (n, 2) [m] the compression and extension gaps (inf: no stop);
        #: (n, 2) [N/m, N s/m] the contact stiffness and damping
        self.stop_gap = np.full((n, 2), np.inf)
        self.stop_kc = np.zeros((n, 2))
        stopped = [i for i, st in enumerate(stops) if st is not None]
        for i in stopped:
            st = stops[i]
            self.stop_gap[i] = (st.gap_compression, st.gap_extension)
            self.stop_kc[i] = (st.stiffness, st.damping)
        #: the entries that have a bump stop
        self.stopped = (np.flatnonzero(np.isfinite(self.stop_gap).any(axis=1)) if stopped
                        else np.zeros(0, dtype=np.intp))
        lin, poly, curve = [], [], []
        for i, law in enumerate(laws):
            if isinstance(law, LinearLaw):
                lin.append(i)
            elif isinstance(law, PolynomialLaw):
                poly.append(i)
            elif isinstance(law, CurveLaw):
                curve.append(i)
        if len(lin) + len(poly) + len(curve) != n:
            raise SceneError("unknown mount law type")
        self.all_linear = len(lin) == n
        self.lin = np.array(lin, dtype=np.intp)
        self.k = np.array([laws[i].k for i in lin], dtype=float)
        self.c = np.array([laws[i].c for i in lin], dtype=float)
        self.poly = np.array(poly, dtype=np.intp)
        ds = max([len(laws[i].stiffness) for i in poly], default=1)
        dd = max([len(laws[i].damping) for i in poly], default=1)
        self.pk = np.zeros((len(poly), ds))
        self.pc = np.zeros((len(poly), dd))
        for row, i in enumerate(poly):
            self.pk[row, :len(laws[i].stiffness)] = laws[i].stiffness
            self.pc[row, :len(laws[i].damping)] = laws[i].damping
        self.curve = np.array(curve, dtype=np.intp)
        springs, dampers, self._spring_pot = [], [], []
        for i in curve:
            law = laws[i]
            fs = law.spring_ends.spline(*law.spring, left="linear", right="linear")
            springs.append(fs)
            self._spring_pot.append(fs.antiderivative(x_ref=0.0))
            if law.damper is None:
                dampers.append(PiecewisePolynomial([0.0], [[0.0], [0.0]]))
            else:
                dampers.append(law.damper_ends.spline(*law.damper, left="linear", right="linear"))
        self.curve_springs = tuple(springs)      # per curve law, in ``curve`` order
        self.curve_dampers = tuple(dampers)
        self._pot_stack = _CurveStack(self._spring_pot) if curve else None

    def spring_potential(self, dx: np.ndarray) -> np.ndarray:
        """V(Δx) [J] for dx (..., n) -> (..., n)."""
        dx = np.asarray(dx, dtype=float)
        out = np.zeros_like(dx)
        if self.lin.size:
            out[..., self.lin] = 0.5 * self.k * dx[..., self.lin] ** 2
        if self.poly.size:
            x = dx[..., self.poly]
            acc = np.zeros_like(x)
            for j in range(self.pk.shape[1] - 1, -1, -1):    # Σ k_j x^(j+1)/(j+1)
                acc = (acc + self.pk[:, j] / (j + 1)) * x
            out[..., self.poly] = acc
        if self.curve.size:
            x = dx[..., self.curve]
            flat = x.reshape(-1, self.curve.size)
            vals = np.stack([self._pot_stack(row) for row in flat])
            out[..., self.curve] = vals.reshape(x.shape)
        if self.stopped.size:                  # the stops' springs: ½ k (past the gap)²
            x = dx[..., self.stopped]
            gc, ge = self.stop_gap[self.stopped, 0], self.stop_gap[self.stopped, 1]
            past = np.minimum(x + gc, 0.0) + np.maximum(x - ge, 0.0)
            out[..., self.stopped] += 0.5 * self.stop_kc[self.stopped, 0] * past ** 2
        return out
