"""The agent's own updates on the demonstrations alone, before training (``offline_steps: N``, issue 10 item 5).

The contract: N gradient steps of the algorithm's own update fit its critic to the
demonstrations' discounted returns, for TQC with HER and TD3 without; a run takes them
once, after the demonstrations and with the cloning loss in its actor updates, records
them (a resumed run does not take them again) and the report says so
(tests/experiments/test_bench.py). Asking for them without demonstrations, or a negative count, is a
clear error, one line with exit 2 from the CLI (tests/training/test_pretrain.py, with bc_steps).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import torch
from conftest import demonstrated_model, interrupt_after_first_checkpoint, resume_to_the_end
from test_pretrain import _request as pretrain_request

from unified_manip.training.offline import learn_offline
from unified_manip.training.train import train


def _returns_and_values(model) -> tuple[np.ndarray, np.ndarray]:
    """Each stored (demonstrated) transition's discounted return to the end of its episode,
    from the stored rewards, and the critic's mean value of it, with the stored goal."""
    buffer = model.replay_buffer
    rows = buffer.size()
    rewards, dones = buffer.rewards[:rows, 0], buffer.dones[:rows, 0]
    returns = np.zeros(rows)
    to_go = 0.0
    for i in range(rows - 1, -1, -1):
        to_go = rewards[i] + model.gamma * (0.0 if dones[i] else to_go)
        returns[i] = to_go
    obs = {k: torch.as_tensor(v[:rows, 0]) for k, v in buffer.observations.items()}
    with torch.no_grad():
        values = model.critic(obs, torch.as_tensor(buffer.actions[:rows, 0]))
    values = torch.cat(values, dim=1) if isinstance(values, tuple) else values
    return returns, values.flatten(start_dim=1).mean(dim=1).numpy()


@pytest.mark.parametrize("algo", ["tqc_her", "td3"])
def test_offline_steps_fit_the_critic_to_the_demonstrated_returns(algo, capsys):
    from sb3_contrib import TQC
    from stable_baselines3 import TD3

    model = demonstrated_model(TQC if algo == "tqc_her" else TD3, her=algo == "tqc_her")
    before = np.corrcoef(*_returns_and_values(model))[0, 1]
    actor = [p.detach().clone() for p in model.actor.parameters()]
    done = learn_offline(model, 200, progress=True)
    shown = capsys.readouterr().err  # the progress bar
    assert "offline steps" in shown and "200/200" in shown, shown
    after = np.corrcoef(*_returns_and_values(model))[0, 1]
    assert after > 0.75 and after > before + 0.2, (before, after)  # untrained: -0.44 (TQC), 0.54 (TD3)
    assert done["steps"] == 200 and model._n_updates == 200
    assert done["last"]["train/critic_loss"] < 0.1 * done["first"]["train/critic_loss"], done
    assert any(not torch.equal(p, q) for p, q in zip(actor, model.actor.parameters()))  # the actor updated too


def _request(run_dir):
    """test_pretrain's short run, with offline steps and the Q-filtered loss in place of cloning."""
    return pretrain_request(run_dir, bc_steps=0, offline_steps=30, bc_weight=1.0)


@pytest.mark.slow
def test_a_run_learns_offline_once_with_the_cloning_loss_and_records_it(tmp_path):
    """Taken at the start with the Q-filtered cloning loss in the actor updates (the record
    holds the filter's pass rate), recorded with the demonstrations; interrupted after its
    first checkpoint and resumed, the run does not take them again."""
    run = tmp_path / "run"
    first: list[str] = []
    interrupt_after_first_checkpoint(run, lambda: train(_request(run), progress=False, threads=1, log=first.append))
    document = json.loads((run / "demonstrations.json").read_text())
    assert document["offline_steps"] == 30
    record = document["offline"]
    for values in (record["first"], record["last"]):
        assert {"train/critic_loss", "train/actor_loss", "train/bc_loss", "train/bc_q_filter", "train/bc_error"} <= set(
            values
        )
        assert 0.0 <= values["train/bc_q_filter"] <= 1.0 and np.isfinite(list(values.values())).all()
    assert sum("30 offline steps of tqc_her on the demonstrations alone (critic loss" in line for line in first) == 1
    again = resume_to_the_end(_request(run))
    assert not any("offline steps" in line for line in again), again


@pytest.mark.parametrize("steps", [0, 1, 2, 3, 252, 253, 10000])
def test_the_steps_run_in_chunks_with_the_first_and_last_alone(steps):
    from unified_manip.training.offline import CHUNK, _chunks

    chunks = _chunks(steps)
    assert sum(chunks) == steps and all(0 < c <= CHUNK for c in chunks)
    if steps:
        assert chunks[0] == 1 and chunks[-1] == 1
