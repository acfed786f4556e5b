"""The analyses a study runs per point, by name, in a registry.

Each analysis is the Python API's own function (:mod:`flexbed.api`), so a
point's numbers are those of a single ``flexbed static`` / ``simulate`` /
``compare`` of the same scene. An analysis receives the scene, the outcomes
of the analyses run before it at this point (``simulate`` starts from
``static``'s equilibrium when both run) and the bed's modes (computed once
per plate by the runner and shared).

Frequency-domain analyses join with :func:`register`: an :class:`Analysis`
with its name, a function ``run(scene, outcomes, modes) -> outcome`` and,
for files kept with ``--keep-results``, ``files(outcome) -> {suffix:
(datasets, attrs)}``; their metrics join :mod:`flexbed.study.metrics` the
same way. Nothing here depends on them.
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
    files : callable(outcome) -> dict suffix -> (datasets, attrs), or None.
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
    from flexbed.api import simulate
    run = simulate(scene, modes=modes if scene.bed.flexible else None,
                   equilibrium=outcomes.get("static"))
    if not run.complete:
        raise NumericalError(f"simulate: {run.message}")
    return run


def _compare(scene, outcomes, modes):
    from flexbed.api import compare
    return compare(scene, modes=modes)


register(Analysis("static", _static))
register(Analysis("simulate", _simulate, files=lambda run: {"results": run._datasets}))
register(Analysis("compare", _compare, needs_bed_modes=True,
                  files=lambda cmp: {f"compare-{case}": run._datasets
                                     for case, run in cmp.runs.items()}))
