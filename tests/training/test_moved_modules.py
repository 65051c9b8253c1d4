"""Run directories written before the package moved into layers still load: a CrossQ
model and its trimmed replay buffer saved under ``unified_manip.crossq`` (today
``unified_manip.training.crossq``)."""

from __future__ import annotations

import pickle
import sys
import types

import gymnasium as gym
import pytest

from unified_manip.training import crossq, replay_buffers
from unified_manip.training.algorithms import ALGOS

OLD = "unified_manip.crossq"


def _crossq_model():
    from stable_baselines3.common.vec_env import DummyVecEnv

    env = DummyVecEnv([lambda: gym.make("UnifiedManip/Arm4Reach-v0", action_mode="ee_delta")])
    return crossq.CrossQ(
        "MultiInputPolicy",
        env,
        replay_buffer_class=crossq.CatDictHerReplayBuffer,
        buffer_size=1000,
        learning_starts=500,
        batch_size=8,
        policy_kwargs={"net_arch": {"pi": [8], "qf": [8]}},
        device="cpu",
        seed=0,
    ), env


def _as_saved_before_the_move(monkeypatch):
    """Pickle the project's CrossQ classes under their old module path, as runs did."""
    old = types.ModuleType(OLD)
    for name in ("MultiInputCrossQPolicy", "CatDictHerReplayBuffer"):
        cls = getattr(crossq, name)
        setattr(old, name, cls)
        monkeypatch.setattr(cls, "__module__", OLD)
    monkeypatch.setitem(sys.modules, OLD, old)


def test_a_crossq_model_saved_under_the_old_module_loads(tmp_path, monkeypatch):
    model, env = _crossq_model()
    _as_saved_before_the_move(monkeypatch)
    model.save(tmp_path / "model.zip")
    monkeypatch.undo()
    assert OLD not in sys.modules
    with pytest.raises(ModuleNotFoundError, match="unified_manip.crossq"):
        crossq.CrossQ.load(tmp_path / "model.zip", env=env, device="cpu")
    loaded = ALGOS["crossq_her"].load(tmp_path / "model.zip", "MultiInputPolicy", env=env, device="cpu")
    assert type(loaded.policy) is crossq.MultiInputCrossQPolicy
    assert type(loaded.replay_buffer) is crossq.CatDictHerReplayBuffer


def test_a_crossq_replay_buffer_saved_under_the_old_module_restores(tmp_path, monkeypatch):
    model, _ = _crossq_model()
    model.learn(40)
    _as_saved_before_the_move(monkeypatch)
    replay_buffers.save_trimmed(model.replay_buffer, tmp_path / "buffer.pkl")
    monkeypatch.undo()
    with open(tmp_path / "buffer.pkl", "rb") as f:
        assert pickle.load(f)["class"] == f"{OLD}.CatDictHerReplayBuffer"
    fresh, _ = _crossq_model()
    replay_buffers.restore(fresh.replay_buffer, tmp_path / "buffer.pkl")
    assert fresh.replay_buffer.pos == model.replay_buffer.pos == 40
    assert (fresh.replay_buffer.actions[:40] == model.replay_buffer.actions[:40]).all()
