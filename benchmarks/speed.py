"""Env steps per second against the raw physics limit, the upstream envs and training:
``python -m benchmarks.speed``.

For every ID x action mode, random actions are played through ``gym.make``'s env
(wrappers included, env checker off) and two clocks run over the same steps: the wall
time of the whole ``step`` calls (:func:`unified_manip.experiments.speed.step_rate`, what
``unified-manip speed`` reports) and the time spent inside the backend's ``physics_step``
(the substeps of ``mj_step``, nothing else), which this tool wraps on the env's backend for
the measurement. Their ratio is the fraction of the raw physics limit the env reaches on
exactly the states it visited. A family whose step runs the physics inside upstream code
(Fetch, the Shadow Hand, robosuite) has no ``physics_step``: its raw rate is NaN. Compare
ratios, not absolute rates: these machines are shared and noisy.
"""

from __future__ import annotations

import statistics
import sys
import time
from contextlib import contextmanager
from dataclasses import asdict, dataclass
from typing import Iterator

import gymnasium as gym
from rich.console import Console
from rich.table import Table

from benchmarks.parser import ToolParser
from benchmarks.upstream_speed import compare_upstream, train_speed
from unified_manip.cli.args import positive_int, task_ids
from unified_manip.cli.output import write_json
from unified_manip.envs.registry import TASKS
from unified_manip.experiments.speed import WARMUP, rounds, step_rate


@dataclass(frozen=True)
class SpeedResult:
    task_id: str
    action_mode: str
    env_steps_per_s: float
    raw_steps_per_s: float

    @property
    def ratio_to_raw(self) -> float:
        return self.env_steps_per_s / self.raw_steps_per_s

    @property
    def overhead_us(self) -> float:
        """Time per step spent outside the physics (control, observation, reward), µs."""
        return 1e6 * (1.0 / self.env_steps_per_s - 1.0 / self.raw_steps_per_s)

    def as_dict(self) -> dict:
        return {**asdict(self), "ratio_to_raw": self.ratio_to_raw, "overhead_us": self.overhead_us}


@dataclass
class PhysicsTimer:
    """Wall-clock seconds spent in the backend's ``physics_step`` while :func:`timing_physics`
    is open (set ``seconds`` to 0 to start over)."""

    seconds: float = 0.0


@contextmanager
def timing_physics(env: gym.Env) -> Iterator[PhysicsTimer]:
    """Time every call of ``env``'s backend's ``physics_step`` inside the ``with`` block: the
    method is shadowed on the backend instance by a timed call of itself, and restored at the
    end. A backend without one (its physics runs inside upstream code) leaves the timer at 0."""
    timer = PhysicsTimer()
    backend = env.unwrapped.backend
    physics = getattr(backend, "physics_step", None)
    if physics is None:
        yield timer
        return
    clock = time.perf_counter

    def timed_physics() -> None:
        start = clock()
        physics()
        timer.seconds += clock() - start

    backend.physics_step = timed_physics
    try:
        yield timer
    finally:
        del backend.physics_step


def measure(task_id: str, action_mode: str, steps: int = 2000, seed: int = 0) -> SpeedResult:
    """Step rate of the env and of its physics alone, over the same ``steps`` steps."""
    env = gym.make(task_id, action_mode=action_mode, disable_env_checker=True)
    try:
        with timing_physics(env) as physics:
            step_rate(env, WARMUP, seed)
            physics.seconds = 0.0
            rate = step_rate(env, steps, seed)
    finally:
        env.close()
    spent = physics.seconds
    return SpeedResult(task_id, action_mode, rate, steps / spent if spent > 0 else float("nan"))


def run(task_ids=None, modes=None, steps: int = 2000, repeats: int = 3, progress: bool = True) -> list[SpeedResult]:
    """Measure every requested ID x supported mode; each figure is the median of
    ``repeats`` measurements, taken in rounds so that load spikes spread over modes."""
    samples = rounds(task_ids, modes, steps, repeats, progress, measure=measure)
    return [
        SpeedResult(
            tid,
            mode,
            statistics.median(r.env_steps_per_s for r in rs),
            statistics.median(r.raw_steps_per_s for r in rs),
        )
        for (tid, mode), rs in samples.items()
    ]


# ---------------------------------------------------------------------- import time
def import_times(repeats: int = 10, modules: tuple[str, ...] = ("gymnasium", "unified_manip")) -> dict[str, float]:
    """Median wall time, s, of ``python -c "import <module>"`` for each module, each a
    fresh interpreter, run in turn (``repeats`` rounds) so that all see the same load."""
    import subprocess

    times: dict[str, list[float]] = {m: [] for m in modules}
    for _ in range(repeats):
        for m in modules:
            start = time.perf_counter()
            subprocess.run([sys.executable, "-c", f"import {m}"], check=True)
            times[m].append(time.perf_counter() - start)
    return {m: statistics.median(t) for m, t in times.items()}


# ---------------------------------------------------------------------- the command
def _modes_table(results: list[SpeedResult], title: str) -> Table:
    table = Table(title=title)
    for col in (
        "ID",
        "action mode",
        "env steps/s",
        "raw physics steps/s",
        "env / raw",
        "overhead µs/step",
        "mode / joint_position",
    ):
        table.add_column(col, justify="right")
    by_key = {(r.task_id, r.action_mode): r for r in results}
    for r in results:
        jp = by_key.get((r.task_id, "joint_position"))
        rel = f"{r.env_steps_per_s / jp.env_steps_per_s:.2f}" if jp else "-"
        table.add_row(
            r.task_id,
            r.action_mode,
            f"{r.env_steps_per_s:,.0f}",
            f"{r.raw_steps_per_s:,.0f}",
            f"{r.ratio_to_raw:.2f}",
            f"{r.overhead_us:.0f}",
            rel,
        )
    return table


def _upstream_table(rows) -> Table:
    table = Table(title="native mode against the upstream env, same actions, one step of each in turn")
    for col in (
        "ID",
        "upstream",
        "ours steps/s",
        "upstream steps/s",
        "ours / upstream",
        "ours resets/s",
        "upstream resets/s",
    ):
        table.add_column(col, justify="right")
    for r in rows:
        table.add_row(
            r.task_id,
            r.upstream,
            f"{r.ours_steps_per_s:,.0f}",
            f"{r.upstream_steps_per_s:,.0f}",
            f"{r.ratio:.3f}",
            f"{r.ours_resets_per_s:,.0f}",
            f"{r.upstream_resets_per_s:,.1f}",
        )
    return table


def _training_table(rows) -> Table:
    table = Table(title="SAC+HER training steps/s, native mode against the upstream env")
    for col in ("ID", "upstream", "ours steps/s", "upstream steps/s", "ours / upstream"):
        table.add_column(col, justify="right")
    for r in rows:
        table.add_row(
            r.task_id, r.upstream, f"{r.ours_steps_per_s:,.1f}", f"{r.upstream_steps_per_s:,.1f}", f"{r.ratio:.3f}"
        )
    return table


def main(argv: list[str] | None = None) -> int:
    p = ToolParser("benchmarks.speed", __doc__)
    p.add_argument("--env", type=task_ids, help="comma-separated IDs (default: all)")
    p.add_argument("--modes", type=lambda s: s.split(","), help="comma-separated action modes (default: all)")
    p.add_argument("--steps", type=positive_int, default=2000, help="steps per measurement")
    p.add_argument("--repeats", type=positive_int, default=3, help="measurements per figure (median)")
    p.add_argument("--no-upstream", action="store_true", help="skip the comparison with wrapped upstream envs")
    p.add_argument("--train", type=task_ids, help="also time SAC+HER training on these IDs against their upstream envs")
    p.add_argument("--train-steps", type=positive_int, default=1500, help="training steps per timed round")
    p.add_argument("--json", help="also write the results to this JSON file")
    p.add_argument("--width", type=int, default=200, help="table width in characters")
    args = p.parse_args(argv)

    console = Console(width=args.width)
    results = run(args.env, args.modes, steps=args.steps, repeats=args.repeats)
    title = f"env steps/s vs raw physics (median of {args.repeats} x {args.steps} steps)"
    console.print(_modes_table(results, title))
    document: dict = {"modes": [r.as_dict() for r in results]}
    wrapped = [t for t in args.env or list(TASKS) if TASKS[t].upstream_id]
    if wrapped and not args.no_upstream:
        rows = [compare_upstream(t, steps=args.steps) for t in wrapped]
        console.print(_upstream_table(rows))
        document["upstream"] = [r.as_dict() for r in rows]
    if args.train:
        rows = [train_speed(t, steps=args.train_steps) for t in args.train]
        console.print(_training_table(rows))
        document["training"] = [r.as_dict() for r in rows]
    if args.json:
        write_json(args.json, document)
    return 0


if __name__ == "__main__":
    sys.exit(main())
