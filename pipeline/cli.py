"""The ``flexbed`` command: ``main(argv)`` builds the subcommands;
:func:`script` is the program itself (the console script).

Every subcommand lives in its own module ``flexbed.commands.<name>`` with
``add_args(parser)`` and ``run(args) -> int``. Failures the user can act on
come up as :class:`flexbed.errors.FlexbedError` and leave as one line on
stderr and an exit code: 0 success, 1 numerical failure, 2 bad input, 3 a
verdict of FAIL (``flexbed qualify``), 130
interrupted by SIGINT (Ctrl-C), 143 by SIGTERM (both keep what was computed,
marked incomplete: :mod:`flexbed.interrupts`), 141 output pipe closed
(``flexbed post … | head``: the reader stopped; nothing is printed, as
``yes | head`` does).

Start-up stays light: only the module of the command given is imported
(and through it NumPy, SciPy, numba, h5py, matplotlib as that command
needs them); ``flexbed --help`` lists every command from :data:`COMMANDS`
without importing any of them, and ``--version`` reads the installed
distribution's metadata.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

from flexbed.console import run_command
from flexbed.errors import EXIT_INPUT, FlexbedError
from flexbed.interrupts import exit_code, handlers, message, take_interrupt, was_interrupted
from flexbed.threads import limited, pin_environment

#: status of a run whose output pipe was closed by its reader (128 + SIGPIPE,
#: what the shell reports for a program that SIGPIPE ends)
EXIT_PIPE = 141
#: status of a run stopped by Ctrl-C (128 + SIGINT); SIGTERM gives 143
EXIT_INTERRUPT = 130
#: status of a run stopped by SIGTERM (128 + SIGTERM)
EXIT_TERMINATED = 143

COMMANDS = {
    "scene": "print the built-in reference scene as TOML",
    "modes": "free-free modes and invariants of the bed -> modes file",
    "static": "static equilibrium (paper Table 2) -> equilibrium file",
    "modal": "mounted-system modes, energy table, effective masses",
    "frf": "transmissibility to points, mounts and the base",
    "random": "random vibration from base acceleration PSDs: RMS, 3 sigma",
    "simulate": "time integration of the mount system -> results file",
    "compare": "rigid vs flexible vs damped flexible bed -> tables and plots",
    "post": "points of interest and mount forces from a results file",
    "stress": "stresses in a flexible bed over a run, peaks, map, XDMF",
    "transmitted": "force into the base: spectra, third-octaves, insertion loss",
    "srs": "shock response spectra of points from a results file",
    "qualify": "shock verdict against the scene's limits (exit 3: FAIL)",
    "rsa": "response-spectrum analysis against a design spectrum file",
    "synthesise": "a base acceleration matching a design spectrum -> curve data",
    "run": "the whole pipeline on one scene, into one folder",
    "bench": "benchmarks: speed against error, written as a report",
    "sweep": "a design study of many variants on Dask -> one table and plots",
    "optimize": "mount layout optimisation on Dask -> optimum scene and log",
}


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as exit code 2 (bad input), in one
    line (the usage is in ``--help``)."""

    def error(self, message: str):  # pragma: no cover - argparse's own path
        self.exit(EXIT_INPUT, f"{self.prog}: {message} (see '{self.prog} --help')\n")


class _Version(argparse.Action):
    """``--version``: the installed distribution's version, looked up only when asked."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS,
                 help="print the version and exit"):
        super().__init__(option_strings=option_strings, dest=dest, default=default, nargs=0,
                         help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        from importlib import metadata
        try:
            version = metadata.version("flexbed")
        except metadata.PackageNotFoundError:      # running from a source tree
            version = "0+unknown"
        print(f"flexbed {version}")
        parser.exit()


def chosen_command(argv: list[str]) -> str | None:
    """The subcommand named in ``argv`` (its first word that is not an
    option), or None."""
    for word in argv:
        if not word.startswith("-"):
            return word if word in COMMANDS else None
    return None


def build_parser(commands=None) -> argparse.ArgumentParser:
    """The argument parser.

    Parameters
    ----------
    commands : iterable of str, optional
        The subcommands whose options are added (their modules imported);
        the others are listed with their summary only. Default: all.
    """
    full = set(COMMANDS if commands is None else commands)
    parser = _Parser(prog="flexbed", description="Mount systems with flexible common beds "
                     "(Lee, Kim & Jeong 1999): bed modes, statics, dynamics, post-processing.")
    parser.add_argument("--version", action=_Version)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, summary in COMMANDS.items():
        p = sub.add_parser(name, help=summary, description=summary)
        if name in full:
            importlib.import_module(f"flexbed.commands.{name}").add_args(p)
    return parser


def _silence_stdout() -> None:
    """Point stdout at the null device, so that the interpreter's final
    flush of a closed pipe does not fail again at exit."""
    try:
        sys.stdout.flush()
    except (BrokenPipeError, ValueError):
        pass
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # replaced by a test's capture
        return
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, fd)
    os.close(null)


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    argv = sys.argv[1:] if argv is None else list(argv)
    with handlers():                # SIGINT and SIGTERM raise flexbed.interrupts.Interrupted
        try:
            return _main(argv)
        except Exception:
            # an error that followed an interrupt (one lost in a finalizer or
            # a callback, or one some code turned into an error of its own,
            # as numba's compiler and NumPy's import can): the interrupt is
            # what happened
            try:
                interrupt = take_interrupt()
            except KeyboardInterrupt as exc:        # its timer fired here
                interrupt = exc
            if interrupt is None:
                raise
            print(message(interrupt, chosen_command(argv)), file=sys.stderr)
            return exit_code(interrupt)


def _main(argv: list[str]) -> int:
    pin_environment()
    command = chosen_command(argv)
    try:
        parser = build_parser([command] if command else [])
        args = parser.parse_args(argv)
        if not args.command:
            parser.print_help()
            return EXIT_INPUT
        module = importlib.import_module(f"flexbed.commands.{args.command}")
        try:
            with limited():
                code = run_command(module, args)
        except FlexbedError as exc:
            if was_interrupted():      # reported as the interrupt it followed, by main()
                raise
            print(f"flexbed {args.command}: {exc}", file=sys.stderr)
            return exc.exit_code
        sys.stdout.flush()
        return code
    except KeyboardInterrupt as exc:
        print(message(exc, command), file=sys.stderr)
        return exit_code(exc)
    except BrokenPipeError:
        _silence_stdout()
        return EXIT_PIPE


def script() -> None:
    """The ``flexbed`` program: :func:`main` on ``sys.argv``, then the
    process ends with its exit code.

    After an interrupt (130, 143) the process ends at once, its standard
    streams flushed (``os._exit``), without the interpreter's finalizers:
    the signal may have cut numba's compiler between an LLVM object's
    release and its record of it, and a finalizer would then free it a
    second time (a segfault, status -11, where 130 or 143 was due; seen
    once in CI, a Ctrl-C during a first run's compilation). What an
    interrupted run keeps is written and closed before :func:`main`
    returns.
    """
    code = main()
    if code in (EXIT_INTERRUPT, EXIT_TERMINATED):
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError, AttributeError):
                pass
        os._exit(code)
    sys.exit(code)


if __name__ == "__main__":  # pragma: no cover
    script()
