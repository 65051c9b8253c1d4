"""Repository hygiene: CI runs the README's commands; nothing skips silently."""

from __future__ import annotations

import os
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _readme_block(title: str) -> str:
    text = (ROOT / "README.md").read_text()
    section = text.split(f"## {title}", 1)[1]
    return re.search(r"```(?:bash|sh)?\n(.*?)```", section, re.S).group(1)


def test_ci_runs_the_readme_test_commands():
    commands = [line.strip() for line in _readme_block("Test").splitlines() if "pytest" in line]
    ci = [line.strip() for line in (ROOT / ".ci" / "run").read_text().splitlines()]
    assert len(commands) == 2  # the full stack, and the base install without robosuite
    # Then robosuite added to the base install through uv's override (docs/install.md).
    assert [c for c in ci if c.startswith("python -m pytest")][:2] == commands
    assert 'uv pip install -q -e ".[robosuite]" mujoco==3.3.0' in ci
    # ... and then at the top of the range, where uv resolves mink 1.x: mink's modes' golden rollouts.
    top = next(i for i, line in enumerate(ci) if line.startswith('uv pip install -q -e ".[robosuite]" mujoco==3.9.0'))
    assert {'python tests/envs/golden.py --only "|ee_delta|sparse"', 'wait "$target"'} <= set(ci[top:])
    assert (
        '-m "(golden or metaworld or not slow) and not robosuite" tests/envs tests/datasets tests/training'
        in commands[1]
    )
    # The docs' testing page gives the same two commands.
    page = (ROOT / "docs" / "reference" / "testing.md").read_text()
    block = re.search(r"```bash\n(.*?)```", page, re.S).group(1)
    assert [line.strip() for line in block.splitlines() if "pytest" in line] == commands
    # The tests' own processes reuse the bytecode they compile: the installs skip compiling.
    first_install = next(i for i, line in enumerate(ci) if line.startswith("pip install"))
    assert "unset PYTHONDONTWRITEBYTECODE" in ci[:first_install]


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

    code = (
        "import gymnasium as gym, unified_manip; [gym.make(t) for t, s in unified_manip.TASKS.items() if s.installed]"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == "" and proc.stderr == ""


def test_the_readme_test_command_keeps_xdist_groups_on_one_worker(tmp_path):
    """The suite relies on ``--dist loadgroup`` (shared per-case envs, the golden children);
    with pytest 9.2 and pytest-xdist 3.8 the groups were silently spread over both
    workers (pytest-xdist #1386). Two groups of ten tests: each must run on one worker."""
    import subprocess
    import sys

    (tmp_path / "test_groups.py").write_text(
        "import pytest\n\n"
        "CASES = [pytest.param(i, marks=pytest.mark.xdist_group(f'g{i % 2}')) for i in range(20)]\n\n"
        "@pytest.mark.parametrize('i', CASES)\n"
        "def test_member(i):\n"
        "    pass\n"
    )
    (tmp_path / "pytest.ini").write_text("[pytest]\n")  # this directory is the rootdir, not the project's
    cmd = [sys.executable, "-m", "pytest", "-n", "2", "--dist", "loadgroup", "-v", "-p", "no:cacheprovider"]
    proc = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout[-2000:]
    ran = re.findall(r"\[(gw\d)\].*test_member\[(\d+)\]", proc.stdout)
    assert len(ran) == 20, proc.stdout[-2000:]
    workers = {g: {w for w, i in ran if int(i) % 2 == g} for g in (0, 1)}
    assert all(len(w) == 1 for w in workers.values()), f"groups spread over workers: {workers}"


def test_a_local_ray_test_runs_again_only_when_rays_node_did_not_start(tmp_path):
    """``LOCAL_RAY`` (tests/conftest.py) gives a test one more try when Ray's own node start
    timed out, under the README's command; any other failure fails on its first try."""
    import subprocess
    import sys

    (tmp_path / "test_retry.py").write_text(
        "from pathlib import Path\n\n"
        "import pytest\n"
        "from conftest import LOCAL_RAY, RAY_NODE_TIMEOUT\n\n"
        "MESSAGES = {'ray': 'Ray did not start on this machine: ' + RAY_NODE_TIMEOUT + '. This could happen',\n"
        "            'other': 'the run did not finish'}\n\n"
        "@pytest.mark.parametrize('case', [pytest.param(c, marks=LOCAL_RAY) for c in MESSAGES])\n"
        "def test_fails_once(case):\n"
        "    tries = Path(f'tries-{case}')\n"
        "    tries.write_text((tries.read_text() if tries.exists() else '') + 'x')\n"
        "    assert len(tries.read_text()) > 1, MESSAGES[case]\n"
    )
    (tmp_path / "pytest.ini").write_text("[pytest]\n")  # this directory is the rootdir, not the project's
    cmd = [sys.executable, "-m", "pytest", "-n", "2", "--dist", "loadgroup", "-p", "no:cacheprovider"]
    env = {**os.environ, "PYTHONPATH": str(ROOT / "tests")}  # LOCAL_RAY, imported as a module
    proc = subprocess.run(cmd, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1, proc.stdout[-2000:]
    assert "1 failed, 1 passed, 1 rerun" in proc.stdout, proc.stdout[-2000:]
    assert (tmp_path / "tries-ray").read_text() == "xx" and (tmp_path / "tries-other").read_text() == "x"
