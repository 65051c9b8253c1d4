"""Render one frame per registered task for its documentation page.

    MUJOCO_GL=egl python docs/_gen/render_frames.py [--all] [--size 320]

Writes ``docs/images/tasks/<name>-v<N>.png`` for every task that has none (``--all``:
for every task), then ``docs/images/tasks.png``, the home page's picture: every task's
frame at half size, four to a row (a task that shares its previous version's animation,
``animations.json``'s ``"file"``, shares its frame too, and the sheet shows it once). The frame is taken a third of the way through an episode of the task's
scripted policy, seed 0 (at reset where the task has no scripted policy), so the page
shows the robot at work. The PNGs are committed; the site build does not render.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import gymnasium as gym

import unified_manip

OUT = Path(__file__).resolve().parents[1] / "images" / "tasks"


def frame(task_id: str, size: int):
    spec = unified_manip.TASKS[task_id]
    emits = spec.scripted_mode
    mode = emits if emits in spec.action_modes else spec.action_modes[0]
    env = gym.make(task_id, action_mode=mode, render_mode="rgb_array", render_width=size, render_height=size)
    try:
        obs, _ = env.reset(seed=0)
        if spec.scripted_policy is not None and mode == emits:
            policy = spec.scripted_policy(mode)
            for _ in range(spec.max_episode_steps // 3):
                obs, *_ = env.step(policy(obs))
        return env.render()
    finally:
        env.close()


def main(argv: list[str] | None = None) -> int:
    import imageio.v3 as iio

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--all", action="store_true", help="render every task, not only those without a frame")
    parser.add_argument("--size", type=int, default=320, help="frame width and height in pixels")
    args = parser.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    for task_id in own_frames():
        path = OUT / f"{task_id.split('/', 1)[1]}.png"
        if path.exists() and not args.all:
            continue
        iio.imwrite(path, frame(task_id, args.size))
        print(f"wrote {path}")
    write_sheet(OUT.parent / "tasks.png")
    return 0


def own_frames() -> list[str]:
    """The IDs with a frame of their own: all but those sharing a previous version's files."""
    import json

    record = OUT / "animations.json"
    shared = {t for t, a in json.loads(record.read_text()).items() if "file" in a} if record.is_file() else set()
    return [t for t in unified_manip.TASKS if t not in shared]


def write_sheet(path: Path, columns: int = 4) -> None:
    """Every task's frame at half size, ``columns`` to a row, in registration order."""
    import imageio.v3 as iio
    import numpy as np

    frames = [iio.imread(OUT / f"{t.split('/', 1)[1]}.png")[::2, ::2, :3] for t in own_frames()]
    frames += [np.full_like(frames[0], 255)] * (-len(frames) % columns)
    rows = [np.concatenate(frames[i : i + columns], axis=1) for i in range(0, len(frames), columns)]
    iio.imwrite(path, np.concatenate(rows, axis=0))
    print(f"wrote {path}")


if __name__ == "__main__":
    raise SystemExit(main())
