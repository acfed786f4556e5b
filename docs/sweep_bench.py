"""The study engine measured: a 200-point study of the reference scene
(rigid bed, 3 s; ``docs/sweep-study.toml``) on a local Dask cluster of 2
worker processes, against the same points run one after another in this
process, and the scheduler's cost per task from many tiny tasks; with a
model of the study on W workers. Writes ``docs/sweep-benchmark.md`` (and
prints it).

Usage: ``OPENBLAS_NUM_THREADS=1 python docs/sweep_bench.py [POINTS]``
(default 200; the in-process reference runs 40 of them, spread over the
study). Takes about 3 minutes on 2 cores.

- in-process: ``run_point`` (the very function a worker runs: statics,
  simulate, the metrics) on 40 of the study's points, warm, median wall
  and CPU time (of the thread) per point;
- cluster: ``run_plan`` on a fresh 2-worker ``LocalCluster`` (started,
  warmed, stopped: timed apart), in batches (``batch = "auto"``) and then
  one point a task (``batch = 1``); wall time of the points from the first
  submission to the last row; per point on the cluster = wall × workers /
  points; the CPU of every process of the cluster (client, scheduler,
  nannies, workers) over those points, per point; the workers' own
  ``solve_time`` and ``cpu_time`` (median);
- idle: the cluster's CPU per second while it waits (10 s);
- round trip: 2000 no-op tasks, and 2000 tasks that only unpickle one
  point's scene (what a point task carries), submitted and gathered on the
  same cluster: CPU of every process and wall time per task;
- serial parts: on a ``dask scheduler`` + 2 ``dask worker`` processes
  started apart, the scheduler process's CPU per no-op task and per point
  of the same study, and the client's (this process) per point, at 1 and
  16 points a task (so per task and per point apart): the model of W
  workers and B points a task is built on these.
"""

from __future__ import annotations

import os
import platform
import statistics
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _noop(x=None):
    return 0


def _unpack(blob: bytes):
    import pickle
    pickle.loads(blob)
    return 0


def cpu_now() -> float:
    """CPU time [s] (user + system) of this process (the client, the local
    cluster's scheduler and nannies) and all its children (the workers)."""
    import psutil
    me = psutil.Process()
    total = time.process_time()
    for child in me.children(recursive=True):
        try:
            t = child.cpu_times()
            total += t.user + t.system
        except psutil.Error:
            pass
    return total


def serial_costs(plan, k: int, sizes=(1, 16)) -> dict:
    """The serial parts of a study, each one process that every task goes
    through: a ``dask scheduler`` and two ``dask worker`` processes started
    here (with the local cluster's settings), the scheduler's CPU per task
    (``k`` no-op tasks; the study's points) and the client's (this
    process: submitting, gathering, the rows, the table's writes) per
    point, from the processes' own CPU times; the study once per batch
    size in ``sizes`` (points per task), so that the costs per task and
    per point can be told apart."""
    import socket
    import subprocess
    import tempfile

    import psutil
    from distributed import Client

    from flexbed.study import runner
    from flexbed.study.engine import LOCAL_CONFIG, worker_environment

    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    env = {**os.environ, **worker_environment()}
    for key, value in LOCAL_CONFIG.items():
        env["DASK_" + key.upper().replace(".", "__").replace("-", "_")] = str(value)
    dask = str(Path(sys.executable).parent / "dask")
    tmp = tempfile.mkdtemp()
    procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", str(port),
                               "--no-dashboard"], env=env, cwd=tmp,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    procs += [subprocess.Popen([dask, "worker", address, "--nthreads", "1", "--no-dashboard",
                                "--local-directory", tmp], env=env, cwd=tmp,
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
              for _ in range(2)]
    sched = psutil.Process(procs[0].pid)

    def cpu(proc):
        t = proc.cpu_times()
        return t.user + t.system

    try:
        with Client(address, timeout="60s") as client:
            client.wait_for_workers(2, timeout=120)
            c0, w0 = cpu(sched), time.perf_counter()
            time.sleep(10.0)
            idle = (cpu(sched) - c0) / (time.perf_counter() - w0)
            c0 = cpu(sched)
            client.gather(client.map(_noop, range(k), pure=False))
            noop = (cpu(sched) - c0) / k
        out = {"noop": noop, "idle": idle}
        n = len(plan.points)
        for size in sizes:
            c0, m0, w0 = cpu(sched), time.process_time(), time.perf_counter()
            with tempfile.TemporaryDirectory() as folder:
                table = runner.run_plan(plan, scheduler=address, folder=Path(folder),
                                        plots=False, batch=size)
            wall = time.perf_counter() - w0
            assert table.complete
            raw = (cpu(sched) - c0) / n
            out[size] = {"wall": wall, "raw": raw, "scheduler": raw - idle * wall / n,
                         "client": (time.process_time() - m0) / n}
        return out
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            p.wait(timeout=30)


def main() -> None:
    import dataclasses
    import tempfile

    from distributed import Client, LocalCluster

    import flexbed
    from flexbed.study import runner
    from flexbed.study.engine import worker_environment
    from flexbed.study.plan import make_plan
    from flexbed.study.point import run_point, warm
    from flexbed.study.spec import read_study

    n = int(sys.argv[1]) if len(sys.argv) > 1 else 200
    study = read_study(HERE / "sweep-study.toml")
    if n != study.samples:
        study = dataclasses.replace(study, samples=n)
    plan = make_plan(study)
    workers = 2

    # in-process reference: the same function on a spread of the points
    warm(plan.base)
    pick = plan.points[:: max(1, len(plan.points) // 40)][:40]
    run_point(pick[0].scene, plan.analyses, plan.metrics)
    walls, cpus = [], []
    for p in pick:
        t0, c0 = time.perf_counter(), time.thread_time()
        res = run_point(p.scene, plan.analyses, plan.metrics)
        walls.append(time.perf_counter() - t0)
        cpus.append(time.thread_time() - c0)
        assert res.status == "ok", res.message
    t1, c1 = statistics.median(walls), statistics.median(cpus)

    # the study on a 2-worker local cluster
    import dask
    from flexbed.study.engine import LOCAL_CONFIG
    dask.config.set(LOCAL_CONFIG)
    t0 = time.perf_counter()
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           dashboard_address=":0", env=worker_environment())
    client = Client(cluster)
    from flexbed.study.point import WarmUp
    client.register_plugin(WarmUp(plan.base))
    t_start = time.perf_counter() - t0
    # the study one point a task, then in batches (runner.auto_batch)
    from flexbed.study.runner import auto_batch
    auto = auto_batch(n, workers)
    runs = {}
    for size in (1, auto):
        with tempfile.TemporaryDirectory() as tmp:
            t0, c0 = time.perf_counter(), cpu_now()
            table = runner.run_plan(plan, scheduler=client, folder=Path(tmp), plots=False,
                                    batch=size)
            t_study, c_study = time.perf_counter() - t0, cpu_now() - c0
        assert table.complete and table.ok.all()
        runs[size] = {"wall": t_study, "cpu": c_study,
                      "solve": statistics.median(table["solve_time"]),
                      "solve_cpu": statistics.median(table["cpu_time"])}
    t_study, c_study = runs[auto]["wall"], runs[auto]["cpu"]
    solve, solve_cpu = runs[auto]["solve"], runs[auto]["solve_cpu"]

    # the cluster's CPU when idle (heartbeats, event loops)
    t0, c0 = time.perf_counter(), cpu_now()
    time.sleep(10.0)
    idle = (cpu_now() - c0) / (time.perf_counter() - t0)

    # the scheduler's cost per task
    k = 2000
    t0, c0 = time.perf_counter(), cpu_now()
    client.gather(client.map(_noop, range(k), pure=False))
    s_noop, cs_noop = (time.perf_counter() - t0) / k, (cpu_now() - c0) / k
    from flexbed.study.point import pack
    scene = plan.points[0].scene
    t0, c0 = time.perf_counter(), cpu_now()
    client.gather(client.map(_unpack, [pack(scene) for _ in range(k)], pure=False))
    s_scene, cs_scene = (time.perf_counter() - t0) / k, (cpu_now() - c0) / k
    t0 = time.perf_counter()
    client.close()
    cluster.close()
    t_stop = time.perf_counter() - t0
    # the serial parts per task, measured with short points (0.01 s of
    # motion each) so that the study is short and the processes' idle
    # housekeeping (which grows with the wall time) adds little
    fast = dataclasses.replace(study, samples=400,
                               fixed=study.fixed + (("solver.t_end", 0.01),))
    big = 16
    serial = serial_costs(make_plan(fast), k, sizes=(1, big))

    def split(part):
        """(per task, per point) [s of CPU] from the costs per point at
        one point a task and at ``big``."""
        one, many = serial[1][part], serial[big][part]
        per_task = max(0.0, (one - many) / (1.0 - 1.0 / big))
        return per_task, max(0.0, one - per_task)

    (sched_t, sched_p), (client_t, client_p) = split("scheduler"), split("client")

    def serial_per_point(b):
        return max(sched_t / b + sched_p, client_t / b + client_p)

    per_point = t_study * workers / n
    cpu_point = c_study / n
    rate = n / t_study
    lines = [
        "# Design studies on Dask: measured",
        "",
        f"Written by `python docs/sweep_bench.py {n}` on {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; "
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} logical CPUs (shared with "
        f"other work: load average {', '.join(f'{x:.2f}' for x in os.getloadavg())} at the end); "
        f"Python {platform.python_version()}, flexbed {flexbed.__version__}.",
        "",
        f"Study: `docs/sweep-study.toml`, {n} points (Latin hypercube), the reference scene "
        f"(rigid bed, 0-3 s), analyses {', '.join(plan.analyses)}, "
        f"{len(plan.metric_columns)} metric columns; run on the cluster in batches of "
        f"{auto} points a task (`batch = \"auto\"` for {n} points on {workers} workers), "
        f"then again one point a task.",
        "",
        "| quantity | value |",
        "|---|---:|",
        f"| one point in process (statics + simulate + metrics), median of {len(pick)}: CPU | "
        f"{1e3 * c1:.1f} ms |",
        f"| the same, wall | {1e3 * t1:.1f} ms |",
        f"| local cluster start + warm-up ({workers} workers), wall | {t_start:.2f} s |",
        f"| the study's points on the cluster: CPU of every process (client, scheduler, "
        f"nannies, workers) per point | {1e3 * cpu_point:.1f} ms |",
        f"| **overhead per point against in process (CPU)** | "
        f"**{100 * (cpu_point / c1 - 1):+.1f} %** |",
        f"| the same study one point a task (`batch = 1`): CPU of every process per point / "
        f"overhead | {1e3 * runs[1]['cpu'] / n:.1f} ms / "
        f"{100 * (runs[1]['cpu'] / n / c1 - 1):+.1f} % |",
        f"| one point a task: points per second (wall) | {n / runs[1]['wall']:.2f} |",
        f"| a point's own CPU time on its worker (`cpu_time`), median | "
        f"{1e3 * solve_cpu:.1f} ms |",
        f"| the same, wall (`solve_time`) | {1e3 * solve:.1f} ms |",
        f"| the study's points on the cluster, wall | {t_study:.2f} s |",
        f"| per point on the cluster, wall × {workers} / {n} | {1e3 * per_point:.1f} ms |",
        f"| points per second (wall) | {rate:.2f} |",
        f"| scheduler, per no-op task ({k} tasks): CPU of every process / wall | "
        f"{1e3 * cs_noop:.2f} / {1e3 * s_noop:.2f} ms |",
        f"| scheduler, per no-op task carrying a point's scene ({k} tasks): CPU / wall | "
        f"{1e3 * cs_scene:.2f} / {1e3 * s_scene:.2f} ms |",
        f"| the cluster idle (2 workers, scheduler, client), CPU per second of wall | "
        f"{1e3 * idle:.1f} ms/s |",
        f"| cluster stop, wall | {t_stop:.2f} s |",
        "",
        "The machine's 2 cores are shared with other work (see the load average): wall "
        "times are inflated by it, CPU times much less; the overhead is taken from CPU. "
        "Where it goes: the point's own CPU on its worker (the thread that ran it) "
        f"against in process: {100 * (solve_cpu / c1 - 1):+.1f} %; the task round trip "
        f"(scheduler, client, transfer; the no-op task carrying a scene): "
        f"{100 * cs_scene / c1:.1f} % of a point; the cluster's idle housekeeping over "
        f"the study's wall time: {100 * idle * t_study / n / c1:.1f} % of a point "
        "(it grows with the wall time, so with the load of the machine).",
        "",
        f"Serial parts (a `dask scheduler` and 2 `dask worker` processes started apart, "
        f"the same settings; CPU of each process): the scheduler {1e3 * serial['noop']:.2f} ms "
        f"per no-op task (its idle housekeeping {1e3 * serial['idle']:.1f} ms/s, measured "
        f"idle, taken off below). The same study with 0.01 s of motion per point, 400 "
        f"points, run one point a task and {big} points a task:",
        "",
        "| points a task | wall [s] | scheduler CPU per point [ms] | client CPU per point [ms] |",
        "|---:|---:|---:|---:|",
        *(f"| {b} | {serial[b]['wall']:.1f} | {1e3 * serial[b]['scheduler']:.2f} | "
          f"{1e3 * serial[b]['client']:.2f} |" for b in (1, big)),
        "",
        f"So per task / per point: the scheduler {1e3 * sched_t:.2f} / {1e3 * sched_p:.2f} ms, "
        f"the client (this process: submitting, gathering, the rows, the table's writes "
        f"every 5 s) {1e3 * client_t:.2f} / {1e3 * client_p:.2f} ms.",
        "",
        "Model of W workers (one core each): a point costs t_p = "
        f"{1e3 * c1:.0f} ms of CPU (in process) on its worker; every task also passes, one "
        "at a time, through the scheduler and the client: with B points a task, "
        "s(B) = max(scheduler per task / B + per point, client per task / B + per point) "
        f"= {1e3 * serial_per_point(1):.2f} ms at B = 1, {1e3 * serial_per_point(big):.2f} ms "
        f"at B = {big} (measured on 2 shared cores: an upper bound). The study's rate is "
        "min(W / t_p, 1 / s(B)) points per second; `batch = \"auto\"` takes "
        "B = min(16, ceil(N / 8W)) (at least 8 tasks a worker, so that the last ones leave "
        "no worker idle for long).",
        "",
        "| workers W | W / t_p [points/s] | 1 / s(1) | rate, B = 1 [points/s] | efficiency | "
        f"1 / s({big}) | rate, B = {big} | efficiency | B auto for 10,000 points | "
        "rate [points/s] |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for w in (1, 2, 8, 16, 32, 64, 128):
        ideal = w / c1
        r1 = min(ideal, 1 / serial_per_point(1))
        rb = min(ideal, 1 / serial_per_point(big))
        ba = auto_batch(10000, w)
        ra = min(ideal, 1 / serial_per_point(ba))
        lines.append(f"| {w} | {ideal:.1f} | {1 / serial_per_point(1):.0f} | {r1:.1f} | "
                     f"{100 * r1 / ideal:.0f} % | {1 / serial_per_point(big):.0f} | {rb:.1f} | "
                     f"{100 * rb / ideal:.0f} % | {ba} | {ra:.1f} |")
    lines.append("")
    text = "\n".join(lines)
    print(text)
    (HERE / "sweep-benchmark.md").write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()
