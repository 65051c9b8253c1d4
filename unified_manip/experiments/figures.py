"""The report's figures: success against steps per task, and final success per setting.

A *group* is what :func:`unified_manip.experiments.report._group` gives for one task: ``(algo,
action mode, reward) -> runs`` (result rows, one per seed). Intervals over seeds are
:func:`~unified_manip.experiments.stats.seed_interval`'s: the seeds' range below 5 seeds,
the 95% percentile bootstrap of the mean from 5 on.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from unified_manip.experiments.results import setting_label, steps_label
from unified_manip.experiments.stats import MIN_SEEDS_FOR_CI, seed_interval


def interval_label(seed_counts) -> str:
    """What a figure's bands or whiskers over seeds are, for settings of these seed counts."""
    few = {n < MIN_SEEDS_FOR_CI for n in seed_counts if n > 1}
    if not few:
        return "none, one seed each"
    if few == {True}:
        return "range of the seeds"
    if few == {False}:
        return "95% bootstrap CI"
    return f"range of the seeds where n < {MIN_SEEDS_FOR_CI}, 95% bootstrap CI where n ≥ {MIN_SEEDS_FOR_CI}"


#: A group key is :data:`~unified_manip.experiments.results.SETTING`; labels name its parts in
#: this order of the key's indices (action mode, observation, reward, algo, randomisation):
#: what a reader compares first. A label with nothing varying names the first four.
_LABEL_ORDER = (1, 3, 2, 0, 4)


class Bar(NamedTuple):
    """One setting's final success over seeds, as drawn by :func:`plot_final`."""

    label: str
    mean: float
    low: float  # seed_interval: range below 5 seeds, 95% bootstrap CI from 5; NaN with one seed
    high: float
    values: tuple[float, ...]  # per seed, in seed order


def pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _target_lines(targets: dict[str, float] | None) -> list[tuple[float, str]]:
    """One line per target level (action mode -> success), labelled with its modes."""
    modes_at: dict[float, list[str]] = {}
    for mode, level in sorted((targets or {}).items()):
        modes_at.setdefault(level, []).append(mode)
    return [
        (level, f"target {level:.2f}, " + (", ".join(modes) if len(modes) <= 2 else f"{len(modes)} modes"))
        for level, modes in sorted(modes_at.items())
    ]


def curve_band(runs: list[dict[str, Any]]):
    """Eval steps, mean success and a band over seeds at each step (:func:`seed_interval`:
    the seeds' range below 5 seeds, the 95% bootstrap CI of the mean from 5 on).

    Seeds evaluated at different steps (one committed Arm4Push-v1 seed was evaluated at
    10k, 20k, 33,040, 43,040, ...) are read at every step any of them was evaluated at,
    within the range all of them cover, by linear interpolation between each one's own
    points. Runs without an evaluation are left out.
    """
    curves = [c for c in (np.array(r["curve"], dtype=float).reshape(-1, 2) for r in runs) if len(c)]
    if not curves:
        return np.array([]), np.array([]), np.array([]), np.array([])
    first, last = max(c[0, 0] for c in curves), min(c[-1, 0] for c in curves)
    steps = sorted({t for c in curves for t in c[:, 0] if first <= t <= last})
    table = np.array([np.interp(steps, c[:, 0], c[:, 1]) for c in curves])
    mean = table.mean(axis=0)
    low, high = np.full_like(mean, np.nan), np.full_like(mean, np.nan)
    if len(curves) >= 2:
        for i in range(len(steps)):
            low[i], high[i], _ = seed_interval(table[:, i].tolist(), seed=i)
    return np.array(steps), mean, low, high


def plot_task(task: str, groups: dict, out: Path, targets: dict[str, float] | None = None) -> Path:
    """Success against steps, one line per setting; ``targets`` (action mode -> success)
    are drawn as dashed lines."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=110)
    for key, runs in sorted(groups.items()):
        steps, mean, low, high = curve_band(runs)
        (line,) = ax.plot(steps, mean, marker="o", ms=3, label=f"{setting_label(key)} (n={len(runs)})")
        if np.isfinite(low).any():
            ax.fill_between(steps, low, high, color=line.get_color(), alpha=0.2, linewidth=0)
    for level, label in _target_lines(targets):
        ax.axhline(level, color="0.4", linestyle="--", linewidth=1, label=label)
    band = interval_label(len(runs) for runs in groups.values())
    ax.set_title(f"{task}: evaluation success rate\n(mean over seeds, shaded: {band})", fontsize=9)
    ax.set_xlabel(steps_label(r for runs in groups.values() for r in runs))
    ax.set_ylabel("success rate")
    return save_success_figure(fig, ax, out / f"{task.split('/')[-1]}_success.png")


def save_success_figure(fig, ax, path: Path) -> Path:
    """Finish a figure of success rates in [0, 1] (grid, legend, tight layout), write it to
    ``path`` and close it."""
    ax.set_ylim(-0.02, 1.02)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    fig.savefig(path)
    pyplot().close(fig)
    return path


def final_bars(groups: dict) -> list[Bar]:
    """Each setting's final success, best mean first; labels name only the parts of the
    settings that differ (all of them if none does)."""
    varying = [i for i in _LABEL_ORDER if len({key[i] for key in groups}) > 1] or list(_LABEL_ORDER[:4])
    bars = []
    for key, runs in groups.items():
        values = tuple(r["final_success_rate"] for r in sorted(runs, key=lambda r: r["seed"]))
        low, high, _ = seed_interval(list(values))
        label = " / ".join(key[i] for i in varying)
        bars.append(Bar(label, float(np.mean(values)), low, high, values))
    return sorted(bars, key=lambda b: (-b.mean, b.label))


def plot_final(task: str, groups: dict, out: Path, targets: dict[str, float] | None = None) -> Path:
    """Final success per setting as horizontal bars (mean over seeds, the interval of
    :func:`seed_interval`, each seed a dot), best on top; one dashed line per target."""
    plt = pyplot()
    bars = final_bars(groups)
    fig, ax = plt.subplots(figsize=(7, 0.9 + 0.42 * len(bars)), dpi=110)
    y = np.arange(len(bars))[::-1]
    means = np.array([b.mean for b in bars])
    err = np.array([[b.mean - b.low, b.high - b.mean] for b in bars]).T
    ax.barh(y, means, color="C0", alpha=0.55, xerr=np.nan_to_num(err), capsize=3, error_kw={"linewidth": 1})
    for yi, b in zip(y, bars):
        ax.plot(b.values, np.full(len(b.values), yi), "o", color="k", ms=3)
        ax.text(1.03, yi, f"{b.mean:.2f}", va="center", fontsize=8)
    for level, label in _target_lines(targets):
        ax.axvline(level, color="0.4", linestyle="--", linewidth=1)
        ax.text(
            level, 1.0, label, transform=ax.get_xaxis_transform(), ha="center", va="bottom", fontsize=7, color="0.3"
        )
    ax.set_yticks(y, [f"{b.label} (n={len(b.values)})" for b in bars], fontsize=8)
    ax.set_xlim(0, 1.1)
    whisker = interval_label(len(b.values) for b in bars)
    ax.set_xlabel(f"final success rate (bar: mean over seeds, whisker: {whisker}, dots: seeds)", fontsize=8)
    ax.set_title(f"{task}: final evaluation success per setting", fontsize=9, pad=14 if targets else 6)
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    path = out / f"{task.split('/')[-1]}_final.png"
    fig.savefig(path)
    plt.close(fig)
    return path
