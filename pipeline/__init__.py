"""flexbed: mount systems with flexible common beds (Lee, Kim & Jeong 1999).

This folder, ``pipeline/``, *is* the package ``flexbed`` (``pyproject.toml``,
``[tool.setuptools] package-dir``); ``fem/`` installs as :mod:`flexbed.fem`
and ``dynamics/`` as :mod:`flexbed.dynamics`. Everything imports as
``flexbed.…``: there is no ``pipeline``, ``fem`` or ``dynamics`` package.

The Python API (:mod:`flexbed.api`), loaded on first use so that
``import flexbed`` and the command line's start stay cheap::

    import flexbed
    scene = flexbed.load_scene()                 # or load_scene("my.toml")
    run = flexbed.simulate(flexbed.vary(scene, {"bed.model": "flexible"}))

The rooms, each importing only those above it (and :mod:`flexbed.fem`,
:mod:`flexbed.dynamics`, which never import each other nor anything here):

- :mod:`flexbed.files`: file formats (scene files, modes, equilibrium,
  results, frequency-domain files, XDMF), the only h5py user, atomic writes;
- :mod:`flexbed.plots`: every PNG plot (matplotlib), of plain arrays;
- :mod:`flexbed.stages`: the pipeline's stages (modes, the flexible bed,
  the compiled system, statics and simulation, what an interrupt keeps);
- :mod:`flexbed.analyses`: after a run or about the equilibrium (points of
  interest, comparisons, modal analysis, transmissibility, shock spectra);
- :mod:`flexbed.api`: the Python API, the stages as functions;
- :mod:`flexbed.bench`: the work-precision report of ``flexbed bench``;
- :mod:`flexbed.study`: design studies on Dask (on top of the API);
- :mod:`flexbed.commands`: one module per subcommand of the command line
  (:mod:`flexbed.cli`), which nothing else imports.

Two imports go the other way, both on first call: a scene file with
``modes = "auto"`` asks :mod:`flexbed.stages.modes_auto` for its cut-off,
and :func:`flexbed.sweep` runs :mod:`flexbed.study` (:func:`flexbed.optimize`,
:mod:`flexbed.optimization`).

Beside them: :mod:`flexbed.errors`, :mod:`flexbed.console`,
:mod:`flexbed.interrupts`, :mod:`flexbed.threads`, :mod:`flexbed.words`,
and ``scenes/`` (the built-in reference scene).
"""

from __future__ import annotations

__all__ = ["load_scene", "vary", "modes", "statics", "simulate", "compare", "open_results",
           "modal", "frf", "srs", "sweep", "qualify", "Statics", "Results", "Comparison",
           "Modal", "Transmissibility", "Qualification", "transmitted", "Transmitted",
           "random_vibration", "RandomVibration", "InputError", "NumericalError",
           "optimize", "response_spectrum", "synthesise",
           "SpectrumResponse", "Motion", "__version__"]

_API = {"load_scene", "vary", "modes", "statics", "simulate", "compare", "open_results",
        "modal", "frf", "srs", "sweep", "qualify", "Statics", "Results", "Comparison", "Modal",
        "Transmissibility", "Qualification", "transmitted", "Transmitted", "random_vibration",
        "RandomVibration", "optimize", "response_spectrum", "synthesise", "SpectrumResponse",
        "Motion"}


def __getattr__(name: str):
    if name in _API:
        from flexbed import api
        return getattr(api, name)
    if name in ("InputError", "NumericalError"):
        from flexbed import errors
        return getattr(errors, name)
    if name == "__version__":
        from flexbed.files.store import package_version
        return package_version()
    raise AttributeError(f"module 'flexbed' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
