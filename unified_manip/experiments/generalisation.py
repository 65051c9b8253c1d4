"""The generalisation gap of a bench's final policies: success on the nominal task
(``default``) minus success on a shifted test distribution (``in-range``: the training
preset's ranges; ``extreme``: ranges beyond them), per seed, from the rows of
``robustness.csv`` that ``unified-manip robustness --test-distribution`` wrote (Packer et
al. 2018: interpolation against extrapolation). Intervals over seeds are
:func:`~unified_manip.experiments.stats.seed_interval`'s: the seeds' range below 5 seeds.
"""

from __future__ import annotations

from collections import defaultdict
from typing import Any

import numpy as np

from unified_manip.envs.randomization import TEST_DISTRIBUTIONS
from unified_manip.experiments.stats import seed_interval

SHIFTED = ("in-range", "extreme")


def gaps(rows: list[dict[str, Any]]) -> dict[tuple[str, str, str, str], dict[str, list[float]]]:
    """``(task, design, mode, training randomisation) -> shifted distribution -> [gap per
    seed]``: default minus shifted success of each seed evaluated on both, without noise
    or delay, every factor of the distribution together. Settings with no such pair are
    left out."""
    success: dict[tuple, dict[str, float]] = defaultdict(dict)
    for r in rows:
        if r["distribution"] and not r["noise"] and not r["delay"] and not r.get("factor"):
            key = (r["task"], r["observation"], r["action_mode"], r["randomization"], r["seed"])
            success[key][r["distribution"]] = r["success_rate"]
    out: dict[tuple[str, str, str, str], dict[str, list[float]]] = defaultdict(lambda: defaultdict(list))
    for (*setting, seed), by_distribution in sorted(success.items()):
        for shifted in SHIFTED:
            if "default" in by_distribution and shifted in by_distribution:
                out[tuple(setting)][shifted].append(by_distribution["default"] - by_distribution[shifted])
    return {k: dict(v) for k, v in out.items()}


def distribution_lines(rows: list[dict[str, Any]]) -> list[str]:
    """Markdown lines on the test distributions of ``rows`` (robustness.csv's, typed) and a
    table of the generalisation gap; none where no row has a test distribution."""
    order = {d: i for i, d in enumerate(TEST_DISTRIBUTIONS)}
    tested = sorted({(r["distribution"], r["tested"]) for r in rows if r["distribution"]}, key=lambda k: order[k[0]])
    if not tested:
        return []
    lines = [
        "Test distributions (Packer et al. 2018): `default` is the nominal task, `in-range` the training "
        "preset's ranges, `extreme` ranges beyond them with the training ranges excluded. Tested under: "
        + "; ".join(f"{d} `{t}`" for d, t in tested)
        + ". A run trained without randomisation takes its ranges from `--randomization`.",
        "",
    ]
    table = gaps(rows)
    if not table:
        return lines
    lines += [
        "Generalisation gap: success on `default` minus success on the shifted distribution, per seed (no "
        "noise, no delay); mean over seeds, with the seeds' range below 5 seeds and a 95% bootstrap interval "
        "from 5. Positive: the policy does worse off its nominal task.",
        "",
        "| task | observation design | mode | training randomization | seeds | gap in-range | gap extreme |",
        "|---|---|---|---|---:|---:|---:|",
    ]
    for (task, design, mode, rand), by_shift in sorted(table.items()):
        seeds = max(len(v) for v in by_shift.values())
        cells = " | ".join(gap_cell(by_shift.get(s, [])) for s in SHIFTED)
        lines.append(f"| {task.split('/')[-1]} | {design} | {mode} | {rand} | {seeds} | {cells} |")
    return lines + [""]


def gap_cell(values: list[float]) -> str:
    """A gap's mean over seeds, signed, with the seeds' interval (:func:`seed_interval`)."""
    if not values:
        return "—"
    interval = seed_interval(values).text()
    return f"{np.mean(values):+.2f}" + (f" {interval}" if interval else "")
