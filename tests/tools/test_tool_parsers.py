"""Every ``python -m unified_manip.tools.<name>`` command: a plain-text --help that names the
command as it is run, and a bad option refused in one line with exit status 2."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

import unified_manip.tools

TOOLS = sorted(
    m.name
    for m in pkgutil.iter_modules(unified_manip.tools.__path__)
    if hasattr(importlib.import_module(f"unified_manip.tools.{m.name}"), "main")
)


def test_the_tools_with_a_command_are_found():
    assert {"conversion_table", "diagnose", "soak", "vector_bench"} <= set(TOOLS)


@pytest.mark.parametrize("name", TOOLS)
def test_help_is_plain_text_and_a_bad_option_one_line(name, capsys):
    main = importlib.import_module(f"unified_manip.tools.{name}").main
    with pytest.raises(SystemExit) as done:
        main(["--help"])
    assert done.value.code == 0
    text = capsys.readouterr().out
    assert text.startswith(f"usage: python -m unified_manip.tools.{name}")
    assert "``" not in text and ":class:" not in text and ":mod:" not in text

    with pytest.raises(SystemExit) as done:
        main(["--no-such-option"])
    assert done.value.code == 2
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"python -m unified_manip.tools.{name}: error: ")
