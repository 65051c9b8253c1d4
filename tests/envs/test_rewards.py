"""Reward designs: named scales in a reward config, raw terms beside the scaled ones."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import make, random_actions

from unified_manip.envs.config import EnvConfig
from unified_manip.envs.controllers.actions import squared_norm, squared_norms
from unified_manip.envs.rewards import RewardConfig, RewardScales
from unified_manip.envs.tasks.gripper_terms import REACH
from unified_manip.envs.wrappers import RawRewardTerms

TASK = "UnifiedManip/Arm4PickAndPlace-v0"


def _terms(env, steps: int = 20):
    env.reset(seed=3)
    return [env.step(a)[4] for a in random_actions(env, steps, seed=4)]


def test_reward_config_names_the_scales():
    push = "UnifiedManip/Arm4Push-v0"  # its place term has no grasp gate: never 0
    default = _terms(make(push, "ee_delta", "dense_penalized"))
    scales = RewardScales(place=2.0, drop=1.0)
    changed = _terms(make(push, "ee_delta", "dense_penalized", reward_config=RewardConfig(scales=scales)))
    for d, c in zip(default, changed):
        assert d["reward_terms"]["place"] > 0.0
        assert c["reward_terms"]["place"] == pytest.approx(d["reward_terms"]["place"] * 2.0 / 5.0, rel=1e-12)
        assert c["reward_terms"]["reach"] == d["reward_terms"]["reach"]


def test_raw_terms_beside_the_scaled_ones():
    env = RawRewardTerms(make(TASK, "ee_delta", "dense_penalized"))
    scales = RewardScales()
    infos = _terms(env)
    for info in infos:
        raw, scaled = info["reward_terms_raw"], info["reward_terms"]
        assert raw.keys() == scaled.keys() == {"reach", "place", "success", "action", "drop"}
        for name in raw:
            assert raw[name] * getattr(scales, name) == scaled[name]
    assert 0.0 < infos[-1]["reward_terms_raw"]["reach"] <= 1.0
    # The batched API agrees with the wrapper.
    obs, _ = env.reset(seed=0)
    obs, _, _, _, info = env.step(np.zeros(4, np.float32))
    batched = env.unwrapped.compute_reward_terms(
        obs["achieved_goal"][None], obs["desired_goal"][None], [info], raw=True
    )
    assert {k: float(v[0]) for k, v in batched.items()} == info["reward_terms_raw"]


def test_reward_config_and_spec_are_validated():
    with pytest.raises(ValueError) as err:
        RewardScales(reach="1")
    assert str(err.value) == "RewardScales.reach must be a finite number, got '1'"
    with pytest.raises(ValueError) as err:
        RewardConfig(distance_gain=0.0)
    assert str(err.value) == "RewardConfig.distance_gain must be positive, got 0.0"
    with pytest.raises(TypeError) as err:
        EnvConfig(reward_config={"place": 2.0})
    assert str(err.value) == "reward_config must be a RewardConfig or None, got dict"
    with pytest.raises(ValueError) as err:
        REACH.design("shaped")
    assert str(err.value) == "unknown reward_type 'shaped'; expected one of 'sparse', 'dense', 'dense_penalized'"


@pytest.mark.parametrize("columns", [3, 4, 5, 20])
def test_action_sq_does_not_depend_on_where_the_action_lies(columns):
    """The action penalty's sum of squares is the same bits for an action wherever its
    memory starts. OpenBLAS's dot is not: moved 8 bytes off a 16-byte boundary, the plain
    ``v @ v`` of these draws changed its last bit 322 times in 1,000 for 5 columns (on an
    AVX-512 machine), and the vector env's rows of an odd width start there."""
    rng = np.random.default_rng(0)
    buffer = np.zeros(64)
    skew = buffer.ctypes.data % 16 // 8  # 1 where the buffer starts 8 bytes off a 16-byte boundary
    for _ in range(500):
        action = rng.uniform(-1, 1, columns)
        reference = squared_norm(action.copy())
        for start in (skew + 1, skew + 2, skew + 3):
            view = buffer[start : start + columns]
            view[:] = action
            assert squared_norm(view) == reference
        batch = rng.uniform(-1, 1, (5, columns))
        assert squared_norms(batch).tolist() == [squared_norm(row.copy()) for row in batch]
