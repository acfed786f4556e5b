"""The benchmark's cases: the scene with its bed rigid, flexible or damped
flexible, compiled and brought to its static equilibrium.

A case is the scene (default: the reference scene, 0–3 s) with one bed
model, started from its own static equilibrium (the flexible ones with the
bed's sag unless the scene says otherwise), as ``flexbed compare`` does.
The three cases of the integrator benchmark are :data:`CASES`; the
modelling benchmarks build variants through :func:`build_case` (another
number of modes, the first-order invariants).
"""

from __future__ import annotations

import math
import time
import timeit
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from flexbed.dynamics.integrate import Settings, integrate, warm_up
from flexbed.dynamics.kernel import evaluate_many
from flexbed.dynamics.statics import solve_statics
from flexbed.dynamics.system import System

from flexbed.stages.modes import ensure_modes
from flexbed.stages.system import compile_scene
from flexbed.errors import NumericalError
from flexbed.files.scene import SceneFile

__all__ = ["CaseSpec", "Case", "CASES", "ModesStore", "build_case", "fastest_rate",
           "probe_state", "rhs_cost_us", "rhs_cost", "kernel_cost", "divisor_step"]


@dataclass(frozen=True, slots=True)
class CaseSpec:
    """What a case is.

    key : str
        Short name ("rigid", "flexible", "damped").
    n_modes : int or None
        Elastic modes kept; None for the rigid bed.
    damped : bool
        The scene's structural damping (False: α = β = 0).
    invariants : str or None
        "full" or "first_order"; None: the scene's choice.
    static_correction : bool
        Add the residual vectors of the modes left out
        (:mod:`flexbed.stages.residual_modes`).
    """

    key: str
    n_modes: int | None = None
    damped: bool = False
    invariants: str | None = None
    static_correction: bool = False

    def label(self, sf: SceneFile) -> str:
        """A one-line description, with the damping actually applied."""
        if self.n_modes is None:
            return "rigid bed"
        inv = self.invariants or sf.bed.invariants
        inv_s = "" if inv == "full" else f", {inv.replace('_', '-')} invariants"
        if not self.damped:
            return f"flexible bed, {self.n_modes} modes, undamped (α = β = 0){inv_s}"
        if sf.bed.damping_ratio is not None:
            ratios = ", ".join(f"{v:g}" for v in sf.bed.damping_ratio)
            return f"damped flexible bed, {self.n_modes} modes, damping ratio {ratios}{inv_s}"
        alpha, beta = sf.bed.rayleigh
        return (f"damped flexible bed, {self.n_modes} modes, Rayleigh α = {alpha:g} 1/s, "
                f"β = {beta:g} s{inv_s}")


#: The integrator benchmark's cases (the issue's three).
CASES = {
    "rigid": CaseSpec("rigid"),
    "flexible": CaseSpec("flexible", n_modes=2, damped=False),
    "damped": CaseSpec("damped", n_modes=6, damped=True),
}


@dataclass(frozen=True)
class Case:
    """A compiled case at its static equilibrium.

    spec : CaseSpec; label : str; system : System; y0 : (ny,) state at the
    static equilibrium; t_end : float [s], the end of its runs.
    """

    spec: CaseSpec
    label: str
    system: System
    y0: np.ndarray
    t_end: float


class ModesStore:
    """One modes file for every flexible case, holding the most modes asked
    so far (the first n modes of a file are the scene's n modes).

    Parameters
    ----------
    sf : SceneFile
    folder : Path
        Where the modes file is kept (a temporary folder).
    """

    def __init__(self, sf: SceneFile, folder: Path):
        self.sf = sf
        self.path = Path(folder) / "bench-modes.h5"

    def ensure(self, n_modes: int) -> Path:
        """The modes file, computed (again) if it holds fewer than ``n_modes``."""
        sf = replace(self.sf, bed=replace(self.sf.bed, model="flexible", modes=n_modes,
                                          fmax=None))
        data, _ = ensure_modes(sf, self.path, n_modes=n_modes, log=lambda m: None)
        return data.path


def build_case(sf: SceneFile, spec: CaseSpec, modes: ModesStore | None = None,
               t_end: float | None = None) -> Case:
    """Compile a case, solve its static equilibrium and warm up the compiled code.

    Parameters
    ----------
    sf : SceneFile
    spec : CaseSpec
    modes : ModesStore, required for a flexible case
    t_end : float, optional
        End of the runs [s] (default: the scene's).
    """
    if spec.n_modes is None:
        csf = replace(sf, bed=replace(sf.bed, model="rigid"))
        system = compile_scene(csf)
        sag = True
    else:
        inv = spec.invariants or sf.bed.invariants
        csf = replace(sf, bed=replace(sf.bed, model="flexible", modes=spec.n_modes, fmax=None,
                                      invariants=inv, static_correction=spec.static_correction))
        need = max(spec.n_modes, sf.bed.correction_modes) if spec.static_correction \
            else spec.n_modes
        system = compile_scene(csf, modes.ensure(need), damped=spec.damped)
        sag = sf.bed.static_sag
    label = spec.label(sf)
    eq = solve_statics(system, tol=sf.solver.static_tol, sag=sag)
    if not eq.success:
        raise NumericalError(f"{sf.source.name} ({label}): {eq.message}")
    y0 = np.array(eq.y, dtype=float)
    warm_up(system, y0)                  # no numba compilation inside the timings that follow
    return Case(spec=spec, label=label, system=system, y0=y0,
                t_end=float(t_end if t_end is not None else sf.solver.t_end))


def fastest_rate(system: System) -> float:
    """The largest |λ| of the flexible bodies' modal blocks [1/s].

    Per mass-normalised mode, m s² + c s + k = 0 with the diagonal of the
    modal mass, damping and stiffness: |λ| = √(k/m) when underdamped, the
    faster root (c + √(c² − 4km)) / 2m when overdamped. 0 for a rigid bed.
    The mounts' own rates (a few Hz on the reference scene) are far below.
    """
    rate = 0.0
    for fc in system.flex_compiled:
        m = np.diag(fc.eom.I6)
        c = np.diag(fc.eom.C)
        k = np.diag(fc.eom.K)
        disc = c * c - 4.0 * k * m
        over = (c + np.sqrt(np.maximum(disc, 0.0))) / (2.0 * m)
        lam = np.where(disc > 0.0, over, np.sqrt(np.maximum(k / m, 0.0)))
        rate = max(rate, float(np.max(lam, initial=0.0)))
    return rate


def probe_state(case: Case, t: float = 0.1) -> tuple[float, np.ndarray]:
    """A state in motion: (t [s], y (ny,)) after ``t`` seconds of an accurate
    implicit run (cheap on stiff cases too)."""
    t = min(t, case.t_end)
    run = integrate(case.system, case.y0, Settings("radau", t_end=t, rtol=1e-6, atol=1e-9,
                                                   output_dt=t))
    if not run.complete:
        raise NumericalError(f"{case.label}: probe run failed: {run.message}")
    return float(run.t[-1]), run.y[-1]


def rhs_cost_us(system: System, t: float, y: np.ndarray, reps: int = 2000,
                repeat: int = 5) -> float:
    """Best of ``repeat`` timings of ``reps`` right-hand-side evaluations,
    per evaluation [µs]."""
    best = min(timeit.repeat(lambda: system.rhs(t, y), number=reps, repeat=repeat))
    return best / reps * 1e6


def rhs_cost(case: Case, seconds: float = 0.5, repeat: int = 5) -> float:
    """One right-hand side of a case in motion (:func:`probe_state`) [µs]:
    the best of ``repeat`` timings of about ``seconds`` of calls each."""
    t, y = probe_state(case)
    one = rhs_cost_us(case.system, t, y, reps=20, repeat=1) * 1e-6
    reps = max(20, int(seconds / max(one, 1e-7)))
    return rhs_cost_us(case.system, t, y, reps=reps, repeat=repeat)


def kernel_cost(case: Case, seconds: float = 0.5, repeat: int = 5) -> float:
    """One evaluation of the compiled kernel inside compiled code, as the
    compiled steppers call it, at the state of :func:`probe_state` [µs]: the
    best of ``repeat`` timings of about ``seconds`` of calls each."""
    t, y = probe_state(case)
    y = np.ascontiguousarray(y, dtype=float)
    dy = np.empty_like(y)
    d = case.system.kernel
    evaluate_many(1, t, math.inf, y, dy, d)              # compile or load, outside the timing
    t0 = time.perf_counter()
    evaluate_many(100, t, math.inf, y, dy, d)
    one = max((time.perf_counter() - t0) / 100, 1e-8)
    reps = max(100, int(seconds / one))
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        evaluate_many(reps, t, math.inf, y, dy, d)
        best = min(best, time.perf_counter() - t0)
    return best / reps * 1e6


def divisor_step(dt_max: float, span: float) -> float:
    """The largest step ≤ ``dt_max`` that divides ``span`` [s]."""
    return span / math.ceil(span / dt_max - 1e-9)
