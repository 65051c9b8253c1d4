"""Render the observation cameras' pictures for the observation designs page.

    MUJOCO_GL=egl python docs/_gen/camera_frames.py

Writes ``docs/images/cameras.png``: for each family's default camera (and the arm's
wrist camera, and robosuite's collision-geometry view), the ``rgb`` observation at 84 px with the fast settings (top row) and the
same camera with MuJoCo's full look (bottom row), a third of the way through a scripted
episode, seed 0, each shown at 2x. The PNG is committed; the site build does not render.
"""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym
import imageio.v2 as imageio
import numpy as np

import unified_manip
from unified_manip.envs.cameras import FULL, CameraConfig, ImageSensor

OUT = Path(__file__).resolve().parents[1] / "images" / "cameras.png"
VIEWS = (
    ("UnifiedManip/Arm4PickAndPlace-v0", "front"),
    ("UnifiedManip/Arm4PickAndPlace-v0", "wrist"),
    ("UnifiedManip/FetchPickAndPlace-v0", "front"),
    ("UnifiedManip/Lift-v0", "agentview"),
    ("UnifiedManip/Lift-v0", "agentview_collision"),
    ("UnifiedManip/HandManipulateBlock-v0", "front"),
)
SIZE = 84


def pair(task_id: str, camera: str) -> tuple[np.ndarray, np.ndarray]:
    spec = unified_manip.TASKS[task_id]
    if camera not in spec.cameras:
        camera = next(iter(spec.cameras))
    mode = "ee_delta" if "ee_delta" in spec.action_modes else spec.action_modes[0]
    env = gym.make(task_id, action_mode=mode, observation=["default", "rgb"], camera=camera, image_size=SIZE)
    obs, _ = env.reset(seed=0)
    if spec.scripted_policy is not None and mode == "ee_delta":
        policy = spec.scripted_policy(mode)
        for _ in range(spec.max_episode_steps // 3):
            obs, *_ = env.step(policy(obs))
    backend = env.unwrapped.backend
    full = ImageSensor(("rgb",), CameraConfig(spec.cameras[camera].scene, FULL), SIZE)
    look = full.read(backend.model, backend.data)["rgb"]
    full.close()
    env.close()
    return obs["rgb"], look


def main() -> None:
    columns = [np.concatenate(pair(t, c), axis=0) for t, c in VIEWS]
    gap = np.full((2 * SIZE, 4, 3), 255, np.uint8)
    row = np.concatenate([x for col in columns for x in (col, gap)][:-1], axis=1)
    image = np.kron(row, np.ones((2, 2, 1), np.uint8))
    OUT.parent.mkdir(parents=True, exist_ok=True)
    tmp = OUT.with_suffix(".tmp.png")
    imageio.imwrite(tmp, image)
    tmp.replace(OUT)
    print(OUT)


if __name__ == "__main__":
    main()
