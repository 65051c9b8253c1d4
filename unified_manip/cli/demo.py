"""``unified-manip demo``: roll out every task's scripted policy and write a picture strip.

Each row of the strip is one task, each column a moment of the episode (evenly spaced
from the first to the last step). The goal is drawn as a red sphere.
"""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym
import numpy as np

from unified_manip.envs.registry import TASKS


def rollout_frames(task_id: str, seed: int, frames: int, size: int):
    """Play the task's scripted policy for one episode, in the mode it emits; return
    (frames, success)."""
    spec = TASKS[task_id]
    action_mode = spec.scripted_mode
    env = gym.make(task_id, action_mode=action_mode, render_mode="rgb_array", render_width=size, render_height=size)
    policy = spec.scripted_policy(action_mode)
    obs, info = env.reset(seed=seed)
    keep = set(np.linspace(0, spec.max_episode_steps, frames).astype(int).tolist())
    shots = [env.render()] if 0 in keep else []
    for t in range(1, spec.max_episode_steps + 1):
        obs, _, terminated, truncated, info = env.step(policy(obs))
        if t in keep:
            shots.append(env.render())
        if terminated or truncated:
            break
    env.close()
    return shots, bool(info["is_success"])


def run(
    out: Path, seed: int = 0, frames: int = 6, size: int = 200, task_ids=None, progress: bool = True
) -> dict[str, bool]:
    """Write the strip to ``out`` (PNG) and return each task's success. By default every
    task with a scripted policy whose family is installed (the robosuite tasks need the
    robosuite extra); a named task of a missing extra raises ``MissingExtra``."""
    import imageio.v3 as iio
    from tqdm import tqdm

    default = [tid for tid, spec in TASKS.items() if spec.installed]
    ids = [tid for tid in (task_ids or default) if TASKS[tid].scripted_policy is not None]
    for tid in ids:
        TASKS[tid].require_installed()  # before the first rollout
    rows, successes = [], {}
    for tid in tqdm(ids, desc="demo", disable=not progress, unit="task"):
        shots, ok = rollout_frames(tid, seed, frames, size)
        shots += [np.zeros_like(shots[0])] * (frames - len(shots))
        rows.append(np.concatenate(shots, axis=1))
        successes[tid] = ok
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    iio.imwrite(out, np.concatenate(rows, axis=0))
    return successes
