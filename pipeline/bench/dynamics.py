"""Every integrator over a ladder of steps or tolerances on one case.

For each setting: wall time (the integration alone — stepping, dense
output, projection, bookkeeping — not the statics; median of repeats),
accepted and rejected steps, right-hand-side and Jacobian evaluations, and
the maximum position error of bodies 2… and mount-force error against the
case's reference (:mod:`flexbed.bench.reference`).

A setting that the integrator refuses (its stiffness check: the message
starts with "stiff scene") is reported as "stiff: refused", an RK4 step it
refuses as beyond the stability bound as "step too long: refused"; one that
blows up as "unstable"; one whose predicted wall time exceeds the budget is not
run and says so, with the prediction. Predictions: RK4 from its step count
and the reference's cost per right-hand side; DOP853's first setting on a
case with fast damped modes from its stability bound (about 6/|λ| per step,
12 right-hand sides a step); any later setting of a ladder from the one
before it, times the growth seen so far (ladders go from cheap to dear).
"""

from __future__ import annotations

import math
import statistics
from dataclasses import dataclass

import numpy as np

from flexbed.dynamics.integrate import Run, Settings, integrate

from flexbed.bench.cases import Case
from flexbed.bench.markdown import fmt_error, md_table
from flexbed.bench.reference import Reference, errors, sample

__all__ = ["LADDERS", "QUICK_LADDERS", "Measurement", "classify", "settings_for",
           "predict_time", "measure", "run_ladders", "ladder_table", "fastest_reaching",
           "observed_orders", "DOP853_STABILITY"]

#: rk4: step dt [s]; the others: rtol (atol = 1e-3 rtol, on the motion from the start).
LADDERS = {
    "rk4": (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4),
    "adams": (1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10),
    "bdf": (1e-4, 1e-5, 1e-6, 1e-7, 1e-8),
    "radau": (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10),
    "dop853": (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11),
}
QUICK_LADDERS = {
    "rk4": (4e-3, 2e-3),
    "adams": (1e-8,),
    "bdf": (1e-6,),
    "radau": (1e-6,),
    "dop853": (1e-6, 1e-8),
}
#: |hλ| at DOP853's stability bound, about 6 on both axes (6.39 real, 5.96 imaginary).
DOP853_STABILITY = 6.0
ATOL_PER_RTOL = 1e-3


@dataclass
class Measurement:
    """One setting of one integrator on one case.

    status : "ok", "stiff: refused" (the integrator's stiffness check),
    "step too long: refused" (RK4's step beyond its stability bound),
    "unstable", "failed" or "skipped";
    note : why, for anything but "ok"; wall_time : median over ``runs``
    runs [s] (time to failure for a failed run, the prediction for a
    skipped one); position_error [m], force_error [N] : NaN unless "ok".
    """

    case: str
    method: str
    value: float
    status: str = "ok"
    note: str = ""
    steps: int = 0
    rejected: int = 0
    rhs_evaluations: int = 0
    jacobian_evaluations: int = 0
    wall_time: float = math.nan
    runs: int = 0
    position_error: float = math.nan
    force_error: float = math.nan

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    @property
    def setting(self) -> str:
        if self.method == "rk4":
            return f"dt = {self.value:g} s"
        return f"rtol = {self.value:g}"


def settings_for(method: str, value: float, t_end: float, output_dt: float) -> Settings:
    """The integrator settings of one rung of a ladder."""
    if method == "rk4":
        return Settings("rk4", t_end=t_end, dt=value, output_dt=output_dt)
    return Settings(method, t_end=t_end, rtol=value, atol=ATOL_PER_RTOL * value,
                    output_dt=output_dt)


def classify(run: Run) -> tuple[str, str]:
    """(status, note) of a finished run (see :class:`Measurement`)."""
    if run.complete:
        return "ok", ""
    msg = run.message.splitlines()[0] if run.message else "incomplete"
    if msg.startswith("stiff scene"):
        return "stiff: refused", msg
    if "step too long" in msg:
        return "step too long: refused", msg
    if "non-finite" in msg or msg.startswith("diverged"):
        return "unstable", msg
    return "failed", msg


def predict_time(method: str, value: float, case: Case, ref: Reference,
                 before: list[Measurement]) -> tuple[float, str] | None:
    """Predicted wall time [s] of a setting and how it was predicted, or
    None when there is nothing to predict from (see the module docstring)."""
    if method == "rk4":
        nfev = 4.0 * case.t_end / value
        return nfev * ref.seconds_per_rhs, f"{nfev:.3g} right-hand sides"
    ran = [m for m in before if m.ok]
    if ran:
        last = ran[-1].wall_time
        growth = 1.5
        if len(ran) >= 2 and ran[-2].wall_time > 0:
            growth = min(3.0, max(1.2, last / ran[-2].wall_time))
        return last * growth, f"{growth:.2g} x the previous setting"
    if method == "dop853" and ref.rate > 0:
        steps = case.t_end * ref.rate / DOP853_STABILITY
        return 12 * steps * ref.seconds_per_rhs, (f"stability: about {steps:.3g} steps "
                                                  f"at |λ| = {ref.rate:.3g} 1/s")
    return None


def _repeats(first: float, quick: bool, budget: float) -> int:
    if quick:
        n = 3 if first < 0.3 else 1
    else:
        n = 5 if first < 0.3 else 3 if first < 2.0 else 1
    return max(1, min(n, int(budget / max(first, 1e-9))))


def measure(case: Case, ref: Reference, method: str, value: float, *, output_dt: float,
            quick: bool = False, budget: float = math.inf) -> Measurement:
    """Run one setting (repeated when cheap) and measure it against the reference."""
    st = settings_for(method, value, case.t_end, output_dt)
    m = Measurement(case=case.spec.key, method=method, value=value)
    walls = []
    with np.errstate(all="ignore"):          # an unstable setting fails, reported
        run = integrate(case.system, case.y0, st)
    walls.append(run.stats.wall_time)
    m.status, m.note = classify(run)
    s = run.stats
    m.steps, m.rejected = s.steps, s.rejected
    m.rhs_evaluations, m.jacobian_evaluations = s.rhs_evaluations, s.jacobian_evaluations
    if m.ok:
        m.position_error, m.force_error = errors(ref.samples, sample(case.system, run))
        for _ in range(_repeats(walls[0], quick, budget) - 1):
            walls.append(integrate(case.system, case.y0, st).stats.wall_time)
    m.wall_time = statistics.median(walls)
    m.runs = len(walls)
    return m


def run_ladders(case: Case, ref: Reference, ladders: dict, *, output_dt: float,
                budget: float, quick: bool = False, log=lambda m: None) -> list[Measurement]:
    """Every method's ladder on one case, skipping settings predicted to take
    longer than ``budget`` seconds (and, after one, the rest of that ladder)."""
    rows: list[Measurement] = []
    for method, ladder in ladders.items():
        done: list[Measurement] = []
        skipping = False
        for value in ladder:
            guess = predict_time(method, value, case, ref, done)
            if skipping or (guess is not None and guess[0] > budget):
                m = Measurement(case=case.spec.key, method=method, value=value, status="skipped")
                if guess is not None:
                    m.wall_time = guess[0]
                    m.note = f"predicted {guess[0]:.3g} s > budget {budget:g} s ({guess[1]})"
                else:
                    m.note = "after a skipped setting"
                skipping = skipping or method != "rk4"
                log(f"bench {case.spec.key}: {method} {m.setting}: skipped ({m.note})")
            else:
                log(f"bench {case.spec.key}: {method} {settings_label(method, value)} ...")
                m = measure(case, ref, method, value, output_dt=output_dt, quick=quick,
                            budget=budget)
            done.append(m)
            rows.append(m)
    return rows


def settings_label(method: str, value: float) -> str:
    return Measurement(case="", method=method, value=value).setting


def _status_cell(m: Measurement) -> str:
    return "skipped" if m.status == "skipped" else m.status


def ladder_table(rows: list[Measurement]) -> str:
    """The ladder as a Markdown table, then what did not run or finish."""
    head = ["integrator", "setting", "steps", "rejected", "rhs evals", "Jacobians",
            "wall time [s]", "runs", "max position error [m]", "max mount-force error [N]"]
    body = []
    for m in rows:
        if m.status == "skipped":
            body.append([m.method, m.setting, "–", "–", "–", "–",
                         f"(≈ {m.wall_time:.3g})" if math.isfinite(m.wall_time) else "–",
                         "0", "skipped", "skipped"])
            continue
        rej = "n/a" if m.rejected < 0 else str(m.rejected)
        cells = [m.method, m.setting, str(m.steps), rej, str(m.rhs_evaluations),
                 str(m.jacobian_evaluations), f"{m.wall_time:.3f}", str(m.runs)]
        if m.ok:
            cells += [fmt_error(m.position_error), fmt_error(m.force_error)]
        else:
            cells += [_status_cell(m), _status_cell(m)]
        body.append(cells)
    text = md_table(head, body, align="llrrrrrrrr")
    notes = []
    for group in _runs_of_same_outcome([m for m in rows if not m.ok and m.note]):
        first = group[0]
        settings = ", ".join(f"{m.value:g}" for m in group)
        what = "dt" if first.method == "rk4" else "rtol"
        unit = " s" if first.method == "rk4" else ""
        notes.append(f"- {first.method}, {what} = {settings}{unit}: {first.status} — "
                     f"{first.note}" + (" (the first of these)" if len(group) > 1 else ""))
    if notes:
        text += "\n\nNot run or not finished:\n\n" + "\n".join(notes)
    return text


def _runs_of_same_outcome(rows: list[Measurement]) -> list[list[Measurement]]:
    """Consecutive rows of one method with one status, grouped."""
    groups: list[list[Measurement]] = []
    for m in rows:
        if groups and groups[-1][0].method == m.method and groups[-1][0].status == m.status:
            groups[-1].append(m)
        else:
            groups.append([m])
    return groups


def fastest_reaching(rows: list[Measurement], target: float) -> Measurement | None:
    """The fastest finished setting whose position error is ≤ ``target`` [m]."""
    ok = [m for m in rows if m.ok and m.position_error <= target]
    return min(ok, key=lambda m: m.wall_time) if ok else None


def observed_orders(rows: list[Measurement], method: str = "rk4") -> list[float]:
    """log(e1/e2) / log(dt1/dt2) between successive finished settings of a
    fixed-step method (position errors); 4 for RK4 in its asymptotic range."""
    ok = [m for m in rows if m.method == method and m.ok and m.position_error > 0]
    return [math.log(a.position_error / b.position_error) / math.log(a.value / b.value)
            for a, b in zip(ok, ok[1:])]
