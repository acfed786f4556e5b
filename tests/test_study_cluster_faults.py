"""A study on a cluster of its own (``dask scheduler`` and ``dask worker``
processes): the parts its points share with the base scene
(:func:`flexbed.study.point.shared_parts`, one task on the cluster) must not
change what a cluster gives a study: a worker lost is a retry, not a lost
study; workers may join after the study starts. (Both failed while the
parts were scattered data: its only copy died with its worker, and the
scatter raised when no worker had joined.)

The cluster tests start ``dask scheduler`` and ``dask worker`` processes
(each with its nanny, as a user's cluster), tiny studies of the reference
scene."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import threading
from pathlib import Path

import pytest

import flexbed
from row_killer import kill_after_the_first_row

T_END = 0.3
STUDY = """[study]
name = "test"
sampling = "grid"

[[parameter]]
path = "bed.thickness"
from = 0.08
to = 0.14
num = {num}

[study.set]
"solver.t_end" = {t_end}

[[metric]]
kind = "peak_mount_force"
mounts = ["M5"]
"""


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class _Cluster:
    """A ``dask scheduler`` and ``dask worker`` processes on localhost."""

    def __init__(self, where: Path):
        self.where = where
        self.address = f"tcp://127.0.0.1:{_free_port()}"
        self.env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "FLEXBED_THREADS": "1"}
        self.log = open(where / "cluster.log", "w")
        self.dask = str(Path(sys.executable).parent / "dask")
        self.procs = [self._start([self.dask, "scheduler", "--host", "127.0.0.1", "--port",
                                   self.address.rsplit(":", 1)[1], "--no-dashboard"])]

    def _start(self, cmd):
        return subprocess.Popen(cmd, cwd=self.where, env=self.env, stdout=self.log,
                                stderr=self.log, start_new_session=True)

    def worker(self, name: str, nthreads: int = 1):
        self.procs.append(self._start([self.dask, "worker", self.address, "--nthreads",
                                       str(nthreads), "--no-dashboard", "--name", name,
                                       "--local-directory", str(self.where)]))

    def close(self):
        """Stop every process at once (a test's cluster: nothing to save)."""
        for p in self.procs:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGKILL)
            p.wait(timeout=20)
        self.log.close()


@pytest.fixture
def cluster(tmp_path):
    c = _Cluster(tmp_path)
    yield c
    c.close()


@pytest.mark.slow
def test_the_only_worker_lost_mid_study_has_its_points_run_again(tmp_path, cluster):
    """One worker (and its nanny, which restarts it): SIGKILL to the worker
    process once the first row is in. Dask re-runs the lost batch on the
    restarted worker (``retries=1``), the shared parts' task again with it:
    every row must be ok."""
    from distributed import Client

    cluster.worker("w0")
    with Client(cluster.address, timeout="60s") as c:
        c.wait_for_workers(1, timeout=120)
        victim = list(c.run(os.getpid).values())[0]
    study = tmp_path / "study.toml"
    study.write_text(STUDY.format(num=24, t_end=T_END), encoding="utf-8")
    csv_path = tmp_path / "out" / "table.csv"
    killer, killed = kill_after_the_first_row(csv_path, victim)
    table = flexbed.sweep(study, cluster.address, output=tmp_path / "out", plots=False,
                          batch=1)
    killer.join(timeout=5)
    assert killed and killed[0] < 24                   # killed while points were left
    assert table.complete and len(table) == 24
    assert set(table["status"]) == {"ok"}, sorted(set(table["message"]))


@pytest.mark.slow
def test_a_study_waits_for_workers_that_join_later(tmp_path, cluster):
    """A scheduler with no worker yet (a batch system's workers still
    queued): the study's tasks, its shared parts' among them, wait for a
    worker, past the client's connect timeout (15 s for ``--scheduler``;
    1 s here, the worker joining after 3 s)."""
    from distributed import Client

    study = tmp_path / "study.toml"
    study.write_text(STUDY.format(num=4, t_end=0.05), encoding="utf-8")
    timer = threading.Timer(3.0, cluster.worker, args=("late",))
    timer.start()
    try:
        with Client(cluster.address, timeout="1s") as client:
            table = flexbed.sweep(study, client, plots=False)
    finally:
        timer.cancel()
    assert table.complete and len(table) == 4
    assert set(table["status"]) == {"ok"}, sorted(set(table["message"]))

