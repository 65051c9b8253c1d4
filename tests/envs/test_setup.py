"""Keyword arguments become an ``EnvConfig`` in one place: ``gym.make`` and ``gym.make_vec``
take the same arguments, give the same config and play the same rollout."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from test_vector import assert_same, pair, play

import unified_manip
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.rewards import RewardConfig, RewardScales
from unified_manip.envs.setup import CONFIG_FIELDS, env_setup
from unified_manip.envs.tasks.gripper_terms import GRASP
from unified_manip.envs.vector import native_support
from unified_manip.envs.vector.env import NativeVectorEnv

#: A non-default value of every ``EnvConfig`` field a caller passes by name.
FIELD_VALUES = {
    "action_mode": "ee_delta",
    "reward_type": "dense",
    "terminate_on_success": True,
    "terminate_on": ("dropped",),
    "render_mode": "rgb_array",
    "render_width": 64,
    "render_height": 48,
    "reward_config": RewardConfig(scales=RewardScales(success=3.0), distance_gain=2.0),
    "reward_spec": GRASP.design("dense_penalized", RewardConfig(distance_gain=7.0)),
    "controller_options": {"step": 0.03},
    "observation": ["relative", "rgb", "depth"],
    "observation_distractors": 2,
    "observation_noise": 0.01,
    "observation_delay": 1,
    "camera": "front",
    "image_size": 24,
    "camera_meshes": "decimated",
    "randomization": "all",
}

#: One ID of every family with a native vector env.
NATIVE_FAMILY_IDS = sorted(
    {spec.family: tid for tid, spec in unified_manip.TASKS.items() if native_support(tid) is None}.values()
)


def test_every_config_field_is_covered():
    assert sorted(FIELD_VALUES) == sorted(CONFIG_FIELDS)
    assert {f for f in EnvConfig.__dataclass_fields__} == {*CONFIG_FIELDS, "options"}


@pytest.mark.parametrize("task_id", NATIVE_FAMILY_IDS)
def test_make_and_make_vec_take_every_field_alike(task_id):
    native, reference = pair(task_id, 2, **FIELD_VALUES)
    assert isinstance(native, NativeVectorEnv)
    single = gym.make(task_id, **FIELD_VALUES).unwrapped
    assert native.config == single.config == env_setup(task_id, **FIELD_VALUES).config
    assert native.config.reward_spec is FIELD_VALUES["reward_spec"]
    assert native.reward_spec is single.reward_spec is FIELD_VALUES["reward_spec"]
    # The resolved controller config (with its options) is what every backend built.
    assert all(b.control.config.step == 0.03 for b in native._batched._backends)
    assert single.backend.control.config.step == 0.03
    play(native, reference, 5)
    frames = native.render()
    assert [f.shape for f in frames] == [(48, 64, 3)] * 2
    assert_same(frames, tuple(reference.render()))
    for env in (native, reference, single):
        env.close()


@pytest.mark.parametrize("task_id", NATIVE_FAMILY_IDS)
def test_make_and_make_vec_reject_alike(task_id):
    family = unified_manip.TASKS[task_id].family
    name = {"arm4": "Arm4", "fetch": "Fetch"}[family]
    for make in (lambda **kw: gym.make(task_id, **kw), lambda **kw: gym.make_vec(task_id, num_envs=2, **kw)):
        with pytest.raises(TypeError, match=rf"^{name} tasks take no extra options, got \['robot'\]"):
            make(robot="Panda")
        with pytest.raises(
            ValueError, match=r"^unknown controller option 'band' for action_mode 'ee_delta' \(EEDelta\)"
        ):
            make(action_mode="ee_delta", controller_options={"band": 1.0})
        with pytest.raises(TypeError, match=r"^reward_config must be a RewardConfig or None, got dict"):
            make(reward_config={})


def test_setup_resolves_the_controller_once():
    setup = env_setup("UnifiedManip/Arm4Reach-v0", action_mode="joint_position", controller_options={"band": 0.5})
    assert setup.controller.band == 0.5
    backend = setup.build_backend()
    assert backend.control.config is setup.controller
    backend.reset(np.random.default_rng(0))
    backend.close()
