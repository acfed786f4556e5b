"""The study engine measured: a 200-point study of the reference scene
(rigid bed, 3 s; ``docs/sweep-study.toml``) on a local Dask cluster of 2
worker processes, against the same points run without Dask, and the
serial parts of a study (scheduler, client) per task and per point, with a
model of the study on W workers. Writes ``docs/sweep-benchmark.md`` (and
prints it). The measurements are in ``docs/sweep_measure.py``.

Usage: ``OPENBLAS_NUM_THREADS=1 python docs/sweep_bench.py [POINTS [ROUNDS]]
[--exudyn FILE[,FILE]]`` (default 200 points, 4 rounds; ``--exudyn``: the
lines ``docs/sweep_exudyn.py run`` printed, compared with S); ``python
docs/sweep_bench.py --parts [COUNT]``: a point's CPU by part alone
(``sweep_measure.point_parts``, COUNT points, default 40), printed, not
written. About 3
minutes on 2 quiet cores (3 rounds took 3.8 min at load average 1-2.7, 4.8
min at 2.3-4.3; 5 rounds 10.9 min at 4-6).

What is compared (every run does the same work: ``run_point`` — statics,
simulate, the metrics — of each point's scene, warm):

- A, in process: ``run_point`` of 40 of the study's points one after
  another in this process; median wall and CPU time per point. Measured
  before the rounds and after them.
- B, two plain processes side by side (no Dask): the study's points split
  in two, each half run one after another by its own process, both
  started together (each warmed first, as a worker is); the wall time
  from the start to the last point done; the CPU of both processes.
  Both cores busy, as in the study: B is what the machine gives for these
  points on 2 cores without Dask.
- S, the study: ``run_plan`` (what ``flexbed sweep`` runs) on a fresh
  2-worker local cluster (``flexbed.study.engine.cluster_client``, the
  command's own: started, warmed, and stopped apart and timed apart);
  the wall time of the points from the first submission to the last row
  written; the CPU of every process over it, by part: the client's main
  thread (planning the tasks, pickling the scenes, the rows, the table's
  writes), the other threads of the client process (its event loop: the
  scheduler, the nannies and the client's communication, all in this
  process for a local cluster), the worker processes, and within them the
  points' own thread time (``cpu_time`` of the table).

A and B and S are interleaved (ROUNDS rounds of B then S; A before and
after), since the machine may be shared: each round's S is compared with
the B run just before it, and the median over the rounds is given, with
the load average. The overheads:

- against B (the measure of Dask's own cost): S wall / B wall - 1, and
  S CPU per point / B CPU per point - 1 (median over the rounds);
- Dask's own CPU: every process's CPU in S but the points' own thread
  time, against the points' own (one run: free of the load's effect on
  the points' speed);
- against A (time per point on the cluster against one in-process run):
  S wall x 2 / points / A wall per point - 1 — which also holds the cost
  of sharing 2 cores between two busy processes (B against A).

Serial parts: a ``dask scheduler`` and 2 ``dask worker`` processes started
apart (with the local cluster's settings as environment variables), the
scheduler process's CPU per no-op task, and the same study with 0.01 s of
motion per point (400 points) at 1 and 16 points a task: the scheduler's
and the client's (this process's) CPU per point, so per task and per point
apart; the model of W workers and B points a task is built on them.
"""

from __future__ import annotations

import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from sweep_measure import (PARTS, idle_cost, in_process, point_parts, serial_costs,  # noqa: E402
                           side_by_side, study_round)


# ---------------------------------------------------------------------- report
#: what each part of :func:`sweep_measure.point_parts` is, for the table
PART_NAMES = {
    "compile": "compiling the scene (a System)",
    "newton": "Newton-Raphson (`solve_statics`)",
    "stability": "the equilibrium's stability check",
    "plausibility": "its plausibility check (mount deflections, turns)",
    "simulate": "the `simulate` analysis (its arguments, the solve, `PointRun`)",
    "metrics": "the metrics' values (the right-hand-side pass over the 3,001 output "
               "samples, the points' positions, the peaks)",
}


def parts_table(parts: dict) -> list:
    """Markdown lines: a point's CPU by part (:func:`sweep_measure.point_parts`)."""
    solve = parts["solve"]
    lines = ["| part | CPU per point | against the solve |", "|---|---:|---:|"]
    lines += [f"| {PART_NAMES[k]} | {1e3 * parts[k]:.1f} ms | {parts[k] / solve:.2f}× |"
              for k in PARTS]
    total = sum(parts[k] for k in PARTS)
    lines += [f"| the parts together | {1e3 * total:.1f} ms | {total / solve:.2f}× |",
              f"| `run_point` (the whole, the same points) | {1e3 * parts['run_point']:.1f} ms | "
              f"**{parts['run_point'] / solve:.2f}×** |",
              f"| the solve alone (`simulate_system`, the same points) | {1e3 * solve:.1f} ms | "
              f"1.00× |"]
    if "plan" in parts:                  # the client's work per point, before the run
        plan = parts["plan"]
        whole = parts["run_point"] + plan
        lines += [f"| planning, on the client before the run (each point's scene built and "
                  f"checked, `make_plan`) | {1e3 * plan:.1f} ms | {plan / solve:.2f}× |",
                  f"| `run_point` and its planning | {1e3 * whole:.1f} ms | "
                  f"**{whole / solve:.2f}×** |"]
    return lines


def planned(study):
    """(plan, CPU seconds of :func:`make_plan` per point): every point's scene
    built and checked on the client, before anything runs. Timed as a
    study's first plan of its points: the process's one-time imports and
    caches are paid first by a plan of other points of the same parameters
    (the next seed), not by these points' own scenes (the scene reader
    keeps the entries it checked: a second plan of the same points would
    find each point's changed entries checked already)."""
    import dataclasses

    from flexbed.study.plan import make_plan
    make_plan(dataclasses.replace(study, seed=study.seed + 1))
    c0 = time.thread_time()
    plan = make_plan(study)
    return plan, (time.thread_time() - c0) / len(plan.points)


def parts_only(count: int) -> None:
    """``--parts [COUNT]``: :func:`sweep_measure.point_parts` alone, printed
    as a table and as JSON (for side-by-side runs of two versions)."""
    from flexbed.study.spec import read_study
    plan, per_point = planned(read_study(HERE / "sweep-study.toml"))
    parts = dict(point_parts(plan, count), plan=per_point)
    print("\n".join(parts_table(parts)))
    print(json.dumps({k: round(v, 6) for k, v in parts.items()}))


def main() -> None:
    import dataclasses

    import flexbed
    from flexbed.study.plan import make_plan
    from flexbed.study.runner import auto_sizes
    from flexbed.study.spec import read_study

    args = sys.argv[1:]
    if args[:1] == ["--parts"]:
        return parts_only(int(args[1]) if len(args) > 1 else 40)
    exudyn = []
    if "--exudyn" in args:
        i = args.index("--exudyn")
        exudyn = [json.loads(line) for f in args[i + 1].split(",")
                  for line in Path(f).read_text().splitlines() if line.startswith("{")]
        del args[i:i + 2]
    n = int(args[0]) if args else 200
    rounds = int(args[1]) if len(args) > 1 else 4
    study = read_study(HERE / "sweep-study.toml")
    if n != study.samples:
        study = dataclasses.replace(study, samples=n)
    plan, plan_cpu = planned(study)
    workers = 2
    began = time.perf_counter()
    loads = [os.getloadavg()[0]]

    a = [in_process(plan)]
    b, s = [], []
    for _ in range(rounds):
        b.append(side_by_side(plan, workers))
        loads.append(os.getloadavg()[0])
        s.append(study_round(plan, workers))
        loads.append(os.getloadavg()[0])
    a.append(in_process(plan))
    parts = dict(point_parts(plan), plan=plan_cpu)
    idle = idle_cost(workers)
    # the serial parts per task, measured with short points (0.01 s of
    # motion each) so that the study is short and the processes' idle
    # housekeeping (which grows with the wall time) adds little
    fast = dataclasses.replace(study, samples=400,
                               fixed=study.fixed + (("solver.t_end", 0.01),))
    big, k = 16, 2000
    serial = serial_costs(make_plan(fast), k, sizes=(1, big))
    loads.append(os.getloadavg()[0])
    took = time.perf_counter() - began

    med = statistics.median
    t_a, c_a = med([x["wall"] for x in a]), med([x["cpu"] for x in a])
    solve_a, statics_a = med([x["solve"] for x in a]), med([x["statics"] for x in a])
    a_runs = ", ".join(f"{1e3 * x['wall']:.1f} ms wall / {1e3 * x['cpu']:.1f} ms CPU "
                       f"(solve {1e3 * x['solve']:.1f} ms)" for x in a)
    t_b, c_b = med([x["wall"] for x in b]), med([x["cpu"] for x in b]) / n
    t_s, c_s = med([x["wall"] for x in s]), med([x["cpu"] for x in s]) / n
    part = {key: med([x["parts"][key] for x in s]) / n for key in s[0]["parts"]}
    per_point = t_s * workers / n
    own = part["workers"] + part["loop"] + part["client"] - part["points"]
    # the model's time per point on a worker with a core of its own: the
    # worker processes' CPU per point in S (the point's own code and the
    # worker's Dask costs; wall times here are stretched by other work)
    t_p = part["workers"]
    auto = auto_sizes(n, workers)

    def split(which):
        """(per task, per point) [s of CPU] from the costs per point at
        one point a task and at ``big``."""
        one, many = serial[1][which], serial[big][which]
        per_task = max(0.0, (one - many) / (1.0 - 1.0 / big))
        return per_task, max(0.0, one - per_task)

    (sched_t, sched_p), (client_t, client_p) = split("scheduler"), split("client")

    def serial_per_point(size):
        """s(B) [s] for B points a task (B may be a mean)."""
        return max(sched_t / size + sched_p, client_t / size + client_p)

    def ms(x):
        return f"{1e3 * x:.1f} ms"

    def pct(x):
        return f"{100 * x:+.1f} %"

    rows = [
        ("A: one point in process, wall / CPU (median of 40, before and after)",
         f"{ms(t_a)} / {ms(c_a)}"),
        ("**A: a point's CPU against its solve** (the motion from the equilibrium alone, "
         "`simulate_system`, on the same points; medians)",
         f"**{ms(c_a)} / {ms(solve_a)} = {c_a / solve_a:.2f}×**"),
        ("A: the statics alone (`flexbed.statics`: compiling, Newton-Raphson, the checks), "
         "against the solve", f"{ms(statics_a)} = {statics_a / solve_a:.2f}×"),
        ("B: two plain processes side by side, wall for the points / per point "
         f"(wall × {workers} / {n})", f"{t_b:.2f} s / {ms(t_b * workers / n)}"),
        ("B: CPU per point (both processes)", ms(c_b)),
        ("B: points per second", f"{n / t_b:.2f}"),
        ("S: the study on the cluster, wall for the points / per point "
         f"(wall × {workers} / {n})", f"{t_s:.2f} s / {ms(per_point)}"),
        ("S: CPU per point, every process", ms(c_s)),
        ("S: points per second", f"{n / t_s:.2f}"),
        ("**overhead of Dask, wall: S against B** (median over the rounds of S / B - 1, "
         "each round's B and S run one after the other)",
         f"**{pct(med([x['wall'] / y['wall'] - 1 for x, y in zip(s, b)]))}**"),
        ("overhead of Dask, CPU per point: S against B (the same)",
         pct(med([x["cpu"] / y["cpu"] - 1 for x, y in zip(s, b)]))),
        ("**Dask's own CPU in S** (every process's CPU but the points' own) **against the "
         "points' own CPU in S**", f"**{ms(own)} / {ms(part['points'])} = "
                                    f"{100 * own / part['points']:.1f} %**"),
        ("S against A: time per point on the cluster (wall × 2 / points) against one "
         "in-process run (medians)", pct(per_point / t_a - 1)),
        ("B against A: the same for two plain processes (the cost of sharing 2 cores)",
         pct(t_b * workers / n / t_a - 1)),
        ("local cluster start + warm-up / stop, wall (median)",
         f"{med([x['start'] for x in s]):.2f} s / {med([x['stop'] for x in s]):.2f} s"),
        ("S end to end (start, points, stop) against B, wall (median over the rounds)",
         pct(med([(x["wall"] + x["start"] + x["stop"]) / y["wall"] - 1
                  for x, y in zip(s, b)]))),
    ]
    lines = [
        "# Design studies on Dask: measured",
        "",
        f"Written by `python docs/sweep_bench.py {n} {rounds}` on "
        f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} in {took / 60:.1f} min; "
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} logical CPUs; load "
        f"average (1 min) during the runs {min(loads):.2f}-{max(loads):.2f} (other work "
        f"stretches wall times: the rounds are interleaved and their medians given); "
        f"Python {platform.python_version()}, flexbed {flexbed.__version__}.",
        "",
        f"Study: `docs/sweep-study.toml`, {n} points (Latin hypercube), the reference scene "
        f"(rigid bed, 0-3 s), analyses {', '.join(plan.analyses)}, "
        f"{len(plan.metric_columns)} metric columns; on the cluster in {len(auto)} tasks "
        f"of {', '.join(map(str, auto))} points (`batch = \"auto\"` for {n} points on "
        f"{workers} workers: large batches first, single points last). A, B and S are defined "
        "in the script's docstring: A one process, B two plain processes side by side (no "
        "Dask), S the study on a 2-worker local cluster; each runs the same `run_point`.",
        "",
        "A point is its statics, its solve and its metrics. Its `simulate` outcome "
        "(`flexbed.study.outputs.PointRun`) holds the solved motion and evaluates only what "
        "the metrics read: one pass of the right-hand side over the output samples (the "
        "bodies' accelerations, the mounts' deflections and forces) and the frames of the "
        "bodies a point needs, not the whole results file (angles, energies, every "
        "dataset: built only for a point on the bed or a kept file; a peak displacement "
        "reads the point's positions alone); the numbers are the same bit for bit. The "
        "statics' Newton-Raphson takes the exact tangent stiffness at rest as its Jacobian "
        "(`flexbed.dynamics.tangent`: one right-hand side and its derivatives, where central "
        "differences by colour classes took 24), in compiled code for a scene of rigid "
        "bodies (`flexbed.dynamics.rigid_statics`), and polishes with the last one; the "
        "solve keeps the mounts' deflections and forces at rest, which the plausibility "
        "check and the static metrics read (no further evaluation). What a point costs past "
        "its solve is then mostly the right-hand-side pass over the output samples that the "
        "mount forces need (3,001 evaluations, where the reference scene's integration makes "
        "3,538), then the statics (compiling the scene, Newton-Raphson, the checks).",
        "",
        "| quantity | value |",
        "|---|---:|",
        *(f"| {q} | {v} |" for q, v in rows),
        "",
        "Where a point's CPU goes (A's points, each part run alone in the order "
        "`run_point` runs it; medians; `python docs/sweep_bench.py --parts` measures this "
        "table alone):",
        "",
        *parts_table(parts),
        "",
        "Rounds (B then S each; A before and after):",
        "",
        "| round | load | B wall [s] | S wall [s] | S / B - 1 | B CPU / point | "
        "S CPU / point | S / B - 1 (CPU) |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|",
        *(f"| {i + 1} | {x['load']:.1f} | {y['wall']:.2f} | {x['wall']:.2f} | "
          f"{pct(x['wall'] / y['wall'] - 1)} | {ms(y['cpu'] / n)} | {ms(x['cpu'] / n)} | "
          f"{pct(x['cpu'] / y['cpu'] - 1)} |" for i, (x, y) in enumerate(zip(s, b))),
        "",
        f"A: {a_runs} (before, after).",
        "",
        "Time the points ran (the sum of each point's own wall time, `run_point`, over the "
        f"processes) against the wall time: B {100 * med([y['busy'] for y in b]):.1f} %, S "
        f"{100 * med([x['busy'] for x in s]):.1f} % (the rest: waiting for a task, the start "
        "and the end, unpickling); a point's own wall time on a worker (median "
        f"`solve_time`) {ms(med([x['solve'] for x in s]))}.",
        "",
        "Where the study's CPU goes, per point (median of the rounds):",
        "",
        "| part | CPU per point | against B's CPU per point |",
        "|---|---:|---:|",
        f"| the points' own code on the workers (`cpu_time`) | {ms(part['points'])} | "
        f"{pct(part['points'] / c_b - 1)} |",
        f"| the workers' processes besides (event loop, heartbeats, (de)serialising) | "
        f"{ms(part['workers'] - part['points'])} | "
        f"{100 * (part['workers'] - part['points']) / c_b:.1f} % |",
        f"| the client process's event loop (the scheduler, the nannies, the client's "
        f"communication) | {ms(part['loop'])} | {100 * part['loop'] / c_b:.1f} % |",
        f"| the client's main thread (tasks, pickled scenes, rows, table writes) | "
        f"{ms(part['client'])} | {100 * part['client'] / c_b:.1f} % |",
        f"| every process | {ms(c_s)} | {pct(c_s / c_b - 1)} |",
        "",
        f"The first point of each worker (largest `cpu_time`, median of the rounds): "
        f"{ms(med([x['first'] for x in s]))}, against {ms(med([x['median'] for x in s]))} "
        f"the median. The cluster idle (every process): {1e3 * idle:.1f} ms of CPU per "
        "second of wall.",
        "",
        f"Serial parts (a `dask scheduler` and 2 `dask worker` processes started apart, "
        f"the local cluster's settings; CPU of each process): the scheduler "
        f"{1e3 * serial['noop']:.2f} ms per no-op task ({k} tasks; its idle housekeeping "
        f"{1e3 * serial['idle']:.1f} ms/s, measured idle, taken off below). The same study "
        f"with 0.01 s of motion per point, 400 points, run one point a task and {big} "
        "points a task:",
        "",
        "| points a task | wall [s] | scheduler CPU per point [ms] | client CPU per point [ms] |",
        "|---:|---:|---:|---:|",
        *(f"| {size} | {serial[size]['wall']:.1f} | {1e3 * serial[size]['scheduler']:.2f} | "
          f"{1e3 * serial[size]['client']:.2f} |" for size in (1, big)),
        "",
        f"So per task / per point: the scheduler {1e3 * sched_t:.2f} / {1e3 * sched_p:.2f} ms, "
        f"the client (this process: submitting, gathering, the rows, the table's writes) "
        f"{1e3 * client_t:.2f} / {1e3 * client_p:.2f} ms.",
        "",
        "Model of W workers (one core each): a point takes t_p = "
        f"{ms(t_p)} on its worker (S's CPU per point of the worker processes: the point "
        "and the worker's own Dask costs; S's wall × 2 / points, "
        f"{ms(per_point)} here, is stretched by whatever else the 2 cores run); every task "
        "also passes, one at a time, through "
        "the scheduler and the client: with B points a task, s(B) = max(scheduler per "
        "task / B + per point, client per task / B + per point) "
        f"= {1e3 * serial_per_point(1):.2f} ms at B = 1, {1e3 * serial_per_point(big):.2f} ms "
        f"at B = {big} (measured on 2 shared cores: an upper bound). The study's rate is "
        "min(W / t_p, 1 / s(B)) points per second; `batch = \"auto\"` cuts N points into "
        "batches of ceil(points left / 2W), at most 16 (B below: the mean, N / tasks).",
        "",
        "| workers W | W / t_p [points/s] | 1 / s(1) | rate, B = 1 [points/s] | efficiency | "
        f"1 / s({big}) | rate, B = {big} | efficiency | auto, 10,000 points: tasks (mean B) | "
        "rate [points/s] | efficiency |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for w in (1, 2, 8, 16, 32, 64, 128):
        ideal = w / t_p
        r1 = min(ideal, 1 / serial_per_point(1))
        rb = min(ideal, 1 / serial_per_point(big))
        tasks = len(auto_sizes(10000, w))
        ra = min(ideal, 1 / serial_per_point(10000 / tasks))
        lines.append(f"| {w} | {ideal:.1f} | {1 / serial_per_point(1):.0f} | {r1:.1f} | "
                     f"{100 * r1 / ideal:.0f} % | {1 / serial_per_point(big):.0f} | {rb:.1f} | "
                     f"{100 * rb / ideal:.0f} % | {tasks} ({10000 / tasks:.1f}) | {ra:.1f} | "
                     f"{100 * ra / ideal:.0f} % |")
    lines.append("")
    if exudyn:
        lines += exudyn_table(exudyn, s, n, ms)
    text = "\n".join(lines)
    print(text)
    (HERE / "sweep-benchmark.md").write_text(text, encoding="utf-8")


def exudyn_table(runs: list, s: list, n: int, ms) -> list:
    """The comparison with Exudyn's ParameterVariation (the lines of
    ``docs/sweep_exudyn.py run``) against S."""
    med = statistics.median
    rate_s, cpu_s = n / med([x["wall"] for x in s]), med([x["cpu"] for x in s]) / n
    out = ["## Against Exudyn's ParameterVariation", "",
           "The same points in Exudyn (`docs/sweep_exudyn.py`, whose docstring says what is "
           "compared: the same bodies, mounts, loads, statics with the base held, 3 s, output "
           "every 1 ms, the same 17 figures per point), `ParameterVariation` with 2 processes, "
           "run on the same machine apart from this report (the loads differ from run to run: "
           "CPU per point is the steadier figure). Agreement: the largest relative difference "
           "of Exudyn's figures from flexbed's on the first 4 points.", "",
           "Commands: `python docs/sweep_exudyn.py variants variants.json 200` (flexbed's "
           "environment), then `EXUDYN_PYTHON docs/sweep_exudyn.py run variants.json 2 1 "
           "dopri5` and `... 2 1 alpha` (Exudyn's), their lines given to this script with "
           "`--exudyn`. `dopri5`: Exudyn's DOPRI5 at the scene's rtol 1e-8 / atol 1e-10 "
           "(flexbed's `auto` picks dop853 at the same tolerances); `alpha`: Exudyn's default "
           "generalized-alpha, one step per output step (1 ms), no error control.", "",
           "| run | solver | load | points/s | CPU per point | flexbed S against it: "
           "points/s | CPU | largest relative difference |",
           "|---|---|---:|---:|---:|---:|---:|---:|"]
    for r in runs:
        for x in r["rounds"]:
            cpu = x["cpu_per_point_ms"] / 1e3
            out.append(f"| Exudyn {r['exudyn']} | {r['solver']} | {x['load']:.1f} | "
                       f"{x['points_per_s']:.2f} | {ms(cpu)} | {rate_s / x['points_per_s']:.2f}× | "
                       f"{cpu / cpu_s:.2f}× less | "
                       f"{r['largest_relative_difference_from_flexbed']:.1e} |")
    out += [f"| flexbed S (above) | dop853 (auto) | {med([x['load'] for x in s]):.1f} | "
            f"{rate_s:.2f} | {ms(cpu_s)} | | | |", ""]
    return out


if __name__ == "__main__":
    main()
