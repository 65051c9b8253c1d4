"""The package as users get it: a wheel that works outside the checkout, and an import
that registers every ID without loading any simulator."""

from __future__ import annotations

import json
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from wheel_install import build_wheel, no_checkout_env, wheel_venv

import unified_manip

ROOT = Path(__file__).resolve().parents[1]
#: Third-party packages that ``import unified_manip`` must not import.
HEAVY = ("mujoco", "robosuite", "metaworld", "gymnasium_robotics", "torch", "mink", "stable_baselines3")


def _python(code: str, cwd: Path | None = None, python: str = sys.executable) -> str:
    env = no_checkout_env()
    proc = subprocess.run([python, "-c", code], capture_output=True, text=True, cwd=cwd, env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


def test_every_package_is_listed_in_pyproject():
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    found = {"unified_manip.baselines"}  # data only: no __init__.py
    for top, name in ((ROOT / "unified_manip", "unified_manip"),):
        for init in top.rglob("__init__.py"):
            rel = init.parent.relative_to(top).parts
            found.add(".".join((name, *rel)))
    assert sorted(found - listed) == [], "add these packages to [tool.setuptools] packages in pyproject.toml"
    assert sorted(listed - found) == []


def test_import_registers_every_id_without_loading_a_simulator():
    out = _python(
        f"import sys, unified_manip\nprint(len(unified_manip.TASKS), [m for m in {HEAVY!r} if m in sys.modules])"
    )
    assert out.split(maxsplit=1) == [str(len(unified_manip.TASKS)), "[]\n"]


@pytest.mark.robosuite
def test_make_loads_only_its_family_simulator():
    code = (
        "import sys, gymnasium as gym, unified_manip\n"
        "gym.make('UnifiedManip/Arm4Reach-v0', action_mode='ee_delta')\n"
        "print(sorted(m for m in ('robosuite', 'torch', 'stable_baselines3') if m in sys.modules))\n"
        "gym.make('UnifiedManip/Lift-v0')\n"
        "print('robosuite' in sys.modules)"
    )
    assert _python(code).splitlines() == ["[]", "True"]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """The wheel built from the working tree's sources, once for this module's tests."""
    return build_wheel(tmp_path_factory.mktemp("wheel"))


@pytest.mark.slow
@pytest.mark.xdist_group("wheel")  # one worker builds the wheel for both
def test_wheel_installs_into_a_fresh_venv_and_trains_outside_the_checkout(wheel, tmp_path):
    venv, work = tmp_path / "venv", tmp_path / "work"
    work.mkdir()
    python = wheel_venv(wheel, venv)
    site = _python("import sysconfig; print(sysconfig.get_paths()['purelib'])", python=python).strip()
    where = _python(
        "import unified_manip, unified_manip.training.hyperparams as h; print(unified_manip.__file__); "
        "print(h.DEFAULT_DIR)",
        cwd=work,
        python=python,
    ).splitlines()
    assert all(line.startswith(site) for line in where), where
    env = no_checkout_env()
    proc = subprocess.run(
        [
            str(venv / "bin" / "unified-manip"),
            "train",
            "--env",
            "UnifiedManip/Arm4Reach-v0",
            "--algo",
            "sac_her",
            "--action-mode",
            "ee_delta",
            "--steps",
            "200",
            "--set",
            "learning_starts=100",
            "--set",
            "buffer_size=1000",
            "--run-dir",
            "run",
            "--no-progress",
            "--device",
            "cpu",
        ],
        cwd=work,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    status = json.loads((work / "run" / "status.json").read_text())
    assert status["state"] == "finished" and status["num_timesteps"] == 200


@pytest.mark.slow
@pytest.mark.xdist_group("wheel")
def test_the_base_install_is_the_env_library_alone(wheel, tmp_path):
    """``pip install unified_manip`` with no extras: numpy 2, every ID but robosuite's steps,
    robosuite, torch, SB3 and Ray are absent, and a command or ID that needs an extra says
    which in one line."""
    venv, work = tmp_path / "venv", tmp_path / "work"
    work.mkdir()
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=120)
    python = str(venv / "bin" / "python")
    proc = subprocess.run(
        [python, "-m", "pip", "--disable-pip-version-check", "-q", "install", "--no-compile", str(wheel)],
        capture_output=True,
        text=True,
        timeout=900,
        env=no_checkout_env(),  # a checkout on PYTHONPATH with build metadata reads as installed to pip
    )
    assert proc.returncode == 0, proc.stderr
    code = (
        "import importlib.util, gymnasium as gym, numpy, unified_manip\n"
        "print(numpy.__version__.split('.')[0])\n"
        "print([m for m in ('robosuite', 'torch', 'stable_baselines3', 'ray', 'rliable', 'pandas', 'rl_zoo3')"
        " if importlib.util.find_spec(m)])\n"
        "for tid, spec in unified_manip.TASKS.items():\n"
        "    if spec.extra is None:\n"
        "        env = gym.make(tid)\n"
        "        env.reset(seed=0)\n"
        "        env.step(env.action_space.sample())\n"
        "        env.close()\n"
        "print(sorted({spec.family for spec in unified_manip.TASKS.values() if spec.installed}))"
    )
    assert _python(code, cwd=work, python=python).splitlines() == [
        "2",
        "[]",
        "['adroit', 'arm4', 'fetch', 'kitchen', 'shadow_hand']",
    ]
    env = no_checkout_env()
    train = subprocess.run(
        [
            str(venv / "bin" / "unified-manip"),
            "train",
            "--env",
            "UnifiedManip/Arm4Reach-v0",
            "--algo",
            "sac_her",
            "--steps",
            "10",
        ],
        capture_output=True,
        text=True,
        cwd=work,
        env=env,
        timeout=300,
    )
    assert train.returncode == 2
    assert train.stderr == (
        "unified-manip train: error: unified-manip train needs the train extra: "
        'pip install "unified_manip[train]" (missing: torch, stable_baselines3, sb3_contrib, tensorboard)\n'
    )
    demo = subprocess.run(
        [str(venv / "bin" / "unified-manip"), "demo", "--env", "UnifiedManip/Lift-v0", "--no-progress"],
        capture_output=True,
        text=True,
        cwd=work,
        env=env,
        timeout=300,
    )
    assert (demo.returncode, demo.stderr) == (
        2,
        "unified-manip demo: error: UnifiedManip/Lift-v0 needs the robosuite extra: "
        'pip install "unified_manip[robosuite]" (missing: robosuite, h5py)\n',
    )
    listed = subprocess.run(
        [str(venv / "bin" / "unified-manip"), "list"], capture_output=True, text=True, cwd=work, env=env, timeout=300
    )
    assert listed.returncode == 0 and "UnifiedManip/Arm4Reach-v0" in listed.stdout
