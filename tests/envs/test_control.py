"""Every action mode really moves the arm, through physics, the way it says."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import make

import unified_manip

TASK = "UnifiedManip/Arm4PickAndPlace-v0"


def _env(mode):
    env = make(TASK, mode, max_episode_steps=1000)
    env.reset(seed=0)
    backend = env.unwrapped._backend
    return env, backend, backend.rig


def _config(mode):
    return unified_manip.TASKS[TASK].controllers[mode]


def _qpos(rig):
    return rig.data.qpos[rig.qpos_adr].copy()


@pytest.mark.parametrize("joint", range(4))
def test_joint_position_reaches_absolute_target(joint):
    env, backend, rig = _env("joint_position")
    q0 = _qpos(rig)
    action = (q0 - 0.5 * (rig.upper + rig.lower)) / (0.5 * (rig.upper - rig.lower))
    target = q0.copy()
    target[joint] += 0.3
    action[joint] = (target[joint] - 0.5 * (rig.upper[joint] + rig.lower[joint])) / (
        0.5 * (rig.upper[joint] - rig.lower[joint])
    )
    a = np.append(action, 1.0).astype(np.float32)
    for _ in range(50):  # 1 s
        env.step(a)
    np.testing.assert_allclose(_qpos(rig), target, atol=0.02)


def test_joint_delta_targets_are_relative_to_the_measured_position():
    """As in the design document: servo target = q + a * max_delta, clipped to the range."""
    env, backend, rig = _env("joint_delta")
    q0 = _qpos(rig)
    a = np.zeros(5, np.float32)
    a[0] = 1.0
    moved = []
    for _ in range(10):
        q_before = _qpos(rig)
        env.step(a)
        np.testing.assert_allclose(
            backend.data.ctrl[rig.actuator_ids],
            np.clip(q_before + a[:4] * _config("joint_delta").max_delta, rig.lower, rig.upper),
        )
        moved.append(_qpos(rig)[0] - q_before[0])
    assert all(m > 0 for m in moved)
    assert _qpos(rig)[0] - q0[0] > 0.05
    # A zero delta holds the pose.
    a[0] = 0.0
    for _ in range(25):
        env.step(a)
    held = _qpos(rig)
    for _ in range(25):
        env.step(a)
    np.testing.assert_allclose(_qpos(rig), held, atol=0.01)


def test_joint_velocity_tracks_commanded_speed():
    env, backend, rig = _env("joint_velocity")
    a = np.zeros(5, np.float32)
    a[0] = 0.25
    for _ in range(10):
        env.step(a)
    speed = backend.data.qvel[rig.dof_adr][0]
    assert speed == pytest.approx(0.25 * _config("joint_velocity").max_velocity, rel=0.1)


def test_joint_torque_zero_holds_against_gravity_and_pushes_when_asked():
    env, backend, rig = _env("joint_torque")
    q0 = _qpos(rig)
    zero = np.zeros(5, np.float32)
    for _ in range(50):
        env.step(zero)
    np.testing.assert_allclose(_qpos(rig), q0, atol=0.02)  # gravity compensation
    a = zero.copy()
    a[0] = 0.5
    for _ in range(5):
        env.step(a)
    assert _qpos(rig)[0] > q0[0] + 0.05
    # The actuator saturates at the torque limit.
    assert abs(backend.data.actuator_force[rig.actuator_ids[0]]) <= rig.max_torque[0] + 1e-9


def test_ee_delta_moves_grip_site_in_commanded_direction():
    """A steady command moves the grip site along it, at 50-100% of the step per step
    (targets are relative to the measured position, so the servos' lag is not made up)."""
    env, backend, rig = _env("ee_delta")
    site = lambda: backend.data.site_xpos[rig.site_id].copy()  # noqa: E731
    for axis in range(3):
        a = np.zeros(4, np.float32)
        a[axis] = -0.5 if axis == 2 else 0.5
        for _ in range(3):  # get going
            env.step(a)
        start = site()
        for _ in range(5):
            _, _, _, _, info = env.step(a)
        moved = site() - start
        per_step = abs(moved[axis]) / 5
        assert np.sign(moved[axis]) == np.sign(a[axis])
        step = _config("ee_delta").step
        assert 0.5 * 0.5 * step <= per_step <= 0.5 * step * 1.05, (axis, moved)
        assert np.delete(np.abs(moved), axis).max() < 0.2 * abs(moved[axis])
        assert info["ik_residual"] < 1e-3
        assert info["ik_limit_active"] is False
        for _ in range(10):
            env.step(np.zeros(4, np.float32))


def test_ee_delta_reports_joint_limit_when_target_is_out_of_reach():
    env, backend, rig = _env("ee_delta")
    limited = False
    for _ in range(60):  # reach straight up, far beyond the arm's length
        _, _, _, _, info = env.step(np.array([0.0, 0.0, 1.0, 1.0], np.float32))
        limited |= info["ik_limit_active"] or info["ik_residual"] > 0.01
    assert limited
    assert info["ik_residual"] > 0.01


def test_gripper_opens_and_closes():
    env, backend, rig = _env("joint_delta")
    fingers = backend._fingers_q
    for command, expected in ((-1.0, 0.0), (1.0, 0.04)):
        a = np.array([0, 0, 0, 0, command], np.float32)
        for _ in range(25):
            env.step(a)
        np.testing.assert_allclose(backend.data.qpos[fingers], expected, atol=0.003)


def test_native_is_joint_delta_on_the_arm():
    env_native, _, _ = _env("native")
    env_delta, _, _ = _env("joint_delta")
    rng = np.random.default_rng(0)
    for _ in range(20):
        a = rng.uniform(-1, 1, 5).astype(np.float32)
        o1 = env_native.step(a)[0]
        o2 = env_delta.step(a)[0]
        np.testing.assert_array_equal(o1["observation"], o2["observation"])
