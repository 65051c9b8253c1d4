"""Fetch: native parity with gymnasium-robotics, and joint modes that really move the arm."""

from __future__ import annotations

import gymnasium as gym
import gymnasium_robotics
import numpy as np
import pytest
from conftest import make

import unified_manip
from unified_manip.envs.tasks.fetch import ARM_JOINTS, FROZEN_JOINTS

gym.register_envs(gymnasium_robotics)

FETCH = ["FetchReach", "FetchPush", "FetchSlide", "FetchPickAndPlace"]
JOINT_MODES = ["joint_torque", "joint_position", "joint_delta", "joint_velocity"]


# ---------------------------------------------------------------------- native parity
@pytest.mark.parametrize("name", FETCH)
def test_native_sparse_is_identical_to_upstream(name):
    """Same seed and actions: observations, rewards and is_success equal gym.make("...-v4")'s."""
    ours = make(f"UnifiedManip/{name}-v0", "native", "sparse")
    ref = gym.make(f"{name}-v4")
    assert unified_manip.TASKS[f"UnifiedManip/{name}-v0"].upstream_id == f"{name}-v4"
    successes = 0
    for seed in (0, 1, 2, 3):
        o1, i1 = ours.reset(seed=seed)
        o2, _ = ref.reset(seed=seed)
        rng = np.random.default_rng(seed)
        for t in range(51):  # one step past the time limit: both truncate identically
            for key in ("observation", "achieved_goal", "desired_goal"):
                assert o1[key].dtype == np.float32
                np.testing.assert_array_equal(o1[key], o2[key].astype(np.float32), err_msg=f"{key} seed {seed} t {t}")
            if t == 50:
                break
            a = rng.uniform(-1, 1, 4).astype(np.float32)
            if t < 30:  # steer to the goal (reach) or the object, so contacts and successes happen
                to = o2["desired_goal"] - o2["achieved_goal"] if name == "FetchReach" else o2["observation"][6:9]
                a[:3] = np.clip(10 * to, -1, 1)
            o1, r1, term1, trunc1, i1 = ours.step(a)
            o2, r2, term2, trunc2, i2 = ref.step(a)
            assert r1 == float(r2), (seed, t)
            assert i1["is_success"] == float(i2["is_success"]), (seed, t)
            assert (term1, trunc1) == (term2, trunc2)
            successes += i1["is_success"]
    if name == "FetchReach":
        assert successes > 0  # the comparison covered successful steps too


# ---------------------------------------------------------------------- joint modes
def _env(mode, task="UnifiedManip/FetchPickAndPlace-v0"):
    env = make(task, mode, max_episode_steps=1000)
    env.reset(seed=0)
    backend = env.unwrapped._backend
    return env, backend, backend.rig


def _q(rig):
    return rig.data.qpos[rig.qpos_adr].copy()


def _frozen(backend):
    m = backend.model
    return backend.data.qpos[[m.jnt_qposadr[m.joint(j).id] for j in FROZEN_JOINTS]].copy()


def _hold_action(mode, rig):
    """The action that asks the arm to stay where it is (gripper closed)."""
    if mode == "joint_position":
        arm = (_q(rig) - 0.5 * (rig.upper + rig.lower)) / (0.5 * (rig.upper - rig.lower))
    else:
        arm = np.zeros(rig.n)
    return np.append(arm, -1.0).astype(np.float32)


@pytest.mark.parametrize("mode", JOINT_MODES)
def test_zero_command_holds_the_arm_against_gravity(mode):
    env, backend, rig = _env(mode)
    assert env.action_space.shape == (8,)
    assert env.observation_space["observation"].shape == (25 + 14,)
    for _ in range(10):  # let the reset's residual motion die out
        obs, *_ = env.step(_hold_action(mode, rig))
    q0, base0 = _q(rig), _frozen(backend)
    for _ in range(50):  # 2 s
        obs, *_ = env.step(_hold_action(mode, rig) if mode == "joint_position" else np.append(np.zeros(7), -1.0))
    np.testing.assert_allclose(_q(rig), q0, atol=0.01)
    np.testing.assert_allclose(_frozen(backend), base0, atol=1e-4)
    # The appended observation entries are the arm's angles and velocities.
    np.testing.assert_allclose(obs["observation"][25:32], _q(rig), atol=1e-6)
    np.testing.assert_allclose(obs["observation"][32:39], backend.data.qvel[rig.dof_adr], atol=1e-5)


@pytest.mark.parametrize("mode", JOINT_MODES)
@pytest.mark.parametrize("joint", range(7))
def test_joint_mode_drives_a_joint_to_its_target(mode, joint):
    env, backend, rig = _env(mode)
    base0 = _frozen(backend)
    q0 = _q(rig)
    target = q0.copy()
    target[joint] -= 0.3  # this direction keeps the gripper clear of the table
    for _ in range(75):  # 3 s
        q, qd = _q(rig), backend.data.qvel[rig.dof_adr]
        if mode == "joint_position":
            arm = (target - 0.5 * (rig.upper + rig.lower)) / (0.5 * (rig.upper - rig.lower))
        elif mode == "joint_delta":
            arm = (target - q) / backend.control.config.max_delta
        elif mode == "joint_velocity":
            arm = 10.0 * (target - q) / backend.control.scale
        else:  # the test closes a PD loop through the torque interface
            arm = (400.0 * (target - q) - 20.0 * qd) / rig.max_torque
        env.step(np.append(np.clip(arm, -1, 1), -1.0).astype(np.float32))
    np.testing.assert_allclose(_q(rig), target, atol=0.02)
    np.testing.assert_allclose(_frozen(backend), base0, atol=1e-4)


def test_joint_velocity_tracks_commanded_speed():
    env, backend, rig = _env("joint_velocity")
    a = np.zeros(8, np.float32)
    a[0] = 0.3
    for _ in range(10):
        env.step(a)
    assert backend.data.qvel[rig.dof_adr][0] == pytest.approx(0.3 * backend.control.scale[0], rel=0.1)


def test_actuated_copy_has_arm_servos_no_weld_and_gravcomp():
    import mujoco

    env, backend, rig = _env("joint_position")
    m = backend.model
    assert [m.joint(m.actuator_trnid[i, 0]).name for i in rig.actuator_ids] == list(ARM_JOINTS)
    assert not (m.eq_type == mujoco.mjtEq.mjEQ_WELD).any()
    assert m.body_gravcomp[m.body("robot0:shoulder_pan_link").id] == 1.0
    assert m.body_gravcomp[m.body("robot0:gripper_link").id] == 1.0
    # native keeps upstream's model: the weld and no arm actuators.
    native = make("UnifiedManip/FetchPickAndPlace-v0", "native").unwrapped._backend.model
    assert (native.eq_type == mujoco.mjtEq.mjEQ_WELD).sum() == 1 and native.nu == 2


@pytest.mark.parametrize("mode", ["joint_delta", "ee_delta"])
def test_blocked_gripper_stays_closed_without_writing_qpos(mode):
    env, backend, rig = _env(mode, "UnifiedManip/FetchPush-v0")
    a = np.zeros(env.action_space.shape, np.float32)
    a[-1] = 1.0  # "open": ignored, as upstream ignores it on Push
    for _ in range(20):
        obs, *_ = env.step(a)
    np.testing.assert_allclose(obs["observation"][9:11], 0.0, atol=2e-3)
    assert np.all(backend.data.ctrl[rig.gripper_ids] == 0.0)


# ---------------------------------------------------------------------- ee_delta
def test_ee_delta_moves_the_arm_only_with_torso_below_its_range():
    env, backend, rig = _env("ee_delta")
    m = backend.model
    torso = m.joint("robot0:torso_lift_joint")
    upstream_range = gym.make("FetchPickAndPlace-v4").unwrapped.model.jnt_range[torso.id]
    assert backend.data.qpos[m.jnt_qposadr[torso.id]] < upstream_range[0]  # the upstream quirk
    base0 = _frozen(backend)
    site = lambda: backend.data.site_xpos[rig.site_id].copy()  # noqa: E731
    for axis in range(3):
        a = np.zeros(4, np.float32)
        a[axis] = 0.5
        start = site()
        for _ in range(8):
            _, _, _, _, info = env.step(a)
        moved = site() - start
        assert moved[axis] > 0.5 * 8 * 0.5 * backend.control.config.step, (axis, moved)
        assert np.delete(np.abs(moved), axis).max() < 0.25 * moved[axis], (axis, moved)
        assert info["ik_residual"] < 5e-3
        for _ in range(10):
            env.step(np.zeros(4, np.float32))
    np.testing.assert_allclose(_frozen(backend), base0, atol=1e-4)


def test_pick_and_place_scripted_run_reports_grasp():
    task_id = "UnifiedManip/FetchPickAndPlace-v0"
    env = make(task_id, "ee_delta", "dense_penalized")
    policy = unified_manip.TASKS[task_id].scripted_policy("ee_delta")
    for seed in range(10):  # an episode with the goal in the air
        obs, _ = env.reset(seed=seed)
        if obs["desired_goal"][2] > obs["achieved_goal"][2] + 0.1:
            break
    grasped = []
    for _ in range(50):
        obs, _, _, _, info = env.step(policy(obs))
        grasped.append(info["grasped"])
    assert info["is_success"] == 1.0
    assert np.mean(grasped[-10:]) == 1.0
    assert info["reward_terms"]["place"] > 4.0
