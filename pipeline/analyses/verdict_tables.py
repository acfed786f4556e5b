"""A verdict (:mod:`flexbed.analyses.verdict`) as a Markdown report and as
CSV.

The Markdown is what an engineer reads: the verdict, its reasons, then one
table per kind (mounts, with their bottoming on bump stops; mount strokes
per direction, bodies, points, clearances) in mm, N, g and s. The CSV is
one row per figure, in SI with the unit in its own column (and g beside
m/s²), for a script:
``item,name,direction,quantity,value,unit,limit,time_s,pass``.
"""

from __future__ import annotations

import math

import numpy as np

from flexbed.analyses.verdict import G, Verdict

__all__ = ["markdown", "csv"]


def _num(v: float, fmt: str = "{:.4g}", scale: float = 1.0) -> str:
    return "–" if v is None or (isinstance(v, float) and math.isnan(v)) else \
        fmt.format(scale * v)


def _ok(passed: bool) -> str:
    return "PASS" if passed else "**FAIL**"


def _bottoming(m) -> str:
    """'–' without a stop; 'none' without contact; else how often, from
    when, and the peak contact force."""
    if not any(m.limits.stops):
        return "–"
    if not m.contacts:
        return "none"
    return (f"{m.contacts}× from t = {m.first_contact:.4f} s, peak {m.peak_contact_force:.4g} N "
            f"at {m.peak_contact_time:.4f} s")


def markdown(v: Verdict, title: str = "") -> str:
    """The verdict as Markdown (title: a line saying which run it is)."""
    lines = [f"# Verdict: {'PASS' if v.passed else 'FAIL'}"]
    if title:
        lines += ["", title]
    if v.reasons:
        lines += ["", "Fails on:"] + [f"- {r}" for r in v.reasons]
    lines += ["", "## Mounts", "",
              "| mount | static load [N] | rated [N] | peak force [N] | at t [s] | max [N] "
              "| stroke used [%] | bottoming | verdict |", "|---|---|---|---|---|---|---|---|---|"]
    for m in v.mounts:
        used = np.nanmax(m.stroke_used) if np.any(np.isfinite(m.stroke_used)) else math.nan
        lines.append(f"| {m.name} | {m.static_load:.6g} | {_num(m.limits.rated_load, '{:g}')} "
                     f"| {m.peak_force:.6g} | {m.peak_force_time:.4f} "
                     f"| {_num(m.limits.max_force, '{:g}')} | {_num(used, '{:.1f}', 100)} "
                     f"| {_bottoming(m)} | {_ok(m.passed)} |")
    lines += ["", "## Mount strokes per direction", "",
              "Δx < 0 is compression, Δx > 0 extension (the results file's sign); dynamic: "
              "Δx − Δx_static.", "",
              "| mount | dir | static Δx [mm] | compression total / dynamic [mm] | at t [s] "
              "| extension total / dynamic [mm] | at t [s] | limits c / e [mm] | used [%] |",
              "|---|---|---|---|---|---|---|---|---|"]
    for m in v.mounts:
        lim = m.limits
        for k in range(3):
            c = _num(lim.compression[k] if lim.compression else None, "{:g}", 1e3)
            e = _num(lim.extension[k] if lim.extension else None, "{:g}", 1e3)
            lines.append(f"| {m.name} | {k + 1} | {1e3 * m.static_deflection[k]:.4f} "
                         f"| {1e3 * m.compression[k]:.4f} / {1e3 * m.dynamic_compression[k]:.4f} "
                         f"| {m.compression_time[k]:.4f} "
                         f"| {1e3 * m.extension[k]:.4f} / {1e3 * m.dynamic_extension[k]:.4f} "
                         f"| {m.extension_time[k]:.4f} | {c} / {e} "
                         f"| {_num(m.stroke_used[k], '{:.1f}', 100)} |")
    lines += ["", "## Bodies", "", "| body | peak acceleration [g] | [m/s²] | at t [s] "
              "| fragility [g] | verdict |", "|---|---|---|---|---|---|"]
    for b in v.bodies:
        frag = _num(b.fragility.peak / G if b.fragility else None, "{:.4g}")
        lines.append(f"| {b.name} | {b.peak_acceleration / G:.4g} | {b.peak_acceleration:.5g} "
                     f"| {b.time:.4f} | {frag} | {_ok(b.passed) if b.fragility else '–'} |")
    if v.points:
        lines += ["", "## Points of interest", "",
                  "| point | body | peak acceleration [g] | at t [s] | relative to "
                  "| peak relative displacement [mm] | at t [s] |",
                  "|---|---|---|---|---|---|---|"]
        for p in v.points:
            lines.append(f"| {p.name} | {p.body} | {p.peak_acceleration / G:.4g} "
                         f"| {p.time:.4f} | {p.relative_to or '–'} "
                         f"| {_num(p.peak_relative_displacement, '{:.4f}', 1e3)} "
                         f"| {_num(p.relative_time, '{:.4f}')} |")
    if v.clearances:
        lines += ["", "## Clearances", "", "| clearance | body → other | minimum [mm] "
                  "| at t [s] | allowed [mm] | margin [mm] | verdict |",
                  "|---|---|---|---|---|---|---|"]
        for c in v.clearances:
            cl = c.clearance
            lines.append(f"| {cl.name} | {cl.body} → {cl.other} ({cl.kind}) "
                         f"| {1e3 * c.minimum:.4f} | {c.time:.4f} | {1e3 * cl.minimum:g} "
                         f"| {1e3 * c.margin:.4f} | {_ok(c.passed)} |")
    if v.stresses:
        lines += ["", "## Bed stresses", "", "von Mises in the plate, |σ| at a stiffener's "
                  "extreme fibres; places in the bed's drawing frame (as the scene's points).",
                  "", "| part | peak [MPa] | at (x, y) [m] | where | at t [s] | allowable [MPa] "
                  "| used [%] | verdict |", "|---|---|---|---|---|---|---|---|"]
        for st in v.stresses:
            p = st.peak
            lines.append(f"| {st.part} | {p.value / 1e6:.4g} | ({p.x:.4g}, {p.y:.4g}) "
                         f"| {p.where} | {p.time:.4f} | {st.allowable / 1e6:.4g} "
                         f"| {100 * st.usage:.1f} | {_ok(st.passed)} |")
    return "\n".join(lines) + "\n"


def csv(v: Verdict) -> str:
    """The verdict as CSV, one figure a row (SI; empty limit/time where none)."""
    rows = [("verdict", "", "", "pass", 1.0 if v.passed else 0.0, "1", None, None, v.passed)]

    def add(item, name, direction, quantity, value, unit, limit=None, time=None, ok=""):
        rows.append((item, name, direction, quantity, value, unit, limit, time, ok))

    for m in v.mounts:
        lim = m.limits
        for k in range(3):
            d = k + 1
            add("mount", m.name, d, "static_deflection", m.static_deflection[k], "m")
            add("mount", m.name, d, "static_force", m.static_force[k], "N")
            add("mount", m.name, d, "compression", m.compression[k], "m",
                lim.compression[k] if lim.compression else None, m.compression_time[k])
            add("mount", m.name, d, "dynamic_compression", m.dynamic_compression[k], "m",
                None, m.dynamic_compression_time[k])
            add("mount", m.name, d, "extension", m.extension[k], "m",
                lim.extension[k] if lim.extension else None, m.extension_time[k])
            add("mount", m.name, d, "dynamic_extension", m.dynamic_extension[k], "m",
                None, m.dynamic_extension_time[k])
            add("mount", m.name, d, "stroke_used", m.stroke_used[k], "1", 1.0
                if np.isfinite(m.stroke_used[k]) else None)
        if any(lim.stops):
            add("mount", m.name, "", "contacts", float(m.contacts), "1", None, m.first_contact)
            add("mount", m.name, "", "peak_contact_force", m.peak_contact_force, "N", None,
                m.peak_contact_time)
        add("mount", m.name, "", "static_load", m.static_load, "N", lim.rated_load)
        add("mount", m.name, "", "peak_force", m.peak_force, "N", lim.max_force,
            m.peak_force_time, m.passed)
    for b in v.bodies:
        frag = b.fragility.peak if b.fragility else None
        add("body", b.name, "", "peak_acceleration", b.peak_acceleration, "m/s2", frag, b.time,
            b.passed)
        add("body", b.name, "", "peak_acceleration_g", b.peak_acceleration / G, "g",
            frag / G if frag else None, b.time, b.passed)
    for p in v.points:
        add("point", p.name, "", "peak_acceleration", p.peak_acceleration, "m/s2", None, p.time)
        add("point", p.name, "", "peak_acceleration_g", p.peak_acceleration / G, "g", None,
            p.time)
        if p.relative_to:
            add("point", p.name, "", f"peak_displacement_relative_to:{p.relative_to}",
                p.peak_relative_displacement, "m", None, p.relative_time)
    for c in v.clearances:
        add("clearance", c.clearance.name, "", "minimum_distance", c.minimum, "m",
            c.clearance.minimum, c.time, c.passed)
        add("clearance", c.clearance.name, "", "margin", c.margin, "m", 0.0, c.time, c.passed)
    for st in v.stresses:
        add("bed_stress", st.part, "", "peak_stress", st.peak.value, "Pa", st.allowable,
            st.peak.time, st.passed)

    def cell(x) -> str:
        if x is None or x == "":
            return ""
        if isinstance(x, (bool, np.bool_)):
            return "true" if x else "false"
        if isinstance(x, (float, np.floating)):
            return "" if math.isnan(x) else f"{x:.10g}"
        text = str(x)
        quoted = text.replace('"', '""')
        return f'"{quoted}"' if any(ch in text for ch in ',"\n') else text

    lines = ["item,name,direction,quantity,value,unit,limit,time_s,pass"]
    lines += [",".join(cell(x) for x in row) for row in rows]
    return "\n".join(lines) + "\n"
