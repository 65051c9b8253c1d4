"""HER relabelling keeps the observation's goal-dependent group (``goal_rel``) on the new
goal, on every ID: in the harness by default (``relabel_goal_rel``; false reproduces SB3's
relabelling and the runs saved before it, which resume as trained), and for plain SB3
scripts with :class:`unified_manip.training.GoalRelHerReplayBuffer`."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import torch
import yaml
from conftest import HER_IDS, smoke_mode
from stable_baselines3 import HerReplayBuffer
from stable_baselines3.common.vec_env import DummyVecEnv

import unified_manip
from unified_manip.training import rundir
from unified_manip.training.algorithms import get_algo
from unified_manip.training.her import GoalRelHerReplayBuffer
from unified_manip.training.hyperparams import resolve_run
from unified_manip.training.run_envs import make_vec_env, model_kwargs
from unified_manip.training.settings import RunConfig

ROOT = Path(__file__).resolve().parents[2]
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


def _goal_rel(env) -> slice | None:
    """The ``goal_rel`` slice of a vector env's observation layout (None: it has none)."""
    return env.get_attr("observation_layout", [0])[0].get("goal_rel")


def _mismatch(batch, part: slice) -> tuple[np.ndarray, np.ndarray]:
    """|goal_rel - (desired_goal - achieved_goal)| of each sampled observation and next observation."""
    out = []
    for obs in (batch.observations, batch.next_observations):
        expected = obs["desired_goal"].numpy() - obs["achieved_goal"].numpy()
        out.append(np.abs(obs["observation"].numpy()[:, part] - expected).max(axis=1))
    return out[0], out[1]


# One task per family: which groups depend on the goal is measured on every ID
# (tests/envs/test_goal_dependence.py); this checks the buffer moves them.
@pytest.mark.parametrize("task_id", HER_IDS)
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


def test_it_is_on_by_default_and_false_is_sb3s_relabelling():
    assert RunConfig().relabel_goal_rel is True
    assert resolve_run("tqc_her", "UnifiedManip/Arm4Push-v0").run.relabel_goal_rel is True
    env = make_vec_env("UnifiedManip/Arm4Reach-v0", {"action_mode": "ee_delta"}, 1, 0, None, "dummy")
    part = _goal_rel(env)  # the arm's default design ends with it
    for run, slices in ((RunConfig(), ((part.start, part.stop),)), (RunConfig(relabel_goal_rel=False), ())):
        kwargs = model_kwargs("sac_her", {"replay_buffer_kwargs": HER_KWARGS}, run, env)
        assert kwargs["replay_buffer_kwargs"] == {**HER_KWARGS, "goal_rel": slices}  # stated, so the model keeps it
    env.close()
    model, _ = _model("UnifiedManip/FetchReach-v0", relabel=True, observation="default")
    assert model.replay_buffer.goal_rel == () and model.replay_buffer_kwargs["goal_rel"] == ()  # no goal_rel there


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
    """A model saved without ``goal_rel`` in its buffer's keyword arguments (every run
    before the harness stated them: SB3's buffer, or this one with no slices) loads
    without slices, though the buffer alone would read them from the env; one trained
    with the default loads with them, one trained with false without."""
    env = make_vec_env("UnifiedManip/Arm4Reach-v0", {"action_mode": "ee_delta"}, 1, 0, None, "dummy")
    policy = resolve_run(algo, "UnifiedManip/Arm4Reach-v0", ("learning_starts=10",)).algo_kwargs["policy"]
    base = {"policy": policy, "replay_buffer_kwargs": HER_KWARGS, "buffer_size": 1000, "learning_starts": 10}
    cls = get_algo(algo).cls()
    part = _goal_rel(env)  # the arm's default design holds it
    old_buffers = [get_algo(algo).buffer_cls()] + ([HerReplayBuffer] if algo != "crossq_her" else [])
    for i, buffer in enumerate(old_buffers):
        old = cls(env=env, replay_buffer_class=buffer, **base)
        assert "goal_rel" not in old.replay_buffer_kwargs
        old.save(tmp_path / f"old{i}.zip")
        loaded = get_algo(algo).load(tmp_path / f"old{i}.zip", policy, env=env)
        assert isinstance(loaded.replay_buffer, GoalRelHerReplayBuffer) and loaded.replay_buffer.goal_rel == ()
    for run, slices in ((RunConfig(), ((part.start, part.stop),)), (RunConfig(relabel_goal_rel=False), ())):
        new = cls(env=env, **model_kwargs(algo, base, run, env))
        new.save(tmp_path / "new.zip")
        loaded = get_algo(algo).load(tmp_path / "new.zip", policy, env=env)
        assert type(loaded.replay_buffer) is type(new.replay_buffer)
        assert loaded.replay_buffer.goal_rel == slices
    env.close()


@pytest.mark.slow
def test_a_fresh_run_relabels_goal_rel_with_no_setting_and_resumes_with_it(tmp_path):
    from conftest import interrupt_after_first_checkpoint, resume_to_the_end

    from unified_manip.training.request import TrainRequest
    from unified_manip.training.train import train

    run_dir = tmp_path / "run"
    settings = ("learning_starts=50", "batch_size=32", "eval_freq=150", "n_eval_episodes=1", "checkpoint_freq=100")
    request = TrainRequest(
        "UnifiedManip/Arm4Reach-v0", "ee_delta", "sparse", "tqc_her", 300, run_dir=run_dir, overrides=settings
    )
    interrupt_after_first_checkpoint(run_dir, lambda: train(request, progress=False, threads=1, log=lambda m: None))
    config = yaml.safe_load((run_dir / "config.yaml").read_text())
    assert "relabel_goal_rel" not in config["hyperparameters"]  # the default, as every unset setting
    assert rundir.run_settings(run_dir, config)[0].relabel_goal_rel is True
    resume_to_the_end(request)
    env = make_vec_env("UnifiedManip/Arm4Reach-v0", {"action_mode": "ee_delta"}, 1, 0, None, "dummy")
    final = get_algo("tqc_her").load(run_dir / "final_model.zip", "MultiInputPolicy", env=env)
    part = _goal_rel(env)
    assert final.replay_buffer.goal_rel == ((part.start, part.stop),)
    env.close()


def test_a_committed_run_reads_the_setting_it_was_trained_with():
    """Every run committed before the default became true was trained with SB3's
    relabelling, and its config.yaml says so; the goal_rel_her study's runs say true."""
    configs = {c.parent: rundir.read_config(c.parent) for c in sorted((ROOT / "results").rglob("config.yaml"))}
    read = {d: rundir.run_settings(d, c)[0].relabel_goal_rel for d, c in configs.items()}
    stated = {d: c["hyperparameters"].get("relabel_goal_rel") for d, c in configs.items()}
    assert sum(v is False for v in stated.values()) >= 381  # the run directories committed before
    assert {d.parents[1].name for d, v in stated.items() if v is True} >= {"goal_rel_her"}
    assert all(read[d] is stated[d] for d in configs if stated[d] is not None)
    benchmark = ROOT / "results/benchmark_arm/runs/Arm4Push-v0__ee_delta__sparse__tqc_her__s0"
    assert read[benchmark] is False


# ---------------------------------------------------------------------- plain SB3
def _other_entries(obs: dict, part: slice) -> np.ndarray:
    """Each row's observation without the goal_rel slice, with its achieved goal: what
    relabelling leaves as it was, so it names the stored row a sample came from."""
    vector = np.asarray(obs["observation"])
    return np.concatenate([vector[:, : part.start], vector[:, part.stop :], np.asarray(obs["achieved_goal"])], axis=1)


@pytest.mark.parametrize("buffer_class", [GoalRelHerReplayBuffer, HerReplayBuffer], ids=["ours", "sb3"])
def test_plain_sb3_with_the_exported_buffer_moves_goal_rel_by_the_goal_change(buffer_class):
    """The README's script, briefly, under noise and a one-step delay: in each relabelled
    sample, goal_rel has moved by exactly the change of desired_goal, so its noise and
    delay (goal_rel - (desired_goal - achieved_goal)) are the stored row's. SB3's own
    buffer leaves goal_rel where it was."""
    import gymnasium as gym
    from stable_baselines3 import SAC

    from unified_manip.training import GoalRelHerReplayBuffer as exported

    assert exported is GoalRelHerReplayBuffer
    torch.set_num_threads(1)
    env = gym.make("UnifiedManip/Arm4Push-v0", action_mode="ee_delta", observation_noise=0.01, observation_delay=1)
    part = env.unwrapped.goal_dependent_layout["goal_rel"]
    steps = 2 * unified_manip.TASKS["UnifiedManip/Arm4Push-v0"].max_episode_steps
    model = SAC(
        "MultiInputPolicy",
        env,
        replay_buffer_class=buffer_class,
        replay_buffer_kwargs=HER_KWARGS,
        learning_starts=steps + 1,
        buffer_size=10_000,
        seed=0,
        device="cpu",
    )
    model.learn(steps)
    buffer = model.replay_buffer
    if buffer_class is GoalRelHerReplayBuffer:
        assert buffer.goal_rel == ((part.start, part.stop),)  # read from the env
    stored = {k: v[: buffer.pos, 0] for k, v in buffer.observations.items()}
    rows = {tuple(r): i for i, r in enumerate(_other_entries(stored, part))}
    assert len(rows) > 0.9 * buffer.pos  # noise makes rows their own (the delay repeats an episode's first)
    batch = buffer.sample(512).observations
    sampled = {k: v.numpy() for k, v in batch.items()}
    index = np.array([rows[tuple(r)] for r in _other_entries(sampled, part)])
    goal_change = sampled["desired_goal"] - stored["desired_goal"][index]
    relabelled = np.abs(goal_change).max(axis=1) > 1e-6
    assert relabelled.mean() > 0.5  # 4 of 5 samples get a later achieved goal
    moved = sampled["observation"][:, part] - stored["observation"][index][:, part]
    sensor = stored["observation"][index][:, part] - (stored["desired_goal"] - stored["achieved_goal"])[index]
    assert np.median(np.abs(sensor).max(axis=1)) > 1e-3  # noise and delay: goal_rel is not goal - cube
    if buffer_class is GoalRelHerReplayBuffer:
        np.testing.assert_allclose(moved, goal_change, atol=1e-5)
    else:
        assert not moved.any()
    env.close()
