"""An optimisation's files: the optimum as a scene file, the convergence
plot, and the initial design against the optimum side by side — the
variables, the goals, the mounted system's modes with each mode's
dominant direction and its share (the decoupling table) and the
transmissibility from the base (z) to the scene's points.

Files in the folder: ``optimum.toml`` (a scene file: ``flexbed modal
optimum.toml`` reads it), ``convergence.png``, ``comparison.md``,
``transmissibility.png`` (when the scene has points of interest),
``pareto.csv`` (a two-objective front),
beside ``evaluations.csv`` (:mod:`flexbed.optimization.evaluate`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from flexbed.files.destination import write_text
from flexbed.optimization.driver import Optimum
from flexbed.study.layout_metrics import DIRECTIONS, direction_shares

__all__ = ["write_report", "comparison_text", "plot_convergence", "FILES"]

FILES = ("optimum.toml", "convergence.png", "comparison.md", "transmissibility.png",
         "pareto.csv")


def write_report(opt: Optimum, folder: Path, *, plots: bool = True) -> list[Path]:
    """Write the files into ``folder`` (created); return their paths."""
    folder.mkdir(parents=True, exist_ok=True)
    out = [write_text(folder / "optimum.toml", _scene_text(opt))]
    initial, best = opt.problem.scene(opt.x0), opt.scene
    modal = _modal(initial), _modal(best)
    out.append(write_text(folder / "comparison.md", comparison_text(opt, *modal)))
    if opt.pareto:
        out.append(write_text(folder / "pareto.csv", pareto_csv(opt)))
    if plots:
        out.append(plot_convergence(opt, folder / "convergence.png"))
        if initial.points and modal[0] is not None and modal[1] is not None:
            out.append(_plot_transmissibility(initial, best, folder / "transmissibility.png"))
    return out


def _scene_text(opt: Optimum) -> str:
    shown = "\n".join(f"#   {p} = {v:.10g}" for p, v in opt.values.items())
    state = "feasible" if opt.feasible else f"NOT feasible (violation {opt.violation:.3g})"
    return (f"# The optimum of '{opt.problem.spec.name}' ({opt.problem.spec.source.name}): "
            f"{state}, objective {opt.objective:.10g}\n{shown}\n" + opt.scene.text)


def _modal(scene):
    from flexbed.api import modal
    try:
        return modal(scene)
    except Exception:                                   # reported as "no modes"
        return None


def _mode_rows(m) -> list:
    if m is None:
        return []
    groups = direction_shares(np.asarray(m.energy), tuple(m.labels))
    names = DIRECTIONS + ("elastic",)
    return [(float(f), names[int(np.argmax(g))], float(np.max(g)))
            for f, g in zip(m.frequency, groups)]


def _cell(r) -> str:
    return f"{r[0]:.3f} | {r[1]} | {100 * r[2]:.1f}" if r else " | | "


def comparison_text(opt: Optimum, before, after) -> str:
    """Markdown: variables, goals, modes (frequency, dominant direction,
    its share) of the initial design and the optimum."""
    p = opt.problem
    lines = [f"# {p.spec.name}: initial design against optimum", "",
             f"{opt.evaluations} evaluations computed, {opt.reused} reused, "
             f"{opt.wall_time:.1f} s; optimum {'feasible' if opt.feasible else 'NOT feasible'}"
             f" (largest violation {opt.violation:.3g}); {opt.message}", "",
             "| variable | initial | optimum |", "|---|---|---|"]
    lines += [f"| {v.path} | {a:.6g} | {b:.6g} |" for v, a, b in zip(p.variables, opt.x0, opt.x)]
    lines += ["", "| metric | initial | optimum | bound |", "|---|---|---|---|"]
    i = 0
    for g, m in zip(p.goals, p.metrics):
        for c, u in zip(m.columns, m.units):
            a = opt.initial.result.values[i]
            b = opt.best.result.values[i]
            lo, hi = g.lower, g.upper
            bound = (f"{lo:g} to {hi:g}" if lo is not None and hi is not None
                     else f">= {lo:g}" if lo is not None else f"<= {hi:g}" if hi is not None
                     else "")
            if g.role == "objective":
                bound = g.sense
            lines.append(f"| {c} [{u}] | {a:.6g} | {b:.6g} | {bound} |")
            i += 1
    rows_a, rows_b = _mode_rows(before), _mode_rows(after)
    lines += ["", "Modes of the mounted system (base held): frequency, the direction "
              "holding most of the mode's kinetic energy, and its share.", "",
              "| mode | initial f [Hz] | direction | share [%] | optimum f [Hz] | direction "
              "| share [%] |", "|---|---|---|---|---|---|---|"]
    for k in range(max(len(rows_a), len(rows_b))):
        a = rows_a[k] if k < len(rows_a) else None
        b = rows_b[k] if k < len(rows_b) else None
        lines.append(f"| {k + 1} | {_cell(a)} | {_cell(b)} |")
    for title, m in (("initial", before), ("optimum", after)):
        if m is not None:
            lines += ["", f"Kinetic energy decoupling table, {title} [%]:", "",
                      m.energy_table()]
    return "\n".join(lines) + "\n"


def pareto_csv(opt: Optimum) -> str:
    """The Pareto front's points: the weight w of the first objective, the
    variables (scene units), both objectives as minimised (signed,
    scaled) and their metrics' columns."""
    p = opt.problem
    ws = np.linspace(0.0, 1.0, len(opt.pareto))
    head = ["w"] + [v.path for v in p.variables] + ["objective1", "objective2"] + list(p.columns)
    lines = [",".join(head)]
    for w, e in zip(ws, opt.pareto):
        obj = p.objectives(e.result.values) if e.ok else [float("nan")] * 2
        lines.append(",".join(repr(float(v)) for v in
                              [w, *e.x, *obj, *e.result.values]))
    return "\n".join(lines) + "\n"


def plot_convergence(opt: Optimum, path: Path) -> Path:
    """Each evaluation's objective's distance from the optimum's (feasible:
    filled, infeasible: open — an infeasible point may lie below) and the
    best feasible one so far's, on a log axis (the gap spans decades as a
    method converges); with constraints, the largest violation below, also
    on a log axis."""
    from flexbed.plots.figure import plt, save_figure

    hist = [e for e in opt.history if e.ok]
    n = np.arange(1, len(hist) + 1)
    f = np.array([e.objective for e in hist])
    feas = np.array([e.feasible for e in hist], dtype=bool)
    viol = np.array([e.violation for e in hist])
    best = np.full(f.size, np.nan)
    run = np.inf
    for i in range(f.size):
        if feas[i]:
            run = min(run, f[i])
        best[i] = run if np.isfinite(run) else np.nan
    floor = 1e-16 * max(1.0, abs(opt.objective))
    gap = np.abs(f - opt.objective) + floor
    constrained = any(g.role == "constraint" for g in opt.problem.goals)
    fig, axes = plt.subplots(2 if constrained else 1, 1, figsize=(7, 5.5 if constrained else 4),
                             sharex=True, squeeze=False,
                             gridspec_kw={"height_ratios": [2, 1] if constrained else [1]})
    ax = axes[0, 0]
    ax.semilogy(n[feas], gap[feas], "o", ms=3, color="tab:blue", label="feasible evaluation")
    ax.semilogy(n[~feas], gap[~feas], "o", ms=3, mfc="none", color="tab:red",
                label="infeasible evaluation")
    ax.semilogy(n, np.abs(best - opt.objective) + floor, "k-", lw=1.5,
                label="best feasible so far")
    ax.set_ylabel("|objective − optimum's| [1]")
    ax.set_title(f"{opt.problem.spec.name}: {opt.problem.spec.method}, optimum "
                 f"{opt.objective:.6g}\n{len(hist)} evaluations ({opt.evaluations} new in "
                 f"this run)", fontsize=10, pad=22)
    # above the axes, clear of the points wherever the method put them
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=3, fontsize=8,
              frameon=False)
    ax.grid(True, which="both", alpha=0.3)
    if constrained:
        bx = axes[1, 0]
        bx.semilogy(n, np.maximum(viol, 1e-16), ".", ms=3, color="tab:red")
        bx.set_ylabel("largest violation\n[share of bound]")
        bx.grid(True, which="both", alpha=0.3)
    axes[-1, 0].set_xlabel("evaluation (in the order asked; repeats included)")
    fig.tight_layout()
    return save_figure(fig, path)


def _plot_transmissibility(initial, best, path: Path) -> Path:
    from flexbed.api import frf
    from flexbed.plots.figure import plt, save_figure

    fig, ax = plt.subplots(figsize=(8.5, 4.5))
    for scene, style, tag in ((initial, "--", "initial"), (best, "-", "optimum")):
        t = frf(scene)
        colours = iter(plt.rcParams["axes.prop_cycle"].by_key()["color"])
        for j, name in enumerate(t.names):
            if name.endswith(" az") and "@" not in name:      # absolute, vertical
                ax.loglog(t.frequency, t.magnitude[:, j], style, lw=1.0,
                          color=next(colours), label=f"{name[:-3]}, {tag}")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("transmissibility |T|, base z to point z [1]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), framealpha=0.9)
    fig.tight_layout()
    return save_figure(fig, path)
