"""Families from other packages: the ``unified_manip.families`` entry-point group.

Each test installs a plugin the way pip would leave it (a module and a ``.dist-info``
folder with ``entry_points.txt``) in a temporary folder on ``PYTHONPATH``, and runs a fresh
interpreter, since the group is read once, at ``import unified_manip``.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import gymnasium as gym

import unified_manip
from unified_manip.envs import tasks


def _install(site: Path, package: str, module: str, source: str) -> None:
    (site / f"{module}.py").write_text(source)
    info = site / f"{package.replace('-', '_')}-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {package}\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(f"[unified_manip.families]\n{module} = {module}\n")


def _run(site: Path, code: str, *argv: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), *sys.path])}
    cmd = [sys.executable, "-c", code, *argv] if code else list(argv)
    return subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)


# A plugin family: the arm's reach task under another name (its own backend would do too).
PLUGIN = """
from dataclasses import replace
from unified_manip.envs.registry import TASKS
SPECS = (replace(TASKS["UnifiedManip/Arm4Reach-v0"], name="PluginReach", family="plugin"),)
"""


def test_a_plugin_family_registers_its_ids_and_they_make_and_step(tmp_path):
    _install(tmp_path, "unified-manip-plugin", "um_plugin", PLUGIN)
    out = _run(
        tmp_path,
        "import gymnasium as gym, unified_manip\n"
        "from unified_manip.envs import tasks\n"
        "env = gym.make('UnifiedManip/PluginReach-v0', action_mode='ee_delta')\n"
        "obs, info = env.reset(seed=0)\n"
        "print(tasks.PLUGIN_IDS, len(unified_manip.TASKS), env.step(env.action_space.sample())[0]['observation'].shape)",
    )
    assert out.returncode == 0, out.stderr
    n, shape = (
        len(unified_manip.TASKS) + 1,
        gym.make("UnifiedManip/Arm4Reach-v0").observation_space["observation"].shape,
    )
    # Plugins register in the order of their packages' names: unified-manip-plugin before
    # the example family this process has (unified-manip-valve, which CI installs).
    ids = ("UnifiedManip/PluginReach-v0", *tasks.PLUGIN_IDS)
    assert out.stdout.split("\n")[0] == f"{ids} {n} {shape}"


def test_a_plugin_that_fails_to_import_is_named_with_its_error_and_the_rest_load(tmp_path):
    _install(tmp_path, "unified-manip-broken", "um_broken", "import not_a_module_anywhere\n")
    out = _run(
        tmp_path,
        "import warnings\n"
        "warnings.simplefilter('error')\n"
        "try:\n"
        "    import unified_manip\n"
        "except Warning as w:\n"
        "    print(type(w).__name__, w)\n",
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout == (
        "FamilyPluginWarning the family plugin 'um_broken' of package 'unified-manip-broken' failed to load: "
        "ModuleNotFoundError: No module named 'not_a_module_anywhere'\n"
    )
    # The CLI names it in the one line of an unknown ID, exit 2, no traceback.
    cli = _run(
        tmp_path, "", sys.executable, "-W", "ignore", "-m", "unified_manip.cli", "list", "--doc", "UnifiedManip/X-v0"
    )
    assert cli.returncode == 2
    assert len(cli.stderr.strip().splitlines()) == 1, cli.stderr
    assert cli.stderr.rstrip().endswith(
        "the family plugin 'um_broken' of package 'unified-manip-broken' failed to load: "
        "ModuleNotFoundError: No module named 'not_a_module_anywhere'"
    )
    assert "UnifiedManip/Arm4Reach-v0" in cli.stderr  # the built-in families loaded


def test_a_plugin_whose_specs_clash_registers_nothing(tmp_path):
    clash = PLUGIN.replace('name="PluginReach", ', "") + "SPECS = (SPECS[0], SPECS[0])\n"
    _install(tmp_path, "unified-manip-clash", "um_clash", clash)
    out = _run(tmp_path, "import warnings, unified_manip\nprint(len(unified_manip.TASKS))")
    assert out.returncode == 0, out.stderr
    assert out.stdout == f"{len(unified_manip.TASKS)}\n"
    assert "the family plugin 'um_clash' of package 'unified-manip-clash' failed to load: ValueError: " in out.stderr
