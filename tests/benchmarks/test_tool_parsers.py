"""Every ``python -m benchmarks.<name>`` command: a plain-text --help that names the
command as it is run, and a bad option refused in one line with exit status 2."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

import benchmarks
from benchmarks.parser import ToolParser

#: The tools whose command is built on :class:`ToolParser` (the two scripts run as
#: ``python benchmarks/<name>.py`` parse their options with argparse's own parser).
TOOLS = sorted(
    m.name
    for m in pkgutil.iter_modules(benchmarks.__path__)
    if m.name != "parser" and getattr(importlib.import_module(f"benchmarks.{m.name}"), "ToolParser", None) is ToolParser
)


def test_the_tools_with_a_command_are_found():
    assert {"conversion_table", "diagnose", "soak", "speed", "vector_bench"} <= set(TOOLS)


@pytest.mark.parametrize("name", TOOLS)
def test_help_is_plain_text_and_a_bad_option_one_line(name, capsys):
    main = importlib.import_module(f"benchmarks.{name}").main
    with pytest.raises(SystemExit) as done:
        main(["--help"])
    assert done.value.code == 0
    text = capsys.readouterr().out
    assert text.startswith(f"usage: python -m benchmarks.{name}")
    assert "``" not in text and ":class:" not in text and ":mod:" not in text

    with pytest.raises(SystemExit) as done:
        main(["--no-such-option"])
    assert done.value.code == 2
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"python -m benchmarks.{name}: error: ")
