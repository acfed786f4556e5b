"""The verdict file (HDF5 via flexbed.files.store).

``flexbed.verdict`` 1.0 — a run judged against the scene's limits
(:mod:`flexbed.analyses.verdict`); nan marks a limit the scene does not give:

- root attributes ``passed`` (bool), ``reasons`` (one failure a line, or
  ""), ``scene_digest``, ``method`` (the integrator that ran), ``t_end``
  [s], ``output_dt`` [s];
- ``mounts/``: ``names`` (M,), ``static_deflection``, ``static_force``
  (M, 3) [m, N]; ``compression``, ``extension`` (M, 3) [m] total, and
  ``dynamic_compression``, ``dynamic_extension`` (M, 3) [m], each with its
  ``…_time`` (M, 3) [s]; ``stroke_compression``, ``stroke_extension``
  (M, 3) [m] the limits; ``stroke_used`` (M, 3) [1]; ``static_load``,
  ``rated_load``, ``peak_force``, ``max_force`` (M,) [N],
  ``peak_force_time`` (M,) [s]; ``contacts`` (M,) bump-stop contacts
  begun, ``first_contact`` [s], ``peak_contact_force`` [N] (M,);
  ``passed`` (M,);
- ``bodies/``: ``names``, ``peak_acceleration`` [m/s²], ``time`` [s],
  ``fragility`` [m/s²], ``passed`` (nb − 1,), the base left out;
- ``points/``: ``names``, ``peak_acceleration`` [m/s²], ``time`` [s],
  ``peak_relative_displacement`` [m], ``relative_time`` [s];
- ``clearances/``: ``names``, ``minimum`` [m], ``time`` [s], ``allowed``
  [m], ``margin`` [m], ``passed``;
- ``scene/toml``: the scene file's text.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from flexbed.files.store import Dataset, write_file

__all__ = ["write_verdict", "verdict_contents", "VERDICT_SCHEMA"]

VERDICT_SCHEMA = "flexbed.verdict"
VERSION = "1.0"


def _names(items) -> np.ndarray:
    return np.array([str(n) for n in items], dtype=str)


def _limit(values) -> np.ndarray:
    return np.array([np.nan if v is None else v for v in values], dtype=float)


def _strokes(mounts, key: str) -> np.ndarray:
    return np.array([getattr(m.limits, key) or (np.nan,) * 3 for m in mounts],
                    dtype=float).reshape(len(mounts), 3)


def verdict_contents(sf, verdict, run_attrs: dict) -> tuple[dict, dict]:
    """The datasets and group attributes of the verdict file, in memory.

    sf : SceneFile; verdict : Verdict; run_attrs : the run's ``solver``
    attributes (``method``, ``t_end``, ``output_dt``).
    """
    v, M = verdict, verdict.mounts
    ds = {"scene/toml": Dataset(sf.text, "", "the scene file this came from")}

    def put(group, name, data, units, description, missing=False):
        ds[f"{group}/{name}"] = Dataset(np.asarray(data), units, description, missing=missing)

    put("mounts", "names", _names(m.name for m in M), "", "mount names")
    for key, units, what in (("static_deflection", "m", "deflection at the static equilibrium"),
                             ("static_force", "N", "force at the static equilibrium"),
                             ("compression", "m", "largest compression, max(0, -min dx)"),
                             ("compression_time", "s", "when"),
                             ("extension", "m", "largest extension, max(0, max dx)"),
                             ("extension_time", "s", "when"),
                             ("dynamic_compression", "m", "largest compression of dx - dx_static"),
                             ("dynamic_compression_time", "s", "when"),
                             ("dynamic_extension", "m", "largest extension of dx - dx_static"),
                             ("dynamic_extension_time", "s", "when")):
        put("mounts", key, np.array([getattr(m, key) for m in M]).reshape(len(M), 3), units, what)
    put("mounts", "stroke_compression", _strokes(M, "compression"), "m",
        "compression stroke limit", missing=True)
    put("mounts", "stroke_extension", _strokes(M, "extension"), "m", "extension stroke limit",
        missing=True)
    put("mounts", "stroke_used", np.array([m.stroke_used for m in M]).reshape(len(M), 3), "1",
        "stroke used: largest of compression and extension over their limits", missing=True)
    put("mounts", "static_load", [m.static_load for m in M], "N", "|static force|")
    put("mounts", "rated_load", _limit(m.limits.rated_load for m in M), "N", "rated static load",
        missing=True)
    put("mounts", "peak_force", [m.peak_force for m in M], "N", "peak |force| over the run")
    put("mounts", "peak_force_time", [m.peak_force_time for m in M], "s", "when")
    put("mounts", "max_force", _limit(m.limits.max_force for m in M), "N",
        "largest dynamic force allowed", missing=True)
    put("mounts", "contacts", np.array([m.contacts for m in M], dtype=np.int64), "1",
        "bump-stop contacts that began")
    put("mounts", "first_contact", np.array([m.first_contact for m in M], dtype=float), "s",
        "the first", missing=True)
    put("mounts", "peak_contact_force", np.array([m.peak_contact_force for m in M], dtype=float),
        "N", "largest |contact force| of a direction")
    put("mounts", "passed", np.array([m.passed for m in M], dtype=bool), "", "within limits")
    B = v.bodies
    put("bodies", "names", _names(b.name for b in B), "", "bodies after the base")
    put("bodies", "peak_acceleration", [b.peak_acceleration for b in B], "m/s^2",
        "peak |absolute acceleration| at the centre of mass or the fragility's point")
    put("bodies", "time", [b.time for b in B], "s", "when")
    put("bodies", "fragility", _limit(b.fragility.peak if b.fragility else None for b in B),
        "m/s^2", "fragility limit", missing=True)
    put("bodies", "passed", np.array([b.passed for b in B], dtype=bool), "", "within fragility")
    P = v.points
    put("points", "names", _names(p.name for p in P), "", "points of interest")
    put("points", "peak_acceleration", np.array([p.peak_acceleration for p in P], dtype=float),
        "m/s^2", "peak |absolute acceleration|")
    put("points", "time", np.array([p.time for p in P], dtype=float), "s", "when")
    put("points", "peak_relative_displacement",
        np.array([p.peak_relative_displacement for p in P], dtype=float), "m",
        "peak |displacement relative to relative_to| from t = 0", missing=True)
    put("points", "relative_time", np.array([p.relative_time for p in P], dtype=float), "s",
        "when", missing=True)
    C = v.clearances
    put("clearances", "names", _names(c.clearance.name for c in C), "", "clearances")
    put("clearances", "minimum", np.array([c.minimum for c in C], dtype=float), "m",
        "least distance over the run")
    put("clearances", "time", np.array([c.time for c in C], dtype=float), "s", "when")
    put("clearances", "allowed", np.array([c.clearance.minimum for c in C], dtype=float), "m",
        "least distance allowed")
    put("clearances", "margin", np.array([c.margin for c in C], dtype=float), "m",
        "minimum - allowed")
    put("clearances", "passed", np.array([c.passed for c in C], dtype=bool), "",
        "within the clearance")
    attrs = {"": {"passed": bool(v.passed), "reasons": "\n".join(v.reasons),
                  "scene_digest": sf.digest,
                  "method": str(run_attrs.get("method", "")),
                  "t_end": float(run_attrs.get("t_end", np.nan)),
                  "output_dt": float(run_attrs.get("output_dt", np.nan))}}
    return ds, attrs


def write_verdict(path, sf, verdict, run_attrs: dict) -> Path:
    """Write the verdict file atomically (see the module docstring)."""
    datasets, attrs = verdict_contents(sf, verdict, run_attrs)
    return write_file(path, schema=VERDICT_SCHEMA, version=VERSION, datasets=datasets,
                      attrs=attrs)
