"""Both routes from one design spectrum side by side: the response-spectrum
estimate (:mod:`flexbed.analyses.response_spectrum`) against the peaks of a
transient run on a motion synthesised to the spectrum
(:mod:`flexbed.dynamics.spectrum_synthesis`), per output, per bed model.

Transient peaks are taken as the response-spectrum method defines its
outputs: a mount's deflection and force along its axes less their values at
the start (the static preload), a point's displacement relative to the base
less its start, its absolute acceleration. The transient's mount force
includes the dampers', the response spectrum's is the springs' alone. A
ratio RSA/transient ≥ 1 says the response-spectrum route is conservative
for that output.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexbed.analyses.points import Point
from flexbed.dynamics.pulses import STANDARD_GRAVITY

__all__ = ["RouteRow", "transient_peaks", "route_rows", "routes_text", "routes_csv"]

_AXES = "xyz"


@dataclass(frozen=True)
class RouteRow:
    """One output of one case: ``case`` (e.g. "rigid"), ``output``, ``unit``
    (SI), ``rsa`` and ``transient`` peaks [unit], ``ratio`` rsa/transient."""

    case: str
    output: str
    unit: str
    rsa: float
    transient: float

    @property
    def ratio(self) -> float:
        return self.rsa / self.transient if self.transient > 0 else float("inf")


def transient_peaks(run, names, units, points: list[Point], base: str) -> np.ndarray:
    """(k,) the transient's peak of each response-spectrum output ``names``
    (module docstring) from a :class:`flexbed.api.results.Results`."""
    mounts = list(run.mount_names)
    by_name = {p.name: p for p in points}
    dfl = np.asarray(run.mount_deflection)
    frc = np.asarray(run.mount_force)
    cache: dict = {}
    out = np.full(len(names), np.nan)
    for j, name in enumerate(names):
        head, tail = name.rsplit(" ", 1)
        if head in mounts and tail[0] in "df":
            x = (dfl if tail[0] == "d" else frc)[:, mounts.index(head), int(tail[1]) - 1]
            out[j] = np.abs(x - x[0]).max()
        elif head in by_name and tail[0] in "ua":
            p = by_name[head]
            key = (head, tail[0])
            if key not in cache:
                if tail[0] == "u":
                    m = run.point(p.body, p.position, relative_to=base, name=p.name)
                    cache[key] = m.position - m.position[0]
                else:
                    cache[key] = run.point(p.body, p.position, name=p.name).acceleration
            out[j] = np.abs(cache[key][:, _AXES.index(tail[1])]).max()
    return out


def route_rows(case: str, axis_response, rule: str, run, points: list[Point],
               base: str) -> list[RouteRow]:
    """The rows of one case: every output the transient has a peak for."""
    a = axis_response
    tr = transient_peaks(run, a.names, a.units, points, base)
    return [RouteRow(case, n, u, float(a.combined[rule][j]), float(tr[j]))
            for j, (n, u) in enumerate(zip(a.names, a.units)) if np.isfinite(tr[j])]


def _field(v: float, unit: str) -> str:
    if unit == "m/s^2":
        return f"{v / STANDARD_GRAVITY:.2f} g"
    if unit == "m":
        return f"{1e3 * v:.2f} mm"
    return f"{v:.0f} N"


def routes_text(rows: list[RouteRow], rule: str, floor: float = 1e-3) -> str:
    """One Markdown table per quantity (mount deflections, mount forces,
    point displacements, point accelerations): per output and case the RSA
    (``rule``) and transient peaks, their ratio and the conservative route.
    Outputs whose transient and RSA peaks are both below ``floor`` of the
    largest of their quantity are left out (axes the spectrum does not reach)."""
    groups = {"mount deflection": " d", "mount force": " f",
              "point displacement relative to the base": " u", "point acceleration": " a"}
    cases = sorted({r.case for r in rows}, key=[r.case for r in rows].index)
    out = []
    for title, tag in groups.items():
        sel = [r for r in rows if r.output[:-1].endswith(tag)]
        if not sel:
            continue
        top = max(max(r.rsa, r.transient) for r in sel)
        names = [n for n in dict.fromkeys(r.output for r in sel)
                 if any(max(r.rsa, r.transient) > floor * top for r in sel if r.output == n)]
        out += [f"\n{title} (RSA: {rule.upper()}):",
                "| output | " + " | ".join(f"{c} RSA | {c} transient | {c} ratio" for c in cases)
                + " | conservative |",
                "|---|" + "---|---|---|" * len(cases) + "---|"]
        for n in names:
            cells, verdict = [], []
            for c in cases:
                r = next((r for r in sel if r.output == n and r.case == c), None)
                if r is None or max(r.rsa, r.transient) <= floor * top:
                    cells.append("— | — | —")          # not reached: round-off
                    continue
                cells.append(f"{_field(r.rsa, r.unit)} | {_field(r.transient, r.unit)} | "
                             f"{r.ratio:.2f}")
                verdict.append(f"{c}: {'RSA' if r.ratio >= 1 else 'transient'}")
            out.append(f"| {n} | " + " | ".join(cells) + " | " + ", ".join(verdict) + " |")
    return "\n".join(out).lstrip("\n")


def routes_csv(rows: list[RouteRow]) -> str:
    """case, output, unit, rsa, transient [SI], ratio."""
    return "case,output,unit,rsa,transient,ratio\n" + "\n".join(
        f"{r.case},{r.output},{r.unit},{r.rsa:.10g},{r.transient:.10g},{r.ratio:.6g}"
        for r in rows) + "\n"
