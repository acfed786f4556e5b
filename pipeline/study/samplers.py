"""A study's points from its parameters: grid (every combination), zip (the
i-th value of each), list (points given one by one) and Latin hypercube
(``samples`` points, one stratum of each parameter's range per point, from
a seeded generator).

A range moves along the segment from its low to its high end (element by
element for a vector entry such as a mount's ``k``), evenly or, with
``scale = "log"``, geometrically. A point is a dict path → value (plain
Python numbers, lists, strings).
"""

from __future__ import annotations

import itertools

import numpy as np

from flexbed.study.spec import Parameter, Study

__all__ = ["points", "parameter_values", "latin_hypercube", "along"]


def along(p: Parameter, u: np.ndarray) -> list:
    """Values of ``p`` at fractions ``u`` (k,) of its range [low, high].

    Returns a list of k values, each a float or a list of floats (the
    shape of ``low``)."""
    lo = np.asarray(p.low, dtype=float)
    hi = np.asarray(p.high, dtype=float)
    u = np.asarray(u, dtype=float).reshape((-1,) + (1,) * lo.ndim)
    if p.scale == "log":
        v = lo * (hi / lo) ** u
    else:
        v = lo + u * (hi - lo)
    # exact ends: u = 0 and u = 1 give low and high as written
    v = np.where(u == 0.0, lo, np.where(u == 1.0, hi, v))
    return [x.tolist() for x in v]


def parameter_values(p: Parameter) -> list:
    """The values of a grid or zip parameter: as given, or ``num`` from
    ``from`` to ``to`` (both included; one value: ``from``)."""
    if p.values is not None:
        return list(p.values)
    u = np.linspace(0.0, 1.0, p.num) if p.num > 1 else np.zeros(1)
    return along(p, u)


def latin_hypercube(n: int, d: int, seed: int) -> np.ndarray:
    """(n, d) fractions in [0, 1): in each column exactly one in each of the
    n strata [i/n, (i+1)/n), strata shuffled independently per column,
    uniform within a stratum (NumPy's PCG64 seeded with ``seed``)."""
    rng = np.random.default_rng(seed)
    u = np.empty((n, d))
    for j in range(d):
        u[:, j] = (rng.permutation(n) + rng.random(n)) / n
    return u


def points(study: Study) -> list[dict]:
    """Every point of the study, in order: dicts path → value (the
    parameters only; ``[study.set]`` is applied by the plan)."""
    params = study.parameters
    if study.sampling == "list":
        return [dict(p) for p in study.points]
    if not params:
        return [{}]
    if study.sampling == "lhs":
        u = latin_hypercube(study.samples, len(params), study.seed)
        columns = [along(p, u[:, j]) for j, p in enumerate(params)]
        return [{p.path: col[i] for p, col in zip(params, columns)}
                for i in range(study.samples)]
    columns = [parameter_values(p) for p in params]
    if study.sampling == "zip":
        return [{p.path: v for p, v in zip(params, row)} for row in zip(*columns)]
    return [{p.path: v for p, v in zip(params, row)} for row in itertools.product(*columns)]
