"""Meta-World: the 50 tasks are Meta-World 3.1.1's, stepped as Meta-World steps them, with
``is_success`` equal to Meta-World's own success.

Real Meta-World and MuJoCo 3.3.0, no mocks. The contract suites cover a sample of the
50 IDs (``conftest.SAMPLED_FAMILIES``); the slow test here plays every one.
"""

from __future__ import annotations

import pickle
import warnings

import gymnasium as gym
import numpy as np
import pytest
from conftest import SAMPLED_FAMILIES

import unified_manip
from unified_manip.envs.tasks.metaworld.cameras import NAMES
from unified_manip.envs.tasks.metaworld.tasks import TASKS

pytestmark = pytest.mark.metaworld  # every test here needs the metaworld extra

#: The newest version of each task (version 1 differs from 0 only off native: the wrists'
#: damping, tested below).
IDS = [tid for tid, spec in unified_manip.TASKS.items() if spec.family == "metaworld" and spec.version == 2]


def _make(task_id: str, action_mode: str = "native", **kwargs) -> gym.Env:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Meta-World's policies warn that their gains clip
        return gym.make(task_id, action_mode=action_mode, **kwargs)


def test_the_task_list_is_metaworlds_own():
    """The static list registered without importing Meta-World is Meta-World's, in its
    order, each with its scripted policy; the cameras are the model's."""
    import metaworld
    from metaworld.policies import ENV_POLICY_MAP

    assert list(TASKS) == list(metaworld.ALL_V3_ENVIRONMENTS)
    assert [unified_manip.TASKS[tid].upstream_id for tid in IDS] == [f"metaworld:{n}" for n in TASKS]
    assert set(TASKS) <= set(ENV_POLICY_MAP)
    assert len(IDS) == 50 and IDS[0] == "UnifiedManip/MetaWorldAssembly-v2"
    assert set(SAMPLED_FAMILIES["metaworld"]) <= set(IDS)
    env = _make("UnifiedManip/MetaWorldReach-v1")
    model = env.unwrapped.backend.model
    assert sorted(NAMES) == sorted(model.camera(i).name for i in range(model.ncam))
    env.close()


def test_the_task_lists_are_metaworlds_benchmarks_and_a_grid_expands_them(tmp_path):
    """``metaworld:MT10``, ``MT50``, ``ML10-train`` and ``ML10-test`` are Meta-World's own
    lists (``metaworld.env_dict``), in its order; a bench grid's ``tasks`` may name one."""
    import metaworld.env_dict as upstream
    import yaml

    from unified_manip.envs.task_lists import TASK_LISTS, expand_task_lists
    from unified_manip.experiments.grid import load_grid

    theirs = {
        "metaworld:MT10": list(upstream.MT10_V3),
        "metaworld:MT50": list(upstream.MT50_V3),
        "metaworld:ML10-train": list(upstream.ML10_V3["train"]),
        "metaworld:ML10-test": list(upstream.ML10_V3["test"]),
    }
    ours = {name: [unified_manip.TASKS[t].upstream_id.split(":")[1] for t in ids] for name, ids in TASK_LISTS.items()}
    assert ours == theirs
    drawer, test = "UnifiedManip/MetaWorldDrawerOpen-v1", list(TASK_LISTS["metaworld:ML10-test"])
    assert expand_task_lists([drawer, "metaworld:ML10-test"]) == [drawer, *(t for t in test if t != drawer)]
    grid = tmp_path / "grid.yaml"
    doc = {"tasks": ["metaworld:ML10-test"], "action_modes": ["native"], "reward_types": ["sparse"], "algos": ["sac"]}
    only = [{"task": test[-1]}]  # the grid checks only the runs it keeps: one env built, not five
    grid.write_text(yaml.safe_dump({**doc, "seeds": [0], "steps": 1000, "only": only}))
    assert [run.task for run in load_grid(grid).runs] == [test[-1]]


@pytest.mark.parametrize("task_id", ["UnifiedManip/MetaWorldPickPlace-v1", "UnifiedManip/MetaWorldBasketball-v1"])
def test_steps_are_metaworlds_steps(task_id):
    """From one state, our steps and Meta-World's own ``step`` (on a copy of its env object,
    pickled with ours) give the same observations, goals, successes and rewards."""
    env = _make(task_id, reward_type="dense")
    env.reset(seed=3)
    twin = pickle.loads(pickle.dumps(env.unwrapped.backend)).upstream  # Meta-World's env, same state
    rng = np.random.default_rng(0)
    for t in range(40):
        a = rng.uniform(-1, 1, 4).astype(np.float32)
        obs, _, _, _, info = env.step(a)
        up_obs, up_reward, _, _, up_info = twin.step(a)
        np.testing.assert_array_equal(obs["observation"], up_obs[:36].astype(np.float32))
        target = np.array(twin._target_pos)
        if "Basketball" in task_id:
            target[2] = 0.3  # the height its success reads
        np.testing.assert_array_equal(obs["desired_goal"], target.astype(np.float32))
        assert info["native_success"] == up_info["success"] and info["native_reward"] == up_reward, t
        assert info["is_success"] == info["native_success"], t
    env.close()


def test_reset_is_seeded_and_draws_new_placements():
    env = _make("UnifiedManip/MetaWorldPickPlace-v1")
    first = [env.reset(seed=s)[0] for s in range(4)]
    again = env.reset(seed=2)[0]
    for k in again:
        np.testing.assert_array_equal(again[k], first[2][k])
    goals = {tuple(o["desired_goal"]) for o in first}
    objects = {tuple(o["achieved_goal"]) for o in first}
    assert len(goals) == len(objects) == 4
    env.close()


def test_goal_distances_reproduce_metaworlds_success_tests():
    """The distances that are not Euclidean, at both sides of their thresholds."""
    hammer, assembly, disassemble = (TASKS[n] for n in ("hammer-v3", "assembly-v3", "disassemble-v3"))
    target = np.array([0.24, 0.74, 0.11])
    nail = target + np.array([[0, -0.0101, 0], [0, -0.0099, 0], [0, 0.001, 0]])  # nail in by 8.99, 9.01, 10.1 cm
    assert (hammer.distance(nail, target) < hammer.threshold).tolist() == [False, True, True]
    peg = np.array([0.0, 0.6, 0.1])
    nut = peg + np.array([[0.015, 0, -0.01], [0.025, 0, -0.01], [0.015, 0, 0.01], [0, 0, -0.2]])
    assert (assembly.distance(nut, peg) < assembly.threshold).tolist() == [True, False, False, True]
    lifted = peg + np.array([[0, 0, 0.001], [0, 0, -0.001]])
    assert (disassemble.distance(lifted, peg) < disassemble.threshold).tolist() == [True, False]


@pytest.mark.parametrize(
    "task_id",
    # the fingertips, an object carried, a handle along one axis
    ["UnifiedManip/MetaWorldReach-v1", "UnifiedManip/MetaWorldPickPlace-v1", "UnifiedManip/MetaWorldDoorOpen-v1"],
)
def test_scripted_policy_succeeds_and_success_is_metaworlds(task_id):
    """Meta-World's own policy, one seeded episode: it succeeds, and ``is_success`` equals
    Meta-World's success at every step."""
    env = _make(task_id)
    policy = unified_manip.TASKS[task_id].scripted_policy("native")
    state = env.unwrapped.state_observation
    env.reset(seed=0)
    succeeded, disagree = False, []
    for t in range(env.spec.max_episode_steps):
        _, _, _, truncated, info = env.step(policy(state()))
        succeeded |= info["is_success"] == 1.0
        if info["is_success"] != info["native_success"]:
            disagree.append(t)
    assert truncated and succeeded and disagree == []
    env.close()


def test_scripted_policy_factory_emits_native_only():
    factory = unified_manip.TASKS["UnifiedManip/MetaWorldReach-v1"].scripted_policy
    with pytest.raises(ValueError, match="emit native actions; got action_mode='ee_delta'"):
        factory("ee_delta")


@pytest.mark.slow
def test_every_task_steps_with_metaworlds_success_and_batched_rewards():
    """All 50: 60 steps of the scripted policy each; ``is_success`` equals Meta-World's
    success (the distance part of it on the two stick tasks), and the batched
    ``compute_reward`` of the steps equals their rewards."""
    for task_id in IDS:
        task = TASKS[unified_manip.TASKS[task_id].upstream_id.split(":")[1]]
        env = _make(task_id, reward_type="dense")
        policy = unified_manip.TASKS[task_id].scripted_policy("native")
        obs, _ = env.reset(seed=1)
        ag, dg, infos, rewards = [], [], [], []
        for _ in range(60):
            obs, r, _, _, info = env.step(policy(env.unwrapped.state_observation()))
            ag.append(obs["achieved_goal"]), dg.append(obs["desired_goal"]), infos.append(info), rewards.append(r)
            if task.exact:
                assert info["is_success"] == info["native_success"], task_id
            else:
                assert info["is_success"] >= info["native_success"], task_id
        batched = env.unwrapped.compute_reward(np.array(ag), np.array(dg), np.array(infos, dtype=object))
        np.testing.assert_array_equal(batched, rewards, err_msg=task_id)
        env.close()


def test_the_recorded_page_spaces_are_the_live_envs():
    """The task pages of the site, built beside a MuJoCo Meta-World cannot run on, read
    the spaces committed in ``docs/_gen/pinned_spaces.json``: they are the live envs'."""
    import json
    import sys
    from importlib.metadata import version
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "docs" / "_gen"))
    import taskspaces

    record = json.loads(taskspaces.PINNED.read_text())
    assert record["versions"]["metaworld"] == {"mujoco": version("mujoco"), "metaworld": version("metaworld")}
    every = [tid for tid, spec in unified_manip.TASKS.items() if spec.family == "metaworld"]  # every version
    assert sorted(record["tasks"]) == sorted(every)
    by_version: dict[int, list[str]] = {}
    for tid in every:
        by_version.setdefault(unified_manip.TASKS[tid].version, []).append(tid)
    for task_version, ids in sorted(by_version.items()):  # a version's IDs share their spaces; one is measured
        task_id = next((t for t in SAMPLED_FAMILIES["metaworld"] if t in ids), ids[0])
        assert taskspaces.measure(task_id) == record["tasks"][task_id], task_id
        assert all(record["tasks"][t] == record["tasks"][task_id] for t in ids), task_version


def test_collect_plays_the_scripted_policy_in_native():
    """``collect --policy scripted`` records Meta-World's policy in the mode it emits."""
    from unified_manip.datasets.policies import scripted

    env = _make("UnifiedManip/MetaWorldReach-v1")
    obs, _ = env.reset(seed=0)
    ours, theirs = scripted(env), unified_manip.TASKS["UnifiedManip/MetaWorldReach-v1"].scripted_policy("native")
    for _ in range(20):
        action = ours(obs)
        np.testing.assert_array_equal(action, theirs(env.unwrapped.state_observation()))
        obs, *_ = env.step(action)
    env.close()


def test_joint_modes_start_where_native_starts_and_drive_the_sawyer():
    """Meta-World's reset (its mocap brings the hand to its start) carries over to the
    actuated copy exactly; a joint target moves the joint, and -1 closes the fingers."""
    native, joint = (
        _make("UnifiedManip/MetaWorldPickPlace-v1"),
        _make("UnifiedManip/MetaWorldPickPlace-v1", action_mode="joint_target_delta"),
    )
    a, b = native.reset(seed=4)[0], joint.reset(seed=4)[0]
    for key in a:
        np.testing.assert_array_equal(a[key], b[key])
    rig = joint.unwrapped.backend.rig
    q0 = rig.joint_positions().copy()
    action = np.zeros(8, dtype=np.float32)
    action[[3, 7]] = (1.0, -1.0)  # j3 up by 0.05 rad a step, fingers closing
    for _ in range(20):
        obs, _, _, truncated, _ = joint.step(action)
    moved = rig.joint_positions() - q0
    assert moved[3] > 0.5 and np.abs(np.delete(moved, 3)).max() < 0.05 and not truncated
    assert obs["observation"][3] < b["observation"][3] - 0.3  # the gripper's opening shrank
    native.close(), joint.close()


def test_version_1_lets_the_wrists_outrun_the_cap_of_version_0():
    """Meta-World damps every joint with 10 N m s/rad, which holds a wrist (9 N m) to
    0.9 rad/s: a wrist target moving at 4 rad/s (0.05 rad per 12.5 ms step) is followed
    at 0.9 rad/s in v0. v1's wrist damping of 1 lets it follow; native is the same."""
    peaks, moved = {}, {}
    for version in (0, 1):
        env = _make(f"UnifiedManip/MetaWorldPickPlace-v{version}", action_mode="joint_target_delta")
        env.reset(seed=4)
        rig = env.unwrapped.backend.rig
        q0, action = rig.joint_positions().copy(), np.zeros(8, dtype=np.float32)
        action[4] = 1.0  # right_j4's target up 0.05 rad a step
        speeds = []
        for _ in range(15):
            env.step(action)
            speeds.append(abs(rig.data.qvel[rig.dof_adr[4]]))
        peaks[version], moved[version] = max(speeds), rig.joint_positions()[4] - q0[4]
        env.close()
    assert 0.85 < peaks[0] < 0.91 and peaks[1] > 3.0, peaks
    assert moved[1] > 2.5 * moved[0]
    a, b = (_make(f"UnifiedManip/MetaWorldPickPlace-v{v}") for v in (0, 1))
    obs = [env.reset(seed=4)[0] for env in (a, b)]
    for _ in range(20):
        step = [env.step(np.array([1.0, 0.0, -1.0, 1.0], dtype=np.float32))[0] for env in (a, b)]
        obs.extend(step)
    np.testing.assert_array_equal(obs[-2]["observation"], obs[-1]["observation"])


@pytest.mark.parametrize("mode", ["native", "ee_delta", "joint_delta", "joint_target_delta"])
def test_version_2_shows_the_joint_modes_the_robots_joints_and_changes_nothing_else(mode):
    """v2's joint modes append the 7 arm joints, the 2 finger slides and their velocities
    to v1's vector; with the same seed and actions, everything else is v1's, bit for bit,
    and native and the ee modes are v1 whole."""
    v1, v2 = (_make(f"UnifiedManip/MetaWorldPickPlace-v{v}", action_mode=mode) for v in (1, 2))
    joints = mode.startswith("joint")
    assert v2.observation_space["observation"].shape == ((54,) if joints else (36,))
    pairs = [(v1.reset(seed=2)[0], v2.reset(seed=2)[0], 0.0, 0.0, {}, {})]
    rng = np.random.default_rng(0)
    for _ in range(30):
        action = rng.uniform(-1, 1, v1.action_space.shape).astype(np.float32)
        (o1, r1, *_, i1), (o2, r2, *_, i2) = v1.step(action), v2.step(action)
        pairs.append((o1, o2, r1, r2, i1, i2))
        if joints:
            rig = v2.unwrapped.backend.rig
            np.testing.assert_array_equal(o2["observation"][36:43], rig.joint_positions().astype(np.float32))
            assert np.abs(o2["observation"][45:52]).max() > 0  # the arm moves
    for o1, o2, r1, r2, i1, i2 in pairs:
        np.testing.assert_array_equal(o1["observation"], o2["observation"][:36])
        for key in ("achieved_goal", "desired_goal"):
            np.testing.assert_array_equal(o1[key], o2[key])
        assert r1 == r2 and i1.keys() == i2.keys() and all(np.array_equal(i1[k], i2[k]) for k in i1)
    v1.close(), v2.close()


def test_collect_translates_the_scripted_policy_into_the_end_effector_modes():
    """In ee_target_delta, whose step is Meta-World's 1 cm, the translated actions are
    Meta-World's with the gripper's sign flipped (the target moves as the mocap); in
    ee_delta the translated policy closes the drawer."""
    from unified_manip.datasets.policies import scripted

    task_id = "UnifiedManip/MetaWorldDrawerClose-v1"
    env = _make(task_id, action_mode="ee_target_delta")
    theirs = unified_manip.TASKS[task_id].scripted_policy("native")
    obs, _ = env.reset(seed=0)
    ours = scripted(env)
    for _ in range(30):
        native = theirs(env.unwrapped.state_observation())
        action = ours(obs)
        np.testing.assert_allclose(action, np.clip(np.append(native[:3], -native[3]), -1, 1), atol=1e-5)
        obs, *_ = env.step(action)
    env.close()
    env = _make(task_id, action_mode="ee_delta")
    obs, _ = env.reset(seed=0)
    policy = scripted(env)
    for _ in range(150):
        obs, _, _, _, info = env.step(policy(obs))
        if info["is_success"]:
            break
    assert info["is_success"] == 1.0 and info["native_success"] == 1.0
    env.close()
