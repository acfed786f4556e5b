"""A study never loses or mixes work (issue 28): one study per output folder
at a time, another study's table never replaced, the table's two files
written whole or not at all, NaN only where a point failed, sizes refused
before anything is planned, and Ctrl-C on the local cluster ends in one
line, without the workers' tracebacks or Dask's log lines."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

import flexbed
from flexbed.errors import InputError
from flexbed.study.point import run_point
from flexbed.study.spec import MAX_POINTS, parse_study
from flexbed.study.table import folder_lock

ONE = """[study]
name = "{name}"
sampling = "list"

[study.set]
"solver.t_end" = 0.02

[[point]]
"bed.thickness" = 0.1

[[metric]]
kind = "max_static_deflection"
"""


@pytest.fixture(scope="module")
def client():
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                      dashboard_address=":0") as cluster, Client(cluster) as c:
        yield c


def study(folder: Path, name: str = "a", text: str = ONE) -> Path:
    path = folder / f"{name}.toml"
    path.write_text(text.format(name=name), encoding="utf-8")
    return path


def test_one_study_per_folder_at_a_time(tmp_path, client):
    out = tmp_path / "out"
    with folder_lock(out):
        with pytest.raises(InputError, match=f"another study is writing into this folder now "
                                             f"\\(process {os.getpid()}\\)"):
            flexbed.sweep(study(tmp_path), client, output=out, plots=False)
    assert not (out / "table.csv").exists()
    table = flexbed.sweep(study(tmp_path), client, output=out, plots=False)   # free again
    assert table.complete and list(table["status"]) == ["ok"]


def test_another_study_s_table_is_never_replaced(tmp_path, client):
    out = tmp_path / "out"
    flexbed.sweep(study(tmp_path, "a"), client, output=out, plots=False)
    before = {n: (out / n).read_bytes() for n in ("table.csv", "table.h5")}
    with pytest.raises(InputError, match="holds the table of another study \\('a'"):
        flexbed.sweep(study(tmp_path, "b"), client, output=out, plots=False)
    other_metric = ONE.replace('kind = "max_static_deflection"',
                               'kind = "peak_mount_force"\nmounts = ["M5"]')
    with pytest.raises(InputError, match="made with other analyses or metrics"):
        flexbed.sweep(study(tmp_path, "a", other_metric), client, output=out, plots=False)
    assert before == {n: (out / n).read_bytes() for n in before}


def test_the_table_s_two_files_are_written_whole(tmp_path, client, monkeypatch):
    """A disk that fills while the HDF5 file is written leaves no CSV (nor
    its staging copy) behind: nothing was written means nothing."""
    from flexbed.files import store

    def full(path, **kwargs):
        raise InputError(f"{path}: cannot write it (No space left on device); nothing was "
                         f"written")

    monkeypatch.setattr(store, "write_file", full)
    out = tmp_path / "out"
    with pytest.raises(InputError, match="No space left"):
        flexbed.sweep(study(tmp_path), client, output=out, plots=False)
    assert sorted(p.name for p in out.iterdir()) == [".flexbed-study.lock"]


@pytest.mark.parametrize("parameters, count", [
    ('[[parameter]]\npath = "bed.thickness"\nfrom = 0.08\nto = 0.14\nnum = 1000\n'
     '[[parameter]]\npath = "mount.M5.k"\nfrom = [1e5, 1e5, 1e5]\nto = [2e5, 2e5, 2e5]\n'
     'num = 1000\n', "1,000,000"),
    ('[[parameter]]\npath = "bed.thickness"\nfrom = 0.08\nto = 0.14\nnum = 100000\n'
     '[[parameter]]\npath = "mount.M5.k"\nfrom = [1e5, 1e5, 1e5]\nto = [2e5, 2e5, 2e5]\n'
     'num = 100000\n', "10,000,000,000"),
])
def test_a_study_too_large_is_refused_before_planning(tmp_path, parameters, count):
    text = f'[study]\nname = "big"\n{parameters}[[metric]]\nkind = "max_static_deflection"\n'
    t0 = time.process_time()
    with pytest.raises(InputError) as info:
        parse_study(text, tmp_path / "big.toml")
    assert time.process_time() - t0 < 1.0          # refused from the spec, not after planning
    assert str(info.value) == (f"big.toml: the study has {count} points; the limit is "
                               f"{MAX_POINTS:,} (split it, or sample it: sampling = \"lhs\")")


@pytest.mark.parametrize("metric, words", [
    ('kind = "transmissibility"\npoint = "A top"\nfrequency = 1e308\n', "frequency = 1e+308"),
    ('kind = "transmissibility"\npoint = "A top"\nfrequency = 5e-324\n', "frequency = 5e-324"),
    ('kind = "peak_transmissibility"\npoint = "A top"\nband = [1, 1e308]\n', "band = 1e+308"),
])
def test_hostile_frequencies_in_metrics_are_refused(tmp_path, metric, words):
    from flexbed.study.plan import make_plan

    text = (f'[study]\nname = "f"\nsampling = "list"\n[[point]]\n"bed.thickness" = 0.1\n'
            f'[[metric]]\n{metric}')
    with pytest.raises(InputError) as info:
        make_plan(parse_study(text, tmp_path / "f.toml"))
    assert words in str(info.value) and "1e-06 – 1e+07 Hz" in str(info.value)


@dataclass(frozen=True)
class Overflowing:
    """A metric whose value overflows (as a hostile metric setting would)."""

    columns: tuple = ("huge",)

    def values(self, outcomes):
        return (float("inf") * 0.0,)


def test_a_metric_that_is_not_finite_fails_its_point():
    res = run_point(flexbed.load_scene(), (), (Overflowing(),))
    assert res.status == "failed"
    assert res.message == "metric huge = nan: not a finite number"
    assert math.isnan(res.values[0])


@pytest.mark.slow
def test_ctrl_c_on_the_local_cluster_is_one_line(tmp_path):
    """SIGINT to the whole process group, as a terminal sends it: exit 130,
    the rows kept, and stderr holds flexbed's lines only — no worker's
    KeyboardInterrupt traceback, no Dask WARNING lines."""
    text = ('[study]\nname = "long"\n[study.set]\n"solver.t_end" = 2.0\n'
            '[[parameter]]\npath = "bed.thickness"\nfrom = 0.08\nto = 0.14\nnum = 200\n'
            '[[metric]]\nkind = "peak_mount_force"\nmounts = ["M5"]\n')
    path = tmp_path / "long.toml"
    path.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    p = subprocess.Popen([sys.executable, "-m", "flexbed.cli", "sweep", str(path), "-o",
                          str(out), "--no-plots", "--batch", "1", "--workers", "1",
                          "--no-progress"],
                         cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True)
    csv = out / "table.csv"
    deadline = time.monotonic() + 180
    while time.monotonic() < deadline and p.poll() is None:
        if csv.exists() and len(csv.read_text().splitlines()) > 1:
            break
        time.sleep(0.05)
    os.killpg(p.pid, signal.SIGINT)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 130, err
    lines = err.splitlines()
    assert lines and lines[-1].startswith("flexbed sweep: interrupted"), err
    for bad in ("Traceback", "KeyboardInterrupt", "WARNING", "distributed."):
        assert bad not in err, err


@pytest.mark.slow
def test_ctrl_c_while_the_local_cluster_starts_is_one_line(tmp_path):
    """SIGINT to the whole process group while the local cluster is still
    starting: exit 130 and flexbed's one line, the cluster closed (no
    "Exception ignored in atexit callback", no failed start's traceback
    from this process). Workers whose interpreters are themselves still
    starting may print Python's own KeyboardInterrupt: they are separate
    programs, not yet flexbed's."""
    path = tmp_path / "st.toml"
    path.write_text('[study]\nname = "start"\nsampling = "list"\n[[point]]\n'
                    '"bed.thickness" = 0.1\n[[metric]]\nkind = "max_static_deflection"\n',
                    encoding="utf-8")
    p = subprocess.Popen([sys.executable, "-m", "flexbed.cli", "sweep", str(path), "-o",
                          str(tmp_path / "out"), "--no-plots", "--workers", "2",
                          "--no-progress"],
                         cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True, env={**os.environ, "PYTHONUNBUFFERED": "1"})
    first = p.stdout.readline()                   # the plan is said, then the cluster starts
    assert first.startswith("study 'start'"), first
    time.sleep(0.3)
    os.killpg(p.pid, signal.SIGINT)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 130, err
    assert err.splitlines()[-1] == "flexbed sweep: interrupted (SIGINT)", err
    # (a worker interrupted while importing shows the source lines it was at,
    # flexbed's or the library's, in its own traceback: only this process's
    # failures are looked for, by their messages)
    for bad in ("Exception ignored", "AssertionError: Status", "failed to start",
                "Task exception"):
        assert bad not in err, err
