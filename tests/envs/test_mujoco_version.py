"""An unsupported MuJoCo is refused in one line naming the supported range, before any
simulator code runs, instead of an upstream traceback mid-step."""

from __future__ import annotations

import os
import subprocess
import tomllib
from importlib.metadata import version
from pathlib import Path

import pytest
from conftest import overlay_venv

from unified_manip.envs.mujoco_version import SUPPORTED, UnsupportedMuJoCo, check_mujoco, supported

ROOT = Path(__file__).resolve().parents[2]


def message(found: str) -> str:
    return (
        f"mujoco {found} is installed, but unified_manip supports mujoco>=3.3.0,<3.10 "
        '(the families\' upstreams break on 3.10 and later): pip install "mujoco>=3.3.0,<3.10"'
    )


def test_the_range_is_the_one_pyproject_requires():
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    assert f"mujoco{SUPPORTED}" in deps


@pytest.mark.parametrize(
    "found, ok",
    [
        ("3.3.0", True),
        ("3.3.7", True),
        ("3.9.0", True),
        ("3.9", True),
        ("3.2.7", False),
        ("3.10.0", False),
        ("3.12.0.dev1", False),
        ("4.0.1", False),
        ("2.3.7", False),
        ("unknown", False),
    ],
)
def test_versions_in_and_out_of_the_range(found, ok):
    assert supported(found) is ok
    if ok:
        check_mujoco(found)
    else:
        with pytest.raises(UnsupportedMuJoCo) as err:
            check_mujoco(found)
        assert str(err.value) == message(found)


def test_the_running_mujoco_is_supported():
    check_mujoco()  # the installed one (CI tests both ends of the range)
    assert supported(version("mujoco"))


@pytest.mark.slow
def test_an_installed_mujoco_3_10_is_refused_in_one_line(tmp_path):
    """A venv whose own mujoco is 3.10.0 (installed over this venv's packages, seen through
    a .pth line): gym.make and the CLI say which range is supported, before any backend
    is built."""
    python = overlay_venv(tmp_path / "venv", "mujoco==3.10.0")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    code = (
        "import gymnasium as gym, unified_manip\n"
        "from importlib.metadata import version\n"
        "from unified_manip.envs.mujoco_version import UnsupportedMuJoCo\n"
        "print(version('mujoco'))\n"
        "try:\n"
        "    gym.make('UnifiedManip/Arm4Reach-v0')\n"
        "except UnsupportedMuJoCo as err:\n"
        "    print(err)\n"
    )
    proc = subprocess.run([python, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert proc.stdout.splitlines() == ["3.10.0", message("3.10.0")], proc.stderr
    cli = subprocess.run(
        [
            python,
            "-m",
            "unified_manip.cli",
            "demo",
            "--env",
            "UnifiedManip/Arm4Reach-v0",
            "--out",
            str(tmp_path / "d.png"),
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert (cli.returncode, cli.stderr) == (2, f"unified-manip demo: error: {message('3.10.0')}\n")
    assert not (tmp_path / "d.png").exists()
