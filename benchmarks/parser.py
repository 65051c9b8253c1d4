"""The argument parser of the ``python -m benchmarks.<name>`` commands.

Like the ``unified-manip`` CLI's: an error is one line, exit status 2, and the help reads as
plain text (the module docstring's reST markup is dropped).
"""

from __future__ import annotations

import argparse
import re

_ROLE = re.compile(r":(?:class|func|mod|meth|attr|data):`~?([^`]+)`")


def plain(text: str) -> str:
    """``text`` without reST markup: a role keeps the last part of its target, double
    backquotes go."""
    return _ROLE.sub(lambda m: m.group(1).rsplit(".", 1)[-1], text).replace("``", "")


class ToolParser(argparse.ArgumentParser):
    """argparse for the tool ``module``, described by the first paragraph of ``doc``.

    Args:
        module: The module's dotted name (``benchmarks.soak``); the usage line
            names it as ``python -m`` runs it.
        doc: The module docstring.
    """

    def __init__(self, module: str, doc: str | None) -> None:
        first = " ".join((doc or "").split("\n\n")[0].split())
        super().__init__(prog=f"python -m {module}", description=plain(first))

    def format_help(self) -> str:  # noqa: D102
        return plain(super().format_help())

    def error(self, message: str) -> None:  # noqa: D102
        self.exit(2, f"{self.prog}: error: {message}\n")
