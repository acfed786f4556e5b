"""The measurements of ``docs/sweep_bench.py`` (see its docstring for what
A, B and S are): A, one process; B, plain processes side by side; S, the
study on a fresh local cluster, its CPU by part; the idle cluster; the
serial parts on a ``dask scheduler`` and ``dask worker`` processes
started apart. Each returns seconds."""

from __future__ import annotations

import os
import statistics
import sys
import threading
import time
from pathlib import Path


def _noop(x=None):
    return 0


# --------------------------------------------------------- B: plain processes
def _plain(conn, scenes: list, setup: bytes, base: bytes) -> None:
    """A plain process of B: warm as a worker is, wait for the start, run
    ``scenes`` (packed) one after another; send back (start, end, CPU)."""
    import pickle

    from flexbed.study.point import run_point, warm
    analyses, metrics, _ = pickle.loads(setup)
    warm(pickle.loads(base))
    conn.send("ready")
    conn.recv()
    t0, c0 = time.perf_counter(), time.process_time()
    busy = 0.0
    for blob in scenes:
        res = run_point(pickle.loads(blob), analyses, metrics)
        assert res.status == "ok", res.message
        busy += res.solve_time
    conn.send((t0, time.perf_counter(), time.process_time() - c0, busy))
    conn.close()


def side_by_side(plan, processes: int = 2) -> dict:
    """B: the plan's points split between ``processes`` plain processes
    started together (multiprocessing, spawn). Returns wall [s] (first
    start to last end) and cpu [s] (all the processes, over their points)."""
    import multiprocessing as mp

    from flexbed.study.point import pack
    ctx = mp.get_context("spawn")
    setup = pack((plan.analyses, plan.metrics, False))
    base = pack(plan.base)
    blobs = [pack(p.scene) for p in plan.points]
    pipes, procs = [], []
    for k in range(processes):
        mine, theirs = ctx.Pipe()
        proc = ctx.Process(target=_plain, args=(theirs, blobs[k::processes], setup, base))
        proc.start()
        pipes.append(mine)
        procs.append(proc)
    for conn in pipes:
        assert conn.recv() == "ready"
    for conn in pipes:
        conn.send("go")
    out = [conn.recv() for conn in pipes]
    for proc in procs:
        proc.join(timeout=60)
    wall = max(o[1] for o in out) - min(o[0] for o in out)
    return {"wall": wall, "cpu": sum(o[2] for o in out),
            "busy": sum(o[3] for o in out) / processes / wall}


# ------------------------------------------------------------------ S: the study
def _cpu(proc) -> float:
    t = proc.cpu_times()
    return t.user + t.system


def _parts(workers) -> dict:
    """CPU [s] so far of this process's main thread, its other threads, and
    the worker processes (psutil)."""
    import psutil
    main = threading.main_thread().native_id
    threads = psutil.Process().threads()
    mine = sum(t.user_time + t.system_time for t in threads if t.id == main)
    rest = sum(t.user_time + t.system_time for t in threads if t.id != main)
    return {"client": mine, "loop": rest, "workers": sum(_cpu(w) for w in workers)}


def study_round(plan, workers: int) -> dict:
    """S: a fresh local cluster as ``flexbed sweep`` starts it; the study's
    points on it (``run_plan``, table written to a temporary folder, no
    plots); start (+ warm-up) and stop timed apart."""
    import tempfile

    import psutil

    from flexbed.study import runner
    from flexbed.study.engine import cluster_client

    t0 = time.perf_counter()
    with cluster_client(None, workers, warm_scene=plan.base) as client:
        client.run(_noop)                             # every worker warmed (plugin set up)
        t_start = time.perf_counter() - t0
        procs = [psutil.Process(pid) for pid in client.run(os.getpid).values()]
        with tempfile.TemporaryDirectory() as tmp:
            p0, w0 = _parts(procs), time.perf_counter()
            table = runner.run_plan(plan, scheduler=client, folder=Path(tmp), plots=False)
            wall = time.perf_counter() - w0
            p1 = _parts(procs)
        assert table.complete and table.ok.all()
        t1 = time.perf_counter()
    t_stop = time.perf_counter() - t1
    parts = {k: p1[k] - p0[k] for k in p0}
    parts["points"] = float(sum(table["cpu_time"]))
    return {"wall": wall, "cpu": parts["client"] + parts["loop"] + parts["workers"],
            "parts": parts, "start": t_start, "stop": t_stop,
            "busy": float(sum(table["solve_time"])) / workers / wall,
            "solve": float(statistics.median(table["solve_time"])),
            "first": float(max(table["cpu_time"])), "median": float(statistics.median(
                table["cpu_time"])), "load": os.getloadavg()[0]}


def idle_cost(workers: int, seconds: float = 5.0) -> float:
    """CPU per second [s/s] of an idle local cluster (every process)."""
    import psutil

    from flexbed.study.engine import cluster_client
    with cluster_client(None, workers) as client:
        procs = [psutil.Process(pid) for pid in client.run(os.getpid).values()]
        me = psutil.Process()
        c0, w0 = _cpu(me) + sum(map(_cpu, procs)), time.perf_counter()
        time.sleep(seconds)
        return (_cpu(me) + sum(map(_cpu, procs)) - c0) / (time.perf_counter() - w0)


def in_process(plan, count: int = 40) -> dict:
    """A: median wall and CPU [s] per point of ``run_point`` in this
    process (``wall``, ``cpu``), and the CPU of its parts run alone on the
    same points: ``solve``, the motion from the equilibrium
    (``simulate_system``: the stiffness check, the integration, the output
    samples; what ``flexbed simulate`` costs past the statics and before its
    results), and ``statics`` (``flexbed.statics``: compiling, Newton, the
    checks)."""
    from flexbed.api import statics
    from flexbed.stages.simulation import simulate_system
    from flexbed.study.point import run_point, warm
    warm(plan.base)
    pick = plan.points[:: max(1, len(plan.points) // count)][:count]
    walls, cpus, solves, eqs = [], [], [], []
    for p in pick:
        t0, c0 = time.perf_counter(), time.thread_time()
        res = run_point(p.scene, plan.analyses, plan.metrics)
        walls.append(time.perf_counter() - t0)
        cpus.append(time.thread_time() - c0)
        assert res.status == "ok", res.message
        c0 = time.thread_time()
        st = statics(p.scene)
        eqs.append(time.thread_time() - c0)
        s = p.scene.solver
        c0 = time.thread_time()
        simulate_system(p.scene, st.system, s.settings(), start="equilibrium", model=s.model,
                        linear_tol=s.linear_tol, eq=st.equilibrium)
        solves.append(time.thread_time() - c0)
    med = statistics.median
    return {"wall": med(walls), "cpu": med(cpus), "solve": med(solves), "statics": med(eqs)}


#: the parts of a point that :func:`point_parts` times, in the order they run
PARTS = ("compile", "newton", "stability", "plausibility", "simulate", "metrics")


def point_parts(plan, count: int = 40) -> dict:
    """A point's CPU by part (median over ``count`` of the study's points,
    [s]), each part run alone in the order ``run_point`` runs them:
    ``compile`` (the scene into a System), ``newton`` (Newton-Raphson,
    :func:`flexbed.dynamics.statics.solve_statics`), ``stability`` and
    ``plausibility`` (the checks of the equilibrium), ``simulate`` (the
    analysis: its arguments, the solve, :class:`PointRun`), ``metrics`` (the
    metrics' values: the right-hand-side pass over the output samples and
    what they read); and for the same points ``run_point`` (the whole, run
    again) and ``solve`` (as :func:`in_process`). The metrics' values are
    checked equal to ``run_point``'s."""
    import numpy as np

    from flexbed.api.bed_modes import compiled
    from flexbed.api.equilibrium import _statics_of
    from flexbed.api.simulation import solved
    from flexbed.dynamics.statics import solve_statics
    from flexbed.stages.plausibility import check_equilibrium
    from flexbed.stages.simulation import checked, simulate_system
    from flexbed.study.outputs import PointRun
    from flexbed.study.point import run_point, warm
    warm(plan.base)
    pick = plan.points[:: max(1, len(plan.points) // count)][:count]
    clock = time.thread_time
    times = {k: [] for k in PARTS + ("run_point", "solve")}
    for p in pick:
        sf = p.scene
        c = [clock()]
        system = compiled(sf, None)
        c.append(clock())
        eq = solve_statics(system, tol=sf.solver.static_tol, sag=sf.bed.static_sag)
        c.append(clock())
        eq = checked(system, eq)
        c.append(clock())
        check_equilibrium(sf, system, eq)
        c.append(clock())
        st = _statics_of(sf, system, eq)
        c0 = clock()
        run = PointRun(*solved(sf, equilibrium=st))
        c.append(clock())
        with np.errstate(all="ignore"):
            values = tuple(v for m in plan.metrics for v in m.values({"static": st,
                                                                      "simulate": run}))
        c.append(clock())
        parts = [b - a for a, b in zip(c, c[1:])]
        parts[4] = c[5] - c0                          # simulate: from its own start
        for k, v in zip(PARTS, parts):
            times[k].append(v)
        c0 = clock()
        res = run_point(sf, plan.analyses, plan.metrics)
        times["run_point"].append(clock() - c0)
        assert res.status == "ok" and res.values == values, res.message
        s = sf.solver
        c0 = clock()
        simulate_system(sf, st.system, s.settings(), start="equilibrium", model=s.model,
                        linear_tol=s.linear_tol, eq=st.equilibrium)
        times["solve"].append(clock() - c0)
    return {k: statistics.median(v) for k, v in times.items()}


# ------------------------------------------------------------ the serial parts
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
    # this module's functions (the no-op task) by reference, on processes
    # started in another folder
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(Path(__file__).resolve().parent),
                                                      env.get("PYTHONPATH")]))
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
    try:
        with Client(address, timeout="60s") as client:
            client.wait_for_workers(2, timeout=120)
            c0, w0 = _cpu(sched), time.perf_counter()
            time.sleep(5.0)
            idle = (_cpu(sched) - c0) / (time.perf_counter() - w0)
            c0 = _cpu(sched)
            client.gather(client.map(_noop, range(k), pure=False))
            noop = (_cpu(sched) - c0) / k
        out = {"noop": noop, "idle": idle}
        n = len(plan.points)
        for size in sizes:
            c0, m0, w0 = _cpu(sched), time.process_time(), time.perf_counter()
            with tempfile.TemporaryDirectory() as folder:
                table = runner.run_plan(plan, scheduler=address, folder=Path(folder),
                                        plots=False, batch=size)
            wall = time.perf_counter() - w0
            assert table.complete
            raw = (_cpu(sched) - c0) / n
            out[size] = {"wall": wall, "raw": raw, "scheduler": raw - idle * wall / n,
                         "client": (time.process_time() - m0) / n}
        return out
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            p.wait(timeout=30)
