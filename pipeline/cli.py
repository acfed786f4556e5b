"""The ``flexbed`` command: ``main(argv)`` builds the subcommands.

Every subcommand lives in its own module ``flexbed.commands.<name>`` with
``add_args(parser)`` and ``run(args) -> int``. Failures the user can act on
come up as :class:`flexbed.errors.FlexbedError` and leave as one line on
stderr and an exit code: 0 success, 1 numerical failure, 2 bad input.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from flexbed.errors import EXIT_INPUT, FlexbedError
from flexbed.threads import limited, pin_environment
from flexbed.files.store import package_version

COMMANDS = {
    "scene": "print the built-in reference scene as TOML",
    "modes": "free-free modes and invariants of the bed -> modes file",
    "static": "static equilibrium (paper Table 2) -> equilibrium file",
    "simulate": "time integration of the mount system -> results file",
    "compare": "rigid vs flexible vs damped flexible bed -> tables and plots",
    "post": "points of interest and mount forces from a results file",
    "run": "the whole pipeline on one scene, into one folder",
    "bench": "benchmarks: speed against error, printed as tables",
}


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as exit code 2 (bad input)."""

    def error(self, message: str):  # pragma: no cover - argparse's own path
        self.print_usage(sys.stderr)
        self.exit(EXIT_INPUT, f"{self.prog}: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="flexbed", description="Mount systems with flexible common beds "
                     "(Lee, Kim & Jeong 1999): bed modes, statics, dynamics, post-processing.")
    parser.add_argument("--version", action="version", version=f"flexbed {package_version()}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, summary in COMMANDS.items():
        module = importlib.import_module(f"flexbed.commands.{name}")
        p = sub.add_parser(name, help=summary)
        module.add_args(p)
        p.set_defaults(_run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the exit code."""
    pin_environment()
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "_run", None):
        parser.print_help()
        return EXIT_INPUT
    try:
        with limited():
            return int(args._run(args) or 0)
    except FlexbedError as exc:
        print(f"flexbed {args.command}: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        print(f"flexbed {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
