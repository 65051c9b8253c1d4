"""Lint, format and types, as users of a typed library expect: ruff over the package,
the task families and the tests; mypy over the env library (configured in pyproject.toml)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
SOURCES = ["."]  # the whole repository, as a contributor runs it (results/ and the docs' Markdown excluded)


def _run(*command: str) -> subprocess.CompletedProcess:
    return subprocess.run(command, capture_output=True, text=True, cwd=ROOT, timeout=600)


def test_ruff_check_passes():
    proc = _run(str(BIN / "ruff"), "check", *SOURCES)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_ruff_format_leaves_every_file_as_it_is():
    proc = _run(str(BIN / "ruff"), "format", "--check", *SOURCES)
    assert proc.returncode == 0, proc.stdout + proc.stderr


@pytest.mark.slow
def test_the_env_library_type_checks():
    proc = _run(str(BIN / "mypy"))
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "Success: no issues found" in proc.stdout
