"""The verdict's figures for the rigid, flexible and damped flexible bed
side by side (``flexbed compare``, :func:`flexbed.compare`): each body's
peak acceleration, each mount's stroke used (its peak deflection where
the scene gives no stroke), peak force and bottoming on its bump stops,
each point of interest's peak
displacement relative to its ``relative_to`` body, each clearance's
minimum, and the verdict itself (:mod:`flexbed.analyses.verdict`).
"""

from __future__ import annotations

import math

import numpy as np

from flexbed.analyses.verdict import G, Verdict

__all__ = ["verdict_rows", "verdict_markdown", "verdict_csv"]

#: quantity → (unit in SI, unit shown, factor from SI to the shown unit)
_UNITS = {"peak acceleration": ("m/s2", "g", 1 / G), "stroke used": ("1", "%", 100.0),
          "peak deflection": ("m", "mm", 1e3), "peak force": ("N", "N", 1.0),
          "peak relative displacement": ("m", "mm", 1e3), "minimum distance": ("m", "mm", 1e3),
          "bump-stop contacts": ("1", "", 1.0), "peak contact force": ("N", "N", 1.0),
          "verdict": ("", "", 1.0)}


def verdict_rows(verdicts: dict[str, Verdict], cases: tuple) -> list[dict]:
    """One row per figure: ``item``, ``quantity``, and per case its value
    in SI (the verdict row: "PASS" or "FAIL").

    Parameters
    ----------
    verdicts : dict case → Verdict
        The same scene's verdicts, one per bed model.
    cases : tuple of str
        The cases in the order of the columns.
    """
    first = verdicts[cases[0]]
    rows = []

    def row(item, quantity, value):
        rows.append({"item": item, "quantity": quantity,
                     **{c: value(verdicts[c]) for c in cases}})

    for i, b in enumerate(first.bodies):
        row(b.name, "peak acceleration", lambda v, i=i: v.bodies[i].peak_acceleration)
    for i, m in enumerate(first.mounts):
        if np.any(np.isfinite(m.stroke_used)):
            row(m.name, "stroke used", lambda v, i=i: float(np.nanmax(v.mounts[i].stroke_used)))
        else:
            row(m.name, "peak deflection", lambda v, i=i: float(max(
                v.mounts[i].compression.max(), v.mounts[i].extension.max())))
        row(m.name, "peak force", lambda v, i=i: v.mounts[i].peak_force)
        if any(m.limits.stops):
            row(m.name, "bump-stop contacts", lambda v, i=i: float(v.mounts[i].contacts))
            row(m.name, "peak contact force", lambda v, i=i: v.mounts[i].peak_contact_force)
    for i, p in enumerate(first.points):
        if p.relative_to:
            row(f"{p.name} (relative to {p.relative_to})", "peak relative displacement",
                lambda v, i=i: v.points[i].peak_relative_displacement)
    for i, c in enumerate(first.clearances):
        row(c.clearance.name, "minimum distance", lambda v, i=i: v.clearances[i].minimum)
    row("all", "verdict", lambda v: "PASS" if v.passed else "FAIL")
    return rows


def _shown(quantity: str, value) -> str:
    if isinstance(value, str):
        return value
    unit, shown, factor = _UNITS[quantity]
    return "n/a" if math.isnan(value) else f"{factor * value:.5g}"


def verdict_markdown(rows: list[dict], cases: tuple, labels: dict) -> str:
    """The rows as a Markdown table (g, %, mm, N)."""
    head = "| item | quantity | " + " | ".join(labels[c] for c in cases) + " |"
    lines = [head, "|---|---|" + "---|" * len(cases)]
    for r in rows:
        unit = _UNITS[r["quantity"]][1]
        q = f"{r['quantity']} [{unit}]" if unit else r["quantity"]
        lines.append(f"| {r['item']} | {q} | "
                     + " | ".join(_shown(r["quantity"], r[c]) for c in cases) + " |")
    return "\n".join(lines)


def verdict_csv(rows: list[dict], cases: tuple) -> str:
    """The rows as CSV in SI: ``item,quantity,unit,<case>…``."""
    def cell(x) -> str:
        if isinstance(x, str):
            return f'"{x}"' if "," in x else x
        return "" if math.isnan(x) else f"{x:.10g}"

    lines = ["item,quantity,unit," + ",".join(cases)]
    for r in rows:
        lines.append(",".join([cell(r["item"]), r["quantity"], _UNITS[r["quantity"]][0]]
                              + [cell(r[c]) for c in cases]))
    return "\n".join(lines) + "\n"
