"""Soak and memory benchmark: long random rollouts, many rendered frames, many make/close
cycles, with resident memory, open file descriptors, threads and live GL contexts counted.

    python -m benchmarks.soak                        # the full sizes (tens of minutes)
    python -m benchmarks.soak --steps 3000 --frames 30 --cycles 6   # a quick check

Three parts, each against its limits (the process exits 1 if one is missed):

- **steps**: ``--steps`` random steps in every action mode of the 4-DOF arm
  (``Arm4PickAndPlace``), reset at every episode end. Resident memory may grow by less
  than 50 MB after a warm-up episode; no step may report ``sim_unstable``.
- **frames**: ``--frames`` ``rgb_array`` frames (a random step each) on the arm, Fetch and
  robosuite. Memory growth after a warm-up under 50 MB.
- **cycles**: ``--cycles`` ``gym.make`` / ``reset`` / ``render`` / ``close`` cycles of each
  family. After them the process holds as many file descriptors (``/proc/self/fd``) and
  live renderer GL contexts as before them; threads and memory are reported beside.

Memory is the resident set size (``VmRSS``), read after a garbage collection.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from benchmarks.gauges import gl_contexts, open_fds, rss_mb, threads
from benchmarks.parser import ToolParser

RSS_LIMIT_MB = 50.0
STEP_TASK = "UnifiedManip/Arm4PickAndPlace-v0"
FRAME_TASKS = ("UnifiedManip/Arm4PickAndPlace-v0", "UnifiedManip/FetchPickAndPlace-v0", "UnifiedManip/Lift-v0")
CYCLE_TASKS = (
    "UnifiedManip/Arm4PickAndPlace-v0",
    "UnifiedManip/FetchPickAndPlace-v0",
    "UnifiedManip/HandManipulateBlock-v0",
    "UnifiedManip/Lift-v0",
)


def _make(task: str, mode: str | None = None, **kwargs):
    import gymnasium as gym

    import unified_manip

    modes = unified_manip.TASKS[task].action_modes
    mode = mode or next(m for m in ("ee_delta", "native") if m in modes)
    return gym.make(task, action_mode=mode, **kwargs)


def _bar(total: int, desc: str, progress: bool, unit_scale: bool = False):
    """A progress bar on stderr (steps are counted in chunks, so it costs nothing measurable)."""
    from tqdm import tqdm

    return tqdm(
        total=total, desc=desc, unit_scale=unit_scale, disable=not progress, dynamic_ncols=True, mininterval=1.0
    )


# ---------------------------------------------------------------------- parts
def soak_steps(steps: int, seed: int = 0, progress: bool = False) -> list[dict[str, Any]]:
    import unified_manip

    rows = []
    modes = unified_manip.TASKS[STEP_TASK].action_modes
    bar = _bar(steps * len(modes), "soak steps", progress, unit_scale=True)
    for mode in modes:
        env = _make(STEP_TASK, mode)
        rng = np.random.default_rng(seed)
        env.reset(seed=seed)
        warmup = env.spec.max_episode_steps
        unstable, episodes, start_rss, start = 0, 0, None, time.perf_counter()
        peak = 0.0
        for t in range(steps + warmup):
            if t == warmup:
                start_rss, start = rss_mb(), time.perf_counter()
            _, _, terminated, truncated, info = env.step(rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))
            unstable += bool(info["sim_unstable"])
            if terminated or truncated:
                env.reset()
                episodes += 1
            if start_rss is not None and t % 20_000 == 0:
                peak = max(peak, rss_mb() - start_rss)
            if t >= warmup and (t - warmup) % 1000 == 999:
                bar.update(1000)
        growth = rss_mb() - start_rss
        env.close()
        bar.update(steps % 1000)
        rows.append(
            {
                "part": "steps",
                "task": STEP_TASK,
                "mode": mode,
                "count": steps,
                "episodes": episodes,
                "steps_per_s": steps / (time.perf_counter() - start),
                "rss_start_mb": start_rss,
                "rss_growth_mb": growth,
                "rss_peak_growth_mb": max(peak, growth),
                "sim_unstable": unstable,
                "ok": growth < RSS_LIMIT_MB and unstable == 0,
            }
        )
    bar.close()
    return rows


def soak_frames(frames: int, size: int = 128, seed: int = 0, progress: bool = False) -> list[dict[str, Any]]:
    rows = []
    bar = _bar(frames * len(FRAME_TASKS), "soak frames", progress)
    for task in FRAME_TASKS:
        env = _make(task, render_mode="rgb_array", render_width=size, render_height=size)
        rng = np.random.default_rng(seed)
        env.reset(seed=seed)
        warmup = min(20, frames)
        start_rss, start = None, time.perf_counter()
        for t in range(frames + warmup):
            if t == warmup:
                start_rss, start = rss_mb(), time.perf_counter()
            _, _, terminated, truncated, _ = env.step(rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))
            frame = env.render()
            assert frame.shape == (size, size, 3)
            bar.update(t >= warmup)
            if terminated or truncated:
                env.reset()
        growth = rss_mb() - start_rss
        env.close()
        rows.append(
            {
                "part": "frames",
                "task": task,
                "count": frames,
                "size": size,
                "frames_per_s": frames / (time.perf_counter() - start),
                "rss_start_mb": start_rss,
                "rss_growth_mb": growth,
                "ok": growth < RSS_LIMIT_MB,
            }
        )
    return rows


def soak_cycles(cycles: int, warmup: int = 2, progress: bool = False) -> list[dict[str, Any]]:
    import unified_manip

    rows = []
    bar = _bar(cycles * len(CYCLE_TASKS), "soak make/close cycles", progress)
    for task in CYCLE_TASKS:

        def cycle(i: int) -> None:
            env = _make(task, render_mode="rgb_array", render_width=64, render_height=64)
            env.reset(seed=i)
            env.render()
            env.close()

        for i in range(warmup):
            cycle(i)
        before = {"fds": open_fds(), "threads": threads(), "gl_contexts": gl_contexts(), "rss_mb": rss_mb()}
        start = time.perf_counter()
        for i in range(cycles):
            cycle(warmup + i)
            bar.update(1)
        seconds = time.perf_counter() - start
        after = {"fds": open_fds(), "threads": threads(), "gl_contexts": gl_contexts(), "rss_mb": rss_mb()}
        rows.append(
            {
                "part": "cycles",
                "task": task,
                "family": unified_manip.TASKS[task].family,
                "count": cycles,
                "cycles_per_s": cycles / seconds,
                "before": before,
                "after": after,
                "ok": after["fds"] <= before["fds"] and after["gl_contexts"] <= before["gl_contexts"],
            }
        )
    bar.close()
    return rows


# ---------------------------------------------------------------------- report
def tables(rows: list[dict[str, Any]]) -> str:
    out = []
    steps = [r for r in rows if r["part"] == "steps"]
    if steps:
        out += [
            "| mode | steps | episodes | steps/s | RSS at start (MB) | growth (MB) | peak growth (MB) | sim_unstable | ok |",
            "|---|---:|---:|---:|---:|---:|---:|---:|---|",
        ]
        out += [
            f"| {r['mode']} | {r['count']:,} | {r['episodes']:,} | {r['steps_per_s']:,.0f} | {r['rss_start_mb']:.0f} | "
            f"{r['rss_growth_mb']:+.1f} | {r['rss_peak_growth_mb']:+.1f} | {r['sim_unstable']} | {_ok(r)} |"
            for r in steps
        ]
        out.append("")
    frames = [r for r in rows if r["part"] == "frames"]
    if frames:
        out += [
            "| task | frames | size | frames/s | RSS at start (MB) | growth (MB) | ok |",
            "|---|---:|---:|---:|---:|---:|---|",
        ]
        out += [
            f"| {r['task']} | {r['count']:,} | {r['size']}x{r['size']} | {r['frames_per_s']:,.1f} | "
            f"{r['rss_start_mb']:.0f} | {r['rss_growth_mb']:+.1f} | {_ok(r)} |"
            for r in frames
        ]
        out.append("")
    cycles = [r for r in rows if r["part"] == "cycles"]
    if cycles:
        out += [
            "| family | cycles | cycles/s | fds before → after | GL contexts before → after | threads before → after "
            "| RSS growth (MB) | ok |",
            "|---|---:|---:|---|---|---|---:|---|",
        ]
        for r in cycles:
            b, a = r["before"], r["after"]
            out.append(
                f"| {r['family']} | {r['count']:,} | {r['cycles_per_s']:.2f} | {b['fds']} → {a['fds']} | "
                f"{b['gl_contexts']} → {a['gl_contexts']} | {b['threads']} → {a['threads']} | "
                f"{a['rss_mb'] - b['rss_mb']:+.1f} | {_ok(r)} |"
            )
    return "\n".join(out)


def _ok(row: dict[str, Any]) -> str:
    return "yes" if row["ok"] else "**no**"


def _positive(value: str) -> int:
    n = int(value) if value.isdigit() else 0
    if n <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value!r}")
    return n


def main(argv: list[str] | None = None) -> int:
    parser = ToolParser("benchmarks.soak", __doc__)
    parser.add_argument("--steps", type=_positive, default=200_000, help="random steps per arm action mode")
    parser.add_argument("--frames", type=_positive, default=5_000, help="rgb_array frames per family")
    parser.add_argument("--cycles", type=_positive, default=1_000, help="make/close cycles per family")
    parser.add_argument("--parts", default="steps,frames,cycles", help="comma-separated: steps, frames, cycles")
    parser.add_argument("--json", help="also write every figure to this JSON file")
    parser.add_argument("--no-progress", action="store_true", help="no progress bars (on stderr)")
    args = parser.parse_args(argv)
    parts = [p.strip() for p in args.parts.split(",") if p.strip()]
    unknown = [p for p in parts if p not in ("steps", "frames", "cycles")]
    if unknown or not parts:
        parser.error(f"unknown part {unknown[0] if unknown else ''!r}; expected steps, frames or cycles")
    os.environ.setdefault("MUJOCO_GL", "egl")
    command = "python -m benchmarks.soak " + " ".join(sys.argv[1:] if argv is None else argv)
    for task in {STEP_TASK, *FRAME_TASKS, *CYCLE_TASKS}:  # load every family now, not hours into the run
        _make(task).close()
    started = time.time()
    rows: list[dict[str, Any]] = []
    for part, run, size in (
        ("steps", soak_steps, args.steps),
        ("frames", soak_frames, args.frames),
        ("cycles", soak_cycles, args.cycles),
    ):
        if part not in parts:
            continue
        new = run(size, progress=not args.no_progress)
        rows += new
        print(tables(new) + "\n", flush=True)  # each part as soon as it is done: a long run keeps what it measured
        if args.json:
            tmp = Path(args.json).with_name(Path(args.json).name + ".tmp")
            tmp.write_text(json.dumps({"command": command, "seconds": time.time() - started, "rows": rows}, indent=2))
            os.replace(tmp, args.json)
    print(f"{time.time() - started:,.0f} s; command: {command}")
    return 0 if all(r["ok"] for r in rows) else 1


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
