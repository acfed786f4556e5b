"""Report section: how the stages' cost grows with the number of pieces of
equipment, on the built-in scene tiled c × c times
(:mod:`flexbed.bench.tiling`), rigid bed. A ``section(ctx) -> str`` of
:mod:`flexbed.bench.report`.

Stages, CPU seconds (``time.process_time``, every thread of the process):

- statics: :func:`flexbed.dynamics.statics.solve_statics` from the scene's
  positions, the scene's ``static_tol`` (the stability check of the
  equilibrium is not in it);
- static: ``flexbed static``'s solve, the statics above and the stability
  check of the equilibrium (:func:`flexbed.dynamics.stability.instability`);
- simulate: :func:`flexbed.dynamics.integrate.integrate` over the first
  1 s (the base's 1 s force burst), the scene's settings (``integrator =
  "auto"``: the stiffness check and the method choice are in the time),
  from the equilibrium, compiled code loaded first;
- modal: ``flexbed modal``'s solve (linearisation, mass, stiffness and
  damping matrices, eigen-solution and tables: ``Mounted.solve_time``);
  above 100 coordinates the eigen-solutions use the hub-and-leaves
  structure (:mod:`flexbed.dynamics.frequency.star`);
- frf: ``flexbed frf``'s solve at :data:`FRF_FREQUENCIES` given log-spaced
  frequencies (base acceleration along z to every body's centre of mass and
  every mount force: ``FRF.solve_time``), the leaves eliminated onto the
  bed per frequency (:mod:`flexbed.dynamics.frequency.blocks`) and the
  isolation crossings of all outputs searched together.

Each stage is timed ``repeats`` times after one untimed call (statics,
modal, frf) or compiling (simulate), and the median kept: a process's
first call of a large system's modal solution also pays the operating
system's page faults on the memory it is the first to use (at N = 128 a
quarter to a half more than the third call).

Growth exponents: log(t_b / t_a) / log(N_b / N_a) between the last two sizes.
"""

from __future__ import annotations

import math
import statistics
import time

import numpy as np

from flexbed.analyses.frf import frequency_response
from flexbed.analyses.modal import mounted
from flexbed.bench.context import BenchContext
from flexbed.bench.markdown import md_table
from flexbed.bench.tiling import equipment_count, tiled_scene
from flexbed.dynamics.integrate import integrate, warm_up
from flexbed.dynamics.stability import instability
from flexbed.dynamics.statics import solve_statics
from flexbed.errors import NumericalError
from flexbed.stages.system import compile_scene

__all__ = ["section_scaling", "TILES", "QUICK_TILES", "FRF_FREQUENCIES", "SIMULATE_T_END",
           "AIMS", "growth_exponent", "stage_times"]

#: c of the c × c tilings: N = 2, 8, 32, 128 pieces of equipment
TILES = (1, 2, 4, 8)
#: the quick report's: N ≤ 32
QUICK_TILES = (1, 2, 4)
#: given frequencies of the timed FRF
FRF_FREQUENCIES = 2000
#: end of the timed simulation [s]
SIMULATE_T_END = 1.0
#: CPU seconds aimed at N = 128, and the largest growth exponent from 32 to 128
AIMS = {"statics": 0.5, "simulate": 0.5, "modal": 0.5, "frf": 3.0}
AIM_EXPONENT = 1.3
STAGES = ("statics", "static", "simulate", "modal", "frf")


def growth_exponent(n_a: float, t_a: float, n_b: float, t_b: float) -> float:
    """p of t ∝ Nᵖ between (n_a, t_a) and (n_b, t_b); NaN if a time is not positive."""
    if not (t_a > 0.0 and t_b > 0.0):
        return math.nan
    return math.log(t_b / t_a) / math.log(n_b / n_a)


def _cpu(fn):
    t0 = time.process_time()
    out = fn()
    return time.process_time() - t0, out


def stage_times(c: int, repeats: int = 1, log=lambda m: None) -> dict:
    """CPU seconds of each stage on the c × c tiling (median of ``repeats``),
    with the sizes: {"N", "coordinates", "statics", "static", "simulate",
    "modal", "frf", "iterations", "method"}."""
    sf = tiled_scene(c, bed_model="rigid")
    system = compile_scene(sf)
    n = equipment_count(c)
    log(f"bench scaling: N = {n} ...")
    eq = solve_statics(system, tol=sf.solver.static_tol)     # compiled code loaded
    instability(system, eq.y)
    times = {s: [] for s in STAGES}
    for _ in range(repeats):
        t, eq = _cpu(lambda: solve_statics(system, tol=sf.solver.static_tol))
        if not eq.success:
            raise NumericalError(f"{sf.source.name}: {eq.message}")
        times["statics"].append(t)
        t_check, _ = _cpu(lambda y=eq.y: instability(system, y))
        times["static"].append(t + t_check)
    y0 = system.initial_state(eq.y)
    settings = sf.solver.settings(t_end=SIMULATE_T_END)
    warm_up(system, y0, methods=("dop853", "radau"))
    for _ in range(repeats):
        t, run = _cpu(lambda: integrate(system, y0, settings))
        if not run.complete:
            raise NumericalError(f"{sf.source.name}: {run.message}")
        times["simulate"].append(t)
    mt = mounted(sf, system, y_eq=eq.y)           # once untimed, as the statics above
    for _ in range(repeats):
        mt = mounted(sf, system, y_eq=eq.y)
        times["modal"].append(mt.solve_time)
    f = mt.modes.frequency[np.isfinite(mt.modes.frequency) & (mt.modes.frequency > 0)]
    grid = np.geomspace(0.25 * float(f.min()), 2.0 * float(f.max()), FRF_FREQUENCIES)
    frequency_response(sf, mt, frequencies=grid)   # once untimed
    for _ in range(repeats):
        r = frequency_response(sf, mt, frequencies=grid)
        times["frf"].append(r.solve_time)
    out = {s: statistics.median(v) for s, v in times.items()}
    out.update(N=n, coordinates=int(mt.ms.n), iterations=eq.iterations,
               method=run.stats.method, outputs=len(r.names))
    return out


def section_scaling(ctx: BenchContext) -> str:
    """The scaling table: CPU time of each stage for N = 2 … 128 pieces of
    equipment, with the growth exponents and the aims at N = 128."""
    tiles = QUICK_TILES if ctx.quick else TILES
    rows_data = []
    for c in tiles:
        rows_data.append(stage_times(c, repeats=3, log=ctx.log))
    ctx.results["scaling"] = rows_data
    rows = []
    for r in rows_data:
        rows.append([str(r["N"]), str(r["coordinates"])]
                    + [f"{r[s]:.4f}" for s in STAGES] + [r["method"]])
    a, b = rows_data[-2], rows_data[-1]
    exps = {s: growth_exponent(a["N"], a[s], b["N"], b[s]) for s in STAGES}
    ctx.results["scaling_exponents"] = exps
    rows.append([f"exponent {a['N']} → {b['N']}", ""]
                + [f"{exps[s]:.2f}" for s in STAGES] + [""])
    last = rows_data[-1]
    aims = []
    if last["N"] == 128:
        for s in AIMS:
            ok = last[s] < AIMS[s] and exps[s] <= AIM_EXPONENT
            aims.append(f"- {s}: {last[s]:.3f} s (aim < {AIMS[s]:g} s), exponent "
                        f"{exps[s]:.2f} (aim ≤ {AIM_EXPONENT:g}): {'met' if ok else 'NOT met'}")
    else:
        aims.append(f"- (the aims are stated at N = 128; this report stops at N = {last['N']})")
    return "\n".join([
        "## Scaling with the number of pieces of equipment", "",
        "The built-in scene tiled c × c times (`flexbed.bench.tiling`: one bed of 0.8c × "
        "4.8c m carrying c² copies of the two pieces of equipment on their 4 mounts each, "
        "each copy on its own 4 mounts to the base), rigid bed: N = 2c² pieces of "
        "equipment. CPU seconds (median of 3 runs, after one untimed run of the "
        "statics, modal and frf: a process's first call also pays for the memory it "
        "is the first to touch) of: statics "
        "(Newton–Raphson from the scene's positions), static (`flexbed static`'s solve: "
        "the statics and the stability check of the equilibrium), simulate (the first "
        f"{SIMULATE_T_END:g} s, the base's force burst, the scene's integrator and "
        "tolerances, stiffness check included), modal (linearisation and eigen-solution, "
        f"`flexbed modal`'s solve) and frf ({FRF_FREQUENCIES} given log-spaced frequencies, "
        "base acceleration along z to every body's centre of mass and every mount force, "
        "with the isolation crossings). Above 100 coordinates modal solves by the "
        "hub-and-leaves structure (`flexbed.dynamics.frequency.star`): each piece of "
        "equipment's block diagonalised on its own, the combinations of identical pieces' "
        "modes that neither drive nor feel the bed found exactly with the bed at rest, one "
        "dense eigen-solution of the rest (60 of the 1548 first-order states at N = 128) — "
        "every mode, exact but for the spread of identical pieces' eigenvalues (round-off; "
        "`docs/theory.md`); frf eliminates each piece of equipment onto the bed "
        "per frequency (`flexbed.dynamics.frequency.blocks`: batched 6 × 6 solves, O(N) "
        "per frequency) and searches the isolation crossings of all outputs together (one "
        "batched solve per step). "
        "Coordinates: the mounted system's (6 per body). Last row: the growth exponent p of "
        "t ∝ Nᵖ between the last two sizes.", "",
        md_table(["N", "coordinates", "statics [s]", "static [s]", "simulate [s]", "modal [s]",
                  "frf [s]", "integrator"], rows, align="rrrrrrrl"),
        "", "Aims at N = 128:", ""] + aims + [""])
