"""Demonstrations from a dataset (``demonstrations: PATH``, issue 39 item 4).

The contract: a dataset recorded with the scripted policy fills the replay buffer with
exactly the arrays the live scripted prefill stores (same seed); a dataset of another
task, action mode, observation design or reward type is refused in one line that names
the difference and the command that fixes it.
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from test_train import cli

from unified_manip.datasets.policies import scripted
from unified_manip.datasets.recording import collect
from unified_manip.training import dataset_demonstrations
from unified_manip.training.demonstrations import SEED_OFFSET, DemonstrationError, prefill
from unified_manip.training.request import TrainRequest
from unified_manip.training.train import train

ARM = "UnifiedManip/Arm4PickAndPlace-v0"
SPARSE = {"action_mode": "ee_delta", "reward_type": "sparse"}
N_ENVS = 3


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    """Three scripted ee_delta episodes of ARM, reset with seeds 20000-20002: the episodes
    the live prefill of a seed-0 run with three envs plays."""
    out = tmp_path_factory.mktemp("data") / "arm4-pick-v0"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        collect(ARM, SPARSE, scripted, "scripted", "test", N_ENVS, out, seed=SEED_OFFSET, progress=False)
    return out


def _model(n_envs: int):
    from sb3_contrib import TQC
    from stable_baselines3 import HerReplayBuffer

    from unified_manip.training.run_envs import make_vec_env

    env = make_vec_env(ARM, SPARSE, n_envs, 0, None, "dummy")
    return TQC(
        "MultiInputPolicy", env, buffer_size=1000, replay_buffer_class=HerReplayBuffer, learning_starts=10, seed=0
    )


@pytest.mark.slow
def test_a_scripted_dataset_fills_the_buffer_exactly_as_the_live_prefill(dataset):
    from unified_manip.training.run_envs import make_vec_env

    live, recorded = _model(N_ENVS), _model(N_ENVS)
    venv = make_vec_env(ARM, SPARSE, N_ENVS, SEED_OFFSET, None, "dummy")
    try:
        played = prefill(live, venv, ARM, "ee_delta", N_ENVS)
    finally:
        venv.close()
    stored = dataset_demonstrations.prefill(recorded, str(dataset), ARM, SPARSE)
    assert (stored["episodes"], stored["transitions"]) == (played["episodes"], played["transitions"]) == (3, 300)
    assert stored["success"] == played["success"]
    a, b = live.replay_buffer, recorded.replay_buffer
    assert (a.pos, a.full) == (b.pos, b.full) == (100, False)
    for key in a.observations:
        np.testing.assert_array_equal(a.observations[key], b.observations[key], err_msg=key)
        np.testing.assert_array_equal(a.next_observations[key], b.next_observations[key], err_msg=key)
    for name in ("actions", "rewards", "dones", "timeouts", "ep_start", "ep_length", "_current_ep_start"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    # HER relabels the dataset's episodes like the live ones.
    assert b.sample(16, env=None).rewards.shape == (16, 1)


def test_a_buffer_of_fewer_envs_takes_the_episodes_in_rounds(dataset):
    model = _model(2)
    stored = dataset_demonstrations.prefill(model, str(dataset), ARM, SPARSE)
    assert (stored["episodes"], stored["dataset_episodes"], model.replay_buffer.pos) == (2, 3, 100)


@pytest.mark.parametrize(
    "task_id,config,message",
    [
        ("UnifiedManip/Arm4Push-v0", SPARSE, "holds episodes of UnifiedManip/Arm4PickAndPlace-v0, not of"),
        (
            ARM,
            {"action_mode": "joint_delta", "reward_type": "sparse"},
            "was recorded with action_mode 'ee_delta', the run's is 'joint_delta'; convert it: unified-manip "
            "convert {path} --action-mode joint_delta --out ",
        ),
        (
            ARM,
            {**SPARSE, "observation": "relative"},
            "observation design 'default', the run's is 'relative'; convert it: unified-manip convert {path} "
            "--action-mode ee_delta --observation relative --out ",
        ),
        (ARM, {"action_mode": "ee_delta", "reward_type": "dense"}, "reward_type 'sparse', the run's is 'dense'"),
    ],
)
def test_a_dataset_of_another_task_mode_design_or_reward_is_refused(dataset, task_id, config, message):
    with pytest.raises(DemonstrationError) as err:
        dataset_demonstrations.check(str(dataset), task_id, config)
    assert message.format(path=dataset) in str(err.value)
    assert "\n" not in str(err.value)


def test_a_dataset_with_fewer_episodes_than_envs_is_refused_before_the_run(dataset):
    """A prefill gives each env one episode at least: ``train`` and a grid's loading refuse
    a run of more envs than the dataset has episodes, before anything starts."""
    assert dataset_demonstrations.check(str(dataset), ARM, SPARSE, N_ENVS)
    with pytest.raises(DemonstrationError) as err:
        dataset_demonstrations.check(str(dataset), ARM, SPARSE, N_ENVS + 1)
    assert str(err.value) == (
        f"demonstrations: {dataset} holds 3 episodes, fewer than the run's 4 envs (a prefill gives each env one "
        "at least); train with n_envs of at most 3, or without them (demonstrations=0)"
    )


def test_nominal_episodes_suit_a_run_under_a_preset_only(dataset):
    """The nominal world is one every preset draws (their ranges hold the nominal values);
    a list of terms need not hold it, and a run's other env keywords must still match."""
    assert dataset_demonstrations.check(str(dataset), ARM, {**SPARSE, "randomization": "dynamics+objects"})
    terms = [{"entity": "object", "field": "mass", "range": [0.05, 0.1], "operation": "abs"}]
    for config in (
        {**SPARSE, "randomization": terms},
        {**SPARSE, "randomization": "objects", "controller_options": {"band": 0.75}},
    ):
        with pytest.raises(DemonstrationError, match="was recorded with other env keyword arguments"):
            dataset_demonstrations.check(str(dataset), ARM, config)


def test_convert_fixes_an_observation_mismatch(dataset):
    from unified_manip.datasets.convert import convert

    report = convert(dataset, "ee_delta", None, progress=False, first=1, observation="relative")
    assert [e.success_converted for e in report.episodes] == [True]


@pytest.mark.slow
def test_a_run_prefilled_from_a_dataset_records_it(dataset, tmp_path):
    run = tmp_path / "run"
    logs: list[str] = []
    settings = ("learning_starts=50", "batch_size=32", "eval_freq=100", "n_eval_episodes=1", "n_envs=1")
    req = TrainRequest(
        env=ARM,
        action_mode="ee_delta",
        reward_type="sparse",
        algo="tqc_her",
        steps=100,
        run_dir=run,
        overrides=(*settings, f"demonstrations={dataset}", "bc_steps=5"),
    )
    train(req, progress=False, threads=1, log=logs.append)
    record = json.loads((run / "demonstrations.json").read_text())
    assert (record["episodes"], record["transitions"], record["demonstrations"]) == (3, 300, str(dataset))
    assert any(
        f"3 demonstration episodes (300 transitions, 1.00 success) in the replay buffer from {dataset}" in line
        for line in logs
    ), logs


@pytest.mark.slow
def test_the_cli_names_the_convert_command_for_another_mode(dataset, tmp_path):
    proc = cli(
        "train",
        "--env",
        ARM,
        "--algo",
        "tqc_her",
        "--action-mode",
        "joint_delta",
        "--steps",
        "10",
        "--demonstrations",
        str(dataset),
        "--run-dir",
        str(tmp_path / "r"),
        check=False,
    )
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1
    assert f"unified-manip convert {dataset} --action-mode joint_delta --out " in proc.stderr
    assert not (tmp_path / "r").exists()


def test_a_dataset_path_names_each_task_and_mode():
    from unified_manip.training.dataset_demonstrations import dataset_path

    path = dataset_path("data/{task}/{action_mode}-v0", "UnifiedManip/Lift-v0", {"action_mode": "joint_delta"})
    assert path == "data/Lift-v0/joint_delta-v0"


def test_the_cli_refuses_more_envs_than_demonstrated_episodes(dataset, tmp_path):
    proc = cli(
        "train", "--env", ARM, "--algo", "tqc_her", "--action-mode", "ee_delta", "--steps", "10",
        "--n-envs", "4", "--demonstrations", str(dataset), "--run-dir", str(tmp_path / "r"), check=False,
    )  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1
    assert "holds 3 episodes, fewer than the run's 4 envs" in proc.stderr
    assert not (tmp_path / "r").exists()
