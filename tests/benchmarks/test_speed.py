"""``python -m benchmarks.speed``: the env step rate against the raw physics, timed by
wrapping the backend's ``physics_step``, and native mode against the upstream env."""

from __future__ import annotations

import json

import gymnasium as gym
import pytest

from benchmarks import speed


def test_env_and_raw_rates_are_timed_over_the_same_steps(tmp_path, capsys):
    out = tmp_path / "speed.json"
    argv = ["--env", "UnifiedManip/Arm4Reach-v0", "--modes", "joint_position,ee_delta"]
    assert speed.main([*argv, "--steps", "200", "--repeats", "1", "--json", str(out)]) == 0
    rows = json.loads(out.read_text())["modes"]
    assert [r["action_mode"] for r in rows] == ["joint_position", "ee_delta"]
    for r in rows:
        # The physics is part of the step: its rate is above the env's.
        assert 0 < r["env_steps_per_s"] < r["raw_steps_per_s"]
        assert r["ratio_to_raw"] == r["env_steps_per_s"] / r["raw_steps_per_s"]
    assert "env / raw" in capsys.readouterr().out


def test_the_physics_timer_counts_each_physics_step_and_leaves_the_backend_as_it_was():
    env = gym.make("UnifiedManip/Arm4Reach-v0", action_mode="joint_position")
    backend = env.unwrapped.backend
    env.reset(seed=0)
    with speed.timing_physics(env) as physics:
        assert physics.seconds == 0.0
        env.step(env.action_space.sample())
        once = physics.seconds
        assert once > 0
        env.reset(seed=0)  # a reset runs no physics step
        assert physics.seconds == once
    assert "physics_step" not in vars(backend)  # the method is the class's again
    env.step(env.action_space.sample())
    assert physics.seconds == once


def test_a_family_without_a_physics_step_has_no_raw_rate():
    row = speed.measure("UnifiedManip/FetchReach-v0", "native", steps=20)
    assert row.env_steps_per_s > 0 and row.raw_steps_per_s != row.raw_steps_per_s  # NaN


def test_native_mode_is_compared_with_the_upstream_env(tmp_path, capsys):
    out = tmp_path / "speed.json"
    argv = ["--env", "UnifiedManip/FetchReach-v0", "--modes", "native", "--steps", "100", "--repeats", "1"]
    assert speed.main([*argv, "--json", str(out)]) == 0
    (row,) = json.loads(out.read_text())["upstream"]
    assert row["task_id"] == "UnifiedManip/FetchReach-v0" and row["upstream"] == "FetchReach-v4"
    assert row["ours_steps_per_s"] > 0 and row["upstream_steps_per_s"] > 0
    assert row["ratio"] == pytest.approx(row["ours_steps_per_s"] / row["upstream_steps_per_s"])
    assert row["ours_resets_per_s"] > 0 and row["upstream_resets_per_s"] > 0
    assert "one step of each in turn" in capsys.readouterr().out
