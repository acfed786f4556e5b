"""numba's cache of the compiled modules: one stamp over all their sources
(flexbed.dynamics.jitcache) covers every module that holds compiled code,
and a changed stamp flushes the cache of all of them."""

import importlib
import os
import pickle
import pkgutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numba
import numpy as np
import pytest
from numba.core.ccallback import CFunc
from numba.core.dispatcher import Dispatcher

import flexbed.dynamics
from flexbed.dynamics import jitcache


def _modules_with_compiled_code():
    found = set()
    prefix = flexbed.dynamics.__name__ + "."
    for info in pkgutil.walk_packages(flexbed.dynamics.__path__, prefix):
        module = importlib.import_module(info.name)
        for value in vars(module).values():
            if isinstance(value, (Dispatcher, CFunc)):
                py_func = value.py_func if isinstance(value, Dispatcher) else value._pyfunc
                if py_func.__module__ == info.name:
                    found.add(info.name[len(prefix):])
    return found


def test_every_module_with_compiled_code_is_covered():
    found = _modules_with_compiled_code()
    assert "kernel.rhs" in found and "steppers.radau" in found      # the scan sees them
    assert found <= set(jitcache.COMPILED), sorted(found - set(jitcache.COMPILED))
    # and nothing listed is stale
    assert set(jitcache.COMPILED) <= found, sorted(set(jitcache.COMPILED) - found)


def test_a_changed_stamp_flushes_every_compiled_module(tmp_path, monkeypatch):
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(tmp_path))
    files = []
    for name in jitcache.COMPILED:
        folder = Path(jitcache.cache_dir(jitcache._source(name)))
        assert folder.is_relative_to(tmp_path)
        stem = jitcache._source(name).stem
        for suffix in (".nbi", ".nbc"):
            f = folder / f"{stem}.some_function-12.py311{suffix}"
            f.write_bytes(b"old")
            files.append(f)
    other = Path(jitcache.cache_dir(jitcache._source(jitcache.COMPILED[0]))) / "unrelated.nbi"
    other.write_bytes(b"keep")
    stamp_file = Path(jitcache.cache_dir(jitcache._source(jitcache.COMPILED[0]))) / \
        "flexbed-compiled.stamp"
    stamp_file.write_text("an older source")
    assert jitcache.refresh(force=True)
    assert not any(f.exists() for f in files)
    assert other.exists()
    assert stamp_file.read_text() == jitcache.stamp()
    # the same sources: nothing flushed
    files[0].write_bytes(b"new")
    assert not jitcache.refresh(force=True)
    assert files[0].exists()


def test_without_numbas_cache_locators_the_check_is_skipped_with_a_warning(monkeypatch, capsys):
    """numba's locator list is private (numba.core.caching.CacheImpl._locator_classes):
    a numba without it must not break flexbed, only lose the freshness check."""
    from numba.core import caching

    monkeypatch.delattr(caching.CacheImpl, "_locator_classes")
    assert jitcache.cache_dir(jitcache._source(jitcache.COMPILED[0])) is None
    assert jitcache.refresh(force=True) is False
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("flexbed: warning:") and "skipped" in err[0], err


def test_the_stamp_covers_the_coefficients_compiled_in_as_constants():
    import flexbed.dynamics.steppers.dop853 as dop853
    assert {"steppers.dop853_coefficients", "steppers.radau_coefficients"} <= set(
        jitcache.CONSTANTS)
    assert all(jitcache._source(name).is_file() for name in jitcache.CONSTANTS)
    assert dop853.DOP853.__module__ == "flexbed.dynamics.steppers.dop853_coefficients"


_ONE_OF_EACH = r"""
import sys, tempfile
from pathlib import Path
import numpy as np
from numba.core.dispatcher import Dispatcher
import flexbed
from flexbed.bench.cases import CASES, ModesStore, build_case
from flexbed.dynamics.integrate import Settings
from flexbed.dynamics.linear.run import run_linear
from flexbed.dynamics.precompile import compile_callers, compile_linear_path, compile_statics

compile_callers()              # the first run's steppers, compiled without the right-hand side
compile_linear_path()          # and the linear path's functions, by their signatures
compile_statics()              # and the rigid statics' pieces, on a stand-in
sf = flexbed.load_scene()
store = ModesStore(sf, Path(tempfile.mkdtemp()))
for key in ("rigid", "damped"):
    case = build_case(sf, CASES[key], store)      # statics, and every stepper warmed up
    for flex in case.system._flex:                  # the Python side of the flexible bed
        flex.eom.forces_body(np.zeros(3), np.zeros(flex.eom.n), np.zeros(flex.eom.n),
                             np.array([0.0, 0.0, -9.81]))
    run_linear(case.system, case.y0, case.y0, Settings("dop853", t_end=0.01))
for name, module in sorted(sys.modules.items()):
    if not name.startswith("flexbed.dynamics"):
        continue
    for value in vars(module).values():
        if isinstance(value, Dispatcher) and value.py_func.__module__ == name:
            # storage.view1..5 take the dtype as an argument: one signature per dtype
            dtypes = {str(sig[-1]) for sig in value.signatures}
            extra = len(value.signatures) - (len(dtypes) if name.endswith(".storage") else 1)
            if extra > 0:
                print(f"{name}.{value.py_func.__name__}: {len(value.signatures)}")
print("checked")
"""


@pytest.mark.slow
def test_each_compiled_function_is_compiled_for_one_signature(tmp_path):
    """The steppers compiled as a first run compiles them beside the
    right-hand side (flexbed.dynamics.precompile, with a stand-in for its
    pointer, and the rigid statics' pieces on a stand-in), then the rigid
    and the damped flexible reference cases (their statics), every
    stepper, the flexible bed's Python side and the linear path, in a fresh
    interpreter:
    each compiled function of flexbed.dynamics ends with one signature (a
    second one — a read-only array, a literal int, another layout — is a
    second compilation of the same code on a first run)."""
    out = subprocess.run([sys.executable, "-c", _ONE_OF_EACH], capture_output=True, text=True,
                         cwd=tmp_path, timeout=1800)
    assert out.returncode == 0, out.stderr[-2000:]
    lines = out.stdout.strip().splitlines()
    assert lines[-1] == "checked" and lines[:-1] == [], lines


def _children(pid: int) -> list[int]:
    found = []
    for task in Path(f"/proc/{pid}/task").iterdir():
        found += [int(c) for c in (task / "children").read_text().split()]
    return found


@pytest.mark.slow
@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="reads /proc")
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_first_run_stopped_while_it_compiles_leaves_nothing_behind(tmp_path, signum):
    """On an empty cache ``flexbed bench`` compiles the right-hand side in a
    child process (flexbed.dynamics.precompile). Ctrl-C (SIGINT to the whole
    process group) or a SIGTERM to flexbed alone while both compile: exit
    128 + signal, one line, no traceback, the child gone, every cache index
    whole."""
    cache = tmp_path / "cache"
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    proc = subprocess.Popen(
        [sys.executable, "-c", "from flexbed.cli import script; script()",
         "bench", "rigid", "--quick", "-o", str(tmp_path / "out")],
        cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        start_new_session=True)
    try:
        children, t0 = [], time.monotonic()
        while not children and time.monotonic() - t0 < 120 and proc.poll() is None:
            time.sleep(0.2)
            children = _children(proc.pid)
        assert children, "no child process was started"
        time.sleep(1.0)                                  # both compiling
        if signum == signal.SIGINT:
            os.killpg(proc.pid, signum)                  # as the terminal's Ctrl-C does
        else:
            proc.send_signal(signum)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert proc.returncode == 128 + signum, err
    assert "Traceback" not in err, err
    assert err.strip().splitlines()[-1] == \
        f"flexbed bench: interrupted ({signal.Signals(signum).name})", err
    for child in children:
        assert not Path(f"/proc/{child}").exists(), f"process {child} left running"
    for index in cache.rglob("*.nbi"):               # numba's indexes: whole, never torn
        with open(index, "rb") as f:
            pickle.load(f)
            pickle.loads(f.read())


def test_few_distinct_ranks_as_numpys_unique():
    """The linear path's few_distinct ranks its values by counting (numba's
    sort is not compiled for it): the same ranks, first indices and count as
    np.unique, and −1 past ``most``."""
    from flexbed.dynamics.linear.sweep import few_distinct
    rng = np.random.default_rng(7)
    for _ in range(100):
        pool = rng.random(int(rng.integers(1, 40))) * 10.0 ** rng.integers(-6, 1)
        keys = rng.choice(pool, int(rng.integers(1, 80)))
        which, first = np.empty(keys.size, dtype=np.int64), np.empty(32, dtype=np.int64)
        m = few_distinct(keys, which, first, 32)
        values, index, inverse = np.unique(keys, return_index=True, return_inverse=True)
        if values.size > 32:
            assert m == -1
            continue
        assert m == values.size
        assert np.array_equal(which, inverse) and np.array_equal(first[:m], index)


def test_the_quick_report_leaves_out_the_linear_path_and_says_so(tmp_path, monkeypatch):
    """A first quick report compiles no linear path: ``bench --quick`` runs
    every section but "linear" (its header names the command that runs it);
    the target ``linear`` still runs it quick."""
    from flexbed.bench import report

    ran = []
    monkeypatch.setattr(report, "SECTIONS", [
        report.Section(name, lambda ctx, name=name: ran.append(name) or f"## {name}\n")
        for name in ("rhs", "linear", "verdict")])
    text = report.write_report(tmp_path, quick=True).path.read_text()
    assert ran == ["rhs", "verdict"]
    assert "- sections: rhs, verdict (left out of the quick report: linear; " \
           "`flexbed bench linear --quick`)" in text
    ran.clear()
    report.write_report(tmp_path, quick=True, sections=["linear"])
    assert ran == ["linear"]
    ran.clear()
    report.write_report(tmp_path, quick=False)
    assert ran == ["rhs", "linear", "verdict"]
