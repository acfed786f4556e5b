"""Errors the command line turns into one clear line and an exit code.

Exit codes shared by every subcommand: 0 success, 1 numerical failure,
2 bad input (scene, options or files).
"""

EXIT_OK = 0
EXIT_NUMERICAL = 1
EXIT_INPUT = 2


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
