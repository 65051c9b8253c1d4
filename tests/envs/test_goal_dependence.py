"""Which observation groups depend on the goal, measured on every ID, against the groups
marked ``goal_dependent`` (the ones HER relabelling moves; :mod:`unified_manip.training.her`).

Two envs of one ID reset with different seeds hold different goals (where a task's goal is
fixed, the second env's ``desired_goal`` is moved by hand: the goal hindsight relabelling
would give it). Both are put at one physics state and stepped alike; every group that then
differs between them depends on the goal. A family with no stateless mode (Meta-World's
mocap) plays one seeded episode twice instead, the second with its goal moved. A marked group must differ by exactly the change of ``desired_goal`` (the
relabelling shifts it by that change), every other group not at all.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from conftest import ALL_IDS

import unified_manip

#: The goal-dependent groups of each family's default observation (the arm's ends with
#: goal - cube, or goal - grip site on Reach; Fetch, the Shadow Hand and robosuite keep
#: upstream's vectors, which hold no goal). A new family is listed here once measured.
DEFAULT_GOAL_DEPENDENT = {
    "arm4": {"goal_rel"},
    "fetch": set(),
    "shadow_hand": set(),
    "robosuite": set(),
    "adroit": set(),
    "kitchen": set(),
    "valve": {"goal_rel"},
    "metaworld": set(),
}

#: How far a fixed goal is moved, entry for entry.
MOVE = 0.1

#: Action modes whose controller keeps no memory of the episode, so two envs put at one
#: physics state step alike (the target-holding modes would carry each env's reset along).
STATELESS_MODES = ("joint_torque", "joint_delta")

#: Steps after the common state: robosuite's object observables read the grip pose of the
#: step before, which the second step makes common too.
STEPS = 2


def _at_one_state_with_two_goals(task_id: str):
    """Two envs of ``task_id`` (design ``full``) with different goals, put at one physics
    state and stepped alike; their last observations and the envs."""
    spec = unified_manip.TASKS[task_id]
    mode = next((m for m in STATELESS_MODES if m in spec.action_modes), None)
    if mode is None:  # only a controller with memory (Meta-World's mocap): one seed, one episode
        return _one_episode_with_two_goals(task_id)
    envs = [gym.make(task_id, action_mode=mode, observation="full") for _ in range(2)]
    for seed, env in enumerate(envs):
        env.reset(seed=seed)
    first, second = (env.unwrapped.backend for env in envs)
    if np.array_equal(first.desired_goal(), second.desired_goal()):  # a fixed goal
        # The first's seed too: a seed that draws only observation noise (the kitchen's)
        # would move every noisy group.
        envs[1].reset(seed=0)
        _move_goal(second)
    # The scene's fixed placements live in the model (robosuite places Door's frame by
    # moving its body): the second env takes the first's.
    second.model.body_pos[:] = first.model.body_pos
    second.model.body_quat[:] = first.model.body_quat
    state = first.get_state()
    # Both go through set_state's mj_forward, so the derived quantities agree too.
    first.set_state(second.get_state())
    first.set_state(state)
    second.set_state(state)
    # The contact solver starts from the last step's accelerations, which the state leaves
    # out: with objects resting on the table, the last bits would differ.
    second.data.qacc_warmstart[:] = first.data.qacc_warmstart
    action = np.zeros(envs[0].action_space.shape, dtype=np.float32)
    for _ in range(STEPS):
        obs = [env.step(action)[0] for env in envs]
    return obs, envs


def _move_goal(backend) -> None:
    """Move ``backend``'s goal by :data:`MOVE`: the goal hindsight relabelling would give it."""
    fixed = backend.desired_goal
    backend.desired_goal = lambda: np.asarray(fixed()) + MOVE


def _one_episode_with_two_goals(task_id: str):
    """Two envs of ``task_id`` (``native``, design ``full``) reset with one seed, the second's
    goal moved, stepped alike: the same episode under two goals."""
    envs = [gym.make(task_id, action_mode="native", observation="full") for _ in range(2)]
    for env in envs:
        env.reset(seed=0)
    _move_goal(envs[1].unwrapped.backend)
    action = np.zeros(envs[0].action_space.shape, dtype=np.float32)
    for _ in range(STEPS):
        obs = [env.step(action)[0] for env in envs]
    return obs, envs


@pytest.mark.parametrize("task_id", ALL_IDS, ids=lambda t: t.split("/")[1])
def test_the_groups_that_depend_on_the_goal_are_the_marked_ones(task_id):
    (a, b), envs = _at_one_state_with_two_goals(task_id)
    np.testing.assert_array_equal(a["achieved_goal"], b["achieved_goal"])  # one physics state
    goal_change = a["desired_goal"] - b["desired_goal"]
    assert np.abs(goal_change).max() > 1e-3, "the two seeds drew the same goal: nothing to measure"
    env = envs[0].unwrapped
    marked = env.goal_dependent_layout
    measured = set()
    for name, part in env.observation_layout.items():
        change = a["observation"][part] - b["observation"][part]
        if np.any(change != 0):
            measured.add(name)
        if name in marked:
            np.testing.assert_allclose(change, goal_change, atol=1e-5, err_msg=name)
    assert measured == set(marked), f"depend on the goal: {sorted(measured)}; marked: {sorted(marked)}"
    default = set(env.backend.default_observation())
    assert default & measured == DEFAULT_GOAL_DEPENDENT[unified_manip.TASKS[task_id].family]
    for e in envs:
        e.close()


def test_the_layout_of_the_goal_dependent_groups_follows_the_design():
    env = gym.make("UnifiedManip/Arm4Push-v0", observation=["goal_rel", "object_pos"], observation_distractors=2)
    assert env.unwrapped.goal_dependent_layout == {"goal_rel": slice(0, 3)}
    env.close()
    env = gym.make("UnifiedManip/Arm4Push-v0")  # the default ends with goal - cube (the task page's 31-33)
    assert env.unwrapped.goal_dependent_layout == {"goal_rel": slice(31, 34)}
    env.close()
    env = gym.make("UnifiedManip/FetchPush-v0")
    assert env.unwrapped.goal_dependent_layout == {}
    env.close()
    vec = gym.make_vec("UnifiedManip/Arm4Reach-v0", num_envs=2, vectorization_mode="vector_entry_point")
    assert vec.unwrapped.goal_dependent_layout == {"goal_rel": slice(15, 18)}
    vec.close()
