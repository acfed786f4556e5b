"""The shock verdict as a library call (as ``flexbed qualify``): statics,
then the transient the scene describes, judged against the scene's limits.

>>> import flexbed
>>> q = flexbed.qualify(flexbed.load_scene("skid.toml"))   # doctest: +SKIP
>>> q.passed, q.verdict.reasons                            # doctest: +SKIP
>>> print(q.markdown())                                    # doctest: +SKIP
>>> q.save("skid-verdict.h5")                              # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from flexbed.analyses.verdict import Verdict, contact_events, judge
from flexbed.analyses.verdict_tables import csv, markdown
from flexbed.api import bed_modes
from flexbed.api.arguments import Arguments
from flexbed.api.equilibrium import Statics, statics
from flexbed.api.results import Results
from flexbed.api.simulation import simulate, solver_with
from flexbed.errors import NumericalError
from flexbed.files.limits import check_static_strokes
from flexbed.files.modes import ModesData
from flexbed.files.scene import SceneFile
from flexbed.files.verdict import write_verdict
from flexbed.threads import limited

__all__ = ["Qualification", "qualify", "static_mounts"]


@dataclasses.dataclass(frozen=True)
class Qualification:
    """A scene judged against its limits.

    verdict : Verdict (:mod:`flexbed.analyses.verdict`: ``passed``,
    ``reasons``, ``mounts``, ``bodies``, ``points``, ``clearances``);
    statics : Statics; results : Results (the run); scene : SceneFile.
    """

    verdict: Verdict
    statics: Statics
    results: Results
    scene: SceneFile

    @property
    def passed(self) -> bool:
        return self.verdict.passed

    def markdown(self) -> str:
        """The verdict report (Markdown, in mm, N, g and s)."""
        st = self.results.solver
        return markdown(self.verdict, f"'{self.scene.scene.name}' "
                                      f"({self.scene.source.name}), 0–{st.get('t_end', 0):g} s, "
                                      f"{st.get('method', '')}, samples every "
                                      f"{st.get('output_dt', 0):g} s")

    def csv(self) -> str:
        """The verdict as CSV, one figure a row, SI."""
        return csv(self.verdict)

    def save(self, path: str | Path) -> Path:
        """Write the verdict file (``flexbed.verdict``, as ``flexbed qualify``)."""
        path = Arguments("Qualification.save").path(path, "path", optional=False)
        return write_verdict(path, self.scene, self.verdict, self.results.solver)


def static_mounts(eq: Statics):
    """The mounts' deflections [m] and forces [N] at rest, (M, 3) each."""
    o = eq.system.observe(0.0, eq.equilibrium.y)
    return o.dx, o.f


@limited()
def qualify(scene: SceneFile, *, modes: ModesData | None = None, progress=None,
            **settings) -> Qualification:
    """Statics, the transient, and the verdict against the scene's limits.

    Parameters
    ----------
    scene : SceneFile
        With its limits (``stroke_compression``, ``rated_load``,
        ``fragility``, ``[[clearance]]``, …; a scene without any is judged
        on nothing and passes, its figures reported all the same).
    modes : ModesData, optional
        A flexible bed's modes (default: computed in memory).
    progress : callable(t), optional
    **settings
        ``integrator``, ``t_end``, ``dt``, ``rtol``, ``atol``,
        ``output_dt``: override the scene's ``[solver]``.

    Raises
    ------
    InputError
        Bad arguments, or a stroke limit the static deflection already
        passes (checked before the transient).
    NumericalError
        No equilibrium, or a run that stopped early.
    """
    check = Arguments("qualify")
    scene, modes = check.scene(scene), check.modes(modes)
    progress = check.callback(progress, "progress")
    solver_with(scene, settings, "qualify")             # checked before any work
    if scene.bed.flexible and modes is None:
        modes = bed_modes.modes(scene)
    eq = statics(scene, modes=modes)
    dx, f = static_mounts(eq)
    check_static_strokes(scene.source.name, scene.limits, [m.name for m in scene.scene.mounts],
                         dx)
    results = simulate(scene, modes=modes, equilibrium=eq, progress=progress, **settings)
    if not results.complete:
        raise NumericalError(f"{scene.source.name}: {results.message}")
    verdict = judge(results._run(), scene.limits, dx, f, contact_events(results.contents.datasets))
    return Qualification(verdict, eq, results, scene)
