"""One freshness check for numba's on-disk cache of every compiled module.

Numba invalidates a cached function only when its *own* source file
changes, yet the cached machine code of a function holds its compiled
callees too: after an edit of :mod:`flexbed.dynamics.kernel.inputs` the
cached right-hand side in :mod:`flexbed.dynamics.kernel.rhs` would still
run the old inputs. So this module keeps one stamp, a hash of the sources
of every module of :data:`COMPILED` (all the modules of this package that
hold numba functions), beside the cache, and when it differs from the
sources at hand it flushes the cache of all of them (their index and data
files are removed; numba compiles afresh and writes new ones).

:func:`refresh` runs once per process, when :mod:`flexbed.dynamics.kernel`
or :mod:`flexbed.dynamics.steppers` is first imported, before any compiled
function is called (numba reads a function's cache at its first call).
It reads files only: no compiled module needs to be imported for it.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

__all__ = ["COMPILED", "refresh", "stamp", "cache_dir"]

#: Every module of flexbed.dynamics that holds numba-compiled functions
#: (relative names); a test checks that none is missing.
COMPILED = (
    "kernel.storage", "kernel.inputs", "kernel.mount_laws", "kernel.flexible_body",
    "kernel.rhs", "kernel.batch",
    "steppers.common", "steppers.rk4", "steppers.dop853", "steppers.radau",
    "steppers.propagate",
)

_ROOT = Path(__file__).resolve().parent
_STAMP_FILE = "flexbed-compiled.stamp"
_done = False


def _source(name: str) -> Path:
    return _ROOT.joinpath(*name.split(".")).with_suffix(".py")


def stamp() -> str:
    """SHA-256 of the names and sources of the modules of :data:`COMPILED`."""
    digest = hashlib.sha256()
    for name in COMPILED:
        digest.update(name.encode())
        digest.update(_source(name).read_bytes())
    return digest.hexdigest()


def _probe():
    """A function for numba's cache locators (they read its line number only)."""


def cache_dir(source: str | os.PathLike) -> str | None:
    """The folder where numba caches the functions of a source file, as
    numba chooses it (``NUMBA_CACHE_DIR``, the ``__pycache__`` beside the
    file, or the user-wide cache), or None if none is writable."""
    from numba.core import caching

    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl")
    for cls in impl._locator_classes:
        locator = cls.from_function(_probe, str(source))
        if locator is not None:
            return locator.get_cache_path()
    return None


def refresh(force: bool = False) -> bool:
    """Flush the cache of every compiled module if their sources changed.

    Parameters
    ----------
    force : bool
        Check again even if this process already did.

    Returns
    -------
    bool
        Whether the cache was flushed.
    """
    global _done
    if _done and not force:
        return False
    _done = True
    dirs = {name: cache_dir(_source(name)) for name in COMPILED}
    home = dirs[COMPILED[0]]
    if home is None:
        return False
    stamp_path = Path(home) / _STAMP_FILE
    current = stamp()
    try:
        if stamp_path.read_text() == current:
            return False
    except OSError:
        pass
    for name, folder in dirs.items():
        if folder is None or not os.path.isdir(folder):
            continue
        prefix = _source(name).stem + "."
        for entry in os.listdir(folder):
            if entry.startswith(prefix) and entry.endswith((".nbi", ".nbc")):
                try:
                    os.remove(os.path.join(folder, entry))
                except OSError:
                    pass
    try:
        stamp_path.write_text(current)
    except OSError:
        pass
    return True
