"""Where flexbed writes: only regular files, and atomically.

Every file flexbed writes (HDF5, CSV, PNG, XDMF, TOML, Markdown) goes through
:func:`atomic_write`: the destination is checked first — absent, or a
regular file; a directory, a device, a FIFO, a socket or a symbolic link
(even a dangling one) is refused with one line naming it, so that no
output can replace what is not a plain file (``-o /dev/full`` run as root
would otherwise rename a file over the device node) — then the content is
written to a temporary file in the same folder and renamed over the
destination, so a reader never sees half a file and a failure leaves
nothing behind. A write that fails (a full disk, ``ENOSPC``; a file size
limit, ``EFBIG``; a quota; a folder one may not write in; a read-only file
system) removes its temporary file and becomes one line naming the file
and saying what to do (:class:`~flexbed.errors.InputError`, exit 2).
:func:`refuse_inputs` refuses an output that is one of the command's
input files (compared by their resolved real paths, so a link or a
``./`` does not hide it). Light: the standard library only.
"""

from __future__ import annotations

import os
import stat
import tempfile
from pathlib import Path
from typing import Callable

from flexbed.errors import InputError, os_error_text

__all__ = ["check_source", "check_destination", "atomic_write", "write_text", "refuse_inputs",
           "make_folder"]

_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO"),
          (stat.S_ISSOCK, "a socket"))


def _no_nul(path: str | os.PathLike, doing: str) -> None:
    """InputError for a name holding a NUL character, which no file name
    can (the operating system's calls refuse it with a ValueError), or
    another control character (a line break, a tab, an escape: a name the
    one-line messages that name files could not show on one line)."""
    name = os.fsdecode(path)
    if "\x00" in name:
        raise InputError(f"{name!r}: {doing}: a file name cannot hold a NUL character")
    bad = next((c for c in name if ord(c) < 0x20 or ord(c) == 0x7F), None)
    if bad is not None:
        raise InputError(f"{name!r}: {doing}: flexbed does not take a file name holding a "
                         f"control character ({bad!r})")


def check_source(path: str | os.PathLike, what: str) -> Path:
    """``path`` as a Path if flexbed may read it as ``what`` ("scene file",
    "results file", …): it exists and is a regular file (or a link to one).
    A FIFO would block the read for ever and a device would be read without
    end, so anything else is InputError naming what it is."""
    _no_nul(path, f"cannot read the {what}")
    path = Path(path)
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file; cannot read the {what}") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read the {what} ({exc.strerror or exc})") from None
    if not stat.S_ISREG(st.st_mode):
        kind = next((name for test, name in _KINDS if test(st.st_mode)), "not a regular file")
        raise InputError(f"{path}: cannot read the {what}: it is {kind}, not a file")
    return path


def check_destination(path: str | os.PathLike) -> Path:
    """``path`` as a Path if flexbed may write it (absent, or a regular file);
    else InputError naming what it is."""
    _no_nul(path, "cannot write here")
    path = Path(path)
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return path
    except OSError as exc:
        raise InputError(f"{path}: cannot write here ({exc.strerror or exc})") from None
    if stat.S_ISLNK(st.st_mode):
        raise InputError(f"{path}: is a symbolic link; flexbed writes only regular files "
                         f"(give the link's target, or another name)")
    if not stat.S_ISREG(st.st_mode):
        what = next((name for test, name in _KINDS if test(st.st_mode)), "not a regular file")
        raise InputError(f"{path}: is {what}; flexbed writes only regular files "
                         f"(choose a file name)")
    return path


def atomic_write(path: str | os.PathLike, write: Callable[[Path], None]) -> Path:
    """Write a file atomically: ``write(tmp)`` fills a temporary file in the
    destination's folder (created if needed), which then replaces
    ``path``; on any failure (or an interrupt) the temporary file is
    removed and ``path`` is untouched. Returns ``path``."""
    path = check_destination(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{path.parent}: cannot create the folder "
                         f"({os_error_text(exc)})") from None
    try:
        fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise InputError(f"{path}: cannot write in {path.parent} ({os_error_text(exc)})") \
            from None
    os.close(fd)
    tmp = Path(name)
    try:
        write(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)     # mkstemp makes it private; use the usual mode
        os.replace(tmp, path)
    except OSError as exc:
        tmp.unlink(missing_ok=True)
        raise InputError(f"{path}: cannot write it ({_reason(exc)}); nothing was written") \
            from None
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def _reason(exc: OSError) -> str:
    """The reason of a failed write; h5py reports the C library's errno
    only inside its message ("errno = 28")."""
    if exc.errno is None:
        import errno
        import re
        found = re.search(r"errno = (\d+)", str(exc))
        if found:
            code = int(found.group(1))
            return os_error_text(OSError(code, os.strerror(code)))
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        for code in (errno.ENOSPC, errno.EFBIG, errno.EDQUOT):
            if os.strerror(code).lower() in first.lower():
                return os_error_text(OSError(code, os.strerror(code)))
        return first
    return os_error_text(exc)


def make_folder(path: str | os.PathLike, option: str = "-o") -> Path:
    """An output folder, created if absent; InputError if it names a file,
    a device or a folder that cannot be made."""
    _no_nul(path, f"{option}: cannot create the folder")
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise InputError(f"{option} {path}: is not a folder (it names an existing file or "
                         f"device); give a folder for the output files")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{option} {path}: cannot create the folder ({os_error_text(exc)})") \
            from None
    return path


def refuse_inputs(path: str | os.PathLike, *inputs: str | os.PathLike | None,
                  option: str = "-o") -> None:
    """InputError if the output ``path`` is one of ``inputs`` (None ignored),
    compared by resolved real paths."""
    out = os.path.realpath(path)
    for given in inputs:
        if given is not None and os.path.realpath(given) == out:
            raise InputError(f"{option} {path}: is the input file {given}; flexbed never "
                             f"writes over its inputs (choose another name)")


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write UTF-8 text atomically (:func:`atomic_write`)."""
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))
