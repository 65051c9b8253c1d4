"""Behaviour cloning on the demonstrations before training (``bc_steps: N``, issue 10 item 5).

The contract: N actor gradient steps on the demonstrations bring the actor's own actions
on the demonstrated observations closer to the demonstrated actions, for a stochastic
(TQC) and a deterministic (TD3) actor; a run records them once (a resumed run does not
clone again); asking for them without demonstrations, or a negative count, is a clear
error, one line with exit 2 from the CLI.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import torch
from conftest import interrupt_after_first_checkpoint

from unified_manip.demonstrations import prefill
from unified_manip.pretrain import PretrainError, behaviour_clone, check
from unified_manip.request import TrainRequest
from unified_manip.train import train

ARM = "UnifiedManip/Arm4PickAndPlace-v0"
MODE = "joint_position"  # the mode the lever is for


def _demonstrated_model(algo_cls, her: bool, normalize: bool = False):
    from stable_baselines3 import HerReplayBuffer
    from stable_baselines3.common.vec_env import VecNormalize

    from unified_manip.vecenvs import make_vec_env

    kwargs = {"action_mode": MODE, "reward_type": "sparse"}
    venv = make_vec_env(ARM, kwargs, 1, 3, None, "dummy")
    extra = {"replay_buffer_class": HerReplayBuffer} if her else {}
    env = make_vec_env(ARM, kwargs, 1, 0, None, "dummy")
    env = VecNormalize(env, norm_reward=False) if normalize else env
    model = algo_cls("MultiInputPolicy", env, buffer_size=2000, learning_starts=10, batch_size=64, seed=0, **extra)
    prefill(model, venv, ARM, MODE, episodes=2)
    venv.close()
    return model


def _action_error(model) -> float:
    """Mean absolute difference between the actor's deterministic actions and the stored
    (demonstrated) ones, over every stored row, with the stored goals."""
    buffer = model.replay_buffer
    rows = buffer.size()
    obs = {k: torch.as_tensor(v[:rows, 0]) for k, v in buffer.observations.items()}
    with torch.no_grad():
        mine = model.actor(obs, deterministic=True) if hasattr(model.actor, "action_dist") else model.actor(obs)
    return float(np.mean(np.abs(mine.numpy() - buffer.actions[:rows, 0])))


@pytest.mark.parametrize("algo", ["tqc_her", "td3"])
def test_cloning_brings_the_actors_actions_to_the_demonstrated_ones(algo):
    from sb3_contrib import TQC
    from stable_baselines3 import TD3

    model = _demonstrated_model(TQC if algo == "tqc_her" else TD3, her=algo == "tqc_her")
    before = _action_error(model)
    done = behaviour_clone(model, 300)
    after = _action_error(model)
    assert done["steps"] == 300 and done["loss_last"] < done["loss_first"]
    assert after < 0.5 * before, (before, after)
    if algo == "td3":  # the target actor starts from the cloned one
        for p, q in zip(model.actor.parameters(), model.actor_target.parameters()):
            assert torch.equal(p, q)


def test_a_normalising_runs_statistics_start_from_the_demonstrations():
    """Fitted to inputs normalised as the first rollouts' will be: the observation
    statistics hold the demonstrated observations before cloning (else they would be the
    identity until the first rollout, and change under the cloned actor)."""
    from sb3_contrib import TQC

    model = _demonstrated_model(TQC, her=True, normalize=True)
    stats = model._vec_normalize_env.obs_rms
    assert np.allclose(stats["observation"].mean, 0.0)  # nothing seen yet
    behaviour_clone(model, 1)
    stored = model.replay_buffer.observations
    rows = model.replay_buffer.size()
    for key in ("observation", "desired_goal"):
        np.testing.assert_allclose(stats[key].mean, stored[key][:rows, 0].mean(axis=0), atol=1e-3)
        np.testing.assert_allclose(stats[key].var, stored[key][:rows, 0].var(axis=0), atol=1e-3)


def _request(run_dir, **overrides) -> TrainRequest:
    settings = {"demonstrations": 2, "bc_steps": 20, "learning_starts": 50, "batch_size": 32, "eval_freq": 1000,
                "n_eval_episodes": 1, "checkpoint_freq": 100, "n_envs": 1}
    settings.update(overrides)
    return TrainRequest(env=ARM, action_mode=MODE, reward_type="sparse", algo="tqc_her", steps=200,
                        run_dir=run_dir, overrides=tuple(f"{k}={v}" for k, v in settings.items()))


def test_a_run_clones_once_and_records_it(tmp_path):
    """Cloned at the start, recorded with the demonstrations (demonstrations.json); interrupted after its first
    checkpoint and resumed, the run goes on from the checkpointed (cloned) actor."""
    run = tmp_path / "run"
    first: list[str] = []
    interrupt_after_first_checkpoint(run, lambda: train(_request(run), progress=False, threads=1, log=first.append))
    record = json.loads((run / "demonstrations.json").read_text())
    assert record["episodes"] == 2 and record["behaviour_cloning"]["steps"] == 20
    assert np.isfinite([record["behaviour_cloning"]["loss_first"], record["behaviour_cloning"]["loss_last"]]).all()
    assert sum("behaviour cloning, 20 actor steps on the demonstrations" in line for line in first) == 1
    again: list[str] = []
    status = train(_request(run), progress=False, threads=1, log=again.append)
    assert status["state"] == "finished"
    assert any("resuming from step" in line for line in again), again
    assert not any("behaviour cloning" in line for line in again), again


@pytest.mark.parametrize(
    "bc_steps,demonstrations,message",
    [
        (10, 0, "bc_steps=10 clones the demonstrations; set demonstrations to 1 or more episodes"),
        (-1, 5, "bc_steps must be a number of gradient steps, 0 or more; got -1"),
    ],
)
def test_cloning_without_demonstrations_is_refused(bc_steps, demonstrations, message):
    with pytest.raises(PretrainError) as err:
        check(bc_steps, demonstrations)
    assert message in str(err.value)
    check(0, demonstrations)  # none asked: always fine


def test_the_cli_refuses_cloning_without_demonstrations_in_one_line(tmp_path):
    proc = subprocess.run(
        [sys.executable, "-m", "unified_manip.cli", "train", "--env", ARM, "--algo", "tqc_her", "--steps", "10",
         "--set", "demonstrations=0", "--set", "bc_steps=100", "--run-dir", str(tmp_path / "r"), "--no-progress"],
        capture_output=True, text=True, timeout=300,
    )
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "set demonstrations to 1 or more episodes" in lines[0], proc.stderr
    assert not (tmp_path / "r").exists()
