"""Design studies on Dask (issue 15): a real scheduler and two worker
processes run a study through ``--scheduler`` and every metric equals the
one of a single in-process statics / simulate of the same scene, bit for
bit; the local cluster by default; a failing point; resumption; an
interrupted study keeps its finished rows; a study is refused, with the
path or metric named, before anything runs.

Studies are tiny: the reference scene (rigid bed) over 0.05 s."""

from __future__ import annotations

import csv
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import flexbed
from row_killer import kill_after_the_first_row
from flexbed.cli import main
from flexbed.errors import InputError
from flexbed.files.store import read_file
from flexbed.study.plan import make_plan
from flexbed.study.samplers import latin_hypercube, points
from flexbed.study.spec import parse_study

T_END = 0.05

METRICS = """
[[metric]]
kind = "peak_displacement"
point = "A top"

[[metric]]
kind = "peak_acceleration"
body = "equipment B"
position = [0.1, 0.0, 0.15]
direction = "z"

[[metric]]
kind = "peak_mount_force"
mounts = ["M5", "M12"]

[[metric]]
kind = "peak_mount_deflection"
mounts = ["M1"]
axis = 3

[[metric]]
kind = "static_deflection"
mounts = ["M1", "M9"]
axis = 3

[[metric]]
kind = "max_static_deflection"
"""


def study_file(folder: Path, body: str, t_end: float = T_END, metrics: str = METRICS,
               name: str = "study.toml") -> Path:
    path = folder / name
    path.write_text(f'[study]\nname = "test"\n{body}\n[study.set]\n"solver.t_end" = {t_end}\n'
                    f'{metrics}', encoding="utf-8")
    return path


GRID = """sampling = "grid"

[[parameter]]
path = "mount.M5.k"
values = [[1.0e5, 1.0e5, 1.0e5], [2.0e5, 2.0e5, 1.5e5]]

[[parameter]]
path = "bed.thickness"
values = [0.1, 0.12]
"""


def expected(values: dict) -> dict:
    """The metrics from a single in-process statics and simulate of the
    point's scene, computed here from the runs' arrays."""
    scene = flexbed.vary(flexbed.load_scene(), {"solver.t_end": T_END, **values})
    st = flexbed.statics(scene)
    run = flexbed.simulate(scene)
    a = run.point("equipment A", [0.0, 0.0, 0.15], relative_to="bed")
    b = run.point("equipment B", [0.1, 0.0, 0.15])
    dx = run.mount_deflection[0]                  # the run starts at the equilibrium
    np.testing.assert_array_equal(dx, st.system.observe(0.0, st.equilibrium.y).dx)
    names = run.mount_names
    return {
        "peak_displacement.A top@bed": np.linalg.norm(a.position - a.position[0], axis=1).max(),
        "peak_acceleration.equipment B (0.1 0 0.15).z": np.abs(b.acceleration[:, 2]).max(),
        "peak_mount_force.M5": np.linalg.norm(run.mount_force[:, names.index("M5")], axis=1).max(),
        "peak_mount_force.M12": np.linalg.norm(run.mount_force[:, names.index("M12")],
                                               axis=1).max(),
        "peak_mount_deflection.M1.axis3": np.abs(run.mount_deflection[:, 0, 2]).max(),
        "static_deflection.M1.axis3": dx[0, 2],
        "static_deflection.M9.axis3": dx[names.index("M9"), 2],
        "max_static_deflection": np.linalg.norm(dx, axis=1).max(),
    }


def table_columns(folder: Path) -> tuple[dict, dict]:
    c = read_file(folder / "table.h5", schema="flexbed.study", major=1)
    cols = {k[len("table/"):]: np.atleast_1d(v) for k, v in c.datasets.items()}
    return cols, c.attrs[""]


# ------------------------------------------------------------------ a real cluster
def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def scheduler(tmp_path_factory):
    """``dask scheduler`` and two ``dask worker`` processes on localhost."""
    from distributed import Client

    where = tmp_path_factory.mktemp("cluster")
    dask = str(Path(sys.executable).parent / "dask")
    address = f"tcp://127.0.0.1:{_free_port()}"
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "FLEXBED_THREADS": "1"}
    log = open(where / "cluster.log", "w")
    procs = [subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port",
                               address.rsplit(":", 1)[1], "--no-dashboard"],
                              cwd=where, env=env, stdout=log, stderr=log,
                              start_new_session=True)]
    try:
        for i in range(2):
            procs.append(subprocess.Popen([dask, "worker", address, "--nthreads", "1",
                                           "--no-dashboard", "--name", f"w{i}",
                                           "--local-directory", str(where)],
                                          cwd=where, env=env, stdout=log, stderr=log,
                                          start_new_session=True))
        with Client(address, timeout="60s") as client:
            client.wait_for_workers(2, timeout=120)
        yield address
        with Client(address, timeout="20s") as client:
            client.shutdown()                 # the scheduler and its workers, at once
    finally:
        deadline = time.monotonic() + 3.0
        for p in procs:              # each its own process group: the worker and its nanny
            try:
                p.wait(timeout=max(0.1, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait(timeout=20)
        log.close()


@pytest.mark.slow
def test_a_study_on_a_scheduler_and_two_workers_equals_single_runs(tmp_path, scheduler,
                                                                    capsys):
    study = study_file(tmp_path, GRID)
    out = tmp_path / "out"
    assert main(["sweep", str(study), "--scheduler", scheduler, "-o", str(out),
                 "--no-progress", "--no-plots"]) == 0
    assert "4 points" in capsys.readouterr().out
    cols, attrs = table_columns(out)
    assert attrs["complete"] and attrs["points_done"] == 4
    assert list(cols["point"]) == [0, 1, 2, 3]
    assert list(cols["status"]) == ["ok"] * 4
    assert list(cols["bed.thickness"]) == [0.1, 0.12, 0.1, 0.12]
    assert list(cols["mount.M5.k[2]"]) == [1e5, 1e5, 1.5e5, 1.5e5]
    for i in range(4):
        values = {"mount.M5.k": [cols[f"mount.M5.k[{j}]"][i] for j in range(3)],
                  "bed.thickness": cols["bed.thickness"][i]}
        for name, value in expected(values).items():
            assert cols[name][i] == value, (i, name)          # exactly
        assert cols["scene_hash"][i] == flexbed.vary(
            flexbed.load_scene(), {"solver.t_end": T_END, **values}).digest
    # the CSV holds the same numbers, exactly
    with open(out / "table.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    for name in ("peak_mount_force.M5 [N]", "static_deflection.M1.axis3 [m]"):
        assert [float(r[name]) for r in rows] == list(cols[name.split(" [")[0]])


@pytest.mark.slow
def test_an_interrupted_study_keeps_its_finished_rows(tmp_path, scheduler):
    """SIGINT (Ctrl-C) to a running ``flexbed sweep``: exit 130, every row
    finished so far written, the table marked incomplete. (240 points of
    2 s of motion, one a task, so that the first row comes early and the
    signal long before the last: with "auto" batches of 60 points the first
    rows came after a quarter of them, and the rest were done before the
    signal arrived.)"""
    body = """sampling = "grid"

[[parameter]]
path = "bed.thickness"
from = 0.08
to = 0.14
num = 240
"""
    study = study_file(tmp_path, body, t_end=2.0, metrics='[[metric]]\nkind = "peak_mount_force"'
                       '\nmounts = ["M5"]\n')
    out = tmp_path / "out"
    p = subprocess.Popen([sys.executable, "-m", "flexbed.cli", "sweep", str(study),
                          "--scheduler", scheduler, "-o", str(out), "--no-plots", "--batch", "1"],
                         cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    csv = out / "table.csv"
    deadline = time.monotonic() + 120
    seen = 0
    while time.monotonic() < deadline and p.poll() is None:
        if csv.exists():
            seen = len(csv.read_text().splitlines()) - 1
            if seen >= 1:
                break
        time.sleep(0.02)
    assert seen >= 1, p.communicate()
    p.send_signal(signal.SIGINT)
    out_text, err = p.communicate(timeout=120)
    assert p.returncode == 130, (seen, out_text, err)
    assert "flexbed sweep: interrupted" in err
    cols, attrs = table_columns(out)
    assert not attrs["complete"]
    assert seen <= attrs["points_done"] < 240
    assert set(cols["status"]) == {"ok"}
    assert np.all(np.isfinite(cols["peak_mount_force.M5"]))


@pytest.mark.slow
def test_a_worker_lost_mid_study_has_its_points_run_again(tmp_path, scheduler):
    """SIGKILL to one worker process once the first row is in: its points
    are run again on the other worker (or its restart); every row ok."""
    from distributed import Client

    with Client(scheduler, timeout="30s") as c:
        victim = sorted(c.run(os.getpid).values())[0]
    body = ('sampling = "grid"\n\n[[parameter]]\npath = "bed.thickness"\nfrom = 0.08\n'
            'to = 0.14\nnum = 24\n')
    study = study_file(tmp_path, body, t_end=0.3,
                       metrics='[[metric]]\nkind = "peak_mount_force"\nmounts = ["M5"]\n')
    csv_path = tmp_path / "out" / "table.csv"
    killer, killed = kill_after_the_first_row(csv_path, victim)
    table = flexbed.sweep(study, scheduler, output=tmp_path / "out", plots=False)
    killer.join(timeout=5)
    assert killed and killed[0] < 24                   # killed while points were left
    with pytest.raises(ProcessLookupError):
        os.kill(victim, 0)
    assert table.complete and len(table) == 24
    assert set(table["status"]) == {"ok"}, set(table["message"])


# ------------------------------------------------------------ an in-process cluster
@pytest.fixture(scope="module")
def client():
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                      dashboard_address=":0") as cluster, Client(cluster) as c:
        yield c


@pytest.mark.slow
def test_a_failing_point_keeps_its_message_and_the_study_goes_on(tmp_path, client):
    body = """sampling = "list"

[[point]]
"solver.static_tol" = 1.0e-6

[[point]]
"solver.static_tol" = 1.0e-30
"""
    table = flexbed.sweep(study_file(tmp_path, body), client, output=tmp_path / "out",
                          plots=False)
    assert table.complete and len(table) == 2
    assert list(table["status"]) == ["ok", "failed"]
    assert table["message"][0] == ""
    assert table["message"][1].startswith("lee1999.toml: no static equilibrium")
    assert "\n" not in table["message"][1]
    assert np.isnan(table["max_static_deflection"][1])
    assert table["max_static_deflection"][0] == expected({})["max_static_deflection"]
    cols, _ = table_columns(tmp_path / "out")
    assert list(cols["status"]) == ["ok", "failed"]


@pytest.mark.slow
def test_a_rerun_skips_the_points_done(tmp_path, client):
    body = """sampling = "zip"

[[parameter]]
path = "bed.thickness"
values = [0.1, 0.12]

[[parameter]]
path = "mount.M9.k"
values = [[1.0e5, 1.0e5, 1.0e5], [2.0e5, 2.0e5, 2.0e5]]
"""
    out = tmp_path / "out"
    first = flexbed.sweep(study_file(tmp_path, body), client, output=out, plots=False)
    assert first.complete and list(first["status"]) == ["ok", "ok"]
    # one more point: the two done are read back (their solve times are
    # those recorded, not new ones), the new one runs
    more = body.replace("[0.1, 0.12]", "[0.1, 0.12, 0.09]").replace(
        "[2.0e5, 2.0e5, 2.0e5]]", "[2.0e5, 2.0e5, 2.0e5], [3.0e5, 3.0e5, 3.0e5]]")
    second = flexbed.sweep(study_file(tmp_path, more), client, output=out, plots=False)
    assert second.complete and len(second) == 3
    np.testing.assert_array_equal(second["solve_time"][:2], first["solve_time"])
    np.testing.assert_array_equal(second["scene_hash"][:2], first["scene_hash"])
    assert second["scene_hash"][2] not in first["scene_hash"]
    assert second["peak_mount_force.M5"][2] == expected(
        {"bed.thickness": 0.09, "mount.M9.k": [3e5, 3e5, 3e5]})["peak_mount_force.M5"]


@pytest.mark.slow
def test_the_local_cluster_is_the_default(shared_command):
    """No --scheduler: a local cluster of processes, one per core, started
    and stopped by the command; every metric equals the single in-process
    run's, bit for bit; plots of each metric against the varied parameter.
    Checked on the tour page's study (docs/tour.md's ``stiffness.toml``:
    M5's stiffness at 4 points over 0.5 s), whose ``flexbed sweep`` line
    runs once per pytest run for both (conftest's ``shared_command``)."""
    cp = shared_command("flexbed sweep stiffness.toml -o stiffness --no-progress")
    assert cp.returncode == 0, cp.stderr
    assert "--scheduler" not in cp.stdout and "4 points" in cp.stdout
    out = cp.cwd / "stiffness"
    cols, attrs = table_columns(out)
    assert attrs["complete"] and list(cols["status"]) == ["ok"] * 4
    assert [cols["mount.M5.k[0]"][i] for i in (0, 3)] == [5e4, 2e5]
    for i in (0, 3):
        k = [cols[f"mount.M5.k[{j}]"][i] for j in range(3)]
        single = expected({"solver.t_end": 0.5, "mount.M5.k": k})
        for name in ("peak_mount_force.M5", "peak_displacement.A top@bed"):
            assert cols[name][i] == single[name], (i, name)          # exactly
    for name in ("peak_mount_force.M5", "peak_displacement.A_top@bed"):
        assert (out / "plots" / f"{name}--mount.M5.k_0.png").stat().st_size > 0


# --------------------------------------------------- refused before anything runs
@pytest.mark.parametrize("body, metrics, message", [
    ('sampling = "grid"\n[[parameter]]\npath = "mount.M55.k"\nvalues = [[1.0, 1.0, 1.0]]\n',
     METRICS, "parameter 'mount.M55.k': variant path 'mount.M55.k': no entry named 'M55'"),
    ('sampling = "grid"\n[[parameter]]\npath = "bed.thickness"\nvalues = [0.1, -0.1]\n',
     METRICS, "point 1 (bed.thickness = -0.1)"),
    ('sampling = "grid"\n', '[[metric]]\nkind = "peak_stress"\n',
     "metric 1: unknown kind 'peak_stress'"),
    ('sampling = "grid"\n', '[[metric]]\nkind = "peak_mount_force"\nmounts = ["M13"]\n',
     "metric 1 (peak_mount_force): mount 'M13' is not a mount of the scene"),
    ('sampling = "grid"\n', '[[metric]]\nkind = "peak_displacement"\npoint = "C top"\n',
     "point = 'C top' is not a [[point]] of the scene"),
    ('sampling = "lhs"\nsamples = 0\n', METRICS, "samples = 0 must be an integer >= 1"),
    ('sampling = "grid"\n', '[[metric]]\nkind = "natural_frequency"\nmode = 19\n',
     "metric 1 (natural_frequency): mode = 19: the mounted system has 18 coordinates"),
    ('sampling = "grid"\n', '[[metric]]\nkind = "transmissibility"\npoint = "C top"\n'
     'frequency = 8.0\n', "metric 1 (transmissibility): point = 'C top' is not a [[point]]"),
    ('sampling = "grid"\n', '[[metric]]\nkind = "transmissibility"\npoint = "A top"\n'
     'frequency = -8.0\n', "metric 1 (transmissibility): frequency = -8.0 must be a number > 0"),
    ('sampling = "grid"\n', '[[metric]]\nkind = "effective_mass_fraction"\naxis = "w"\n',
     "metric 1 (effective_mass_fraction): axis = 'w' must be x, y or z"),
])
def test_a_study_is_refused_with_the_entry_named(tmp_path, capsys, body, metrics, message):
    study = study_file(tmp_path, body, metrics=metrics)
    out = tmp_path / "out"
    assert main(["sweep", str(study), "-o", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("flexbed sweep: study.toml: ") and message in err, err
    assert err.count("\n") == 1
    assert not out.exists()


# ------------------------------------------------------------------------ samplers
def test_samplers():
    def study(body):
        return parse_study(f"[study]\n{body}\n[[metric]]\nkind = \"max_static_deflection\"\n",
                           Path("s.toml"))
    grid = points(study('sampling = "grid"\n[[parameter]]\npath = "a"\nfrom = 1.0\nto = 100.0\n'
                        'num = 3\nscale = "log"\n[[parameter]]\npath = "b"\nvalues = ["x", "y"]'))
    assert [(p["a"], p["b"]) for p in grid] == [(1.0, "x"), (1.0, "y"), (10.0, "x"),
                                               (10.0, "y"), (100.0, "x"), (100.0, "y")]
    z = points(study('sampling = "zip"\n[[parameter]]\npath = "k"\nfrom = [1.0, 2.0]\n'
                     'to = [3.0, 6.0]\nnum = 3\n[[parameter]]\npath = "b"\nvalues = [7, 8, 9]'))
    assert z == [{"k": [1.0, 2.0], "b": 7}, {"k": [2.0, 4.0], "b": 8},
                 {"k": [3.0, 6.0], "b": 9}]
    # Latin hypercube: one sample in each of the n strata of every parameter
    u = latin_hypercube(50, 3, seed=7)
    for j in range(3):
        assert sorted(np.floor(u[:, j] * 50).astype(int)) == list(range(50))
    np.testing.assert_array_equal(u, latin_hypercube(50, 3, seed=7))
    assert not np.array_equal(u, latin_hypercube(50, 3, seed=8))
    lhs = points(study('sampling = "lhs"\nsamples = 5\nseed = 3\n[[parameter]]\npath = "t"\n'
                       'low = 0.1\nhigh = 0.2'))
    assert sorted(int((p["t"] - 0.1) / 0.02) for p in lhs) == [0, 1, 2, 3, 4]
    with pytest.raises(InputError, match="counts differ: a 2, b 3"):
        study('sampling = "zip"\n[[parameter]]\npath = "a"\nvalues = [1, 2]\n'
              '[[parameter]]\npath = "b"\nvalues = [1, 2, 3]')


def test_identical_points_are_one_computation(tmp_path):
    plan = make_plan(parse_study(
        '[study]\nsampling = "list"\n[[point]]\n"bed.thickness" = 0.1\n[[point]]\n'
        '"bed.thickness" = 0.12\n[[point]]\n"bed.thickness" = 0.1\n'
        '[[metric]]\nkind = "max_static_deflection"\n', tmp_path / "s.toml"))
    keys = [p.key for p in plan.points]
    assert keys[0] == keys[2] != keys[1]
    assert plan.analyses == ("static",)


@pytest.mark.slow
def test_a_flexible_bed_s_modes_are_one_task_shared_by_its_points(tmp_path, client):
    """Two points on the same flexible bed (one plate): one modes request;
    the mount force and the compare figure equal single in-process runs."""
    body = """sampling = "list"

[[point]]
"mount.M5.k" = [1.0e5, 1.0e5, 1.0e5]

[[point]]
"mount.M5.k" = [2.0e5, 2.0e5, 2.0e5]
"""
    metrics = ('[[metric]]\nkind = "peak_mount_force"\nmounts = ["M5"]\n\n'
               '[[metric]]\nkind = "compare"\nequipment = "equipment A"\n')
    study = study_file(tmp_path, body, metrics=metrics).read_text().replace(
        '[study.set]\n', '[study.set]\n"bed.model" = "flexible"\n')
    (tmp_path / "study.toml").write_text(study)
    plan = make_plan(parse_study(study, tmp_path / "study.toml"))
    assert len({p.modes_key for p in plan.points}) == 1
    table = flexbed.sweep(tmp_path / "study.toml", client, plots=False)
    assert list(table["status"]) == ["ok", "ok"]
    scene = flexbed.vary(flexbed.load_scene(), {"solver.t_end": T_END, "bed.model": "flexible",
                                                "mount.M5.k": [2e5, 2e5, 2e5]})
    run = flexbed.simulate(scene)
    assert table["peak_mount_force.M5"][1] == np.linalg.norm(run.mount_force[:, 4], axis=1).max()
    rows = flexbed.compare(scene).rows
    assert table["compare.damped.equipment A.peak"][1] == next(
        r["peak"] for r in rows if r["equipment"] == "equipment A" and r["case"] == "damped")


@pytest.mark.slow
def test_frequency_metrics_equal_single_modal_and_frf_runs(tmp_path, scheduler):
    """natural_frequency, effective_mass_fraction, transmissibility and
    peak_transmissibility of two points, run by the `dask worker`
    processes (which import the metric kinds afresh when they unpickle
    them), equal, exactly, a single in-process flexbed.modal / flexbed.frf
    of each point's scene (the modes about the statics' equilibrium when a
    static metric runs too)."""
    body = ('sampling = "list"\n\n[[point]]\n"mount.M5.k" = [1.0e5, 1.0e5, 1.0e5]\n\n'
            '[[point]]\n"mount.M5.k" = [3.0e5, 3.0e5, 2.0e5]\n')
    metrics = """
[[metric]]
kind = "natural_frequency"

[[metric]]
kind = "natural_frequency"
mode = 11
quantity = "damping_ratio"

[[metric]]
kind = "effective_mass_fraction"
axis = "z"
mode = 3

[[metric]]
kind = "transmissibility"
point = "A top"
frequency = 8.0

[[metric]]
kind = "transmissibility"
body = "equipment B"
position = [0.1, 0.0, 0.15]
relative_to = "bed"
input = "base y"
frequency = 12.5

[[metric]]
kind = "peak_transmissibility"
point = "B top"
band = [3.0, 5.0]

[[metric]]
kind = "max_static_deflection"
"""
    table = flexbed.sweep(study_file(tmp_path, body, metrics=metrics), scheduler, plots=False)
    assert list(table["status"]) == ["ok", "ok"], list(table["message"])
    assert table.units["transmissibility.A top.z.8Hz"] == "1"
    for i, k in enumerate(([1e5, 1e5, 1e5], [3e5, 3e5, 2e5])):
        scene = flexbed.vary(flexbed.load_scene(), {"solver.t_end": T_END, "mount.M5.k": k})
        m = flexbed.modal(scene)
        assert table["natural_frequency.mode1"][i] == m.frequency[0]
        assert table["natural_frequency.mode11.damping_ratio"][i] == m.damping_ratio[10]
        assert table["effective_mass_fraction.z.mode3"][i] == m.effective_mass[2, 2] / m.moving_mass
        t = flexbed.frf(scene, input="base z", points=[("A top", "equipment A", [0, 0, 0.15])],
                        frequencies=[8.0])
        assert table["transmissibility.A top.z.8Hz"][i] == t.magnitude[0, t.column("A top az")]
        label = "equipment B (0.1 0 0.15)"
        t = flexbed.frf(scene, input="base y", frequencies=[12.5],
                        points=[(label, "equipment B", [0.1, 0, 0.15], "bed")])
        assert table[f"transmissibility.{label}@bed.y.12.5Hz"][i] == \
            t.magnitude[0, t.column(f"{label}@bed ay")]
        t = flexbed.frf(scene, band=(3.0, 5.0), points=[("B top", "equipment B", [0, 0, 0.15])])
        peak = table["peak_transmissibility.B top.z.3-5Hz"][i]
        assert peak == t.magnitude[:, t.column("B top az")].max() and peak > 100
    # the modes of the stiffer M5 are higher
    assert table["natural_frequency.mode1"][1] > table["natural_frequency.mode1"][0]


@pytest.mark.slow
def test_a_batched_study_equals_an_unbatched_one_row_for_row(tmp_path, client):
    """Three points a task (one of them failing, one a duplicate) give the
    same rows as one point a task; a re-run in batches of two skips the
    points done and runs the new ones."""
    from flexbed.study.runner import auto_batch, auto_sizes, batches

    body = ('sampling = "list"\n' + "".join(
        f'\n[[point]]\n"bed.thickness" = {t}\n"solver.static_tol" = {tol}\n'
        for t, tol in ((0.1, 1e-6), (0.11, 1e-30), (0.12, 1e-6), (0.1, 1e-6), (0.13, 1e-6))))
    metrics = '[[metric]]\nkind = "static_deflection"\nmounts = ["M5"]\n' \
              '[[metric]]\nkind = "max_static_deflection"\n'
    study = study_file(tmp_path, body, metrics=metrics)
    one = flexbed.sweep(study, client, plots=False, batch=1)
    three = flexbed.sweep(study, client, plots=False, batch=3)
    assert list(one["status"]) == ["ok", "failed", "ok", "ok", "ok"]
    for name in one.columns:
        if name not in ("solve_time", "cpu_time"):
            np.testing.assert_array_equal(three[name], one[name], err_msg=name)
    # resumption per point: two points done, then all five in batches of two
    head = study_file(tmp_path, body.split("\n[[point]]", 3)[0] + "\n[[point]]" +
                      body.split("\n[[point]]", 3)[1], metrics=metrics, name="head.toml")
    first = flexbed.sweep(head, client, output=tmp_path / "out", plots=False)
    assert len(first) == 1
    study.write_text(study.read_text().replace('"test"', '"test"\nbatch = 2'))
    again = flexbed.sweep(study, client, output=tmp_path / "out", plots=False)
    assert again["solve_time"][0] == first["solve_time"][0]         # read back, not re-run
    for name in ("status", "message", "static_deflection.M5", "scene_hash"):
        np.testing.assert_array_equal(again[name], one[name], err_msg=name)
    # batches: study order, one bed's modes each, at most `size` points
    assert batches({"a": 0, "b": 0, "c": 0, "d": 0}, {"a": None, "b": "m", "c": None,
                                                     "d": None}, 2) == [["a", "c"], ["d"], ["b"]]
    # "auto": the points left over twice the workers, at most 16, shrinking to 1
    assert auto_sizes(200, 2) == [16] * 9 + [14, 11, 8, 6, 5, 3, 3, 2, 1, 1, 1, 1]
    for n, w in ((5, 1), (10000, 64), (10 ** 5, 2)):
        sizes = auto_sizes(n, w)
        assert sum(sizes) == n and sizes == sorted(sizes, reverse=True)
        assert sizes[0] == auto_batch(n, w) == min(16, -(-n // (2 * w))) and sizes[-1] == 1
    assert batches({"a": 0, "b": 0, "c": 0, "d": 0, "e": 0},
                   {"a": None, "b": "m", "c": None, "d": None, "e": "m"}, None, 1) == \
        [["a", "c", "d"], ["b"], ["e"]]


@pytest.mark.slow
def test_kept_results_are_the_commands_files_of_each_point(tmp_path, client, capsys):
    """``--keep-results`` with simulate, modal and frf: each point's files in
    ``results/`` are those ``flexbed simulate -o``, ``flexbed modal -o …
    --no-plots`` and ``flexbed frf -o … --no-plots`` write for the point's
    scene (run here as commands on the variant's scene file): the same
    datasets, bit for bit, the same attributes but the solve times, the
    same CSV text."""
    import h5py

    body = ('sampling = "list"\nanalyses = ["simulate", "modal", "frf"]\n\n[[point]]\n'
            '"mount.M5.k" = [3.0e5, 3.0e5, 2.0e5]\n')
    metrics = '[[metric]]\nkind = "natural_frequency"\n'
    out = tmp_path / "out"
    table = flexbed.sweep(study_file(tmp_path, body, metrics=metrics), client, output=out,
                          keep_results=True, plots=False)
    assert list(table["status"]) == ["ok"], list(table["message"])
    suffixes = ("results.h5", "modal.h5", "modal-modes.csv", "modal-energy.csv",
                "modal-strain.csv", "modal-effective-mass.csv", "modal-shapes.xdmf",
                "modal-shapes.h5", "frf.h5", "frf.csv")
    assert sorted(p.name for p in (out / "results").iterdir()) == \
        sorted(f"point-0000-{s}" for s in suffixes)

    def timing(key):
        return key.endswith("time") or key in ("created", "written")

    def tree(path):
        items = {}
        with h5py.File(path, "r") as f:
            f.visititems(lambda name, obj: items.__setitem__(name, (
                obj[()] if isinstance(obj, h5py.Dataset) else None,
                {k: v for k, v in obj.attrs.items() if not timing(k)})))
            items[""] = (None, {k: v for k, v in f.attrs.items() if not timing(k)})
        return items

    scene = flexbed.vary(flexbed.load_scene(), {"solver.t_end": T_END,
                                                "mount.M5.k": [3e5, 3e5, 2e5]})
    path = tmp_path / "point.toml"
    path.write_text(scene.text, encoding="utf-8")
    ref = tmp_path / "ref"
    for command, prefix in (("simulate", "results.h5"), ("modal", "modal"), ("frf", "frf")):
        args = [command, str(path), "-o", str(ref / prefix)]
        assert main(args + ([] if command == "simulate" else ["--no-plots"])) == 0
    capsys.readouterr()
    for s in suffixes:
        mine, theirs = out / "results" / f"point-0000-{s}", ref / s
        if s.endswith(".h5"):
            a, b = tree(mine), tree(theirs)
            assert a.keys() == b.keys(), s
            for name in a:
                np.testing.assert_array_equal(a[name][0], b[name][0], err_msg=f"{s}: {name}")
                assert a[name][1].keys() == b[name][1].keys(), (s, name)
                for key in a[name][1]:
                    if key not in ("source", "equilibrium_source"):       # paths
                        np.testing.assert_array_equal(a[name][1][key], b[name][1][key],
                                                      err_msg=f"{s}: {name} @{key}")
        else:
            text = theirs.read_text(encoding="utf-8")
            if s.endswith(".xdmf"):                         # it names itself and its .h5
                text = text.replace("modal-shapes", "point-0000-modal-shapes")
            assert mine.read_text(encoding="utf-8") == text, s


def equal(a, b, where="scene") -> None:
    """a and b equal in every field, arrays bit for bit (their pickles may
    differ where one holds the same object twice and the other two copies)."""
    import dataclasses
    assert type(a) is type(b), where
    if dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            equal(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
    elif isinstance(a, (tuple, list)):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            equal(x, y, f"{where}[{i}]")
    elif isinstance(a, dict):
        assert list(a) == list(b), where
        for k in a:
            equal(a[k], b[k], f"{where}[{k!r}]")
    elif isinstance(a, np.ndarray):
        assert (a.dtype, a.shape, a.tobytes()) == (b.dtype, b.shape, b.tobytes()), where
    elif hasattr(a, "__dict__") and not callable(a):
        equal(vars(a), vars(b), where)
    else:
        assert a == b or (a != a and b != b), where


def test_a_point_is_sent_without_what_it_shares_with_the_base():
    """A study's point is pickled against the base scene's shared parts (its
    bodies, mounts and base, which the variant holds as they are): the
    unpickled scene equals the point's own, field by field, and its bytes
    are a fraction of a whole scene's."""
    import pickle

    from flexbed.files.scene import load_scene
    from flexbed.files.variants import vary
    from flexbed.study.point import pack, shared_parts, unpack
    base = load_scene()
    point = vary(base, {"mount.M5.k": [6.1e4, 7.3e4, 1.9e5], "bed.thickness": 0.0913})
    parts = shared_parts(base)
    blob = pack(point, parts)
    copies = pickle.loads(pack(parts))                  # as a worker has them
    again = unpack(blob, copies)
    equal(again, point)
    assert len(blob) < 0.4 * len(pack(point))
    kept = {id(c) for c in copies}
    assert [m.name for m in again.scene.mounts if id(m) not in kept] == ["M5"]
    assert again.scene.base is copies[-1]
    assert unpack(pack(point), ()).digest == point.digest      # nothing shared: whole


def test_submissions_keep_each_graph_under_the_limit():
    from flexbed.study.runner import submissions
    assert submissions([3, 3, 3, 3, 3], 7) == [[0, 1], [2, 3], [4]]
    assert submissions([10, 1, 1], 7) == [[0], [1, 2]]              # too large: alone
    assert submissions([], 7) == []
    runs = submissions([1] * 50, 7)
    assert [i for r in runs for i in r] == list(range(50)) and max(map(len, runs)) == 7
