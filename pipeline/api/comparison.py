"""The rigid, flexible and damped flexible bed side by side as a library
call (as ``flexbed compare``).

>>> import flexbed
>>> c = flexbed.compare(flexbed.load_scene(), t_end=1.0)  # doctest: +SKIP
>>> print(c.table())                                      # doctest: +SKIP
>>> c.runs["damped"].mount_force                          # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses

from flexbed.analyses.compare import CASES, LABELS, case_run, comparison_rows, markdown_table, \
    solve_case
from flexbed.analyses.compare_verdict import verdict_markdown, verdict_rows
from flexbed.api import bed_modes
from flexbed.api.arguments import Arguments
from flexbed.api.results import Results
from flexbed.api.simulation import solver_with
from flexbed.errors import NumericalError
from flexbed.files.modes import ModesData
from flexbed.files.scene import SceneFile
from flexbed.files.store import in_memory
from flexbed.threads import limited

__all__ = ["Comparison", "compare"]


@dataclasses.dataclass(frozen=True)
class Comparison:
    """The scene with a rigid, a flexible (α = β = 0) and a damped flexible bed.

    rows : list of dict — per equipment and case: ``static_z`` [m], ``peak``
    and ``rms`` of d(t) [m], ``frequency`` [Hz], ``delay`` [s], ``decay``
    [–] (as ``flexbed compare`` reports them); runs : dict case → Results;
    verdicts : dict case → Verdict (:mod:`flexbed.analyses.verdict`),
    each case against the scene's limits.
    """

    rows: list
    runs: dict
    verdicts: dict = dataclasses.field(default_factory=dict)

    def table(self) -> str:
        """The rows as a Markdown table (mm and ms, as ``flexbed compare``)."""
        return markdown_table(self.rows)

    def verdict_rows(self) -> list:
        """The verdict's figures per case, SI
        (:func:`~flexbed.analyses.compare_verdict.verdict_rows`)."""
        return verdict_rows(self.verdicts, CASES)

    def verdict_table(self) -> str:
        """The verdict's figures per case as a Markdown table (g, %, mm, N)."""
        return verdict_markdown(self.verdict_rows(), CASES, LABELS)


@limited()
def compare(scene: SceneFile, *, modes: ModesData | None = None, **settings) -> Comparison:
    """Run the scene with its bed rigid, flexible undamped and flexible with
    its damping, each from its own static equilibrium (``**settings`` as in
    :func:`flexbed.simulate`)."""
    check = Arguments("compare")
    scene, modes = check.scene(scene), check.modes(modes)
    if settings:
        scene = dataclasses.replace(scene, solver=solver_with(scene, settings, "compare"))
    if modes is None:
        flexible = dataclasses.replace(scene, bed=dataclasses.replace(scene.bed,
                                                                      model="flexible"))
        modes = bed_modes.modes(flexible)
    runs, cases = {}, {}
    for case in CASES:
        sol = solve_case(scene, modes, case)
        if sol.interrupt is not None:      # Ctrl-C: stop here, as Python does
            raise sol.interrupt
        res = Results(in_memory(*sol.contents), modes=modes if case != "rigid" else None,
                      datasets=sol.contents)
        if not res.complete:
            raise NumericalError(f"{LABELS[case]}: {res.message}")
        runs[case] = res
        cases[case] = case_run(sol)
    names = [b.name for b in scene.scene.bodies]
    bed = scene.bed.body or names[1]
    equipment = [i for i in range(1, len(names)) if names[i] != bed]
    return Comparison(comparison_rows(cases, names, equipment), runs,
                      {c: r.verdict for c, r in cases.items()})
