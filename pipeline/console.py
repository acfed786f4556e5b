"""How a command's failures and warnings reach the terminal: one line each.

:func:`run_command` runs a subcommand's ``run(args)`` so that

- a :class:`~flexbed.errors.FlexbedWarning` is printed as one line,
  ``flexbed COMMAND: warning: …``, each distinct message once;
- NumPy's floating-point ``RuntimeWarning`` lines (overflow, invalid value,
  division by zero) are not printed: they are recorded, and when the
  command then fails with a :class:`~flexbed.errors.NumericalError`, its
  one line names the first of them as the cause (the code that meets a
  non-finite value names the body, the entry or the dataset);
- an ``OSError`` that no reader or writer turned into a message (standard
  output on a full device or a closed terminal) becomes an
  :class:`~flexbed.errors.InputError` naming what could not be written.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings
from types import ModuleType

from flexbed.errors import (FlexbedError, FlexbedWarning, InputError, NumericalError,
                            os_error_text)

__all__ = ["run_command"]

def run_command(module: ModuleType, args: argparse.Namespace) -> int:
    """``module.run(args)`` with the rules of the module docstring; returns
    its exit code, raises FlexbedError for the command line to print."""
    shown: set[str] = set()
    numeric: list[str] = []

    def show(message, category, filename, lineno, file=None, line=None):
        text = str(message)
        if issubclass(category, FlexbedWarning):
            if text not in shown:
                shown.add(text)
                print(f"flexbed {args.command}: warning: {text}", file=sys.stderr)
        elif issubclass(category, RuntimeWarning):
            numeric.append(text)
        else:                                       # another library's warning: one line
            first = text.splitlines()[0] if text else category.__name__
            if first not in shown:
                shown.add(first)
                print(f"flexbed {args.command}: warning: {first}", file=sys.stderr)

    stdout = sys.stdout
    watched = sys.stdout = _Watched(stdout)
    with warnings.catch_warnings():
        warnings.simplefilter("always", RuntimeWarning)
        warnings.showwarning = show
        try:
            code = int(module.run(args) or 0)
            sys.stdout.flush()
            return code
        except NumericalError as exc:
            if numeric and "overflow" not in str(exc) and "not finite" not in str(exc):
                raise NumericalError(f"{exc} (after a floating-point error: {numeric[0]})") \
                    from None
            raise
        except FlexbedError:
            raise
        except (BrokenPipeError, KeyboardInterrupt):
            raise
        except RecursionError:
            raise InputError("input nested too deeply to read (RecursionError)") from None
        except MemoryError:
            raise NumericalError("out of memory") from None
        except OSError as exc:
            if exc.filename:
                raise InputError(f"{exc.filename}: {os_error_text(exc)}") from None
            if watched.failed:
                _silence(stdout)
                raise InputError(f"cannot write to standard output ({os_error_text(exc)})") \
                    from None
            raise InputError(os_error_text(exc)) from None
        finally:
            sys.stdout = stdout


class _Watched:
    """Standard output, noting whether a write or flush to it failed."""

    def __init__(self, stream):
        self._stream = stream
        self.failed = False

    def write(self, text):
        try:
            return self._stream.write(text)
        except OSError:
            self.failed = True
            raise

    def flush(self):
        try:
            return self._stream.flush()
        except OSError:
            self.failed = True
            raise

    def __getattr__(self, name):
        return getattr(self._stream, name)


def _silence(stream) -> None:
    """Point a failed standard output at the null device, so that the
    interpreter's last flush at exit does not fail (and print) again."""
    try:
        fd = stream.fileno()
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, fd)
        os.close(null)
    except (AttributeError, OSError, ValueError):
        pass
