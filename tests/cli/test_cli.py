"""The ``unified-manip`` command line, run as a user would: in a subprocess."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import gymnasium as gym
import imageio.v3 as iio
import pytest
from conftest import cli_in_process

import unified_manip

ROOT = Path(__file__).resolve().parents[2]


def run(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    proc = cli_in_process(*args)
    if check and proc.returncode != 0:
        raise subprocess.CalledProcessError(proc.returncode, proc.args, proc.stdout, proc.stderr)
    return proc


def test_list_shows_every_id_with_modes_rewards_goal_dim_and_length():
    out = run("list", "--width", "320").stdout  # wide enough that no cell wraps
    for tid, spec in unified_manip.TASKS.items():
        row = next(line for line in out.splitlines() if tid in line)
        cells = [c.strip() for c in re.split(r"[│|]", row) if c.strip()]
        assert cells[1] == spec.family
        assert cells[2] == ", ".join(spec.action_modes)
        assert cells[3] == "sparse, dense, dense_penalized"
        assert cells[4] == str(spec.goal_dim)
        assert cells[5] == str(spec.max_episode_steps)


def test_every_help_reads_as_plain_text():
    """No reST markup (double backquotes, :class: roles) leaks into a --help page."""
    commands = re.search(r"\{([a-z,]+)\}", run("--help").stdout).group(1).split(",")
    assert {"train", "collect", "convert"} <= set(commands)
    for args in [("--help",)] + [(c, "--help") for c in commands]:
        text = run(*args).stdout
        assert "``" not in text and not re.search(r":(class|func|mod|meth):", text), args


def test_every_option_of_every_subcommand_has_help():
    import argparse

    from unified_manip.cli.main import build_parser

    missing = []

    def walk(parser: argparse.ArgumentParser, path: list[str]) -> None:
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    walk(sub, [*path, name])
            elif not action.help and not isinstance(action, argparse._HelpAction):
                missing.append(" ".join([*path, *(action.option_strings or [action.dest])]))

    walk(build_parser(), ["unified-manip"])
    assert not missing, f"options without a help text: {missing}"


def test_list_doc_prints_the_task_documentation():
    out = run("list", "--doc", "UnifiedManip/Arm4PickAndPlace-v0").stdout
    assert "Observation (34,)" in out and "Success" in out


def test_bad_input_is_one_line_and_exit_code_2():
    proc = run("list", "--doc", "UnifiedManip/Nope-v0", check=False)
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1
    assert (
        "argument --doc: unknown task 'UnifiedManip/Nope-v0'; expected one of UnifiedManip/Arm4Reach-v0" in proc.stderr
    )
    proc = run("speed", "--steps", "0", check=False)
    assert proc.returncode == 2
    assert proc.stderr.strip().endswith("expected a positive integer, got '0'")
    proc = run("demo", "--env", "UnifiedManip/Nope-v0", check=False)
    assert proc.returncode == 2
    assert "unknown task 'UnifiedManip/Nope-v0'; expected one of UnifiedManip/Arm4Reach-v0" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_speed_reports_the_env_step_rate_of_each_mode(tmp_path):
    out = tmp_path / "speed.json"
    proc = run(
        "speed",
        "--env",
        "UnifiedManip/Arm4Reach-v0",
        "--modes",
        "joint_position,ee_delta",
        "--steps",
        "200",
        "--repeats",
        "1",
        "--json",
        str(out),
    )
    rows = json.loads(out.read_text())["modes"]
    assert [(r["task_id"], r["action_mode"]) for r in rows] == [
        ("UnifiedManip/Arm4Reach-v0", "joint_position"),
        ("UnifiedManip/Arm4Reach-v0", "ee_delta"),
    ]
    assert all(r["env_steps_per_s"] > 0 for r in rows)
    # The table shows each rate, and each mode's against joint_position's.
    ratio = rows[1]["env_steps_per_s"] / rows[0]["env_steps_per_s"]
    assert f"{rows[1]['env_steps_per_s']:,.0f}" in proc.stdout and f"{ratio:.2f}" in proc.stdout


@pytest.mark.slow
def test_demo_writes_a_picture_strip(tmp_path):
    out = tmp_path / "strip.png"
    proc = run("demo", "--out", str(out), "--frames", "3", "--size", "64", "--no-progress")
    assert "demo:" not in proc.stderr  # no progress bar, as train and bench with --no-progress
    image = iio.imread(out)
    ids = [t for t, s in unified_manip.TASKS.items() if s.scripted_policy and s.installed]  # the installed families'
    assert image.shape == (64 * len(ids), 64 * 3, 3)
    verdicts = [line.split(": ")[-1] for line in proc.stdout.splitlines() if line.startswith(tuple(ids))]
    assert len(verdicts) == len(ids) and set(verdicts) <= {"success", "failure"}
    # Each verdict is the episode's own (FetchSlide's policy often fails): replayed without
    # rendering for FetchSlide and the first ID of every family.
    families = {unified_manip.TASKS[t].family: t for t in reversed(ids)}
    for tid in {*families.values(), "UnifiedManip/FetchSlide-v0"}:
        verdict = "success" if _scripted_success(tid, seed=0) else "failure"
        assert f"{tid}: {verdict}" in proc.stdout.splitlines()
    assert "UnifiedManip/Arm4PickAndPlace-v0: success" in proc.stdout


def _scripted_success(task_id: str, seed: int) -> bool:
    """The demo's episode (seed, ee_delta, scripted policy), without rendering."""
    spec = unified_manip.TASKS[task_id]
    env = gym.make(task_id, action_mode="ee_delta")
    policy = spec.scripted_policy("ee_delta")
    obs, info = env.reset(seed=seed)
    for _ in range(spec.max_episode_steps):
        obs, _, terminated, truncated, info = env.step(policy(obs))
        if terminated or truncated:
            break
    env.close()
    return bool(info["is_success"])
