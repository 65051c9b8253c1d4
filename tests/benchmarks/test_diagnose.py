"""What a run's policy did (issue 40, item 3), on a committed run and on a fresh one."""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from conftest import ROOT, cli_in_process

from benchmarks import diagnose
from unified_manip.training.rundir import RunDirectoryError

COMMITTED = ROOT / "results/action_spaces_families/runs/Arm4PickAndPlace-v0__joint_position__sparse__tqc_her__s0"


def test_a_committed_run_gives_its_demonstrations_and_training_episodes(tmp_path, monkeypatch):
    """Committed results carry no model: the demonstrations and the agent's own training
    episodes are measured, and the note says why the policy is not played, and that its
    dataset (a path relative to where it trained) is not at hand here."""
    monkeypatch.chdir(tmp_path)
    d = diagnose.diagnose(COMMITTED)
    assert (d.action_mode, d.demonstrations, d.demonstration_success) == ("joint_position", 96, 1.0)
    # 60k steps of 8 envs, 100-step episodes, as the monitor logged them: none succeeded.
    assert d.training_episodes == 600 and d.training_success == 0.0 and d.training_success_last_tenth == 0.0
    assert d.played is None and "has no model yet" in d.note
    assert d.demonstration_action_change is None
    assert d.note.startswith("its dataset data/Arm4PickAndPlace-v0/joint_position-v0 is not at hand")
    assert "| 96 (1.00) | – | 600 episodes: 0.00 (0.00) | – |" in diagnose.table([d])


def test_action_statistics_by_hand():
    one = np.array([[0.0, 0.0], [1.0, -1.0], [1.0, 0.5]])  # changes: mean(1, 1) = 1, mean(0, 1.5) = 0.75
    two = np.array([[0.995, 0.0]])  # one step: no change; one component at a bound
    stats = diagnose.action_statistics([one, two])
    assert stats.mean_abs == pytest.approx((0 + 0 + 1 + 1 + 1 + 0.5 + 0.995 + 0) / 8)
    assert stats.saturated == pytest.approx(4 / 8)
    assert stats.change == pytest.approx((1 + 0.75) / 2)


def test_the_final_model_is_played_unless_the_best_is_asked_for(tmp_path):
    """The tables report final success, so the final model is the one to explain; a run
    still training plays its newest checkpoint, and only ``best`` falls back like eval."""
    (tmp_path / "best").mkdir()
    for name in ("final_model.zip", "best/best_model.zip"):
        (tmp_path / name).write_bytes(b"")
    assert diagnose.model_to_play(tmp_path) == tmp_path / "final_model.zip"
    assert diagnose.model_to_play(tmp_path, "best") == tmp_path / "best" / "best_model.zip"
    (tmp_path / "final_model.zip").unlink()
    with pytest.raises(RunDirectoryError, match=r"no final model or checkpoint\) \(--model best plays"):
        diagnose.model_to_play(tmp_path)
    assert diagnose.model_to_play(tmp_path, "best") == tmp_path / "best" / "best_model.zip"
    with pytest.raises(ValueError, match="model must be one of final, best; got 'last'"):
        diagnose.model_to_play(tmp_path, "last")


def test_a_dataset_at_hand_gives_its_action_change():
    change, note = diagnose.dataset_action_change(
        {"dataset": str(ROOT / "datasets/examples/arm4-pickandplace-ee_delta-v0")}
    )
    assert note == "" and 0.0 < change < 2.0  # a scripted pick and place moves, within the action bounds


@pytest.fixture(scope="module")
def pick_and_place_run(tmp_path_factory) -> Path:
    run_dir = tmp_path_factory.mktemp("diagnose") / "run"
    sets = ["learning_starts=100", "batch_size=64", "buffer_size=10000", "eval_freq=1000", "n_eval_episodes=1"]
    args = ["train", "--env", "UnifiedManip/Arm4PickAndPlace-v0", "--action-mode", "joint_delta", "--algo", "sac_her"]
    args += ["--steps", "200", "--seed", "0", "--run-dir", str(run_dir), "--no-progress"]
    proc = cli_in_process(*args, *[a for s in sets for a in ("--set", s)])
    assert proc.returncode == 0, proc.stderr
    return run_dir


@pytest.mark.slow
def test_a_trained_policy_is_played_and_measured(pick_and_place_run, tmp_path):
    out = tmp_path / "d.json"
    assert diagnose.main([str(pick_and_place_run), "--episodes", "2", "--json", str(out)]) == 0
    d = diagnose.diagnose(pick_and_place_run, episodes=2)
    p = d.played
    assert p.model == "final_model.zip"
    assert d.training_episodes == 2 and d.demonstrations == 0  # 200 steps of 100-step episodes
    assert p.episodes == 2 and 0.0 <= p.success <= 1.0 and 0.0 <= p.saturated <= 1.0
    # The closest approach is at most the distance at reset, measured here on the same seeds.
    env = gym.make("UnifiedManip/Arm4PickAndPlace-v0", action_mode="joint_delta")
    at_reset, goal_at_reset = [], []
    for ep in range(2):
        obs, _ = env.reset(seed=diagnose.FIRST_SEED + ep)
        groups = env.unwrapped.backend.observation_groups()
        at_reset.append(100 * np.linalg.norm(groups["object_rel"].read(env.unwrapped.backend)))
        goal_at_reset.append(np.linalg.norm(obs["achieved_goal"] - obs["desired_goal"]) / 0.05)
    _, _, _, _, info = env.step(env.action_space.sample())
    env.close()
    assert 0.0 < p.closest_approach_cm <= np.median(at_reset) + 1e-6
    # The goal distance in success thresholds (5 cm here), and no closer than it got.
    assert p.goal_at_reset == pytest.approx(np.median(goal_at_reset), rel=1e-12)
    assert 0.0 < p.closest_to_goal <= p.goal_at_reset
    # The task's own quantities at the end: a distance, and flags as shares of the episodes.
    assert set(p.end_info) == {"grip_to_object", "grasped", "dropped", "action_sq", "sim_unstable"} <= set(info)
    assert p.end_info["grip_to_object"] > 0.0 and 0.0 <= p.end_info["grasped"] <= 1.0
    assert f"| {p.closest_to_goal:.3f} ({p.goal_at_reset:.3f}) | action_sq " in diagnose.table([d])
    assert '"action_mode": "joint_delta"' in out.read_text()


def test_a_directory_that_is_not_a_run_is_one_line(tmp_path, capsys):
    assert diagnose.main([str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: ") and "\n" not in err and "config.yaml" in err
