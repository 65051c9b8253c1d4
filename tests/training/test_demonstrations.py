"""Scripted-policy demonstrations in the replay buffer (``demonstrations: N``, issue 10).

The contract: N episodes (rounded up to whole rounds of the envs) of the task's scripted
policy go into the replay buffer before training, whole and consistent with the task's
reward, played in envs of their own (the run's monitor and step count hold the agent's
episodes only), once per run (a resumed run does not play them again). Runs that cannot
take them are a clear error.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from conftest import interrupt_after_first_checkpoint

import unified_manip
from unified_manip.training import checkpoints
from unified_manip.training.demonstrations import DemonstrationError, check, episodes_per_env, policies, prefill
from unified_manip.training.request import TrainRequest
from unified_manip.training.train import train

ARM = "UnifiedManip/Arm4PickAndPlace-v0"
FETCH = "UnifiedManip/FetchPickAndPlace-v0"


def _model_and_env(task_id: str, n_envs: int, vec: str):
    from sb3_contrib import TQC
    from stable_baselines3 import HerReplayBuffer

    from unified_manip.training.run_envs import make_vec_env

    kwargs = {"action_mode": "ee_delta", "reward_type": "sparse"}
    venv = make_vec_env(task_id, kwargs, n_envs, 7, None, vec)
    model = TQC(
        "MultiInputPolicy",
        make_vec_env(task_id, kwargs, n_envs, 0, None, vec),
        buffer_size=5000,
        replay_buffer_class=HerReplayBuffer,
        learning_starts=10,
        batch_size=16,
        seed=0,
    )
    return model, venv


@pytest.mark.parametrize("task_id,n_envs,vec", [(ARM, 2, "native"), (FETCH, 1, "dummy")])
def test_prefill_stores_whole_scripted_episodes_consistent_with_the_reward(task_id, n_envs, vec):
    model, venv = _model_and_env(task_id, n_envs, vec)
    horizon = gym.spec(task_id).max_episode_steps
    done = prefill(model, venv, task_id, "ee_delta", episodes=3)
    per_env = episodes_per_env(3, n_envs)
    assert done["episodes"] == per_env * n_envs
    assert done["transitions"] == per_env * n_envs * horizon
    buffer = model.replay_buffer
    rows = buffer.size()
    assert rows * n_envs == done["transitions"]
    # Whole episodes: every stored row knows its episode's full length.
    assert np.all(buffer.ep_length[:rows] == horizon)
    # The stored sparse rewards are the task's reward of the stored next achieved goal.
    env = gym.make(task_id, action_mode="ee_delta", reward_type="sparse")
    ag = buffer.next_observations["achieved_goal"][:rows].reshape(rows * n_envs, -1)
    dg = buffer.observations["desired_goal"][:rows].reshape(rows * n_envs, -1)
    expected = env.unwrapped.compute_reward(ag, dg, [{}] * len(ag))
    np.testing.assert_allclose(buffer.rewards[:rows].reshape(-1), expected, atol=1e-6)
    # The reported success is the fraction of episodes whose last step met the goal.
    last = buffer.rewards[horizon - 1 : rows : horizon].reshape(-1)
    assert done["success"] == pytest.approx(float(np.mean(last == 0.0)))
    assert done["success"] >= 0.5  # the scripted policy solves most episodes (>= 0.9 over 100)
    assert np.all(np.abs(buffer.actions[:rows]) <= 1.0)
    # HER samples from the demonstrations (relabelled goals included).
    sample = buffer.sample(32, env=None)
    assert sample.rewards.shape == (32, 1)
    venv.close()


def test_action_noise_measures_how_much_each_mode_disturbs_the_scripted_policy():
    """``python -m benchmarks.exploration --noise``: without noise it is the
    demonstrations' own success; the same small noise that joint_delta shrugs off (its
    step scales it) breaks joint_position, where it moves the absolute target."""
    from benchmarks.exploration import noisy_demonstrations

    assert noisy_demonstrations(ARM, "joint_delta", 0.0, episodes=3) == 1.0
    assert noisy_demonstrations(ARM, "joint_delta", 0.1, episodes=3) == 1.0
    assert noisy_demonstrations(ARM, "joint_position", 0.0, episodes=3) == 1.0
    assert noisy_demonstrations(ARM, "joint_position", 0.1, episodes=3) == 0.0


def test_footprint_shows_absolute_targets_use_a_small_part_of_the_action_box():
    """``python -m benchmarks.exploration --footprint``: the scripted pick-and-place
    uses most of each incremental mode's range, but only a narrow band of each arm
    joint's absolute-target range, and changes its absolute targets far less per step."""
    from benchmarks.exploration import footprint

    position, position_change = footprint(ARM, "joint_position", episodes=2)
    delta, delta_change = footprint(ARM, "joint_delta", episodes=2)
    assert position.shape == delta.shape == gym.make(ARM, action_mode="joint_position").action_space.shape
    assert np.all((position >= 0.0) & (position <= 1.0))
    assert np.all(position[:-1] < 0.5) and position[-1] == 1.0  # arm joints a band; gripper open and shut
    assert np.all(delta[:-1] > 0.5)
    assert position_change < delta_change / 2


@pytest.mark.parametrize("mode", unified_manip.TASKS[ARM].action_modes)
def test_the_scripted_policy_solves_pick_and_place_in_every_arm_mode(mode):
    """Demonstrations in every action mode (issue 10, item 5): the ee_delta policy's
    motion, translated into the mode's own actions, still solves the task."""
    venv = _dummy(ARM, mode, n_envs=1)
    act = policies(ARM, mode, venv)[0]
    env = venv.envs[0]
    successes = []
    for seed in range(5):
        obs, _ = env.reset(seed=seed)
        for _ in range(gym.spec(ARM).max_episode_steps):
            action = act(obs)
            assert action.shape == env.action_space.shape and np.all(np.abs(action) <= 1.0)
            obs, _, terminated, truncated, info = env.step(action)
            if terminated or truncated:
                break
        successes.append(info["is_success"])
    # Measured over these seeds: 1.0 in every mode but joint_torque (0.8).
    assert np.mean(successes) >= 0.8, (mode, successes)


def test_in_joint_position_mode_the_translation_is_the_ee_delta_command():
    """joint_position gets the same IK targets the ee_delta controller sends: the same
    rollout, up to the IK's own rounding."""
    rollouts = {}
    for mode in ("ee_delta", "joint_position"):
        venv = _dummy(ARM, mode, n_envs=1)
        act, env = policies(ARM, mode, venv)[0], venv.envs[0]
        obs, _ = env.reset(seed=3)
        goals = []
        for _ in range(60):
            obs, *_ = env.step(act(obs))
            goals.append(obs["achieved_goal"])
        rollouts[mode] = np.array(goals)
    np.testing.assert_allclose(rollouts["joint_position"], rollouts["ee_delta"], atol=1e-4)


@pytest.mark.parametrize("mode", ["ee_delta", "joint_delta"])
def test_demonstrations_are_the_same_episodes_in_every_observation_design(mode):
    """The scripted policy reads the state, not the agent's observation: the same actions
    and successes under another design, recorded in that design (issue 41: demonstrations
    must not depend on the design). Noise and distractors draw from the env's generator,
    which also samples the next episode's goal, so with them only the seeded first episode
    is the same."""
    from sb3_contrib import TQC
    from stable_baselines3 import HerReplayBuffer

    from unified_manip.training.run_envs import make_vec_env

    horizon = gym.spec(ARM).max_episode_steps
    designs = {
        "default": {},
        "minimal, delayed": {"observation": "minimal", "observation_delay": 1},
        "noisy, distractors": {"observation": "relative", "observation_distractors": 8, "observation_noise": 0.01},
    }
    stored = {}
    for name, kwargs in designs.items():
        config = {"action_mode": mode, "reward_type": "sparse", **kwargs}
        venv = make_vec_env(ARM, config, 1, 7, None, "dummy")
        model = TQC(
            "MultiInputPolicy",
            make_vec_env(ARM, config, 1, 0, None, "dummy"),
            buffer_size=500,
            replay_buffer_class=HerReplayBuffer,
            learning_starts=10,
            seed=0,
        )
        done = prefill(model, venv, ARM, mode, episodes=2)
        buffer = model.replay_buffer
        width = buffer.observations["observation"].shape[-1]
        assert width == gym.make(ARM, action_mode=mode, **kwargs).observation_space["observation"].shape[0]
        stored[name] = (done, buffer.actions[: buffer.size()].copy(), width)
        venv.close()
    done, actions, width = stored["default"]
    assert done["episodes"] == 2 and done["success"] == 1.0
    done_d, actions_d, width_d = stored["minimal, delayed"]
    np.testing.assert_array_equal(actions_d, actions)
    assert done_d == done and width_d != width  # recorded as the agent sees it
    done_n, actions_n, width_n = stored["noisy, distractors"]
    np.testing.assert_array_equal(actions_n[:horizon], actions[:horizon])
    assert done_n["success"] == 1.0 and width_n != width


def test_the_native_vector_env_demonstrates_only_ee_delta_in_the_default_design():
    from unified_manip.training.run_envs import make_vec_env

    venv = make_vec_env(ARM, {"action_mode": "ee_delta", "observation": "minimal"}, 2, 0, None, "native")
    with pytest.raises(DemonstrationError) as err:
        policies(ARM, "ee_delta", venv)
    assert str(err.value) == (
        "demonstrations in action_mode 'ee_delta' with observation design 'minimal' are played in a DummyVecEnv "
        "(the scripted policy reads each env's state); this vector env can play ee_delta with the default design only"
    )
    venv.close()


def _dummy(task_id: str, mode: str, n_envs: int):
    from unified_manip.training.run_envs import make_vec_env

    return make_vec_env(task_id, {"action_mode": mode, "reward_type": "sparse"}, n_envs, 0, None, "dummy")


def _request(run_dir: Path, algo: str = "tqc_her", mode: str = "ee_delta", **overrides) -> TrainRequest:
    settings = {
        "demonstrations": 2,
        "learning_starts": 50,
        "batch_size": 32,
        "eval_freq": 1000,
        "n_eval_episodes": 1,
        "checkpoint_freq": 200,
        "n_envs": 1,
    }
    settings.update(overrides)
    return TrainRequest(
        env=ARM,
        action_mode=mode,
        reward_type="sparse",
        algo=algo,
        steps=300,
        run_dir=run_dir,
        overrides=tuple(f"{k}={v}" for k, v in settings.items()),
    )


def _buffer_rows(path: Path) -> int:
    import pickle

    with open(path, "rb") as f:
        return pickle.load(f).size()  # the final buffer, as SB3's save_replay_buffer writes it


@pytest.mark.slow
@pytest.mark.parametrize("mode", ["ee_delta", "joint_velocity"])
def test_a_run_with_demonstrations_keeps_them_apart_from_its_own_episodes(mode, tmp_path):
    run = tmp_path / "run"
    logs: list[str] = []
    train(_request(run, mode=mode), progress=False, threads=1, log=logs.append)
    record = json.loads((run / "demonstrations.json").read_text())
    assert record["episodes"] == 2 and record["transitions"] == 200
    assert any("2 demonstration episodes (200 transitions" in line for line in logs)
    # The monitor holds the agent's 3 episodes of 100 steps, not the demonstrations.
    with open(next((run / "monitor").rglob("*.monitor.csv"))) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    assert [int(r["l"]) for r in rows] == [100, 100, 100]
    assert json.loads((run / "status.json").read_text())["num_timesteps"] == 300
    # The final buffer holds both: 200 demonstration transitions and the agent's 300.
    assert _buffer_rows(run / "replay_buffer.pkl") == 500


@pytest.mark.slow
def test_a_resumed_run_does_not_play_its_demonstrations_again(tmp_path):
    run = tmp_path / "run"
    first: list[str] = []
    interrupt_after_first_checkpoint(run, lambda: train(_request(run), progress=False, threads=1, log=first.append))
    assert any("demonstration episodes" in line for line in first)
    step = json.loads((run / "status.json").read_text())["num_timesteps"]
    assert 200 <= step < 300
    again: list[str] = []
    train(_request(run), progress=False, threads=1, log=again.append)
    assert not any("demonstration episodes" in line for line in again)
    assert any(f"resuming from step {step} of 300 on cpu with {200 + step} transitions" in line for line in again), (
        again
    )
    assert _buffer_rows(run / "replay_buffer.pkl") == 500


@pytest.mark.slow
def test_ctrl_c_while_demonstrations_play_stops_the_run_with_them_checkpointed(tmp_path):
    """A bench worker ignores SIGINT until train() takes it over. Ctrl-C that lands while
    the demonstrations play (or a checkpoint loads) stops the run before its first
    rollout, with a whole checkpoint that keeps the demonstrations; it was once lost, and
    the run trained on to its end."""
    import os
    import signal

    run = tmp_path / "run"

    def interrupt_once_demonstrated(line: str) -> None:
        if "demonstration episodes" in line:
            os.kill(os.getpid(), signal.SIGINT)

    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)  # as in a bench worker
    try:
        with pytest.raises(KeyboardInterrupt):
            train(_request(run), progress=False, threads=1, log=interrupt_once_demonstrated)
        assert signal.getsignal(signal.SIGINT) == signal.SIG_IGN  # train() put the caller's handler back
    finally:
        signal.signal(signal.SIGINT, previous)
    status = json.loads((run / "status.json").read_text())
    assert (status["state"], status["num_timesteps"]) == ("running", 0)
    written = checkpoints.newest(run)
    assert written.step == 0 and written.digests[checkpoints.REPLAY_BUFFER]["rows"] == 200
    again: list[str] = []
    train(_request(run), progress=False, threads=1, log=again.append)
    assert not any("demonstration episodes" in line for line in again)
    assert any("resuming from step 0 of 300 on cpu with 200 transitions" in line for line in again), again
    assert _buffer_rows(run / "replay_buffer.pkl") == 500


@pytest.mark.robosuite
def test_the_shipped_recipe_leaves_demonstrations_out_of_robosuites_own_controller(tmp_path):
    """tqc_her.yaml gives Lift-v0 100 demonstrations (test_train checks the resolved
    entries), and its "Lift-v0 native" entry takes them out again, as no scripted policy
    plays robosuite's own controller: with no --set, a native run trains without them
    instead of being refused."""
    import yaml

    run = tmp_path / "run"
    settings = (
        "n_envs=1",
        "learning_starts=1000",
        "buffer_size=2000",
        "eval_freq=1000",
        "n_eval_episodes=1",
        "checkpoint_freq=1000",
    )
    logs: list[str] = []
    status = train(
        TrainRequest(
            env="UnifiedManip/Lift-v0",
            action_mode="native",
            reward_type="sparse",
            algo="tqc_her",
            steps=20,
            run_dir=run,
            overrides=settings,
        ),
        progress=False,
        threads=1,
        log=logs.append,
    )
    assert status["state"] == "finished"
    config = yaml.safe_load((run / "config.yaml").read_text())
    assert config["hyperparameters"]["demonstrations"] == 0
    assert not (run / "demonstrations.json").exists()
    assert not any("demonstration episodes" in line for line in logs), logs


@pytest.mark.metaworld
def test_meta_worlds_scripted_policy_demonstrates_in_its_own_native_mode():
    """Meta-World's policies emit native actions: native is demonstrable (with the shared
    modes), and two prefilled native episodes of Reach are whole and end in success."""
    from sb3_contrib import TQC
    from stable_baselines3 import HerReplayBuffer

    from unified_manip.training.demonstrations import demonstrable_modes
    from unified_manip.training.run_envs import make_vec_env

    task_id = "UnifiedManip/MetaWorldReach-v1"
    assert demonstrable_modes(task_id) == list(unified_manip.TASKS[task_id].action_modes)
    check(task_id, "native", True, 2)
    venv = make_vec_env(task_id, {"action_mode": "native", "reward_type": "sparse"}, 1, 0, None, "dummy")
    model = TQC("MultiInputPolicy", venv, buffer_size=2000, replay_buffer_class=HerReplayBuffer, seed=0)
    done = prefill(model, venv, task_id, "native", episodes=2)
    horizon = gym.spec(task_id).max_episode_steps
    assert done == {"episodes": 2, "transitions": 2 * horizon, "success": 1.0}
    assert np.all(model.replay_buffer.ep_length[: 2 * horizon] == horizon)
    venv.close()


@pytest.mark.parametrize(
    "algo,task_id,mode,episodes,message",
    [
        ("ppo", ARM, "ee_delta", 2, "demonstrations go into a replay buffer; use an off-policy algorithm (sac, td3, "),
        (
            "tqc_her",
            FETCH,
            "native",
            2,
            "action_mode 'native' is the source's own controller, which the scripted "
            "ee_delta policy cannot drive; use one of joint_torque, ",
        ),
        ("sac_her", "UnifiedManip/HandReach-v0", "native", 2, "UnifiedManip/HandReach-v0 has no scripted policy"),
        ("tqc_her", ARM, "ee_delta", -1, "demonstrations must be a number of episodes, 0 or more; got -1"),
    ],
)
def test_runs_that_cannot_take_demonstrations_are_refused(algo, task_id, mode, episodes, message):
    from unified_manip.training.algorithms import get_algo

    with pytest.raises(DemonstrationError) as err:
        check(task_id, mode, get_algo(algo).off_policy, episodes)
    assert message in str(err.value)
    check(task_id, mode, get_algo(algo).off_policy, 0)  # none asked: always fine


def test_the_cli_refuses_demonstrations_for_ppo_in_one_line(tmp_path):
    import subprocess
    import sys

    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "unified_manip.cli",
            "train",
            "--env",
            ARM,
            "--algo",
            "ppo",
            "--steps",
            "10",
            "--set",
            "demonstrations=5",
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
    assert len(lines) == 1 and "use an off-policy algorithm" in lines[0], proc.stderr
    assert not (tmp_path / "r").exists()
