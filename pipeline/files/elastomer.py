"""Elastomer mounts in the scene file: a linear mount's frequency-dependent
dynamic stiffness and hysteretic loss factor.

A ``law = "linear"`` mount may carry either

- ``loss_factor = [η1, η2, η3]`` (>= 0): a constant loss factor per
  direction, the dynamic stiffness being the law's ``k``; or
- ``elastomer = {frequency = [...], stiffness = [[k1, k2, k3], ...],
  loss_factor = [[η1, η2, η3], ...]}``: a table per direction over
  strictly increasing frequencies [Hz] (> 0), stiffness [N/m] > 0, loss
  factor >= 0 (``loss_factor`` optional, default 0).

The law's ``k`` stays the static stiffness (the static equilibrium and the
preloads use it); ``c`` stays a viscous damper beside the elastomer. The
stiffness is interpolated log-log in frequency, the loss factor linearly in
log f (it may be 0), both held constant outside the table
(:class:`flexbed.dynamics.frequency.elastomer.ComplexStiffness`).

Time runs take a generalised Maxwell series fitted to each elastomer
(:mod:`flexbed.dynamics.frequency.maxwell`, k∞ = the law's k), whose
error over the band is said in one line when the scene is read
(:func:`report_fits`); :func:`time_run_scene` puts the series into the
scene as internal states (:mod:`flexbed.dynamics.maxwell_terms`).
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np

from flexbed.dynamics.frequency.elastomer import ElastomerTable
from flexbed.dynamics.frequency.maxwell import fit_maxwell
from flexbed.dynamics.laws import LinearLaw
from flexbed.dynamics.maxwell_terms import MaxwellSeries
from flexbed.errors import FlexbedWarning

__all__ = ["ELASTOMER_KEYS", "read_elastomer", "report_fits", "time_run_scene"]

#: the mount keys this module reads
ELASTOMER_KEYS = ("loss_factor", "elastomer")
_TABLE_KEYS = ("frequency", "stiffness", "loss_factor")


def read_elastomer(reader, where: str, t: dict, laws: tuple) -> ElastomerTable | None:
    """The elastomer of the mount table ``t`` (None when it has none).

    ``reader``: the scene's table reader (its ``fail`` raises the one-line
    InputError); ``where``: "mount 'name'"; ``laws``: the mount's 3 laws,
    all :class:`LinearLaw` for an elastomer."""
    given = [key for key in ELASTOMER_KEYS if key in t]
    if not given:
        return None
    if len(given) == 2:
        reader.fail(where, "give either 'loss_factor' (constant) or an 'elastomer' table, "
                           "not both")
    if not all(isinstance(law, LinearLaw) for law in laws):
        reader.fail(where, f"'{given[0]}' applies to law = 'linear' only (an elastomer's "
                           f"complex stiffness is a linear model)")
    k_static = np.array([law.k for law in laws])
    if given[0] == "loss_factor":
        eta = reader.numbers(where, "loss_factor", t["loss_factor"], 3, non_negative=True)
        return ElastomerTable(k_static, np.array([1.0]), k_static[None, :].copy(),
                              np.array(eta)[None, :])
    e = reader.keys(f"{where}: elastomer", t["elastomer"], _TABLE_KEYS,
                    ("frequency", "stiffness"))
    w = f"{where}: elastomer"
    f = np.array(reader.numbers(w, "frequency", e["frequency"], positive=True))
    bad = np.flatnonzero(np.diff(f) <= 0.0)
    if bad.size:
        i = int(bad[0])
        reader.fail(w, f"frequency = {f.tolist()} must increase strictly "
                       f"(frequency[{i + 1}] = {f[i + 1]!r} after {f[i]!r})")
    k = _rows(reader, w, "stiffness", e["stiffness"], f.size, positive=True)
    eta = (_rows(reader, w, "loss_factor", e["loss_factor"], f.size, positive=False)
           if "loss_factor" in e else np.zeros((f.size, 3)))
    return ElastomerTable(k_static, f, k, eta)


def _rows(reader, where: str, key: str, value, n: int, *, positive: bool) -> np.ndarray:
    """``n`` rows of 3 numbers (one row per frequency) (n, 3)."""
    if not isinstance(value, list) or len(value) != n:
        got = len(value) if isinstance(value, list) else "not a list"
        reader.fail(where, f"{key} must be {n} rows [d1, d2, d3], one per frequency "
                           f"(got {got})")
    return np.array([reader.numbers(where, f"{key}[{r}]", row, 3, positive=positive,
                                    non_negative=not positive)
                     for r, row in enumerate(value)])


def report_fits(label: str, elastomers: list) -> None:
    """One line (a :class:`FlexbedWarning`) per distinct elastomer of
    ``elastomers`` ((mount name, ElastomerTable) pairs) with the error of
    its generalised Maxwell fit over its band, the series time runs take;
    mounts with the same table (and static k) share the line."""
    groups: dict = {}
    for name, table in elastomers:
        key = (table.k_static.tobytes(), table.frequency.tobytes(), table.stiffness.tobytes(),
               table.loss_factor.tobytes())
        groups.setdefault(key, (table, []))[1].append(name)
    for table, names in groups.values():
        fit = fit_maxwell(table)
        errs = ", ".join(f"{100 * e:.2g}" for e in fit.error)
        who = (f"mount {names[0]!r}" if len(names) == 1
               else f"mounts {', '.join(map(repr, names))}")
        warnings.warn(FlexbedWarning(
            f"{label}: {who}: elastomer: a generalised Maxwell series of {fit.tau.size} terms "
            f"matches k(f)(1 + i eta(f)) within {errs} % (directions 1-3) over "
            f"{fit.band[0]:g}-{fit.band[1]:g} Hz; frf, random and modal use the table "
            f"exactly, time runs the series"), stacklevel=3)


def time_run_scene(sf):
    """The SceneFile ``sf`` for a time run: its scene with the generalised
    Maxwell series of each elastomer mount (internal states,
    :class:`flexbed.dynamics.maxwell_terms.MaxwellSeries`); ``sf`` itself
    without elastomers, or when its scene has them already."""
    if not sf.elastomers or sf.scene.maxwell:
        return sf
    mounts = sf.scene.mounts
    series = []
    for i, table in sf.elastomers:
        fit = fit_maxwell(table)
        series.append(MaxwellSeries(mounts[i].name, fit.tau, fit.k))
    return replace(sf, scene=replace(sf.scene, maxwell=tuple(series)))
