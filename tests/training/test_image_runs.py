"""Training from images: SAC+HER on ``rgb`` + ``joint_pos`` with a CNN per image key,
``eval`` of the result, and the replay buffer's memory refused up front."""

from __future__ import annotations

import json
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest
from conftest import cli_in_process

import unified_manip  # noqa: F401  (registers the IDs)
from unified_manip.training.images import ImageExtractor, buffer_bytes, check_buffer_fits

# Each test trains from rendered frames.
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
REACH = "UnifiedManip/Arm4Reach-v0"


cli = cli_in_process


def test_sac_her_trains_on_rgb_and_joint_pos_then_evaluates(tmp_path):
    from stable_baselines3.common.save_util import load_from_zip_file

    run_dir = tmp_path / "run"
    sets = ["learning_starts=100", "batch_size=16", "policy_kwargs.net_arch=[16,16]", "eval_freq=500", "n_eval_episodes=2",
            "buffer_size=1000"]  # fmt: skip
    args = ["train", "--env", REACH, "--action-mode", "ee_delta", "--algo", "sac_her", "--steps", "500"]
    proc = cli(*args, "--run-dir", str(run_dir), "--observation", "rgb,joint_pos", "--env-kwarg", "image_size=40",
               "--no-progress", *[x for s in sets for x in ("--set", s)])  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    data, params, _ = load_from_zip_file(run_dir / "final_model.zip", device="cpu")
    assert data["num_timesteps"] == 500
    assert data["policy_kwargs"]["features_extractor_class"] is ImageExtractor
    assert data["observation_space"]["rgb"].shape == (3, 40, 40)  # stored channels-first
    weights = params["policy"]
    # The actor's and the critics' CNNs on rgb; the observation vector flattened.
    assert weights["actor.features_extractor.extractors.rgb.cnn.0.weight"].shape == (32, 3, 8, 8)
    assert "critic.features_extractor.extractors.rgb.cnn.0.weight" in weights
    out = tmp_path / "eval.json"
    proc = cli("eval", str(run_dir), "--episodes", "2", "--json", str(out))
    assert proc.returncode == 0, proc.stderr
    assert json.loads(out.read_text())["episodes"] == 2


def test_the_extractor_gives_depth_a_cnn_too():
    env = gym.make(REACH, observation=["joint_pos", "rgb", "depth"], image_size=40)
    extractor = ImageExtractor(env.observation_space, cnn_output_dim=8)
    assert extractor._permute == ["depth", "rgb"]  # both channels-last here (no VecTransposeImage)
    assert extractor.features_dim == 8 + 8 + 3 + 3 + 4
    import torch

    obs, _ = env.reset(seed=0)
    batch = {k: torch.as_tensor(v[None]).float() for k, v in obs.items()}
    assert extractor(batch).shape == (1, 26)


def test_buffer_bytes_counts_both_observations():
    env = gym.make(REACH, observation=["joint_pos", "rgb"], image_size=84)
    per = buffer_bytes(env.observation_space, 4, 1, her=True)
    assert per == 2 * (84 * 84 * 3 + 4 * (4 + 3 + 3)) + 4 * 4 + 12 + 16
    assert buffer_bytes(env.observation_space, 4, 1_000_000, her=True) == per * 1_000_000  # ~42 GB
    check_buffer_fits(env.observation_space, 4, 1000, her=True)  # 42 MB fits


def test_train_refuses_a_buffer_that_cannot_fit(tmp_path):
    proc = cli("train", "--env", REACH, "--action-mode", "ee_delta", "--algo", "sac_her", "--steps", "500",
               "--run-dir", str(tmp_path / "run"), "--observation", "rgb,joint_pos", "--set", "buffer_size=100000000",
               "--no-progress")  # fmt: skip
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    line = proc.stderr.strip().splitlines()[-1]
    assert "the replay buffer of 100,000,000 transitions needs 4246.0 GB of memory (42.5 kB per transition)" in line
    suggested = int(line.rsplit("--set buffer_size=", 1)[1].rstrip(")"))
    assert 0 < suggested < 100_000_000 and str(suggested).rstrip("0") in "123456789"
    assert not (tmp_path / "run" / "final_model.zip").exists()


@pytest.mark.parametrize("size", [0, -1])
def test_cli_refuses_a_bad_image_size(tmp_path, size):
    proc = cli("train", "--env", REACH, "--action-mode", "ee_delta", "--algo", "sac_her", "--steps", "100",
               "--run-dir", str(tmp_path / "run"), "--observation", "rgb,joint_pos", "--env-kwarg",
               f"image_size={size}")  # fmt: skip
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.strip().splitlines()[-1].endswith(f"image_size must be a positive int (pixels), got {size}")


def test_depth_space_is_in_metres():
    env = gym.make(REACH, observation=["joint_pos", "depth"], image_size=40)
    assert env.observation_space["depth"].low.min() == 0.0 and np.isinf(env.observation_space["depth"].high).all()


def test_a_grid_takes_an_image_design(tmp_path):
    import yaml

    from unified_manip.experiments.grid import load_grid

    doc = {"name": "pixels", "tasks": [REACH], "action_modes": ["ee_delta"], "reward_types": ["sparse"],
           "algos": ["sac_her"], "seeds": [0], "steps": 200, "observations": [["joint_pos", "rgb"]]}  # fmt: skip
    path = tmp_path / "grid.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    [run] = load_grid(path).runs
    assert run.name == "Arm4Reach-v0__ee_delta__sparse__sac_her__obs-joint_pos+rgb__s0"
    assert run.env_kwargs == {"observation": ["joint_pos", "rgb"]}
