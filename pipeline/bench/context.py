"""What the benchmark report's sections share: the scene, the options, the
cases and references (built once, on first use), the results other
sections read, and the figures written."""

from __future__ import annotations

import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable

from flexbed.dynamics.precompile import LINEAR_MAPS, compile_in_parallel

from flexbed.bench.cases import CASES, Case, ModesStore, build_case
from flexbed.bench.reference import Reference, compute_reference
from flexbed.files.scene import SceneFile

__all__ = ["BenchContext", "FULL", "QUICK", "TEST_PROFILE", "quick_profile"]


@dataclass(frozen=True)
class Profile:
    """How thorough a report is.

    cases : integrator cases (keys of :data:`flexbed.bench.cases.CASES`);
    reference_dt : the reference's largest RK4 step [s]; budget : the
    longest predicted wall time of one setting that is still run [s];
    rhs_seconds : length of one timing of the right-hand side [s];
    left_out : names of the report's sections it leaves out when no
    section is asked for; auto_tolerance : the ``mesh_tolerance`` of the
    beds section's ``element_size = "auto"`` beds (the default 0.005).
    """

    name: str
    cases: tuple
    reference_dt: float
    budget: float
    rhs_seconds: float
    left_out: tuple = ()
    auto_tolerance: float = 0.005


FULL = Profile("full", ("rigid", "flexible", "damped"), reference_dt=5e-5, budget=15.0,
               rhs_seconds=0.5)
#: the quick report leaves out the linear fast path (``flexbed bench linear
#: --quick`` runs it): compiling it would double a fresh install's first
#: quick report (docs/first-run.md)
QUICK = Profile("quick", ("rigid", "flexible"), reference_dt=1.25e-4, budget=3.0,
                rhs_seconds=0.05, left_out=("linear",))
#: A test profile, for tests/test_bench.py only: the quick report with the
#: beds section's two ``element_size = "auto"`` beds (the reference bed and
#: the stiffened bed) meshed to a 2 % tolerance rather than 0.5 % (a few
#: coarse meshes rather than the fine ones: about 25 s of the quick report's
#: 90 s of CPU). Every section, table and figure is the same; those two
#: beds' 0.5 % results are checked by the tests of the meshes themselves
#: (tests/test_accuracy.py, tests/test_stiffener_model.py). Chosen by the
#: environment variable ``FLEXBED_BENCH_PROFILE=test`` (:func:`quick_profile`);
#: ``flexbed bench --quick`` without it is unchanged.
TEST_PROFILE = replace(QUICK, auto_tolerance=0.02)


def quick_profile() -> Profile:
    """The quick report's profile: :data:`QUICK`, or :data:`TEST_PROFILE`
    when the environment sets ``FLEXBED_BENCH_PROFILE=test`` (the test
    suite's hook; any other value is the quick profile)."""
    return TEST_PROFILE if os.environ.get("FLEXBED_BENCH_PROFILE") == "test" else QUICK


@dataclass
class BenchContext:
    """Shared state of one report.

    Parameters
    ----------
    scene : SceneFile
    out_dir : Path
        Where the report and its PNGs go.
    workdir : Path
        A scratch folder (modes files).
    profile : Profile
    t_end : float
        End of every run [s] (the scene's unless a shorter one is asked).
    output_dt : float
        Spacing of the samples the errors are measured on [s].
    log : callable(str)
        Progress lines.

    Attributes
    ----------
    results : dict
        Structured results by section name (tests and later sections read them).
    figures : list of Path
        PNGs written so far.
    """

    scene: SceneFile
    out_dir: Path
    workdir: Path
    profile: Profile
    t_end: float
    output_dt: float = 0.01
    log: Callable[[str], None] = lambda m: None
    results: dict[str, Any] = field(default_factory=dict)
    figures: list[Path] = field(default_factory=list)
    _cases: dict = field(default_factory=dict, repr=False)
    _refs: dict = field(default_factory=dict, repr=False)
    _modes: ModesStore | None = field(default=None, repr=False)

    @property
    def quick(self) -> bool:
        return self.profile.name == "quick"

    @property
    def modes(self) -> ModesStore:
        """The modes file shared by every flexible case."""
        if self._modes is None:
            self._modes = ModesStore(self.scene, self.workdir)
        return self._modes

    def case(self, key: str) -> Case:
        """One of :data:`flexbed.bench.cases.CASES`, compiled at its equilibrium."""
        if key not in self._cases:
            if not self._cases:
                # a first run: the right-hand side compiles in a second
                # process while this one compiles the steppers, before
                # anything is timed (flexbed.dynamics.precompile)
                compile_in_parallel(log=self.log, linear=LINEAR_MAPS)
            self._cases[key] = build_case(self.scene, CASES[key], self.modes, self.t_end)
        return self._cases[key]

    def reference(self, key: str) -> Reference:
        """The case's RK4 reference (computed on first use)."""
        if key not in self._refs:
            self._refs[key] = compute_reference(self.case(key), self.output_dt,
                                                self.profile.reference_dt, log=self.log)
        return self._refs[key]

    def figure(self, name: str) -> Path:
        """Path of a PNG of the report (``bench-<name>.png`` in ``out_dir``), recorded."""
        path = self.out_dir / f"bench-{name}.png"
        self.figures.append(path)
        return path
