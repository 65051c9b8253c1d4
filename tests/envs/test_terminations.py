"""Terminations as terms: a task's term set names the conditions that may end an episode,
and ``terminate_on`` switches them on, in the single env and the vector env alike."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import unified_manip

PNP = "UnifiedManip/Arm4PickAndPlace-v0"


def _grasp_then_let_go(env, seed: int = 0, steps: int = 100):
    """The scripted policy until the cube is held, then the gripper opened: the infos of
    every step and the step (counted from 1) the episode ended, or None."""
    policy = unified_manip.TASKS[PNP].scripted_policy("ee_delta")
    obs, info = env.reset(seed=seed)
    infos, held = [], False
    for t in range(1, steps + 1):
        action = policy(env.unwrapped.state_observation()).astype(np.float32)
        if held:
            action[:] = 0.0
            action[-1] = 1.0  # open
        obs, reward, terminated, truncated, info = env.step(action)
        infos.append(info)
        held = held or info["grasped"] > 0.5
        if terminated:
            return infos, t
    return infos, None


def test_terminate_on_dropped_ends_the_episode_on_the_step_the_object_is_let_go():
    env = gym.make(PNP, action_mode="ee_delta", terminate_on=["dropped"])
    infos, ended = _grasp_then_let_go(env)
    assert ended is not None, "the scripted grasp never let go"
    assert infos[-1]["dropped"] == 1.0 and all(i["dropped"] == 0.0 for i in infos[:-1])
    # compute_terminated reads the same info.
    last = infos[-1]
    u = env.unwrapped
    assert u.compute_terminated(np.zeros(3), np.ones(3), last)
    assert not u.compute_terminated(np.zeros(3), np.ones(3), infos[0])
    # Without it, the same play goes on.
    infos_off, ended_off = _grasp_then_let_go(gym.make(PNP, action_mode="ee_delta"), steps=len(infos))
    assert ended_off is None and infos_off[-1]["dropped"] == 1.0


def test_the_vector_env_terminates_where_the_single_env_does():
    single = gym.make(PNP, action_mode="joint_delta", terminate_on=("dropped",))
    vec = gym.make_vec(
        PNP, num_envs=2, vectorization_mode="vector_entry_point", action_mode="joint_delta", terminate_on=("dropped",)
    )
    rng = np.random.default_rng(0)
    single.reset(seed=5)
    vec.reset(seed=[5, 6])
    for _ in range(30):
        a = rng.uniform(-1, 1, (2, 5)).astype(np.float32)
        _, _, term, trunc, info = single.step(a[0])
        _, _, vterm, vtrunc, vinfo = vec.step(a)
        assert vterm[0] == term and vinfo["dropped"][0] == info["dropped"]
        if term or trunc:
            break
    vec.close()


@pytest.mark.parametrize(
    "task,names,message",
    [
        (
            PNP,
            ("lifted",),
            "UnifiedManip/Arm4PickAndPlace-v0 has no termination 'lifted'; terminate_on takes 'dropped'",
        ),
        (
            "UnifiedManip/Arm4Reach-v0",
            ("dropped",),
            "UnifiedManip/Arm4Reach-v0 has no termination 'dropped'; terminate_on takes none",
        ),
    ],
)
def test_an_unknown_termination_names_the_valid_ones(task, names, message):
    with pytest.raises(ValueError) as err:
        gym.make(task, terminate_on=names)
    assert str(err.value) == message


def test_terminate_on_must_be_a_sequence_of_names():
    with pytest.raises(TypeError) as err:
        gym.make(PNP, terminate_on="dropped")
    # gymnasium appends where a TypeError of the env's constructor came from
    assert str(err.value).startswith("terminate_on must be a sequence of termination names, got 'dropped' was raised")
