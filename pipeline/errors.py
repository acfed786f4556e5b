"""Errors the command line turns into one clear line and an exit code.

Exit codes shared by every subcommand: 0 success, 1 numerical failure,
2 bad input (scene, options or files); and ``flexbed qualify``'s 3, a
verdict of FAIL (the run succeeded, the design did not).
"""

import errno

EXIT_OK = 0
EXIT_NUMERICAL = 1
EXIT_INPUT = 2
EXIT_FAIL = 3


class FlexbedError(Exception):
    """Base class: a message for the user and the exit code it maps to."""

    exit_code = EXIT_INPUT


class InputError(FlexbedError):
    """Bad input: a scene entry, an option, or a file that cannot be used."""

    exit_code = EXIT_INPUT


class NumericalError(FlexbedError):
    """A computation that did not succeed (no equilibrium, solver failure)."""

    exit_code = EXIT_NUMERICAL


class FlexbedWarning(UserWarning):
    """Input that is accepted but probably not meant (e.g. a mount point far
    from its body); the command line prints it as one line on stderr."""


#: what to do, per errno, after a failed write
ADVICE = {
    errno.ENOSPC: "the device is full: free some space or write elsewhere",
    errno.EFBIG: "the file would exceed the size allowed (a file size limit, ulimit -f, or "
                 "the file system's): write elsewhere or raise the limit",
    errno.EDQUOT: "the disk quota is used up: free some space or write elsewhere",
    errno.EACCES: "permission denied: choose a folder you may write in",
    errno.EPERM: "operation not permitted: choose a folder you may write in",
    errno.EROFS: "the file system is read-only: choose another folder",
}


def os_error_text(exc: OSError) -> str:
    """The reason of an OSError in words, with what to do when known."""
    reason = exc.strerror or str(exc) or type(exc).__name__
    advice = ADVICE.get(exc.errno)
    return f"{reason}; {advice}" if advice else reason


def one_line(exc: BaseException) -> str:
    """An exception as one line: a FlexbedError's own message (its first
    line), anything else as ``Type: first line`` (a study point's failure,
    a benchmark section's)."""
    text = str(exc).strip().splitlines()
    if isinstance(exc, FlexbedError):
        return text[0] if text else type(exc).__name__
    return f"{type(exc).__name__}: {text[0]}" if text else type(exc).__name__
