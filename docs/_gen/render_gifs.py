"""Render one animated GIF per registered task for its documentation page.

    MUJOCO_GL=egl python docs/_gen/render_gifs.py [--all] [--size 240] [--fps 12]

Writes ``docs/images/tasks/<name>-v<N>.gif`` for every task that has none (``--all``:
for every task) and records how each was made in ``docs/images/tasks/animations.json``,
which the task pages read for their captions. A task whose previous version plays the
same episode, frame for frame (a version that changed only other modes), shares that
version's files: its record says ``"file"``, and nothing is written. One episode, seed 0, played by the task's
scripted policy (in ``ee_delta``, or the mode it emits); where a task has none, by the trained run committed under
``results/`` for it (``collect --all``'s choice), else by seeded random actions. The
episode ends at its time limit, or one second after its first success. Frames are taken
every ``round(1 / (fps * dt))`` env steps and shown in real time, with one palette per
GIF, so the files stay small. They are committed; the site build does not render.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import gymnasium as gym
import numpy as np

import unified_manip

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "docs" / "images" / "tasks"
RECORD = OUT / "animations.json"
HOLD_S = 1.0  # seconds shown after the first success


def choose(task_id: str):
    """``(action mode, what plays, env -> (obs -> action))`` for the task."""
    spec = unified_manip.TASKS[task_id]
    if spec.scripted_policy is not None:  # in the mode it emits (Meta-World's: native)
        mode = spec.scripted_mode
        return mode, "its scripted policy", lambda env: spec.scripted_policy(mode)
    from unified_manip.cli.collect_all import trained_runs

    run = trained_runs(ROOT / "results").get(task_id)
    if run is not None:
        make, source, kwargs = run
        return kwargs.get("action_mode", "native"), "a trained TQC+HER policy, deterministic", make
    rng = np.random.default_rng(0)
    return (
        spec.action_modes[-1],
        "random actions (no policy here solves it)",
        lambda env: lambda obs: rng.uniform(-1.0, 1.0, env.action_space.shape),
    )


def episode(task_id: str, size: int, fps: float) -> tuple[list[np.ndarray], dict]:
    """The frames of one seeded episode and what made them."""
    spec = unified_manip.TASKS[task_id]
    mode, source, make_policy = choose(task_id)
    env = gym.make(task_id, action_mode=mode, render_mode="rgb_array", render_width=size, render_height=size)
    try:
        policy = make_policy(env)
        dt = env.unwrapped.backend.dt
        stride = max(1, round(1.0 / (fps * dt)))
        obs, info = env.reset(seed=0)
        frames, first_success, t = [env.render()], None, 0
        for t in range(1, spec.max_episode_steps + 1):
            obs, _, terminated, truncated, info = env.step(policy(obs))
            if first_success is None and info["is_success"] > 0.5:
                first_success = t
            if t % stride == 0:
                frames.append(env.render())
            if terminated or truncated or (first_success is not None and (t - first_success) * dt >= HOLD_S):
                break
        meta = {
            "policy": source,
            "action_mode": mode,
            "seed": 0,
            "steps": t,
            "first_success_step": first_success,
            "frame_ms": round(stride * dt * 1000),
            "frames": len(frames),
            "size": size,
        }
        return frames, meta
    finally:
        env.close()


def write_gif(path: Path, frames: list[np.ndarray], frame_ms: int, colours: int = 96) -> None:
    """One palette for all frames (no flicker), unchanged areas left to the previous frame."""
    from PIL import Image

    images = [Image.fromarray(np.ascontiguousarray(f[..., :3])) for f in frames]
    sample = Image.fromarray(np.concatenate([np.asarray(images[i]) for i in range(0, len(images), 4)], axis=0))
    palette = sample.quantize(colours, method=Image.Quantize.MEDIANCUT)
    quantized = [im.quantize(palette=palette, dither=Image.Dither.NONE) for im in images]
    durations = [frame_ms] * (len(quantized) - 1) + [1500]  # the last frame lingers before the loop
    quantized[0].save(
        path, save_all=True, append_images=quantized[1:], duration=durations, loop=0, optimize=True, disposal=1
    )


def gif_frames(path: Path) -> int:
    """How many frames the GIF at ``path`` holds."""
    from PIL import Image

    with Image.open(path) as gif:
        return gif.n_frames


def previous_version(task_id: str) -> str | None:
    """``.../Name-vN``'s ``-v(N-1)``, if that is registered."""
    stem, version = task_id.rsplit("-v", 1)
    older = f"{stem}-v{int(version) - 1}"
    return older if older in unified_manip.TASKS else None


def same_episode(task_id: str, frames: list[np.ndarray], meta: dict, record: dict, size: int, fps: float) -> str | None:
    """The file name of the previous version's episode (its own, or the one it shares)
    where that episode is this one, frame for frame (replayed here, not assumed), else None."""
    older = previous_version(task_id)
    if older is None or older not in record:
        return None
    old_frames, old_meta = episode(older, size, fps)
    if old_meta != meta or len(old_frames) != len(frames):
        return None
    if not all(np.array_equal(a, b) for a, b in zip(old_frames, frames)):
        return None
    return record[older].get("file", older.split("/", 1)[1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--all", action="store_true", help="render every task, not only those without a GIF")
    parser.add_argument("--size", type=int, default=240, help="frame width and height in pixels")
    parser.add_argument("--fps", type=float, default=12.0, help="frames per second of simulated time (about)")
    parser.add_argument("--tasks", nargs="*", help="only these IDs")
    args = parser.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    record = json.loads(RECORD.read_text()) if RECORD.is_file() else {}
    for task_id in args.tasks or unified_manip.TASKS:
        name = task_id.split("/", 1)[1]
        path = OUT / f"{name}.gif"
        done = path.exists() or "file" in record.get(task_id, {})
        if done and not args.all and not args.tasks:
            continue
        frames, meta = episode(task_id, args.size, args.fps)
        shared = same_episode(task_id, frames, meta, record, args.size, args.fps)
        if shared is not None:
            record[task_id] = {**record[previous_version(task_id)], "file": shared}
            RECORD.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")
            print(f"{task_id}: the episode of {shared}, frame for frame: its files are shared", flush=True)
            continue
        tmp = path.with_suffix(".tmp.gif")
        write_gif(tmp, frames, meta["frame_ms"])
        tmp.replace(path)
        meta["bytes"] = path.stat().st_size
        meta["frames"] = gif_frames(path)  # Pillow merges identical consecutive frames
        record[task_id] = meta
        RECORD.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")
        print(f"wrote {path}: {meta['frames']} frames, {meta['bytes'] / 1e3:.0f} kB, {meta['policy']}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
