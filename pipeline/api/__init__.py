"""flexbed as a Python library: the stages as functions returning objects
with NumPy arrays; files only when asked.

>>> import flexbed
>>> scene = flexbed.load_scene()                          # the built-in scene
>>> thick = flexbed.vary(scene, {"bed.thickness": 0.12})  # a variant, checked
>>> eq = flexbed.statics(thick)                           # doctest: +SKIP
>>> run = flexbed.simulate(thick, t_end=1.0)              # doctest: +SKIP
>>> top = run.point("equipment A", [0, 0, 0.15], relative_to="bed")  # doctest: +SKIP
>>> run.save("thick.h5")                                  # doctest: +SKIP

Every function takes a :class:`~flexbed.files.scene.SceneFile` (from
:func:`load_scene`, :func:`vary`, or ``dataclasses.replace`` of its
sections). A flexible bed's modes are computed in memory when none are
given, once per plate in a process (or pass ``modes=flexbed.modes(scene)``,
or ``modes=flexbed.modes(scene, file=...)`` to keep them in a modes file).
Errors are :class:`flexbed.errors.InputError` (bad input) and
:class:`flexbed.errors.NumericalError` (no equilibrium); a run that stops
early comes back with ``complete = False`` and the samples it reached.
BLAS and OpenMP pools are held to ``FLEXBED_THREADS`` threads (default 1)
inside each call (:mod:`flexbed.threads`).

The room holds one module per idea, each exported here and as ``flexbed.NAME``:

- :mod:`~flexbed.api.bed_modes`: :func:`modes`, the bed's modes, computed
  once per plate in a process, and the compiled scene the calls share;
- :mod:`~flexbed.api.equilibrium`: :func:`statics` and :class:`Statics`;
- :mod:`~flexbed.api.simulation`: :func:`simulate`;
- :mod:`~flexbed.api.results`: :class:`Results` (a run, its points of
  interest), :func:`open_results` and :func:`srs`;
- :mod:`~flexbed.api.comparison`: :func:`compare` and :class:`Comparison`;
- :mod:`~flexbed.api.frequency`: :func:`modal`, :func:`frf` and their
  :class:`Modal` and :class:`Transmissibility`;
- :mod:`~flexbed.api.qualification`: :func:`qualify` and
  :class:`Qualification`, the verdict against the scene's limits;
- :mod:`~flexbed.api.studies`: :func:`sweep`;
- :mod:`~flexbed.api.optimization`: :func:`optimize`;
- :func:`load_scene` and :func:`vary` are :mod:`flexbed.files`' own.

It may import every other room of flexbed (files, stages, analyses; the
study package on first call only) and :mod:`flexbed.fem` and
:mod:`flexbed.dynamics` through them; only the top-level namespace
(:mod:`flexbed`) and :mod:`flexbed.study` (whose analyses are these
functions) import it.
"""

from __future__ import annotations

from flexbed.api.bed_modes import modes
from flexbed.api.comparison import Comparison, compare
from flexbed.api.equilibrium import Statics, statics
from flexbed.api.frequency import Modal, Transmissibility, frf, modal
from flexbed.api.qualification import Qualification, qualify
from flexbed.api.random_vibration import RandomVibration, random_vibration
from flexbed.api.results import Results, open_results, srs
from flexbed.api.simulation import simulate
from flexbed.api.optimization import optimize
from flexbed.api.spectrum import Motion, SpectrumResponse, response_spectrum, synthesise
from flexbed.api.studies import sweep
from flexbed.api.transmission import Transmitted, transmitted
from flexbed.files.scene import load_scene
from flexbed.files.variants import vary

__all__ = ["load_scene", "vary", "modes", "statics", "simulate", "compare", "open_results",
           "modal", "frf", "srs", "sweep", "qualify", "Statics", "Results", "Comparison",
           "Modal", "Transmissibility", "Qualification", "transmitted", "Transmitted",
           "random_vibration", "RandomVibration", "optimize", "response_spectrum", "synthesise",
           "SpectrumResponse", "Motion"]
