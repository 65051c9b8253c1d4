"""The observation design as a benchmark axis: ``train --observation``, a grid's
``observations:``, run names, ``config.yaml`` and ``results.csv``; ``eval`` under
observation noise and delay. Default designs keep today's run names."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from test_bench import TINY, write_grid

from unified_manip.cli.main import main
from unified_manip.experiments.grid import GridError, load_grid
from unified_manip.experiments.results import collect_row
from unified_manip.training.request import TrainRequest

ROOT = Path(__file__).resolve().parents[2]
REACH = "UnifiedManip/Arm4Reach-v0"


def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "unified_manip.cli", *args], capture_output=True, text=True, timeout=600, cwd=ROOT
    )


@pytest.mark.parametrize(
    "env_kwargs,name",
    [
        ({}, "Arm4Reach-v0__ee_delta__sparse__sac_her__s3"),
        ({"observation": "default"}, "Arm4Reach-v0__ee_delta__sparse__sac_her__s3"),
        ({"observation": "minimal"}, "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-minimal__s3"),
        ({"observation": ["ee_pos", "goal_rel"]}, "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-ee_pos+goal_rel__s3"),
        ({"observation_distractors": 32}, "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-default+distractors32__s3"),
        (
            {"observation": "minimal", "observation_noise": 0.005, "observation_delay": 1},
            "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-minimal+noise0.005+delay1__s3",
        ),
        (
            {"observation_noise": {"ee_pos": 0.01, "goal_rel": 0.0}},
            "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-default+noise_ee_pos0.01__s3",
        ),
    ],
)
def test_run_names_carry_a_non_default_design(env_kwargs, name):
    req = TrainRequest(REACH, "ee_delta", "sparse", "sac_her", 100, seed=3, env_kwargs=env_kwargs)
    assert req.directory == Path("runs") / name


@pytest.mark.slow
def test_a_grid_crosses_observation_designs(tmp_path):
    distractors = {"observation": "default", "observation_distractors": 32}
    designs = ["default", "relative", ["ee_pos"], distractors]
    doc = {**TINY, "action_modes": ["ee_delta"], "seeds": [0], "observations": designs}
    grid = load_grid(write_grid(tmp_path, doc))
    assert [(r.name, r.env_kwargs) for r in grid.runs] == [
        ("Arm4Reach-v0__ee_delta__sparse__sac_her__s0", {}),
        ("Arm4Reach-v0__ee_delta__sparse__sac_her__obs-relative__s0", {"observation": "relative"}),
        ("Arm4Reach-v0__ee_delta__sparse__sac_her__obs-ee_pos__s0", {"observation": ["ee_pos"]}),
        ("Arm4Reach-v0__ee_delta__sparse__sac_her__obs-default+distractors32__s0", {"observation_distractors": 32}),
    ]


@pytest.mark.parametrize(
    "observations,message",
    [
        (
            ["minimal", ["object_pos"]],
            "observation group 'object_pos' is not available on UnifiedManip/Arm4Reach-v0; expected some of "
            "'joint_pos', 'gripper', 'joint_vel', 'gripper_vel', 'ee_pos', 'ee_vel', 'goal_rel'",
        ),
        (
            ["tiny"],
            "unknown observation preset 'tiny'; expected one of 'default', 'minimal', 'relative', 'full' or a list "
            "of groups of UnifiedManip/Arm4Reach-v0 ('joint_pos', 'gripper', 'joint_vel', 'gripper_vel', "
            "'ee_pos', 'ee_vel', 'goal_rel')",
        ),
        (
            "minimal",
            "observations must be a non-empty list of presets (default, minimal, relative, full), lists of group "
            "names or mappings with keys from observation, observation_distractors, observation_noise, "
            "observation_delay, got 'minimal'",
        ),
        (
            ["minimal", {"observation": "minimal", "observation_lag": 1}],
            "unknown key 'observation_lag' in observations; expected observation, observation_distractors, "
            "observation_noise, observation_delay",
        ),
        (
            ["minimal", ["minimal"]],
            "observation design 'minimal' is listed twice",
        ),
        (
            [{"observation": "default", "observation_distractors": -2}],
            "observation_distractors must be an int >= 0, got -2",
        ),
    ],
)
def test_a_grid_with_a_bad_design_fails_in_one_line(tmp_path, observations, message):
    path = write_grid(tmp_path, {**TINY, "observations": observations})
    with pytest.raises(GridError) as err:
        load_grid(path)
    assert str(err.value) == f"{path}: {message}"


@pytest.mark.slow
def test_train_observation_then_eval_under_noise_and_delay(tmp_path, capsys):
    """In this process (``main``), as a user's shell would run each command."""

    def cli(*args: str) -> subprocess.CompletedProcess:
        try:
            code = main(list(args))
        except SystemExit as exit_:
            code = exit_.code
        out = capsys.readouterr()
        return subprocess.CompletedProcess(args, code or 0, out.out, out.err)

    run_dir = tmp_path / "run"
    sets = ["learning_starts=50", "batch_size=32", "policy_kwargs.net_arch=[16,16]", "eval_freq=100"]
    args = ["train", "--env", REACH, "--action-mode", "ee_delta", "--algo", "sac_her", "--steps", "100"]
    proc = cli(*args, "--run-dir", str(run_dir), "--observation", "ee_pos,goal_rel", "--no-progress",
               *[x for s in sets for x in ("--set", s)])  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    config = yaml.safe_load((run_dir / "config.yaml").read_text())
    assert config["env_kwargs"]["observation"] == ["ee_pos", "goal_rel"]
    assert collect_row(run_dir)["observation"] == "ee_pos+goal_rel"
    results = {}
    for extra in ((), ("--observation-noise", "0.01"), ("--observation-delay", "1")):
        out = tmp_path / f"eval{len(results)}.json"
        proc = cli("eval", str(run_dir), "--episodes", "2", "--reward-type", "dense", "--json", str(out), *extra)
        assert proc.returncode == 0, proc.stderr
        results[extra] = json.loads(out.read_text())
    returns = [r["mean_return"] for r in results.values()]  # dense: the actions, and so the returns, differ
    assert returns[0] != returns[1] and returns[0] != returns[2]
    for extra, message in (
        (("--observation-noise", "-0.5"), "--observation-noise must be a standard deviation >= 0, got -0.5"),
        (("--observation-delay", "-1"), "--observation-delay must be an int >= 0, got -1"),
    ):
        proc = cli("eval", str(run_dir), "--episodes", "2", *extra)
        assert proc.returncode == 2
        assert proc.stderr.strip().splitlines()[-1].endswith(message), proc.stderr
        assert "Traceback" not in proc.stderr
    bad = cli(*args, "--run-dir", str(tmp_path / "bad"), "--observation", "object_pos")
    assert bad.returncode == 2 and "Traceback" not in bad.stderr
    assert "observation group 'object_pos' is not available on UnifiedManip/Arm4Reach-v0" in bad.stderr
