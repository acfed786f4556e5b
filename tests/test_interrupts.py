"""SIGINT and SIGTERM sent to a real ``flexbed`` process at each phase.

Every case asserts the exit status (130 for SIGINT, 143 for SIGTERM), one
line on stderr (the progress line, when shown, is rubbed out by a carriage
return and the message takes its place) and no traceback, that what was
computed is kept — written whole and marked incomplete with the time
reached — or that nothing is written when nothing was computed, and that
no temporary file is left behind.

The phases are reached by what the process shows, not by timing: the
progress line on stderr (integration), its "; writing FILE" (history and
file writing), the rigid case's line on stdout (compare's second case).
Only the phases that print nothing are reached after a delay, inside a
phase made long on purpose: reading a scene whose load curve has 3e5
samples, and the modes of a 120 x 120 plate. The processes run side by
side (one fixture starts them all) to keep the suite's time down.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from flexbed.files.results import read_results
from scene_text import base_and_body, four_mounts

#: seven commands run whole in child processes and interrupted (about 15 s)
pytestmark = [pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals"),
              pytest.mark.slow]

MOUNTS = four_mounts("""
law = "linear"
k = [1.0e5, 1.0e5, 1.0e5]
c = [5.0, 5.0, 5.0]
""")

#: 400 s of a lightly damped body: seconds of integration, 40,001 samples
LONG = base_and_body("long", body_extra="velocity = [0.1, 0.2, 0.3]\n"
                     "angular_velocity = [1.0, 2.0, 3.0]") + """
[solver]
t_end = 400.0
output_dt = 0.01
integrator = "dop853"
""" + MOUNTS

T_END = 400.0
TIMEOUT = 120.0
FLEXBED = str(Path(sys.executable).with_name("flexbed"))


class Process:
    """A ``flexbed`` run whose stdout and stderr are read as they come."""

    def __init__(self, args, cwd):
        env = dict(os.environ, PYTHONUNBUFFERED="1")
        self.p = subprocess.Popen([FLEXBED, *args], cwd=cwd, env=env, stdin=subprocess.DEVNULL,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        self.out, self.err = bytearray(), bytearray()
        self.readers = [threading.Thread(target=self._read, args=(s, b), daemon=True)
                        for s, b in ((self.p.stdout, self.out), (self.p.stderr, self.err))]
        for r in self.readers:
            r.start()

    @staticmethod
    def _read(stream, buf):
        while chunk := stream.read1(4096):
            buf.extend(chunk)

    def wait_for(self, marker: bytes, where: str = "err") -> bool:
        """Wait until ``marker`` shows on stderr (or stdout); False if the
        process ended first."""
        buf = self.err if where == "err" else self.out
        deadline = time.monotonic() + TIMEOUT
        while marker not in buf:
            if self.p.poll() is not None or time.monotonic() > deadline:
                return marker in buf
            time.sleep(0.005)
        return True

    def finish(self):
        try:
            self.p.wait(TIMEOUT)
        except subprocess.TimeoutExpired:
            self.p.kill()
            self.p.wait()
        for r in self.readers:
            r.join()
        return self.p.returncode, self.out.decode(), self.err.decode()


def _interrupt(args, cwd, sig, *, marker=None, where="err", delay=0.0):
    """Start flexbed, send ``sig`` when ``marker`` shows (or after ``delay``
    seconds), return (exit status, stdout, stderr, marker seen)."""
    proc = Process(args, cwd)
    seen = True
    if marker is not None:
        seen = proc.wait_for(marker, where)
    else:
        time.sleep(delay)
    if proc.p.poll() is None:
        proc.p.send_signal(sig)
    code, out, err = proc.finish()
    return code, out, err, seen


CASES = {
    "simulate integrating SIGINT": ("long", ["simulate", "long.toml", "-o", "r.h5"],
                                    signal.SIGINT, b"simulate [", "err", 0.0),
    "simulate integrating SIGTERM": ("long", ["simulate", "long.toml", "-o", "r.h5"],
                                     signal.SIGTERM, b"simulate [", "err", 0.0),
    "simulate writing SIGTERM": ("long", ["simulate", "long.toml", "-o", "r.h5"],
                                 signal.SIGTERM, b"; writing", "err", 0.0),
    "simulate loading SIGINT": ("curve", ["simulate", "curve.toml", "-o", "r.h5"],
                                signal.SIGINT, None, "err", 1.5),
    "static loading SIGTERM": ("curve", ["static", "curve.toml", "-o", "e.h5"],
                               signal.SIGTERM, None, "err", 1.5),
    "modes solving SIGINT": ("plate", ["modes", "plate.toml", "-o", "m.h5"],
                             signal.SIGINT, None, "err", 4.0),
    "compare second case SIGTERM": ("compare", ["compare", "cmp.toml", "-o", "out"],
                                    signal.SIGTERM, b"rigid bed:", "out", 0.0),
}


def _scenes(root: Path) -> dict:
    """One folder per kind of case, with its scene."""
    from flexbed.files.scene import builtin_scene_path
    folders = {}
    for kind in ("long", "curve", "plate", "compare"):
        folders[kind] = root / kind
        folders[kind].mkdir()
    (folders["long"] / "long.toml").write_text(LONG)
    t = np.linspace(0.0, 1.0, 300_000)
    lines = "\n".join(f"{a:.7f},{b:.5f}" for a, b in zip(t, np.sin(31.4 * t)))
    (folders["curve"] / "load.csv").write_text("time,value\n" + lines + "\n")
    (folders["curve"] / "curve.toml").write_text(LONG.replace('[solver]', '''[base]
motion = "free"

[[base.force]]
direction = "z"
shape = "curve"
file = "load.csv"

[solver]'''))
    ref = builtin_scene_path().read_text()
    (folders["plate"] / "plate.toml").write_text(
        ref.replace("nx = 10\n", "nx = 120\n").replace("ny = 10\n", "ny = 120\n"))
    (folders["compare"] / "cmp.toml").write_text(ref.replace("t_end = 3.0", "t_end = 8.0"))
    return folders


@pytest.fixture(scope="module")
def outcomes(tmp_path_factory):
    """Every case run at once; {name: (folder, status, stdout, stderr, marker seen)}."""
    folders = _scenes(tmp_path_factory.mktemp("interrupts"))
    results = {}

    def one(name, kind, args, sig, marker, where, delay):
        results[name] = (folders[kind], *_interrupt(args, folders[kind], sig, marker=marker,
                                                    where=where, delay=delay))

    threads = []
    for name, (kind, args, sig, marker, where, delay) in CASES.items():
        if kind == "long":                       # three runs of one scene: a folder each
            sub = folders[kind] / name.replace(" ", "-")
            sub.mkdir()
            (sub / "long.toml").write_text(LONG)
            folders[name] = sub
            kind = name
        threads.append(threading.Thread(target=one, args=(name, kind, args, sig, marker, where,
                                                          delay)))
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    return results


def _one_line(err: str) -> str:
    """The single line on stderr (after any progress line rubbed out by '\\r')."""
    lines = [ln for ln in err.split("\n") if ln.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0].split("\r")[-1]


def _no_tmp(folder: Path):
    left = [p.name for p in folder.rglob("*") if p.name.endswith(".tmp")]
    assert not left


@pytest.mark.parametrize("sig", ["SIGINT", "SIGTERM"])
def test_interrupted_while_integrating_keeps_the_samples(outcomes, sig):
    folder, code, out, err, seen = outcomes[f"simulate integrating {sig}"]
    assert seen
    assert code == 128 + getattr(signal, sig), err
    line = _one_line(err)
    assert line.startswith(f"flexbed simulate: interrupted ({sig}) at t = ")
    assert "r.h5 (marked incomplete)" in line
    c = read_results(folder / "r.h5")
    root = c.attrs[""]
    assert root["complete"] is False and root["message"].startswith(f"interrupted ({sig}) at t =")
    t = c.get("time")
    t_reached = c.attrs["solver"]["t_reached"]
    assert 0.0 < t_reached < T_END and t[-1] <= t_reached < t[-1] + 0.01 + 1e-9
    assert c.get("bodies/position").shape[0] == t.size
    assert np.all(np.isfinite(c.get("bodies/position")))
    _no_tmp(folder)


def test_interrupted_while_the_results_are_written_keeps_them_all(outcomes):
    """The signal arrives once the integration is done (while the history is
    computed or the file written): all the samples are kept, the file is
    marked incomplete saying so."""
    folder, code, out, err, seen = outcomes["simulate writing SIGTERM"]
    assert seen
    assert code == 143, err
    line = _one_line(err)
    assert line.startswith(f"flexbed simulate: interrupted (SIGTERM) at t = {T_END:g} s")
    c = read_results(folder / "r.h5")
    assert c.attrs[""]["complete"] is False
    assert c.attrs[""]["message"] == (f"interrupted (SIGTERM) while the results were written; "
                                      f"the samples reach t = {T_END:g} s")
    assert c.get("time").size == 40_001 and c.get("time")[-1] == T_END
    _no_tmp(folder)


@pytest.mark.parametrize("name, command, output", [
    ("simulate loading SIGINT", "simulate", "r.h5"),
    ("static loading SIGTERM", "static", "e.h5"),
    ("modes solving SIGINT", "modes", "m.h5"),
])
def test_interrupted_before_anything_is_computed_writes_nothing(outcomes, name, command,
                                                                output):
    folder, code, out, err, seen = outcomes[name]
    sig = name.split()[-1]
    assert code == 128 + getattr(signal, sig), err
    assert _one_line(err) == f"flexbed {command}: interrupted ({sig})"
    assert not (folder / output).exists()
    _no_tmp(folder)


def test_compare_interrupted_keeps_the_finished_case(outcomes):
    """SIGTERM once the rigid case is written, during the flexible one: the
    rigid case's file is complete; the flexible one, if it got samples, is
    kept marked incomplete; the tables and plots are not made."""
    folder, code, out, err, seen = outcomes["compare second case SIGTERM"]
    assert seen
    assert code == 143, err
    line = _one_line(err)
    assert line.startswith("flexbed compare: interrupted (SIGTERM)")
    rigid = read_results(folder / "out" / "cmp-rigid.h5")
    assert rigid.attrs[""]["complete"] is True
    flexible = folder / "out" / "cmp-flexible.h5"
    if flexible.exists():
        assert read_results(flexible).attrs[""]["complete"] is False
        assert "in the flexible bed" in line and "(marked incomplete)" in line
    assert not (folder / "out" / "cmp-damped.h5").exists()
    assert not (folder / "out" / "cmp-compare.csv").exists()
    _no_tmp(folder)
