"""The benchmark table of a report: final success against a target, steps and wall time
to the target, per task setting (rl-baselines3-zoo's ``benchmark.md``, in success rates).

A grid may name targets (``targets:`` in the grid file, see :func:`parse_targets`); the
report then marks each setting met or missed. Steps to a threshold are read off the
evaluation curve: the first evaluation point whose success reaches it. Wall time to it is
the run's wall time scaled by that fraction of its steps (training runs at a steady rate;
evaluations are spread evenly through it), stated as such in the report.
"""

from __future__ import annotations

import math
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.experiments.stats import seed_interval

#: Threshold used for "steps to" columns when a setting has no target.
DEFAULT_THRESHOLD = 0.9


@dataclass(frozen=True)
class Target:
    """Final success a task in an action mode should reach."""

    task: str
    action_mode: str
    success: float


class TargetError(ValueError):
    """A grid's ``targets`` entry is malformed."""


def parse_targets(value: Any, where: str) -> tuple[Target, ...]:
    """``targets``: a list of ``{task, action_mode, success}`` mappings, success in (0, 1]."""
    if value is None:
        return ()
    keys = {"task", "action_mode", "success"}
    if not isinstance(value, list) or not all(isinstance(e, dict) and set(e) == keys for e in value):
        raise TargetError(f"{where}: targets must be a list of mappings with keys task, action_mode, success")
    out = []
    for e in value:
        s = e["success"]
        if isinstance(s, bool) or not isinstance(s, (int, float)) or not 0 < s <= 1:
            raise TargetError(f"{where}: target success must be a number in (0, 1], got {s!r}")
        out.append(Target(str(e["task"]), str(e["action_mode"]), float(s)))
    return tuple(out)


def grid_targets(grid_file: Path) -> tuple[Target, ...]:
    """The targets a grid file names; none where the file is absent (a bench writes its
    grid as ``grid.yaml`` beside ``results.csv``)."""
    if not grid_file.is_file():
        return ()
    import yaml

    return parse_targets((yaml.safe_load(grid_file.read_text()) or {}).get("targets"), str(grid_file))


def steps_to(curve: list[list[float]], threshold: float) -> int | None:
    """First evaluation step whose success reaches ``threshold``; None if none does."""
    for step, success in curve:
        if success >= threshold - 1e-12:
            return int(step)
    return None


def _hours(seconds: float) -> str:
    return f"{seconds / 3600:.2f} h" if seconds >= 360 else f"{seconds / 60:.0f} min"


def _meets(mean: float, target: float) -> bool:
    """Whether a mean of success rates reaches the target. Rates are fractions of evaluation
    episodes, so a mean equal to the target in exact arithmetic can land a last bit below it
    in floats (0.96, 0.90 and 0.84 average to 0.8999999999999999): that counts as met."""
    return mean >= target or math.isclose(mean, target, abs_tol=1e-9)


def benchmark_table(rows: list[dict[str, Any]], targets: tuple[Target, ...]) -> list[str]:
    """Markdown lines: one row per (task, action mode, algo, reward, observation design,
    training randomisation) setting, its final success with the interval
    :func:`~unified_manip.experiments.stats.seed_interval` labels. The design and the
    randomisation have a column where some run's is not the default."""
    goal = {(t.task, t.action_mode): t.success for t in targets}
    groups: dict[tuple[str, ...], list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        design, randomization = r.get("observation") or "default", r.get("randomization") or "none"
        groups[(r["task"], r["action_mode"], r["algo"], r["reward_type"], design, randomization)].append(r)
    designs = any(k[4] != "default" for k in groups)
    randomized = any(k[5] != "none" for k in groups)
    extra = f"{' observation |' if designs else ''}{' randomization |' if randomized else ''}"
    rule = "---|" * (designs + randomized)
    lines = [
        f"| task | mode |{extra} algo | reward | budget | seeds | final success "
        "[interval] | target | met | steps to target (per seed) | wall time to target (per seed) | "
        "wall time per run | steps/s |",
        f"|---|---|{rule}---|---|---:|---:|---|---:|---|---|---|---|---:|",
    ]
    for (task, mode, algo, reward, design, randomization), runs in sorted(groups.items()):
        runs = sorted(runs, key=lambda r: r["seed"])
        finals = [r["final_success_rate"] for r in runs]
        mean = float(np.mean(finals))
        interval = seed_interval(finals).text()
        interval = f" {interval}" if interval else ""
        target = goal.get((task, mode))
        threshold = target if target is not None else DEFAULT_THRESHOLD
        reached = [steps_to(r["curve"], threshold) for r in runs]
        steps_s = ", ".join("—" if s is None else f"{s:,}" for s in reached)
        wall_s = ", ".join(
            "—" if s is None else _hours(r["wall_time_s"] * s / max(r["steps"], 1)) for s, r in zip(reached, runs)
        )
        met = "—" if target is None else ("**yes**" if _meets(mean, target) else "no")
        label = f"{target:.2f}" if target is not None else f"— (steps to {threshold:.1f})"
        lines.append(
            f"| {task.split('/')[-1]} | {mode} |{f' {design} |' if designs else ''}"
            f"{f' {randomization} |' if randomized else ''} {algo} | {reward} | "
            f"{runs[0]['steps']:,} | {len(runs)} | "
            f"{mean:.2f}{interval} | {label} | {met} | {steps_s} | {wall_s} | "
            f"{_hours(float(np.median([r['wall_time_s'] for r in runs])))} | "
            f"{float(np.median([r['steps_per_s'] for r in runs])):.0f} |"
        )
    missing = [t for t in targets if not any(k[0] == t.task and k[1] == t.action_mode for k in groups)]
    for t in missing:
        lines.append(
            f"| {t.task.split('/')[-1]} | {t.action_mode} |{' — |' * (designs + randomized)} — | — | — | 0 | not run yet | "
            f"{t.success:.2f} | — | — | — | — | — |"
        )
    lines += [
        "",
        "Steps to target: the first evaluation point whose success reaches the target (0.9 where a setting "
        "has none). Wall time to target: the run's wall time times that fraction of its steps. "
        "Final success: the last evaluation point; a run counts only once it has finished its budget.",
        "",
    ]
    return lines
