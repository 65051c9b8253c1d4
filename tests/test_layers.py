"""The package's architecture as a contract: layers import only downwards, and no two
sibling modules import each other (import-linter, configured in pyproject.toml); the
measurement tools (benchmarks/) stay outside it."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_layers_import_only_downwards_and_nothing_is_circular():
    proc = subprocess.run(
        [str(Path(sys.executable).parent / "lint-imports"), "--config", str(ROOT / "pyproject.toml")],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "Layers: cli > experiments > training > datasets > envs KEPT" in proc.stdout
    assert "No import cycles between sibling modules KEPT" in proc.stdout
    assert "0 broken" in proc.stdout


def test_the_env_library_loads_no_training_code():
    # unified_manip.extras is the table of extras (standard library only): the registry
    # reads it to name a family's missing extra.
    code = (
        "import sys, gymnasium as gym, unified_manip\n"
        "env = gym.make('UnifiedManip/Arm4PickAndPlace-v0', action_mode='ee_delta')\n"
        "env.reset(seed=0); env.step(env.action_space.sample())\n"
        "print(sorted(m for m in sys.modules if m.startswith('unified_manip.')"
        " and not m.startswith('unified_manip.envs') and m != 'unified_manip.extras'))"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"


def test_nothing_in_the_package_imports_the_measurement_tools():
    """benchmarks/ is not installed: an import of it from the package would fail in a wheel."""
    importers = []
    for path in sorted((ROOT / "unified_manip").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else []
            if isinstance(node, ast.ImportFrom) and node.level == 0:
                names = [node.module or ""]
            if any(n == "benchmarks" or n.startswith("benchmarks.") for n in names):
                importers.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert importers == []
    assert not (ROOT / "unified_manip" / "tools").exists()
