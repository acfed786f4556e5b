"""Rigid, flexible and damped flexible bed on one scene (paper, section 5.2).

Three runs of the same scene: the bed rigid; flexible without structural
damping (α = β = 0); flexible with the scene's damping. Each from its own
static equilibrium (the flexible ones with the bed's sag unless the scene
says otherwise). Per piece of equipment (every body after the bed), the
vertical motion relative to the base, d(t) = (z_e − z_base)(t) − (z_e −
z_base)(0), is summarised by its peak, RMS, dominant frequency, its delay
against the rigid case and its decay once the loads have ended. Each case
also carries its verdict against the scene's limits
(:mod:`flexbed.analyses.verdict`, side by side in
:mod:`flexbed.analyses.compare_verdict`).

The delay is the shift that maximises the cross-correlation with the rigid
case, searched over ± half the period of the rigid response's dominant
frequency (beyond that the shift of an oscillation is ambiguous); a best
shift at the edge of that window is reported as "beyond N ms", not as N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np


from flexbed.files.elastomer import time_run_scene
from flexbed.analyses.points import Run
from flexbed.analyses.verdict import contact_events, judge
from flexbed.stages.system import compile_scene
from flexbed.errors import NumericalError
from flexbed.files.store import in_memory
from flexbed.files.modes import ModesData
from flexbed.stages.simulation import equilibrium, simulate_system
from flexbed.files.results import results_contents
from flexbed.interrupts import kept
from flexbed.stages.keep import kept_contents, write_kept
from flexbed.files.scene import SceneFile
from flexbed.words import count

CASES = ("rigid", "flexible", "damped")
LABELS = {"rigid": "rigid bed", "flexible": "flexible bed (α = β = 0)",
          "damped": "damped flexible bed"}


@dataclass(frozen=True)
class CaseRun:
    """One of the three runs: the results file and what it holds."""

    case: str
    path: Path
    t: np.ndarray
    position: np.ndarray          # (k, nb, 3)
    base_acceleration: np.ndarray  # (k, 3)
    static_position: np.ndarray   # (nb, 3)
    steps: int
    rhs_evaluations: int
    wall_time: float
    load_end: float
    verdict: object = None         # flexbed.analyses.verdict.Verdict
    relative: dict | None = None   # point name -> (k, 3) motion relative to its body [m]


@dataclass(frozen=True)
class CaseSolution:
    """One case solved in memory: its scene variant, compiled system, static
    equilibrium, motion, and its results file's contents (datasets, attrs);
    ``interrupt``: the SIGINT or SIGTERM that stopped it (the contents are
    then marked incomplete), else None; ``modes``: the flexible bed's modes
    (None for the rigid case)."""

    case: str
    scene: SceneFile
    system: object
    equilibrium: object
    motion: object
    contents: tuple
    interrupt: BaseException | None = None
    modes: ModesData | None = None


def solve_case(sf: SceneFile, data: ModesData | None, case: str) -> CaseSolution:
    """Statics then simulation of one case (``case`` in :data:`CASES`), in memory.

    A flexible case needs the bed's modes ``data``; the rigid case keeps the
    static sag on (it has none). Raises NumericalError, naming the case,
    when there is no equilibrium."""
    sf = time_run_scene(sf)                 # elastomers: their Maxwell states
    if case == "rigid":
        csf = replace(sf, bed=replace(sf.bed, model="rigid"))
        system = compile_scene(csf)
    else:
        csf = replace(sf, bed=replace(sf.bed, model="flexible"))
        system = compile_scene(csf, modes=data, damped=(case == "damped"))
    sag = sf.bed.static_sag if case != "rigid" else True
    try:
        eq = equilibrium(csf, system, sag=sag)
    except NumericalError as exc:
        raise NumericalError(f"{LABELS[case]}: {exc}") from None
    start = sf.solver.start
    motion = simulate_system(csf, system, sf.solver.settings(), start=start,
                             model=sf.solver.model, linear_tol=sf.solver.linear_tol,
                             eq=eq).motion
    ds, attrs, interrupt = kept_contents(lambda: results_contents(
        csf, system, motion.run, start=start, equilibrium=eq if start == "equilibrium" else None,
        modes_path=data.path if (case != "rigid" and data) else None, model=motion.attrs()),
        motion.run.interrupt)
    return CaseSolution(case, csf, system, eq, motion, (ds, attrs), interrupt,
                        data if case != "rigid" else None)


def case_run(sol: CaseSolution, path: Path | None = None) -> CaseRun:
    """The figures :func:`comparison_rows` needs from a solved (complete)
    case, with its verdict against the scene's limits and its points of
    interest's motion relative to their ``relative_to`` bodies."""
    ds = sol.contents[0]
    st = sol.motion.run.stats
    post = Run(in_memory(*sol.contents), modes=sol.modes)
    rest = sol.system.observe(0.0, sol.equilibrium.y)
    relative = {p.name: post.relative(p, p.relative_to).position
                for p in post.scene_points if p.relative_to}
    return CaseRun(case=sol.case, path=path, t=np.asarray(ds["time"].data),
                   position=np.asarray(ds["bodies/position"].data),
                   base_acceleration=np.asarray(ds["bodies/acceleration"].data)[:, 0, :],
                   static_position=sol.system.observe(0.0, sol.equilibrium.y).r.copy(),
                   steps=st.steps, rhs_evaluations=st.rhs_evaluations,
                   wall_time=st.wall_time, load_end=max(sol.system.breakpoints, default=0.0),
                   verdict=judge(post, sol.scene.limits, rest.dx, rest.f,
                                 contact_events(sol.contents[0])), relative=relative)


def run_case(sf: SceneFile, data: ModesData | None, case: str, path: Path, log=print) -> CaseRun:
    """Statics then simulation of one case; writes its results file. A
    SIGINT or SIGTERM keeps the samples computed, written and marked
    incomplete, and is raised again (saying so) once they are safe."""
    sol = solve_case(sf, data, case)
    result = sol.motion.run
    interrupt = write_kept(path, lambda: sol.contents, sol.interrupt)
    if interrupt is not None:
        raise kept(interrupt, f"in the {LABELS[case]} run at t = {result.t_reached:.6g} s; "
                              f"the samples up to there are in {path} (marked incomplete)")
    if not result.complete:
        raise NumericalError(f"{LABELS[case]}: {result.message}; the samples up to "
                             f"t = {result.t_reached:.6g} s are in {path} (marked incomplete)")
    st = result.stats
    how = (f" (model {sf.solver.model}: {sol.motion.reason})"
           if sf.solver.model != "nonlinear" else "")
    log(f"  {LABELS[case]}: {st.method}, {count(st.steps, 'step')}, "
        f"{count(st.rhs_evaluations, 'right-hand side')}, {st.wall_time:.2f} s{how} "
        f"-> {path.name}")
    return case_run(sol, path)


def relative_vertical(run: CaseRun, body: int) -> np.ndarray:
    """d(t): vertical motion of ``body`` relative to the base, from its start [m]."""
    z = run.position[:, body, 2] - run.position[:, 0, 2]
    return z - z[0]


def dominant_frequency(t: np.ndarray, d: np.ndarray) -> float:
    """Frequency of the largest spectral peak of d (Hann window, parabolic
    refinement of the peak bin) [Hz]."""
    if d.size < 8 or not np.any(d):
        return 0.0
    dt = float(np.mean(np.diff(t)))
    x = (d - d.mean()) * np.hanning(d.size)
    n = 8 * d.size
    spec = np.abs(np.fft.rfft(x, n))
    k = int(np.argmax(spec[1:])) + 1
    if 1 <= k < spec.size - 1:
        a, b, c = np.log(spec[k - 1:k + 2] + 1e-300)
        k = k + 0.5 * (a - c) / (a - 2 * b + c)
    return float(k / (n * dt))


@dataclass(frozen=True)
class Delay:
    """A time shift found by cross-correlation.

    value : float
        The shift [s] (positive: the signal lags the reference); nan when
        the best alignment lies at the edge of the window searched, i.e. the
        shift is beyond it.
    window : float
        The largest shift searched, either way [s].
    beyond : int
        0 when measured; +1 (lags by more than ``window``) or −1 (leads by
        more) when not.
    """

    value: float
    window: float
    beyond: int = 0

    def text(self, scale: float = 1e3, fmt: str = "{:.3f}", unit: str = "ms") -> str:
        """The delay for a table: the value, or "beyond N ms" (−N: leads)."""
        if not self.beyond:
            return fmt.format(scale * self.value)
        return f"beyond {self.beyond * scale * self.window:.4g} {unit}"


def delay_window(t: np.ndarray, ref: np.ndarray) -> float:
    """The largest shift a delay against ``ref`` is searched over [s]: half
    the period of ref's dominant frequency (a longer shift of an
    oscillation is ambiguous by a whole period), at most half the record."""
    span = float(t[-1] - t[0])
    f = dominant_frequency(t, ref)
    return min(0.5 / f, 0.5 * span) if f > 0 else 0.5 * span


def delay(t: np.ndarray, d: np.ndarray, ref: np.ndarray,
          max_lag: float | None = None) -> Delay:
    """Time shift of d against ref that best aligns them (positive: d lags),
    from the cross-correlation with a parabolic refinement of its peak.

    Parameters
    ----------
    t : ndarray (k,)
        Sample times, evenly spaced [s].
    d, ref : ndarray (k,)
        The signal and the reference.
    max_lag : float, optional
        The largest shift searched, either way [s] (default:
        :func:`delay_window`). A best alignment at the edge of this window
        is reported as beyond it, never as the window itself.
    """
    dt = float(np.mean(np.diff(t)))
    window = delay_window(t, ref) if max_lag is None else float(max_lag)
    m = min(max(1, int(round(window / dt))), d.size - 1)
    n = 1 << int(2 * d.size - 1).bit_length()
    cc_full = np.fft.irfft(np.fft.rfft(d, n) * np.conj(np.fft.rfft(ref, n)), n)
    lags = np.arange(-m, m + 1)
    cc = cc_full[lags % n]                   # cc[L] = sum_i d[i + L] ref[i]
    i = int(np.argmax(cc))
    if i == 0 or i == cc.size - 1:
        return Delay(math.nan, m * dt, 1 if i else -1)
    shift = float(lags[i])
    a, b, c = cc[i - 1:i + 2]
    if a - 2 * b + c != 0:
        shift += 0.5 * (a - c) / (a - 2 * b + c)
    return Delay(shift * dt, m * dt)


def decay(t: np.ndarray, d: np.ndarray, t_free: float) -> float:
    """Peak |d| over the second half of the free vibration divided by the
    peak over its first half (1: no decay) [–]; nan without free vibration."""
    if not t_free < t[-1]:
        return math.nan
    mid = 0.5 * (t_free + t[-1])
    first = np.abs(d[(t >= t_free) & (t < mid)])
    second = np.abs(d[t >= mid])
    if first.size == 0 or second.size == 0 or first.max() == 0:
        return math.nan
    return float(second.max() / first.max())


def comparison_rows(runs: dict[str, CaseRun], names: list[str], bodies: list[int]) -> list[dict]:
    """One row per (equipment, case) with the summary figures."""
    rigid = runs["rigid"]
    rows = []
    for body in bodies:
        ref = relative_vertical(rigid, body)
        window = delay_window(rigid.t, ref)
        for case in CASES:
            run = runs[case]
            d = relative_vertical(run, body)
            rows.append({
                "equipment": names[body], "case": case,
                "static_z": float(run.static_position[body, 2]),
                "peak": float(np.abs(d).max()),
                "rms": float(np.sqrt(np.mean(d * d))),
                "frequency": dominant_frequency(run.t, d),
                "delay": (replace(delay(run.t, d, ref, max_lag=window), value=0.0)
                          if case == "rigid" else delay(run.t, d, ref, max_lag=window)),
                "decay": decay(run.t, d, run.load_end),
            })
    return rows


COLUMNS = (("equipment", "equipment", "{}"), ("case", "case", "{}"),
           ("static_z", "static z [m]", "{:.6f}"), ("peak", "peak abs(d) [mm]", "{:.4f}"),
           ("rms", "RMS d [mm]", "{:.4f}"), ("frequency", "dominant f [Hz]", "{:.3f}"),
           ("delay", "delay vs rigid [ms]", "{:.3f}"), ("decay", "decay (2nd/1st half)", "{:.3f}"))


def _cell(key: str, fmt: str, value) -> str:
    if isinstance(value, Delay):
        return value.text(1e3, fmt, "ms")
    if key in ("peak", "rms"):
        value = 1e3 * value
    if isinstance(value, float) and math.isnan(value):
        return "n/a"
    return fmt.format(value)


def markdown_table(rows: list[dict]) -> str:
    """The comparison as a Markdown table."""
    head = "| " + " | ".join(title for _, title, _ in COLUMNS) + " |"
    rule = "|" + "---|" * len(COLUMNS)
    body = ["| " + " | ".join(_cell(k, f, r[k]) for k, _, f in COLUMNS) + " |" for r in rows]
    return "\n".join([head, rule] + body)


def csv_table(rows: list[dict]) -> str:
    """The comparison as CSV (SI units: m, Hz, s). The delay is three
    columns: ``delay_s`` (nan when beyond the window), ``delay_window_s``
    (the largest shift searched) and ``delay_beyond`` (0 measured, +1 lags
    by more than the window, −1 leads by more)."""
    keys = [k for k, _, _ in COLUMNS]
    units = {"static_z": "static_z_m", "peak": "peak_m", "rms": "rms_m",
             "frequency": "frequency_Hz", "delay": "delay_s,delay_window_s,delay_beyond",
             "decay": "decay_ratio"}

    def cell(value) -> str:
        if isinstance(value, Delay):
            return f"{value.value:.10g},{value.window:.10g},{value.beyond}"
        return f"{value:.10g}" if isinstance(value, float) else str(value)

    lines = [",".join(units.get(k, k) for k in keys)]
    lines += [",".join(cell(r[k]) for k in keys) for r in rows]
    return "\n".join(lines) + "\n"
