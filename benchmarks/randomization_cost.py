"""Reset time with and without each randomisation preset, on one task of every family.

Run from the repository root (not part of the wheel):

    python benchmarks/randomization_cost.py [--resets 200] [--out benchmarks/out/randomization_cost.json]

Each task is made once per preset; the resets of all its envs are timed in interleaved
blocks, and each preset's median seconds per reset is compared with ``none``'s. The
time is the process's CPU time (``time.process_time``), not the wall clock: on a machine
shared with other jobs, the wall clock also counts the time the scheduler gives them.
``randomiser_ms_all`` is the randomiser's own part of an ``all`` reset (drawing every
term, writing the model, deriving what the writes change), timed inside those resets;
``randomiser_ms_all_alone`` is the same work called over and over on its own, with its
code and data hot in the cache. A preset that has no term on a task (``objects`` on a
task without an object) is left out of that task's row.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
import warnings
from pathlib import Path

#: One task per family, in the action mode its reset runs the most code for.
TASKS = {
    "arm4": ("UnifiedManip/Arm4PickAndPlace-v0", "ee_delta"),
    "fetch": ("UnifiedManip/FetchPickAndPlace-v0", "ee_delta"),
    "shadow_hand": ("UnifiedManip/HandManipulateBlock-v0", "joint_delta"),
    "robosuite": ("UnifiedManip/Lift-v0", "ee_delta"),
}
PRESETS = ("none", "dynamics", "objects", "visual", "all")
#: The target: randomising at reset costs at most this much more reset time.
TARGET = 0.20


def _envs(task_id: str, mode: str) -> dict:
    import gymnasium as gym

    import unified_manip  # noqa: F401  (registers the IDs)

    out = {}
    for preset in PRESETS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                out[preset] = gym.make(task_id, action_mode=mode, randomization=preset)
            except ValueError:  # no term of the preset applies to this task
                continue
        out[preset].reset(seed=0)
    return out


def _blocks(reset, per_block: int) -> float:
    """CPU seconds per call of ``reset`` over one block of ``per_block`` calls."""
    start = time.process_time()
    for _ in range(per_block):
        reset()
    return (time.process_time() - start) / per_block


class _Timed:
    """A randomiser's ``reset``, counting the CPU seconds spent inside it."""

    def __init__(self, randomizer) -> None:
        self.inner, self.seconds = randomizer.reset, 0.0
        randomizer.reset = self

    def __call__(self, *args, **kwargs):
        start = time.process_time()
        try:
            return self.inner(*args, **kwargs)
        finally:
            self.seconds += time.process_time() - start


def measure(task_id: str, mode: str, resets: int, blocks: int = 20) -> dict:
    envs = _envs(task_id, mode)
    per_block = max(1, resets // blocks)
    times: dict[str, list[float]] = {p: [] for p in envs}
    inner = envs["all"].unwrapped
    timed = _Timed(inner.randomizer)
    inside: list[float] = []
    for _ in range(blocks):
        for preset, env in envs.items():
            before = timed.seconds
            times[preset].append(_blocks(env.reset, per_block))
            if preset == "all":
                inside.append((timed.seconds - before) / per_block)
    alone = [
        _blocks(lambda: timed.inner(inner.backend, inner.np_random, seeded=False), per_block) for _ in range(blocks)
    ]
    for env in envs.values():
        env.close()
    base = statistics.median(times["none"])
    return {
        "task": task_id,
        "action_mode": mode,
        "resets_per_preset": per_block * blocks,
        "ms_per_reset": {p: round(statistics.median(t) * 1e3, 4) for p, t in times.items()},
        "overhead": {p: round(statistics.median(t) / base - 1.0, 4) for p, t in times.items() if p != "none"},
        "randomiser_ms_all": round(statistics.median(inside) * 1e3, 4),
        "randomiser_ms_all_alone": round(statistics.median(alone) * 1e3, 4),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resets", type=int, default=200, help="resets per preset and task")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/out/randomization_cost.json"))
    parser.add_argument("--family", choices=sorted(TASKS), action="append", help="only these families")
    args = parser.parse_args(argv)
    rows = {f: measure(*TASKS[f], args.resets) for f in (args.family or TASKS)}
    result = {
        "command": "python benchmarks/randomization_cost.py " + " ".join(argv if argv is not None else sys.argv[1:]),
        "machine": {
            "python": platform.python_version(),
            "cpus": os.cpu_count(),
            "load_average_1min_at_end": round(os.getloadavg()[0], 2),
            "clock": "time.process_time (CPU seconds of this process)",
        },
        "target_overhead": TARGET,
        "families": rows,
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.out.with_suffix(".partial")
    tmp.write_text(json.dumps(result, indent=2) + "\n")
    tmp.replace(args.out)
    for family, row in rows.items():
        print(
            family, row["ms_per_reset"], {p: f"{v:+.1%}" for p, v in row["overhead"].items()}, row["randomiser_ms_all"]
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
