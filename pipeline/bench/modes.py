"""Benchmark of the bed-modes stage: time, peak memory and accuracy against
mesh density, in-process and as a whole command.

In-process: :func:`flexbed.fem.bed.compute_bed_modes` plus writing the modes file,
after imports, median of repeats; peak memory from ``tracemalloc`` (NumPy
reports its buffers to it) in a separate run. Whole command: ``flexbed
modes --force`` in a fresh Python process, wall time and the child's peak
resident set size (``os.wait4``). Accuracy: the first four frequencies
against the finest mesh of the ladder.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
import tracemalloc
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from flexbed.fem.bed import compute_bed_modes

from flexbed.bench.markdown import md_table
from flexbed.files.modes import write_modes_file
from flexbed.files.scene import builtin_scene_path, load_scene

MESHES = ((10, 10), (20, 20), (40, 40), (100, 100))
QUICK_MESHES = ((10, 10), (20, 20), (40, 40))
N_MODES = 4


def _scene_with_mesh(folder: Path, nx: int, ny: int) -> Path:
    text = builtin_scene_path().read_text()
    text = text.replace("nx = 10", f"nx = {nx}", 1).replace("ny = 10", f"ny = {ny}", 1)
    path = folder / f"bench-{nx}x{ny}.toml"
    path.write_text(text)
    return path


def _in_process(spec, folder: Path, repeats: int) -> tuple[float, dict, object]:
    times, parts, bed = [], [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        bed = compute_bed_modes(spec, n_modes=N_MODES)
        t1 = time.perf_counter()
        write_modes_file(folder / "bench.h5", bed)
        t2 = time.perf_counter()
        times.append(t2 - t0)
        parts.append(dict(bed.timings, write=t2 - t1))
    best = int(np.argsort(times)[len(times) // 2])
    return statistics.median(times), parts[best], bed


def _peak_memory(spec, folder: Path) -> float:
    tracemalloc.start()
    try:
        bed = compute_bed_modes(spec, n_modes=N_MODES)
        write_modes_file(folder / "bench.h5", bed)
        return tracemalloc.get_traced_memory()[1] / 2 ** 20
    finally:
        tracemalloc.stop()


def _whole_command(scene: Path, folder: Path) -> tuple[float, float]:
    cmd = [sys.executable, "-c", "import sys; from flexbed.cli import main; "
           "sys.exit(main(sys.argv[1:]))", "modes", str(scene), "-o",
           str(folder / "cmd.h5"), "--modes", str(N_MODES), "--force"]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    elapsed = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise RuntimeError(f"flexbed modes failed: {proc.stderr.read().decode()}")
    return elapsed, usage.ru_maxrss / 1024.0


@dataclass
class MeshRow:
    """One mesh of the ladder.

    nx, ny : elements; dofs : int; in_process : median [s]; parts : dict of
    stage times [s] (assemble, eigen, invariants, write); peak_mib :
    tracemalloc peak [MiB]; whole_command : [s]; rss_mib : the child's peak
    resident set [MiB]; frequency : (N_MODES,) [Hz]; error : largest relative
    error of the first N_MODES frequencies against the finest mesh [–].
    """

    nx: int
    ny: int
    dofs: int
    in_process: float
    parts: dict
    peak_mib: float
    whole_command: float
    rss_mib: float
    frequency: np.ndarray
    error: float = float("nan")


def mesh_rows(meshes=MESHES, repeats: int = 3, whole_command: bool = True,
              log=print) -> list[MeshRow]:
    """Run the mesh ladder; errors against its finest mesh. Without
    ``whole_command`` the fresh-process runs are left out (NaN)."""
    base = load_scene(None).bed.plate
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        compute_bed_modes(base, n_modes=N_MODES)         # warm-up (imports, ARPACK)
        for nx, ny in meshes:
            spec = replace(base, nx=nx, ny=ny)
            reps = repeats if nx * ny <= 2500 else 1
            log(f"bench mesh: {nx} x {ny} ...")
            total, parts, bed = _in_process(spec, folder, reps)
            peak = _peak_memory(spec, folder)
            wall, rss = (_whole_command(_scene_with_mesh(folder, nx, ny), folder)
                         if whole_command else (float("nan"), float("nan")))
            rows.append(MeshRow(nx, ny, (nx + 1) * (ny + 1) * 4, total, parts, peak, wall, rss,
                                np.array(bed.modes.frequency[:N_MODES], dtype=float)))
    finest = max(rows, key=lambda r: r.nx * r.ny).frequency
    for r in rows:
        r.error = float(np.abs(r.frequency / finest - 1).max())
    return rows


def mesh_table(rows: list[MeshRow]) -> str:
    """The mesh ladder as a Markdown table."""
    head = ["mesh", "DOFs", "in-process [s]", "assemble", "eigen", "invariants", "write",
            "peak memory (tracemalloc) [MiB]", "whole command [s]", "peak RSS [MiB]",
            "f1 [Hz]", f"max rel. error f1-f{N_MODES} vs finest"]
    body = [[f"{r.nx} x {r.ny}", str(r.dofs), f"{r.in_process:.3f}",
             f"{r.parts['assemble']:.3f}", f"{r.parts['eigen']:.3f}",
             f"{r.parts['invariants']:.3f}", f"{r.parts['write']:.3f}", f"{r.peak_mib:.0f}",
             _num(r.whole_command, "{:.2f}"), _num(r.rss_mib, "{:.0f}"), f"{r.frequency[0]:.6f}",
             f"{r.error:.1e}"] for r in rows]
    return md_table(head, body, align="lrrrrrrrrrrr")


def _num(value: float, fmt: str) -> str:
    return "–" if value != value else fmt.format(value)
