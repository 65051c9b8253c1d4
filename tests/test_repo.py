"""Repository hygiene: CI runs the README's commands; nothing skips silently."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _readme_block(title: str) -> str:
    text = (ROOT / "README.md").read_text()
    section = text.split(f"## {title}", 1)[1]
    return re.search(r"```(?:bash|sh)?\n(.*?)```", section, re.S).group(1)


def test_ci_runs_the_readme_test_command():
    command = [line for line in _readme_block("Test").splitlines() if "pytest" in line][0].strip()
    ci = (ROOT / ".ci" / "run").read_text()
    assert command in [line.strip() for line in ci.splitlines()]


def test_no_test_can_skip_on_a_missing_package():
    for path in (ROOT / "tests").rglob("*.py"):
        if path.name == Path(__file__).name:
            continue
        text = path.read_text()
        assert "importorskip" not in text and "pytest.skip(" not in text, path.name


def test_import_and_make_are_quiet():
    """A user of ``import unified_manip`` sees no third-party import chatter."""
    import subprocess
    import sys

    code = "import gymnasium as gym, unified_manip; [gym.make(t) for t in unified_manip.TASKS]"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == "" and proc.stderr == ""
