"""The report's per-task rankings: of action modes, of observation designs, of training
randomisations, and of algorithm and reward settings, each with rliable's probability that the best beats the others.

A ranking compares the settings of one task that differ in one thing and share the rest;
groups are keyed by :data:`~unified_manip.experiments.results.SETTING`.
"""

from __future__ import annotations

from collections import defaultdict
from typing import Any

import numpy as np

from unified_manip.experiments.stats import probability_of_improvement

Groups = dict[str, dict[tuple[str, str, str, str, str], list[dict[str, Any]]]]


def _finals(runs: list[dict[str, Any]]) -> list[float]:
    return [r["final_success_rate"] for r in runs]


def _by_factor(by_task: Groups, index: int, title: str, column: str) -> list[str]:
    """One table per task and per setting of everything but the key's ``index``-th part,
    where two or more values of that part were run."""
    lines: list[str] = []
    for task, groups in by_task.items():
        rest: dict[tuple[str, ...], dict[str, list[float]]] = defaultdict(dict)
        for key, runs in groups.items():
            rest[key[:index] + key[index + 1 :]][key[index]] = _finals(runs)
        for shared, values in sorted(rest.items()):
            if len(values) < 2:
                continue
            full = shared[:index] + ("",) + shared[index:]
            algo, mode, reward, design, randomization = full
            where = [algo, *([mode] if index != 1 else []), f"{reward} reward"]
            if index != 3 and design != "default":
                where.append(f"observation {design}")
            if index != 4 and randomization != "none":
                where.append(f"randomization {randomization}")
            lines += [f"**{task.split('/')[-1]}**, {', '.join(where)}:", ""]
            lines += ranking_table([column], {(v,): vals for v, vals in values.items()})
    return [f"## Ranking of {title}", "", *lines] if lines else []


def design_rankings(by_task: Groups) -> list[str]:
    """Markdown lines: the rankings of action modes, of observation designs and of training
    randomisations, where a task ran several with the rest of the setting the same."""
    return (
        _by_factor(by_task, 1, "action modes", "action mode")
        + _by_factor(by_task, 3, "observation designs", "observation design")
        + _by_factor(by_task, 4, "training randomisations", "training randomization")
    )


def config_rankings(by_task: Groups) -> list[str]:
    """Markdown lines: the ranking of algorithm and reward settings on each task that ran one
    action mode, one observation design and one training randomisation."""
    lines: list[str] = []
    single = {t: g for t, g in by_task.items() if len({(k[1], k[3], k[4]) for k in g}) == 1 and len(g) > 1}
    if single:
        lines += ["## Ranking of algorithm and reward settings", ""]
        for task, groups in single.items():
            _, mode, _, design, randomization = next(iter(groups))
            suffix = "" if design == "default" else f", observation {design}"
            suffix += "" if randomization == "none" else f", randomization {randomization}"
            lines += [f"**{task.split('/')[-1]}**, {mode} mode{suffix}:", ""]
            lines += ranking_table(
                ["algo", "reward"], {(algo, reward): _finals(runs) for (algo, _, reward, *_), runs in groups.items()}
            )
    return lines


def ranking_table(columns: list[str], settings: dict[tuple[str, ...], list[float]]) -> list[str]:
    """Markdown rows ranking ``settings`` (label -> final success per seed) by mean, with
    rliable's probability that the best beats each one."""
    ranked = sorted(settings.items(), key=lambda kv: -np.mean(kv[1]))
    best = ranked[0][1]
    lines = [
        f"| rank | {' | '.join(columns)} | mean final success | P(best > this) |",
        "|---:|" + "---|" * len(columns) + "---:|---:|",
    ]
    for i, (label, vals) in enumerate(ranked, 1):
        enough = len(vals) >= 2 and len(best) >= 2
        poi = "—" if i == 1 else (f"{probability_of_improvement(best, vals):.2f}" if enough else "— (one seed)")
        lines.append(f"| {i} | {' | '.join(label)} | {np.mean(vals):.2f} | {poi} |")
    return lines + [""]
