"""The Q-filtered cloning loss during training (``bc_weight: λ``, issue 10 item 5).

The contract: attached, every actor update also pulls the actor's actions toward the
demonstrated ones, but only on transitions where the critic rates the demonstrated action
strictly above the actor's own (a critic that rates every action alike moves nothing); on
the sampled action (``bc_sampled: true``) it pulls a stochastic actor's noise down too; a
run attaches it again when it resumes (its TensorBoard log carries the loss from the
resumed segment); asking for it without demonstrations, below 0, or with a replay buffer
that would overwrite the demonstrations, or a sampled action of a deterministic actor, is a
clear error, one line with exit 2 from the CLI.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
import torch
from conftest import DEMO_MODE, DEMO_TASK, demonstrated_model, interrupt_after_first_checkpoint
from test_pretrain import _action_error, _request
from test_train import tb_tags

from unified_manip.training.cloning_loss import CloningLossError, attach, check
from unified_manip.training.train import train


def _pure_cloning_steps(model, steps: int) -> None:
    """``steps`` actor optimiser steps with no loss of the algorithm's own: what moves the
    actor is the attached cloning loss alone."""
    from stable_baselines3.common.logger import configure

    model.set_logger(configure(None, []))
    model.policy.set_training_mode(True)
    for _ in range(steps):
        model.actor.optimizer.zero_grad()
        model.actor.optimizer.step()


@pytest.mark.parametrize("algo", ["tqc_her", "td3"])
def test_the_loss_pulls_the_actor_toward_the_demonstrations(algo):
    from sb3_contrib import TQC
    from stable_baselines3 import TD3

    model = demonstrated_model(TQC if algo == "tqc_her" else TD3, her=algo == "tqc_her")
    before = _action_error(model)
    attach(model, model.replay_buffer.size(), steps=100, weight=1.0)
    _pure_cloning_steps(model, 300)
    assert _action_error(model) < 0.7 * before, (before, _action_error(model))


@pytest.mark.parametrize("q_filter", [True, False])
def test_a_critic_that_rates_every_action_alike_filters_everything_out(q_filter):
    """Q(s, a_demo) > Q(s, π(s)) never holds when Q ignores the action: the actor is
    untouched (its distance to the demonstrations is logged all the same). Unfiltered
    (``bc_q_filter: false``), the same critic lets every demonstrated transition through."""
    from sb3_contrib import TQC

    model = demonstrated_model(TQC, her=True)
    with torch.no_grad():
        for net in model.critic.q_networks:
            net[-1].weight.zero_()  # each quantile is its bias alone
    before, error = [p.detach().clone() for p in model.actor.parameters()], _action_error(model)
    attach(model, model.replay_buffer.size(), steps=100, weight=1.0, q_filter=q_filter)
    _pure_cloning_steps(model, 20)
    logged = model.logger.name_to_value
    if q_filter:
        for p, q in zip(before, model.actor.parameters()):
            assert torch.equal(p, q)
        assert logged["train/bc_loss"] == 0.0 and logged["train/bc_q_filter"] == 0.0
    else:
        assert _action_error(model) < 0.9 * error
        assert logged["train/bc_q_filter"] == 1.0
    assert logged["train/bc_error"] > 0.0  # how far the actor is, filtered or not


def _noise(model) -> float:
    """The actor's mean standard deviation (before the tanh) over the demonstrated states."""
    buffer = model.replay_buffer
    rows = buffer.size()
    obs = {k: torch.as_tensor(v[:rows, 0]) for k, v in buffer.observations.items()}
    with torch.no_grad():
        _, log_std, _ = model.actor.get_action_dist_params(obs)
    return float(log_std.exp().mean())


@pytest.mark.parametrize("sampled", [False, True])
def test_only_the_sampled_loss_pulls_the_noise_down(sampled):
    """On the mean action the loss never reaches the actor's standard-deviation head; on
    the sampled action (``bc_sampled: true``) its expected squared error includes the
    variance, so the noise where the demonstrations act shrinks, and the mean action still
    comes toward them."""
    from sb3_contrib import TQC

    model = demonstrated_model(TQC, her=True)
    head = [p.detach().clone() for p in model.actor.log_std.parameters()]
    noise, error = _noise(model), _action_error(model)
    attach(model, model.replay_buffer.size(), steps=100, weight=1.0, q_filter=False, sampled=sampled)
    _pure_cloning_steps(model, 300)
    assert _action_error(model) < 0.7 * error
    if sampled:
        assert _noise(model) < 0.5 * noise, (noise, _noise(model))
    else:
        assert all(torch.equal(p, q) for p, q in zip(head, model.actor.log_std.parameters()))


def test_the_sampled_loss_needs_a_stochastic_actor():
    from stable_baselines3 import TD3

    model = demonstrated_model(TD3, her=False)
    with pytest.raises(
        CloningLossError,
        match="bc_sampled=true needs a stochastic actor .SAC, TQC, CrossQ.; TD3's actor is deterministic",
    ):
        attach(model, model.replay_buffer.size(), steps=100, weight=1.0, sampled=True)


@pytest.mark.slow
def test_a_resumed_run_keeps_the_loss(tmp_path):
    """SB3 writes its training log every 4 episodes: at step 200 here, after the resume at
    100, so the loss in the log was computed by a hook the resumed run attached."""
    run = tmp_path / "run"
    settings = {"bc_steps": 0, "bc_weight": 1.0, "bc_q_filter": False, "bc_sampled": True}
    interrupt_after_first_checkpoint(
        run, lambda: train(_request(run, **settings), progress=False, threads=1, log=lambda msg: None)
    )
    assert not {"train/bc_loss", "train/bc_q_filter"} & tb_tags(run)
    record = json.loads((run / "demonstrations.json").read_text())
    assert (record["bc_weight"], record["bc_q_filter"], record["bc_sampled"]) == (1.0, False, True)
    status = train(_request(run, **settings), progress=False, threads=1, log=lambda msg: None)
    assert status["state"] == "finished"
    assert {"train/bc_loss", "train/bc_q_filter"} <= tb_tags(run)


@pytest.mark.parametrize(
    "weight,demonstrations,q_filter,sampled,message",
    [
        (0.5, 0, True, False, "bc_weight=0.5 imitates the demonstrations; set demonstrations to 1 or more episodes"),
        (-1.0, 5, True, False, "bc_weight must be a loss weight, 0 or more; got -1.0"),
        (float("nan"), 5, True, False, "bc_weight must be a loss weight, 0 or more; got nan"),
        (0.0, 5, False, False, "bc_q_filter=false changes the cloning loss; set bc_weight above 0 as well"),
        (0.0, 5, True, True, "bc_sampled=true changes the cloning loss; set bc_weight above 0 as well"),
    ],
)
def test_the_loss_without_demonstrations_is_refused(weight, demonstrations, q_filter, sampled, message):
    with pytest.raises(CloningLossError) as err:
        check(weight, demonstrations, q_filter, sampled)
    assert message in str(err.value)
    check(0.0, demonstrations)  # none asked: always fine


def test_a_buffer_that_would_overwrite_the_demonstrations_is_refused():
    from sb3_contrib import TQC

    model = demonstrated_model(TQC, her=True)  # buffer_size 2000
    demonstrated = model.replay_buffer.size()
    with pytest.raises(CloningLossError, match=f"buffer_size must be at least 2001 transitions [(]{demonstrated} "):
        attach(model, demonstrated, steps=2001 - demonstrated, weight=1.0)
    attach(model, demonstrated, steps=2000 - demonstrated, weight=1.0)


@pytest.mark.parametrize(
    "sets,message",
    [
        (["demonstrations=0", "bc_weight=1"], "set demonstrations to 1 or more episodes"),
        (["demonstrations=1", "bc_weight=1", "buffer_size=200"], "buffer_size must be at least"),
        (["demonstrations=1", "bc_sampled=true"], "bc_sampled=true changes the cloning loss; set bc_weight above 0"),
    ],
)
def test_the_cli_refuses_in_one_line(tmp_path, sets, message):
    args = [a for s in sets for a in ("--set", s)]
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "unified_manip.cli",
            "train",
            "--env",
            DEMO_TASK,
            "--action-mode",
            DEMO_MODE,
            "--algo",
            "tqc_her",
            "--steps",
            "200",
            *args,
            "--set",
            "n_envs=1",
            "--run-dir",
            str(tmp_path / "r"),
            "--no-progress",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], proc.stderr
