"""``relabel_goal_rel``: HER relabelling keeps the observation's ``goal_rel`` group on the
new goal, on every ID; it is off by default, and runs saved before it resume as trained."""

from __future__ import annotations

import numpy as np
import pytest
import torch
import yaml
from conftest import smoke_mode
from stable_baselines3 import HerReplayBuffer
from stable_baselines3.common.vec_env import DummyVecEnv

import unified_manip
from unified_manip.training.algorithms import get_algo
from unified_manip.training.her import GoalRelHerReplayBuffer
from unified_manip.training.hyperparams import resolve_run
from unified_manip.training.run_envs import make_vec_env, model_kwargs
from unified_manip.training.settings import RunConfig

HER_KWARGS = {"n_sampled_goal": 4, "goal_selection_strategy": "future"}


def _model(task_id: str, relabel: bool, episodes: int = 1, **env_kwargs):
    """A SAC+HER model on ``task_id`` (``relative`` design unless given) whose buffer holds
    ``episodes`` episodes of random actions (no updates)."""
    torch.set_num_threads(1)
    kwargs = {"action_mode": smoke_mode(task_id), "reward_type": "sparse", "observation": "relative", **env_kwargs}
    env = make_vec_env(task_id, kwargs, 1, 0, None, "dummy")
    assert isinstance(env, DummyVecEnv)
    steps = episodes * unified_manip.TASKS[task_id].max_episode_steps
    algo_kwargs = {
        "replay_buffer_kwargs": HER_KWARGS,
        "learning_starts": steps + 1,
        "buffer_size": 10_000,
        "policy": "MultiInputPolicy",
    }
    run = RunConfig(relabel_goal_rel=relabel)
    model = get_algo("sac_her").cls()(env=env, seed=0, device="cpu", **model_kwargs("sac_her", algo_kwargs, run, env))
    model.learn(steps)
    return model, _goal_rel(env)


def _goal_rel(env) -> slice:
    """The ``goal_rel`` slice of a vector env's observation layout."""
    return env.get_attr("observation_layout", [0])[0]["goal_rel"]


def _mismatch(batch, part: slice) -> tuple[np.ndarray, np.ndarray]:
    """|goal_rel - (desired_goal - achieved_goal)| of each sampled observation and next observation."""
    out = []
    for obs in (batch.observations, batch.next_observations):
        expected = obs["desired_goal"].numpy() - obs["achieved_goal"].numpy()
        out.append(np.abs(obs["observation"].numpy()[:, part] - expected).max(axis=1))
    return out[0], out[1]


@pytest.mark.parametrize("task_id", list(unified_manip.TASKS))
def test_relabelled_samples_show_their_own_goal_in_goal_rel(task_id):
    model, part = _model(task_id, relabel=True)
    buffer = model.replay_buffer
    assert type(buffer) is GoalRelHerReplayBuffer and buffer.goal_rel == ((part.start, part.stop),)
    batch = buffer.sample(1024)
    # The desired goals are mostly relabelled (4 of 5), each sample agrees with its own goal.
    obs_gap, next_gap = _mismatch(batch, part)
    assert obs_gap.max() < 1e-5 and next_gap.max() < 1e-5
    # The same buffer relabelled as SB3 does leaves goal_rel at the episode's goal.
    buffer.goal_rel = ()
    stale, _ = _mismatch(buffer.sample(1024), part)
    assert (stale > 1e-3).mean() > 0.3


def test_relabelling_keeps_the_sensor_model_of_goal_rel():
    """Under noise and a one-step delay goal_rel is not desired - achieved; relabelling
    moves it with the goal and keeps the rest (goal_rel - desired_goal is unchanged)."""
    model, part = _model("UnifiedManip/Arm4Reach-v0", True, episodes=2, observation_noise=0.01, observation_delay=1)
    buffer = model.replay_buffer
    rows = np.arange(buffer.pos - 100 * buffer.n_envs, buffer.pos)
    envs = np.zeros_like(rows)
    virtual = buffer._get_virtual_samples(rows, envs)
    for sampled, stored in (
        (virtual.observations, buffer.observations),
        (virtual.next_observations, buffer.next_observations),
    ):
        new = sampled["observation"].numpy()[:, part] - sampled["desired_goal"].numpy()
        old = stored["observation"][rows, envs][:, part] - stored["desired_goal"][rows, envs]
        np.testing.assert_allclose(new, old, atol=1e-6)
    assert (
        np.abs(virtual.observations["desired_goal"].numpy() - buffer.observations["desired_goal"][rows, envs]).max()
        > 0.01
    )
    # noise and delay: goal_rel is not simply desired - achieved
    obs_gap, _ = _mismatch(virtual, part)
    assert np.median(obs_gap) > 1e-3


def test_it_is_off_by_default_and_a_design_without_goal_rel_gets_no_slices():
    assert RunConfig().relabel_goal_rel is False
    model, _ = _model("UnifiedManip/FetchReach-v0", relabel=False)
    assert model.replay_buffer.goal_rel == () and "goal_rel" not in model.replay_buffer_kwargs
    env = make_vec_env("UnifiedManip/FetchReach-v0", {"action_mode": "native"}, 1, 0, None, "dummy")
    kwargs = model_kwargs("sac_her", {"replay_buffer_kwargs": HER_KWARGS}, RunConfig(relabel_goal_rel=True), env)
    assert kwargs["replay_buffer_kwargs"] == HER_KWARGS  # the default design has no goal_rel
    env.close()


@pytest.mark.parametrize(
    "slices,message",
    [
        (((9, 11),), "goal_rel slice (9, 11) must lie in the observation's 12 entries and be as wide as the goal (3)"),
        (
            ((10, 13),),
            "goal_rel slice (10, 13) must lie in the observation's 12 entries and be as wide as the goal (3)",
        ),
    ],
)
def test_a_slice_that_cannot_hold_goal_rel_is_refused(slices, message):
    env = make_vec_env("UnifiedManip/Arm4Reach-v0", {"observation": "relative"}, 1, 0, None, "dummy")
    with pytest.raises(ValueError) as err:
        GoalRelHerReplayBuffer(100, env.observation_space, env.action_space, env=env, goal_rel=slices)
    assert str(err.value) == message
    env.close()


@pytest.mark.parametrize("algo", ["sac_her", "tqc_her", "crossq_her"])
def test_a_model_saved_with_or_without_slices_loads_as_it_was_trained(algo, tmp_path):
    """A model saved with SB3's own buffer (every run before the setting) loads without
    slices; one trained with the setting loads with them."""
    env = make_vec_env("UnifiedManip/Arm4Reach-v0", {"action_mode": "ee_delta"}, 1, 0, None, "dummy")
    policy = resolve_run(algo, "UnifiedManip/Arm4Reach-v0", ("learning_starts=10",)).algo_kwargs["policy"]
    base = {"policy": policy, "replay_buffer_kwargs": HER_KWARGS, "buffer_size": 1000, "learning_starts": 10}
    cls = get_algo(algo).cls()
    if algo != "crossq_her":
        old = cls(env=env, replay_buffer_class=HerReplayBuffer, **base)
        old.save(tmp_path / "old.zip")
        loaded = get_algo(algo).load(tmp_path / "old.zip", policy, env=env)
        assert isinstance(loaded.replay_buffer, GoalRelHerReplayBuffer) and loaded.replay_buffer.goal_rel == ()
    new = cls(env=env, **model_kwargs(algo, base, RunConfig(relabel_goal_rel=True), env))
    new.save(tmp_path / "new.zip")
    loaded = get_algo(algo).load(tmp_path / "new.zip", policy, env=env)
    assert type(loaded.replay_buffer) is type(new.replay_buffer)
    part = _goal_rel(env)  # the arm's default design holds it
    assert loaded.replay_buffer.goal_rel == ((part.start, part.stop),)
    env.close()


@pytest.mark.slow
def test_a_run_with_the_setting_records_it_and_resumes_with_it(tmp_path):
    from conftest import interrupt_after_first_checkpoint, resume_to_the_end

    from unified_manip.training.request import TrainRequest
    from unified_manip.training.train import train

    run_dir = tmp_path / "run"
    settings = ("learning_starts=50", "batch_size=32", "eval_freq=150", "n_eval_episodes=1", "checkpoint_freq=100")
    request = TrainRequest(
        "UnifiedManip/Arm4Reach-v0",
        "ee_delta",
        "sparse",
        "sac_her",
        300,
        run_dir=run_dir,
        overrides=settings + ("relabel_goal_rel=true",),
    )
    interrupt_after_first_checkpoint(run_dir, lambda: train(request, progress=False, threads=1, log=lambda m: None))
    config = yaml.safe_load((run_dir / "config.yaml").read_text())
    assert config["hyperparameters"]["relabel_goal_rel"] is True
    resume_to_the_end(request)
    env = make_vec_env("UnifiedManip/Arm4Reach-v0", {"action_mode": "ee_delta"}, 1, 0, None, "dummy")
    final = get_algo("sac_her").load(run_dir / "final_model.zip", "MultiInputPolicy", env=env)
    part = _goal_rel(env)
    assert final.replay_buffer.goal_rel == ((part.start, part.stop),)
    env.close()
