"""flexbed: mount systems with flexible common beds (Lee, Kim & Jeong 1999).

The Python API (:mod:`flexbed.api`), loaded on first use so that
``import flexbed`` and the command line's start stay cheap::

    import flexbed
    scene = flexbed.load_scene()                 # or load_scene("my.toml")
    run = flexbed.simulate(flexbed.vary(scene, {"bed.model": "flexible"}))

Packages: :mod:`flexbed.fem` (the bed's plate model and modes),
:mod:`flexbed.dynamics` (the mount system's equations and solvers); the
command line (:mod:`flexbed.commands`), files (:mod:`flexbed.files`),
stages, analyses and benchmarks live beside them.
"""

from __future__ import annotations

__all__ = ["load_scene", "vary", "modes", "statics", "simulate", "compare", "open_results",
           "modal", "frf", "srs", "sweep", "Statics", "Results", "Comparison", "Modal", "Transmissibility", "InputError", "NumericalError", "__version__"]

_API = {"load_scene", "vary", "modes", "statics", "simulate", "compare", "open_results",
        "modal", "frf", "srs", "sweep", "Statics", "Results", "Comparison", "Modal", "Transmissibility"}


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
