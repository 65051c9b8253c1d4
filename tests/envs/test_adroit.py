"""Adroit: native parity with gymnasium-robotics, and goals whose success is upstream's
``success``."""

from __future__ import annotations

import gymnasium as gym
import gymnasium_robotics
import numpy as np
import pytest
from conftest import make

import unified_manip

gym.register_envs(gymnasium_robotics)

#: Our ID -> (upstream ID, how our observation maps onto upstream's: (ours, theirs) slices).
ADROIT = {
    "AdroitRelocate": ("AdroitHandRelocate-v1", [(slice(0, 33), slice(0, 33))]),
    # Upstream's vector leaves out the arm's first joint, ARTz (our entry 0).
    "AdroitDoor": ("AdroitHandDoor-v1", [(slice(1, 40), slice(0, 39))]),
}


def _pair(name):
    upstream_id, layout = ADROIT[name]
    spec = unified_manip.TASKS[f"UnifiedManip/{name}-v0"]
    assert spec.upstream_id == upstream_id
    return make(spec.id, "native", "sparse"), gym.make(upstream_id, reward_type="sparse"), layout


def _same(o1, o2, layout):
    for ours, theirs in layout:
        np.testing.assert_array_equal(o1["observation"][ours], o2[theirs].astype(np.float32))


@pytest.mark.parametrize("name", list(ADROIT))
def test_native_is_identical_to_upstream(name):
    """Same seed and actions: the observation (where upstream's holds no goal), and
    is_success equals upstream's ``success`` info; sparse reward = success - 1."""
    ours, ref, layout = _pair(name)
    try:
        for seed in (0, 1):
            o1, _ = ours.reset(seed=seed)
            o2, _ = ref.reset(seed=seed)
            _same(o1, o2, layout)
            rng = np.random.default_rng(seed)
            for t in range(60):
                a = rng.uniform(-1, 1, ours.action_space.shape).astype(np.float32)
                o1, r1, _, _, i1 = ours.step(a)
                o2, _, _, _, i2 = ref.step(a)
                _same(o1, o2, layout)
                assert i1["is_success"] == float(i2["success"]) and r1 == i1["is_success"] - 1.0, (seed, t)
        if name == "AdroitRelocate":  # the goal is upstream's target: ball - target as upstream's
            np.testing.assert_allclose(o1["achieved_goal"] - o1["desired_goal"], o2[36:39], atol=1e-6)
    finally:
        ours.close()
        ref.close()


def _success_near_the_threshold(name, place):
    """``place(backend or upstream env, k)`` puts the object at the k-th state near the
    success threshold, in both envs; one zero step of each: is_success == success."""
    ours, ref, _ = _pair(name)
    try:
        outcomes = []
        for k in range(24):
            ours.reset(seed=k)
            ref.reset(seed=k)
            for env in (ours.unwrapped.backend, ref.unwrapped):
                place(env, k)
            zero = np.zeros(ours.action_space.shape, np.float32)
            _, _, _, _, i1 = ours.step(zero)
            _, _, _, _, i2 = ref.step(zero)
            assert i1["is_success"] == float(i2["success"]), k
            outcomes.append(i1["is_success"])
        assert 0 < sum(outcomes) < len(outcomes)  # both sides of the threshold were seen
    finally:
        ours.close()
        ref.close()


def test_door_success_is_upstreams_at_the_threshold():
    def open_door(env, k):
        m, d = env.model, env.data
        adr = m.jnt_qposadr[m.joint("door_hinge").id]
        d.qpos[adr] = 1.25 + 0.2 * k / 23  # 1.25 .. 1.45 rad: upstream's 1.35 in the middle
        d.qvel[:] = 0.0

    _success_near_the_threshold("AdroitDoor", open_door)


def test_relocate_success_is_upstreams_at_the_threshold():
    def near_target(env, k):
        m, d = env.model, env.data
        target = m.site_pos[m.site("target").id]  # the target site is a child of the world
        ball = m.body_pos[m.body("Object").id]
        offset = np.array([0.05 + 0.1 * k / 23, 0.0, 0.0])  # 5 .. 15 cm from the target
        d.qpos[30:33] = target + offset - ball  # the ball's slide joints move it from its body_pos
        d.qvel[:] = 0.0
        m.opt.gravity[:] = 0.0  # the ball stays where it was put for the step

    _success_near_the_threshold("AdroitRelocate", near_target)


def test_free_camera_is_upstreams():
    from gymnasium_robotics.envs.adroit_hand import adroit_door, adroit_relocate

    from unified_manip.envs.tasks.adroit.cameras import FREE_CAMERA

    assert FREE_CAMERA == adroit_door.DEFAULT_CAMERA_CONFIG == adroit_relocate.DEFAULT_CAMERA_CONFIG


def test_joint_target_delta_settles_the_arm_where_commanded():
    """The rig commands the position a joint settles at, though the arm's servo gain
    (500) is not its stiffness (200): five +1 actions on ARTz's slide (0.02 m each) move
    its settled position by about 0.1 m against the same rollout without them (gravity and
    the other joints pull it a little), not 2.5 times that."""
    settled = []
    for pulse in (0.0, 1.0):
        env = make("UnifiedManip/AdroitDoor-v0", "joint_target_delta")
        try:
            env.reset(seed=0)
            action = np.zeros(env.action_space.shape, np.float32)
            action[0] = pulse  # ARTz
            for _ in range(5):
                env.step(action)
            action[0] = 0.0
            for _ in range(100):  # let it settle
                env.step(action)
            settled.append(env.unwrapped.backend.data.qpos[0])
        finally:
            env.close()
    assert 0.07 < settled[1] - settled[0] < 0.13  # 0.1 m up to the other joints' pull; ctrl = target: 0.25 m
