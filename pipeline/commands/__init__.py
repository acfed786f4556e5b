"""The command line's subcommands, one module each (``flexbed NAME`` runs
:mod:`flexbed.commands.NAME`, loaded by :mod:`flexbed.cli` only when named):
``add_args(parser)`` declares its options, ``run(args)`` does the work and
returns the exit code; :mod:`~flexbed.commands.arguments` holds the
arguments several share.

A command reads its inputs, calls the stages and analyses, prints and
writes files. It may import every other room (files, stages, analyses,
plots, bench, study); the heavy ones (plots, bench, study and with them
matplotlib and Dask) only where the command needs them, so that
``flexbed --help``, ``scene`` and ``simulate`` start light
(tests/test_cli_startup.py). Nothing imports this package but the
command line.
"""
