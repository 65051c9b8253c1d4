"""The report's cross-task aggregates per action mode, and per observation design: Markdown
and figures.

Written when a setting's results span more than one task and more than one mode (or design) that ran
on all of them (:func:`aggregate_section`); the numbers are :mod:`.aggregates`'.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.experiments.aggregates import (
    FACTORS,
    MIN_RUNS_PER_TASK_FOR_CI,
    REPS,
    SEED,
    STEPS_THRESHOLD,
    TAUS,
    ModeScores,
    improvement_intervals,
    iqm_intervals,
    mode_scores,
    performance_profiles,
    rank_table,
    settings,
)
from unified_manip.experiments.figures import pyplot

#: Thresholds the performance profile is tabulated at (the figure draws all of TAUS).
PROFILE_TAUS = (0.2, 0.5, 0.8)


def aggregate_section(rows: list[dict[str, Any]], out: Path) -> list[str]:
    """Markdown lines of the aggregates of every setting (algorithm, reward) whose runs span
    at least two tasks and at least two modes run on every one of them; figures go to
    ``out``. No lines where no setting qualifies."""
    lines: list[str] = []
    for factor in FACTORS:
        for (algo, reward), setting_rows in settings(rows).items():
            scores = mode_scores(setting_rows, factor)
            if len(scores.tasks) > 1 and len(scores.modes) > 1:
                lines += _setting_lines(scores, algo, reward, out, factor)
    if not lines:
        return []
    return ["## Aggregates across tasks", "", *lines]


#: How the report names each compared factor (one, many), and its figures' file suffix.
_WORDS = {
    "action_mode": ("action mode", "Action modes", "", "mode"),
    "observation": ("observation design", "Observation designs", "_observation", "design"),
}


def _setting_lines(s: ModeScores, algo: str, reward: str, out: Path, factor: str = "action_mode") -> list[str]:
    what, whats, suffix, short = _WORDS[factor]
    stem = f"aggregates_{algo}_{reward}{suffix}"
    names = [t.split("/")[-1] for t in s.tasks]
    iqm = iqm_intervals(s.final)
    auc = iqm_intervals(s.auc)
    profiles, bands = performance_profiles(s.final)
    poi_ci = improvement_intervals(s.final)
    poi = {pair: p for pair, (p, _, _) in poi_ci.items()}
    ranks = rank_table(s.final)
    order = sorted(s.modes, key=lambda m: (-iqm[m][0], m))
    runs = ", ".join(f"{m} {n}" for m, (n, _) in s.runs.items())
    ci = min(n for n, _ in s.runs.values()) >= MIN_RUNS_PER_TASK_FOR_CI
    cut = {m: c for m, (_, c) in s.runs.items() if c}
    lines = [
        f"### {'' if factor == 'action_mode' else whats + ': '}{algo}, {reward} reward",
        "",
        f"{whats} run on all {len(s.tasks)} tasks ({', '.join(names)}), their runs per task: {runs}. "
        f"Each {short}'s final success over all its runs of all tasks; intervals are rliable's stratified "
        f"bootstrap (runs resampled within each task, {REPS:,} resamples, 95%, seed {SEED})"
        + (
            "."
            if ci
            else f", shown only once every {short} has at least {MIN_RUNS_PER_TASK_FOR_CI} runs on each task: "
            "with one run per task there is nothing to resample, so no interval is shown ([—])."
        ),
        *(
            [
                "Left out, as not run on every task: "
                + "; ".join(
                    f"{m} (no runs of {', '.join(t.split('/')[-1] for t in ts)})" for m, ts in s.left_out.items()
                )
                + "."
            ]
            if s.left_out
            else []
        ),
        *(
            [
                f"Runs beyond a {short}'s fewest on any task are left out (lowest seeds kept): "
                + ", ".join(f"{m} {c}" for m, c in cut.items())
                + "."
            ]
            if cut
            else []
        ),
        "",
        f"| {what} | runs | IQM final success [95% CI] | IQM area under the success curve [95% CI] | mean rank |",
        "|---|---:|---|---|---:|",
    ]
    for m in order:
        lines.append(
            f"| {m} | {s.final[m].size} | {iqm_text(iqm[m], ci)} | {iqm_text(auc[m], ci)} | {ranks[m][1]:.2f} |"
        )
    lines += [
        "",
        "Area under the success curve: each run's evaluation success averaged over the steps between its "
        "first and last evaluation (trapezoids), so 1.0 is success at every evaluation.",
        "",
        f"![IQM across tasks, {algo}, {reward}]({_plot_iqm(order, iqm, auc, out / f'{stem}_iqm.png', ci).name})",
        "",
        "**Performance profile**: the fraction of runs (all tasks) whose final success exceeds τ.",
        "",
        f"| {what} | " + " | ".join(f"τ = {t}" for t in PROFILE_TAUS) + " |",
        "|---|" + "---:|" * len(PROFILE_TAUS),
    ]
    at = [int(np.argmin(np.abs(TAUS - t))) for t in PROFILE_TAUS]
    lines += [f"| {m} | " + " | ".join(f"{profiles[m][i]:.2f}" for i in at) + " |" for m in order]
    fig = _plot_profiles(order, profiles, bands, out / f"{stem}_profile.png")
    lines += ["", f"![Performance profile, {algo}, {reward}]({fig.name})", ""]
    lines += [
        f"**Probability of improvement**: P(row {short} > column {short}), the chance that a run of the row's {short} "
        "scores a higher final success than a run of the column's on the same task (ties half), averaged "
        "over tasks; in brackets its 95% stratified-bootstrap interval.",
        "",
        "| P(row > column) | " + " | ".join(order) + " |",
        "|---|" + "---:|" * len(order),
    ]
    lines += [
        f"| {x} | " + " | ".join("—" if x == y else iqm_text(poi_ci[(x, y)], ci) for y in order) + " |" for x in order
    ]
    fig = _plot_improvement(order, poi, out / f"{stem}_improvement.png", short)
    lines += ["", f"![Probability of improvement, {algo}, {reward}]({fig.name})", ""]
    lines += [
        f"**Sample efficiency**: environment steps to the first evaluation with success ≥ {STEPS_THRESHOLD} "
        "(per run, seed order; — where never reached), and the mean area under the success curve.",
        "",
        f"| {what} | " + " | ".join(f"{n} steps to {STEPS_THRESHOLD}" for n in names) + " | mean area |",
        "|---|" + "---|" * len(names) + "---:|",
    ]
    for m in order:
        cells = [", ".join("—" if x is None else f"{x:,}" for x in col) for col in s.steps[m]]
        lines.append(f"| {m} | " + " | ".join(cells) + f" | {s.auc[m].mean():.2f} |")
    lines += [
        "",
        "**Rank per task** by mean final success (1 = best; ties share their mean rank), the mean in parentheses.",
        "",
        f"| {what} | " + " | ".join(names) + " | mean rank |",
        "|---|" + "---:|" * (len(names) + 1),
    ]
    for m in sorted(s.modes, key=lambda m: (ranks[m][1], m)):
        cells = [f"{r:g} ({v:.2f})" for r, v in zip(ranks[m][0], s.final[m].mean(axis=0))]
        lines.append(f"| {m} | " + " | ".join(cells) + f" | {ranks[m][1]:.2f} |")
    return lines + [""]


def iqm_text(v: tuple[float, float, float], ci: bool = True) -> str:
    """A value and its interval, or ``[—]`` where no interval is shown."""
    return f"{v[0]:.2f} [{v[1]:.2f}, {v[2]:.2f}]" if ci else f"{v[0]:.2f} [—]"


def _plot_iqm(order: list[str], iqm: dict, auc: dict, path: Path, ci: bool = True) -> Path:
    """IQM of final success and of the area under the curve, one row per mode, 95% CIs
    (none with ``ci`` False)."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(8, 0.9 + 0.38 * len(order)), dpi=110, sharey=True)
    y = np.arange(len(order))[::-1]
    for ax, values, title in ((axes[0], iqm, "IQM final success"), (axes[1], auc, "IQM area under success curve")):
        points = np.array([values[m][0] for m in order])
        err = np.array([[values[m][0] - values[m][1], values[m][2] - values[m][0]] for m in order]).T
        ax.errorbar(points, y, xerr=err if ci else None, fmt="o", color="C0", capsize=3)
        ax.set_title(title, fontsize=9)
        ax.set_xlim(-0.02, 1.02)
        ax.grid(axis="x", alpha=0.3)
    axes[0].set_yticks(y, order, fontsize=8)
    bar = "bar: 95% stratified bootstrap CI" if ci else "no interval: one run per task"
    fig.supxlabel(f"across tasks (point: IQM of all runs; {bar})", fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def _plot_profiles(order: list[str], profiles: dict, bands: dict, path: Path) -> Path:
    """rliable's performance-profile plot: fraction of runs above each tau, 95% bands."""
    plt = pyplot()
    from rliable import plot_utils

    fig, ax = plt.subplots(figsize=(6.5, 4), dpi=110)
    colours = {m: f"C{i % 10}" for i, m in enumerate(order)}
    plot_utils.plot_performance_profiles(
        {m: profiles[m] for m in order},
        TAUS,
        performance_profile_cis={m: bands[m] for m in order},
        colors=colours,
        ax=ax,
        xlabel=r"final success rate ($\tau$)",
        ylabel=r"fraction of runs with success $> \tau$",
        labelsize="medium",
        ticklabelsize="small",
        legend=True,
        legendsize="x-small",
    )
    ax.set_title("Performance profile across tasks (95% stratified bootstrap bands)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def _plot_improvement(order: list[str], poi: dict, path: Path, short: str = "mode") -> Path:
    """P(row > column) as a matrix, each cell annotated."""
    plt = pyplot()
    matrix = np.array([[np.nan if x == y else poi[(x, y)] for y in order] for x in order])
    fig, ax = plt.subplots(figsize=(1.6 + 0.75 * len(order), 1.2 + 0.6 * len(order)), dpi=110)
    image = ax.imshow(matrix, vmin=0, vmax=1, cmap="RdBu")
    for i in range(len(order)):
        for j in range(len(order)):
            if i != j:
                dark = abs(matrix[i, j] - 0.5) > 0.3
                ax.text(j, i, f"{matrix[i, j]:.2f}", ha="center", va="center", fontsize=7, color="w" if dark else "k")
    ax.set_xticks(range(len(order)), order, rotation=45, ha="right", fontsize=8)
    ax.set_yticks(range(len(order)), order, fontsize=8)
    ax.set_title(f"P(row {short} > column {short}), final success", fontsize=9)
    fig.colorbar(image, ax=ax, fraction=0.046)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path
