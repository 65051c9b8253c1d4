"""Behaviour cloning on the demonstrations before training (``bc_steps: N``, issue 10 item 5).

The contract: N actor gradient steps on the demonstrations bring the actor's own actions
on the demonstrated observations closer to the demonstrated actions, for a stochastic
(TQC) and a deterministic (TD3) actor; a run records them once (a resumed run does not
clone again); asking for them without demonstrations, or a negative count, is a clear
error, one line with exit 2 from the CLI (and so is asking that of ``offline_steps``).
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import torch
from conftest import DEMO_MODE, DEMO_TASK, demonstrated_model, interrupt_after_first_checkpoint, resume_to_the_end

from unified_manip.training.offline import OfflineError
from unified_manip.training.pretrain import PretrainError, behaviour_clone, check_settings, seed_statistics
from unified_manip.training.request import TrainRequest
from unified_manip.training.settings import RunConfig
from unified_manip.training.train import train


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

    model = demonstrated_model(TQC if algo == "tqc_her" else TD3, her=algo == "tqc_her")
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

    model = demonstrated_model(TQC, her=True, normalize=True)
    stats = model._vec_normalize_env.obs_rms
    assert np.allclose(stats["observation"].mean, 0.0)  # nothing seen yet
    seed_statistics(model)  # what a run does before cloning (or offline steps)
    stored = model.replay_buffer.observations
    rows = model.replay_buffer.size()
    for key in ("observation", "desired_goal"):
        np.testing.assert_allclose(stats[key].mean, stored[key][:rows, 0].mean(axis=0), atol=1e-3)
        np.testing.assert_allclose(stats[key].var, stored[key][:rows, 0].var(axis=0), atol=1e-3)


def _request(run_dir, **overrides) -> TrainRequest:
    settings = {
        "demonstrations": 2,
        "bc_steps": 20,
        "learning_starts": 50,
        "batch_size": 32,
        "eval_freq": 1000,
        "n_eval_episodes": 1,
        "checkpoint_freq": 100,
        "n_envs": 1,
    }
    settings.update(overrides)
    return TrainRequest(
        env=DEMO_TASK,
        action_mode=DEMO_MODE,
        reward_type="sparse",
        algo="tqc_her",
        steps=200,
        run_dir=run_dir,
        overrides=tuple(f"{k}={v}" for k, v in settings.items()),
    )


@pytest.mark.slow
def test_a_run_clones_once_and_records_it(tmp_path):
    """Cloned at the start, recorded with the demonstrations (demonstrations.json); interrupted after its first
    checkpoint and resumed, the run goes on from the checkpointed (cloned) actor."""
    run = tmp_path / "run"
    first: list[str] = []
    interrupt_after_first_checkpoint(run, lambda: train(_request(run), progress=False, threads=1, log=first.append))
    record = json.loads((run / "demonstrations.json").read_text())
    assert record["episodes"] == 2 and record["bc_steps"] == 20
    assert np.isfinite([record["behaviour_cloning"]["loss_first"], record["behaviour_cloning"]["loss_last"]]).all()
    assert sum("behaviour cloning, 20 actor steps on the demonstrations" in line for line in first) == 1
    again = resume_to_the_end(_request(run))
    assert not any("behaviour cloning" in line for line in again), again


@pytest.mark.parametrize(
    "settings,error,message",
    [
        (
            {"bc_steps": 10, "demonstrations": 0},
            PretrainError,
            "bc_steps=10 clones the demonstrations; set demonstrations to 1 or more episodes",
        ),
        (
            {"offline_steps": 10, "demonstrations": 0},
            OfflineError,
            "offline_steps=10 learns from the demonstrations alone; set demonstrations to 1 or more episodes",
        ),
    ],
)
def test_pretraining_without_demonstrations_is_refused(settings, error, message):
    """Cloning (bc_steps) and offline steps (offline_steps, :mod:`unified_manip.training.offline`)
    both need demonstrations and a count of 0 or more."""
    with pytest.raises(error) as err:
        check_settings(DEMO_TASK, DEMO_MODE, True, RunConfig.from_mapping(settings))
    assert str(err.value) == message
    none_asked = RunConfig.from_mapping({"demonstrations": settings["demonstrations"]})
    check_settings(DEMO_TASK, DEMO_MODE, True, none_asked)  # fine


@pytest.mark.parametrize("key", ["bc_steps", "offline_steps"])
def test_the_cli_refuses_pretraining_without_demonstrations_in_one_line(tmp_path, key):
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "unified_manip.cli",
            "train",
            "--env",
            DEMO_TASK,
            "--algo",
            "tqc_her",
            "--steps",
            "10",
            "--set",
            "demonstrations=0",
            "--set",
            f"{key}=100",
            "--run-dir",
            str(tmp_path / "r"),
            "--no-progress",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "set demonstrations to 1 or more episodes" in lines[0], proc.stderr
    assert not (tmp_path / "r").exists()
