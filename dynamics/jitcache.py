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

:func:`refresh` runs once per process, when :mod:`flexbed.dynamics.kernel`,
:mod:`flexbed.dynamics.steppers` or :mod:`flexbed.dynamics.linear` is first
imported, before any compiled function is called (numba reads a
function's cache at its first call). It reads files only: no compiled
module needs to be imported for it.

Where no cache location numba knows is writable (``NUMBA_CACHE_DIR``
unwritable and the package's ``__pycache__`` read-only and no writable
user-wide cache), numba would refuse to import the compiled modules at
all; :func:`refresh` then points numba at a private folder in the
temporary directory, ``flexbed-numba-<uid>`` (created with mode 0700 and
used only if it is a directory this user owns), and says so in one line
on stderr. A ``NUMBA_CACHE_DIR`` that is not writable while another
location is gets one line naming the one numba uses instead.

Where numba's cache is found: numba has no public call for it, so this
module asks numba's own cache locators (``numba.core.caching``: the list
``CacheImpl._locator_classes``, formerly ``_CacheImpl``, and each
locator's ``from_function`` and ``get_cache_path``), internals that may
change in any numba release. That is why ``pyproject.toml`` bounds numba
above (``<0.69``: checked on 0.68.1; the lower bound 0.59 is the
project's), and why a numba without them is met by a fallback, never a
crash: :func:`refresh` then says in one line on stderr that the freshness
check is skipped (after an edit of a compiled module, its cached ``.nbi``
and ``.nbc`` files must then be removed by hand) and :func:`cache_dir`
returns None. Raise the bound after checking a new numba against
``tests/test_jitcache.py``.
"""

from __future__ import annotations

import hashlib
import os
import stat
import sys
import tempfile
from pathlib import Path

__all__ = ["COMPILED", "CONSTANTS", "refresh", "stamp", "cache_dir", "fallback_dir"]

#: Every module of flexbed.dynamics that holds numba-compiled functions
#: (relative names); a test checks that none is missing.
COMPILED = (
    "kernel.storage", "kernel.inputs", "kernel.mount_laws", "kernel.flexible_body",
    "kernel.rhs", "kernel.batch",
    "steppers.common", "steppers.rk4", "steppers.dop853", "steppers.radau",
    "linear.sweep", "linear.defect", "linear.phi", "sample_passes", "rigid_statics",
)

#: Modules of data that numba compiles into the functions of COMPILED as
#: constants (global arrays): in the stamp, with no cache files of their own.
CONSTANTS = ("steppers.dop853_coefficients", "steppers.radau_coefficients")

_ROOT = Path(__file__).resolve().parent
_STAMP_FILE = "flexbed-compiled.stamp"
_done = False


def _source(name: str) -> Path:
    return _ROOT.joinpath(*name.split(".")).with_suffix(".py")


def stamp() -> str:
    """SHA-256 of the names and sources of the modules of :data:`COMPILED`
    and :data:`CONSTANTS`."""
    digest = hashlib.sha256()
    for name in COMPILED + CONSTANTS:
        digest.update(name.encode())
        digest.update(_source(name).read_bytes())
    return digest.hexdigest()


def _probe():
    """A function for numba's cache locators (they read its line number only)."""


class _NoLocators(Exception):
    """numba's cache locators are not there as this module expects them."""


def cache_dir(source: str | os.PathLike) -> str | None:
    """The folder where numba caches the functions of a source file, as
    numba chooses it (``NUMBA_CACHE_DIR``, the ``__pycache__`` beside the
    file, or the user-wide cache), or None if none is writable or this
    numba's locators are not available (see the module docstring)."""
    try:
        return _locate(source)
    except _NoLocators:
        return None


def _locate(source: str | os.PathLike) -> str | None:
    """:func:`cache_dir`, raising _NoLocators where numba's locators are
    missing or do not take the calls of numba 0.59–0.68."""
    try:
        for cls in _locator_classes():
            locator = cls.from_function(_probe, str(source))
            if locator is not None:
                return locator.get_cache_path()
    except (AttributeError, TypeError) as exc:
        raise _NoLocators(f"numba's cache locators do not work as expected ({exc})") from exc
    return None


def _locator_classes() -> list:
    """numba's cache locators in the order it tries them (its default list,
    or the one ``NUMBA_CACHE_LOCATOR_CLASSES`` names); _NoLocators where
    this numba has no such list (``numba.core.caching.CacheImpl._locator_classes``)."""
    try:
        from numba.core import caching, config
    except ImportError as exc:
        raise _NoLocators(f"numba.core.caching cannot be imported ({exc})") from exc
    names = getattr(config, "CACHE_LOCATOR_CLASSES", "") or ""
    if names:
        found = [getattr(caching, n.strip().rsplit(".", 1)[-1], None) for n in names.split(",")]
        if all(found):
            return found
    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
    classes = getattr(impl, "_locator_classes", None)
    if not classes:
        raise _NoLocators("numba.core.caching has no CacheImpl._locator_classes")
    return list(classes)


def fallback_dir() -> Path | None:
    """The private cache folder used when no other is writable:
    ``<tempdir>/flexbed-numba-<uid>``, created 0700 if absent; None if it
    cannot be used (not a directory owned by this user, or not writable)."""
    uid = os.getuid() if hasattr(os, "getuid") else 0
    path = Path(tempfile.gettempdir()) / f"flexbed-numba-{uid}"
    try:
        path.mkdir(mode=0o700, exist_ok=True)
        st = os.lstat(path)
        if (not stat.S_ISDIR(st.st_mode) or st.st_uid != uid
                or st.st_mode & (stat.S_IWGRP | stat.S_IWOTH)):
            return None
        tempfile.TemporaryFile(dir=path).close()
    except OSError:
        return None
    return path


def _writable(folder: str) -> bool:
    try:
        os.makedirs(folder, exist_ok=True)
        tempfile.TemporaryFile(dir=folder).close()
    except OSError:
        return False
    return True


def _choose_location(source: Path) -> str | None:
    """Make sure numba has a writable cache location for ``source``;
    return the folder, saying in one line on stderr when it is not the one
    asked for (``NUMBA_CACHE_DIR``) or numba's own choices all failed."""
    from numba.core import config

    asked = config.CACHE_DIR
    found = _locate(source)
    if asked and not _writable(asked) and found is not None:
        print(f"flexbed: note: NUMBA_CACHE_DIR = {asked} is not writable; compiled code is "
              f"cached in {found} instead", file=sys.stderr)
    if found is not None:
        return found
    spare = fallback_dir()
    if spare is None:
        return None
    config.CACHE_DIR = str(spare)
    os.environ["NUMBA_CACHE_DIR"] = str(spare)
    where = f"NUMBA_CACHE_DIR = {asked}" if asked else "the package's folder"
    print(f"flexbed: note: {where} is not writable; compiled code is cached in {spare} "
          f"(set NUMBA_CACHE_DIR to a writable folder to choose)", file=sys.stderr)
    return _locate(source)


def refresh(force: bool = False) -> bool:
    """Flush the cache of every compiled module if their sources changed.

    Parameters
    ----------
    force : bool
        Check again even if this process already did.

    Returns
    -------
    bool
        Whether the cache was flushed (False, with one line on stderr, where
        numba's cache locators are not available: see the module docstring).
    """
    global _done
    if _done and not force:
        return False
    _done = True
    try:
        home = _choose_location(_source(COMPILED[0]))
        dirs = {name: _locate(_source(name)) for name in COMPILED}
    except _NoLocators as exc:
        version = getattr(sys.modules.get("numba"), "__version__", "?")
        print(f"flexbed: warning: {exc} (numba {version}); the freshness check of the "
              f"cached compiled code is skipped: after editing a module of "
              f"flexbed.dynamics, delete its cached .nbi and .nbc files", file=sys.stderr)
        return False
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
