"""A base acceleration PSD specification: a g²/Hz table per axis, log–log
between breakpoints, and optional coherences between axes.

Files (``flexbed random SCENE --psd FILE``):

- TOML, one table per axis and optional coherences::

      [z]
      table = [[20, 0.01], [80, 0.04], [350, 0.04], [2000, 0.007]]   # Hz, g²/Hz
      [x]
      table = [[20, 0.005], [2000, 0.005]]
      [coherence]
      xz = 0.3                  # real, or [re, im]: S_xz = γ √(S_xx S_zz)

- CSV, one row per breakpoint: a header ``frequency_Hz`` then any of
  ``x``, ``y``, ``z`` (g²/Hz); ``#`` starts a comment line.

Levels are in g²/Hz with g = 9.80665 m/s² (standard gravity); an axis
absent from the file is not excited.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from flexbed.dynamics.frequency.random import loglog_interpolate
from flexbed.errors import InputError
from flexbed.files.destination import check_source
from flexbed.files.table_reader import FREQUENCY_LIMITS, LARGEST, SMALLEST, out_of_range

__all__ = ["BasePSD", "load_psd", "psd_from_tables", "G0"]

#: standard gravity [m/s²]: the g of g²/Hz
G0 = 9.80665
_AXES = "xyz"
#: the most breakpoints of one axis's table (a specification has tens)
MAX_ROWS = 10_000


@dataclass(frozen=True)
class BasePSD:
    """Base acceleration PSDs.

    tables : tuple of 3 (frequency (b,) [Hz], level (b,) [g²/Hz]) or None
        Per axis X, Y, Z; None: not excited.
    coherence : (3, 3) complex
        γ_de with ``S_de = γ_de √(S_dd S_ee)`` (Hermitian, unit diagonal).
    source : str
        Where it came from (file name), for messages.
    """

    tables: tuple
    coherence: np.ndarray = field(default_factory=lambda: np.eye(3, dtype=complex))
    source: str = "PSD"

    @property
    def axes(self) -> list[int]:
        """The excited axes."""
        return [d for d, t in enumerate(self.tables) if t is not None]

    @property
    def band(self) -> tuple[float, float]:
        """[Hz] from the lowest breakpoint of any axis to the highest."""
        lo = min(self.tables[d][0][0] for d in self.axes)
        hi = max(self.tables[d][0][-1] for d in self.axes)
        return float(lo), float(hi)

    @property
    def breakpoints(self) -> np.ndarray:
        return np.unique(np.concatenate([self.tables[d][0] for d in self.axes]))

    def level(self, f: np.ndarray) -> np.ndarray:
        """(k, 3) auto-spectra [g²/Hz] at f (k,) [Hz] (zero on axes not excited)."""
        out = np.zeros((np.size(f), 3))
        for d in self.axes:
            out[:, d] = loglog_interpolate(*self.tables[d], np.asarray(f, dtype=float))
        return out

    def matrix(self, f: np.ndarray) -> np.ndarray:
        """(k, 3, 3) complex cross-spectral density matrix [(m/s²)²/Hz]."""
        a = np.sqrt(self.level(f)) * G0
        return self.coherence[None] * a[:, :, None] * a[:, None, :]

    def rms_g(self) -> np.ndarray:
        """(3,) the input's RMS per axis [g], exact for the power-law segments."""
        out = np.zeros(3)
        for d in self.axes:
            f, w = self.tables[d]
            total = 0.0
            for f1, f2, w1, w2 in zip(f[:-1], f[1:], w[:-1], w[1:]):
                if w1 <= 0.0 or w2 <= 0.0:
                    continue
                b = np.log(w2 / w1) / np.log(f2 / f1)          # slope on log–log axes
                total += (w1 * f1 * np.log(f2 / f1) if abs(b + 1.0) < 1e-12
                          else w1 * f1 / (b + 1.0) * ((f2 / f1) ** (b + 1.0) - 1.0))
            out[d] = np.sqrt(total)
        return out


def _table(rows, where: str) -> tuple[np.ndarray, np.ndarray]:
    """Check one axis's table of (frequency [Hz], level [g²/Hz]) rows."""
    try:
        a = np.array(rows, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{where}: expected rows of [frequency in Hz, level in g²/Hz] "
                         f"numbers") from None
    if a.ndim != 2 or a.shape[1] != 2 or not 2 <= a.shape[0] <= MAX_ROWS:
        raise InputError(f"{where}: expected 2 to {MAX_ROWS:,} rows of [frequency in Hz, "
                         f"level in g²/Hz]")
    f, w = a[:, 0], a[:, 1]
    for i in range(a.shape[0]):
        if not (np.isfinite(f[i]) and f[i] > 0.0):
            raise InputError(f"{where} row {i + 1}: frequency {f[i]:g} Hz must be finite "
                             f"and > 0")
        if not FREQUENCY_LIMITS[0] <= f[i] <= FREQUENCY_LIMITS[1]:
            raise InputError(f"{where} row {i + 1}: frequency {f[i]:g} Hz is outside "
                             f"{FREQUENCY_LIMITS[0]:g} – {FREQUENCY_LIMITS[1]:g} Hz, where "
                             f"responses are computed")
        if not (np.isfinite(w[i]) and w[i] >= 0.0):
            raise InputError(f"{where} row {i + 1}: level {w[i]:g} g²/Hz must be finite and "
                             f">= 0")
        if out_of_range(w[i]):
            raise InputError(f"{where} row {i + 1}: level {w[i]:g} g²/Hz is out of range "
                             f"(magnitudes from {SMALLEST:g} to {LARGEST:g}, or 0)")
        if i and not f[i] > f[i - 1]:
            raise InputError(f"{where} row {i + 1}: frequency {f[i]:g} Hz must be above the "
                             f"previous row's {f[i - 1]:g} Hz (increasing frequencies)")
    if not np.any(w > 0.0):
        raise InputError(f"{where}: every level is 0")
    f.setflags(write=False)
    w.setflags(write=False)
    return f, w


def psd_from_tables(tables: dict, coherence: dict | None = None, source: str = "psd"
                    ) -> BasePSD:
    """A :class:`BasePSD` from ``{"x"|"y"|"z": rows of [Hz, g²/Hz]}`` and
    ``{"xy"|"xz"|"yz": γ (real or complex, |γ| ≤ 1)}``; InputError naming
    ``source``, the entry and the value otherwise."""
    if not isinstance(tables, dict) or not tables:
        raise InputError(f"{source}: no axis table (expected x, y and/or z)")
    per = [None, None, None]
    for key, rows in tables.items():
        if key not in ("x", "y", "z"):
            raise InputError(f"{source}: axis {key!r} is not x, y or z")
        per[_AXES.index(key)] = _table(rows, f"{source}: [{key}] table")
    gamma = np.eye(3, dtype=complex)
    for key, value in (coherence or {}).items():
        if len(key) != 2 or key[0] not in _AXES or key[1] not in _AXES or key[0] == key[1]:
            raise InputError(f"{source}: [coherence] {key!r}: expected a pair of different "
                             f"axes such as 'xz'")
        try:
            if isinstance(value, (list, tuple)) and len(value) != 2:
                raise ValueError(value)
            g = complex(*value) if isinstance(value, (list, tuple)) else complex(value)
        except (TypeError, ValueError):
            raise InputError(f"{source}: [coherence] {key} = {value!r} must be a number or "
                             f"[re, im]") from None
        if not (np.isfinite(g.real) and np.isfinite(g.imag) and abs(g) <= 1.0):
            raise InputError(f"{source}: [coherence] {key} = {value!r}: |γ| must be <= 1")
        d, e = _AXES.index(key[0]), _AXES.index(key[1])
        if per[d] is None or per[e] is None:
            raise InputError(f"{source}: [coherence] {key}: both axes need a table")
        gamma[d, e], gamma[e, d] = g, np.conj(g)
    if np.linalg.eigvalsh(gamma).min() < -1e-12:
        raise InputError(f"{source}: [coherence]: the coherences are not realisable (their "
                         f"matrix is not positive semi-definite)")
    gamma.setflags(write=False)
    return BasePSD(tuple(per), gamma, source)


def load_psd(path: str | Path) -> BasePSD:
    """Read a PSD file (TOML or CSV, module docstring); InputError naming
    the file, the entry and the value when it cannot be used."""
    path = check_source(path, "PSD file")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read the PSD file ({exc.__class__.__name__}: "
                         f"{getattr(exc, 'strerror', None) or exc})") from None
    if path.suffix.lower() == ".csv":
        return _csv(text, path.name)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path.name}: not valid TOML ({exc})") from None
    tables = {}
    for key, value in data.items():
        if key == "coherence":
            continue
        if not isinstance(value, dict) or "table" not in value:
            raise InputError(f"{path.name}: [{key}] must be an axis table with "
                             f"'table = [[Hz, g²/Hz], ...]'")
        tables[key] = value["table"]
    coherence = data.get("coherence", {})
    if not isinstance(coherence, dict):
        raise InputError(f"{path.name}: [coherence] must be a table of axis pairs")
    return psd_from_tables(tables, coherence, path.name)


def _csv(text: str, name: str) -> BasePSD:
    lines = [ln.strip() for ln in text.splitlines() if ln.strip() and not ln.startswith("#")]
    if len(lines) < 3:
        raise InputError(f"{name}: expected a header and at least 2 rows")
    head = [h.strip().lower() for h in lines[0].split(",")]
    if head[0] not in ("frequency_hz", "frequency", "f") or len(head) < 2:
        raise InputError(f"{name}: header {lines[0]!r}: expected 'frequency_Hz' then x, y "
                         f"and/or z")
    rows = []
    for i, ln in enumerate(lines[1:], 2):
        cells = ln.split(",")
        if len(cells) != len(head):
            raise InputError(f"{name} row {i}: {len(cells)} cells, the header has {len(head)}")
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            raise InputError(f"{name} row {i}: {ln!r} is not numbers") from None
    a = np.array(rows)
    return psd_from_tables({h: np.column_stack([a[:, 0], a[:, j]])
                            for j, h in enumerate(head[1:], 1)}, None, name)
