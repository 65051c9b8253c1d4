"""The ``unified-manip`` command line: ``main`` parses and dispatches, ``runs`` holds the
experiment subcommands (train, eval, bench, report, plot), ``args`` the shared argument
types and ``demo`` the picture strip of every task. The top layer: nothing imports it."""

from unified_manip.cli.main import main

__all__ = ["main"]
