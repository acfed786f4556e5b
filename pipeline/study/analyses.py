"""The analyses a study runs per point, by name, in a registry.

Each analysis is the Python API's own function (:mod:`flexbed.api`), so a
point's numbers are those of a single ``flexbed static`` / ``simulate`` /
``compare`` of the same scene. An analysis receives the scene, the outcomes
of the analyses run before it at this point (``simulate`` starts from
``static``'s equilibrium when both run) and the bed's modes (computed once
per plate by the runner and shared). ``simulate``'s outcome is a
:class:`flexbed.study.outputs.PointRun`: the solved motion, of which only
what the metrics read is evaluated at the output samples (the whole
:class:`flexbed.Results` when asked, and for a kept results file).

The frequency-domain analyses: ``modal`` is :func:`flexbed.modal` of the
point's scene (about ``static``'s equilibrium when that runs too);
``frf`` hands the metrics :class:`Responses`, which call :func:`flexbed.frf`
with the input, points and frequencies each metric asks for, on the
``modal`` outcome's linearisation (computed here when ``modal`` does not
run).

Other analyses join with :func:`register`: an :class:`Analysis` with its
name, a function ``run(scene, outcomes, modes) -> outcome`` and, for files
kept with ``--keep-results``, ``files(outcome) -> {suffix: (writer,
args)}`` (``writer(path, *args)`` writes the file; run on the worker, the
writing on the client); their metrics join :mod:`flexbed.study.metrics`
the same way.

Files kept (``DIR/results/point-NNNN-<suffix>``): ``results.h5``
(simulate), ``compare-<case>.h5`` (compare), ``modal.h5``,
``modal-modes.csv``, ``modal-energy.csv``, ``modal-strain.csv``,
``modal-effective-mass.csv``, ``modal-shapes.xdmf`` + ``modal-shapes.h5``
(modal: ``flexbed modal -o point-NNNN-modal --no-plots``) and
``frf.h5``, ``frf.csv`` (frf: ``flexbed frf -o point-NNNN-frf
--no-plots``, the command's defaults — base z, the scene's points, the
band from the modes — whatever the metrics asked for).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

from flexbed.errors import NumericalError
from flexbed.files.scene import SceneFile

__all__ = ["Analysis", "ANALYSES", "register", "ordered"]


@dataclass(frozen=True)
class Analysis:
    """One analysis of a point.

    name : str; run : callable(scene, outcomes, modes) -> outcome (raises
    FlexbedError on failure); needs_bed_modes : bool — it needs the modes
    of the bed made flexible even when the scene's bed is rigid (compare);
    files : callable(outcome) -> dict suffix -> (writer, args), or None.
    """

    name: str
    run: Callable[[SceneFile, dict, Any], Any]
    needs_bed_modes: bool = False
    files: Callable[[Any], dict] | None = None


#: the analyses by name, in the order they run at a point
ANALYSES: dict[str, Analysis] = {}


def register(analysis: Analysis) -> Analysis:
    """Add (or replace) an analysis; analyses run in registration order."""
    ANALYSES[analysis.name] = analysis
    return analysis


def ordered(names) -> tuple[str, ...]:
    """``names`` in the order the analyses run."""
    wanted = set(names)
    return tuple(n for n in ANALYSES if n in wanted)


def _static(scene, outcomes, modes):
    from flexbed.api import statics
    return statics(scene, modes=modes if scene.bed.flexible else None)


def _simulate(scene, outcomes, modes):
    from flexbed.api.simulation import solved
    from flexbed.study.outputs import PointRun
    run = PointRun(*solved(scene, modes=modes if scene.bed.flexible else None,
                           equilibrium=outcomes.get("static")))
    if not run.complete:
        raise NumericalError(f"simulate: {run.message}")
    return run


def _compare(scene, outcomes, modes):
    from flexbed.api import compare
    return compare(scene, modes=modes)


def _results_file(run) -> tuple:
    from flexbed.files.results import write_results_contents
    from flexbed.study.outputs import PointRun
    if isinstance(run, PointRun):
        run = run.results()
    return write_results_contents, run._datasets


register(Analysis("static", _static))
register(Analysis("simulate", _simulate, files=lambda run: {"results.h5": _results_file(run)}))
register(Analysis("compare", _compare, needs_bed_modes=True,
                  files=lambda cmp: {f"compare-{case}.h5": _results_file(run)
                                     for case, run in cmp.runs.items()}))


def _modal(scene, outcomes, modes):
    from flexbed.api import modal
    return modal(scene, modes=modes if scene.bed.flexible else None,
                 equilibrium=outcomes.get("static"))


class Responses:
    """The ``frf`` outcome of a point: :func:`flexbed.frf` of its scene on
    its ``modal`` linearisation, one call per distinct request (cached).

    scene : SceneFile; modal : flexbed.Modal; modes : ModesData or None.
    """

    def __init__(self, scene, modal, modes):
        self.scene, self.modal, self.modes = scene, modal, modes
        self._cache = {}

    def response(self, input: str, point: tuple, *, frequencies=None, band=None):
        """``flexbed.frf(scene, input=input, points=[point], frequencies=…,
        band=…, equilibrium=modal)``; ``point`` is (name, body, position[,
        relative_to]). Returns a flexbed.Transmissibility."""
        from flexbed.api import frf
        key = (input, tuple(map(str, point)), None if frequencies is None else tuple(frequencies),
               band)
        if key not in self._cache:
            self._cache[key] = frf(self.scene, input=input, points=[point],
                                   frequencies=frequencies, band=band,
                                   modes=self.modes, equilibrium=self.modal)
        return self._cache[key]

    def default(self):
        """``flexbed.frf(scene, equilibrium=modal)``: the command's defaults
        (base z, the scene's points, the band from the modes)."""
        from flexbed.api import frf
        if "default" not in self._cache:
            self._cache["default"] = frf(self.scene, modes=self.modes, equilibrium=self.modal)
        return self._cache["default"]


def _frf(scene, outcomes, modes):
    modes = modes if scene.bed.flexible else None
    modal = outcomes.get("modal") or _modal(scene, outcomes, modes)
    return Responses(scene, modal, modes)


def _modal_files(m) -> dict:
    from flexbed.api.frequency import modal_files
    return {"modal" + suffix: f for suffix, f in
            modal_files(m.scene, m.mounted, shapes=True).items()}


def _frf_files(responses: Responses) -> dict:
    from flexbed.api.frequency import frf_files
    return {"frf" + suffix: f for suffix, f in
            frf_files(responses.scene, responses.default().result).items()}


register(Analysis("modal", _modal, files=_modal_files))
register(Analysis("frf", _frf, files=_frf_files))
