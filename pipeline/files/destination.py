"""Where flexbed writes: only regular files, and atomically.

Every file flexbed writes (HDF5, CSV, PNG, XDMF, TOML, Markdown) goes through
:func:`atomic_write`: the destination is checked first — absent, or a
regular file; a directory, a device, a FIFO, a socket or a symbolic link
(even a dangling one) is refused with one line naming it, so that no
output can replace what is not a plain file (``-o /dev/full`` run as root
would otherwise rename a file over the device node) — then the content is
written to a temporary file in the same folder and renamed over the
destination, so a reader never sees half a file and a failure leaves
nothing behind. Light: the standard library only.
"""

from __future__ import annotations

import os
import stat
import tempfile
from pathlib import Path
from typing import Callable

from flexbed.errors import InputError

__all__ = ["check_destination", "atomic_write", "write_text"]

_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO"),
          (stat.S_ISSOCK, "a socket"))


def check_destination(path: str | os.PathLike) -> Path:
    """``path`` as a Path if flexbed may write it (absent, or a regular file);
    else InputError naming what it is."""
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
                         f"({exc.strerror or exc})") from None
    try:
        fd, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise InputError(f"{path}: cannot write in {path.parent} ({exc.strerror or exc})") \
            from None
    os.close(fd)
    tmp = Path(name)
    try:
        write(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)     # mkstemp makes it private; use the usual mode
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write UTF-8 text atomically (:func:`atomic_write`)."""
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))
