"""``unified-manip plot RESULTS...``: one figure of evaluation success against steps over
one or more benches, a panel per task, for a README or a paper.

Each panel draws one line per *setting* (action mode, reward, algorithm, and whether the
runs started from scripted demonstrations): the mean over seeds with its band
(:func:`unified_manip.experiments.figures.curve_band`: the seeds' range below 5 seeds, the
95% bootstrap CI from 5), and each bench's target for the
task as a dashed line. rl-baselines3-zoo draws one plot per env; this puts a benchmark's
tasks side by side, in the order they first appear in the results files.
"""

from __future__ import annotations

import math
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.experiments.figures import curve_band, interval_label, pyplot
from unified_manip.experiments.results import ResultsError, read_results, steps_label
from unified_manip.experiments.targets import grid_targets

#: File types the figure may be written as (matplotlib picks the format by suffix).
FIGURE_SUFFIXES = (".png", ".svg", ".pdf")

Setting = tuple[str, str, str, bool]  # action mode, reward, algo, demonstrations


def _setting(row: dict[str, Any]) -> Setting:
    return row["action_mode"], row["reward_type"], row["algo"], bool(row.get("demonstrations"))


def collect(sources: list[Path]) -> tuple[dict[str, dict[Setting, list[dict]]], dict[tuple[str, str], float]]:
    """The finished runs of every results file, ``task -> setting -> rows``, and their
    benches' targets. Raises :class:`ResultsError` for a file with no runs."""
    panels: dict[str, dict[Setting, list[dict]]] = defaultdict(lambda: defaultdict(list))
    targets: dict[tuple[str, str], float] = {}
    for path in sources:
        rows = read_results(path)
        if not rows:
            raise ResultsError(f"{path}: no finished runs to plot")
        for row in rows:
            panels[row["task"]][_setting(row)].append(row)
        targets.update({(t.task, t.action_mode): t.success for t in grid_targets(path.parent / "grid.yaml")})
    return panels, targets


def _labeller(settings: list[Setting]):
    """Labels that name the algorithm and whichever other parts differ in the figure."""
    varying = [i for i in (0, 1) if len({s[i] for s in settings}) > 1]

    def label(s: Setting, n: int) -> str:
        algo = s[2] + (" + demos" if s[3] else "")
        return " / ".join([*(s[i] for i in varying), algo]) + f" (n={n})"

    return label


def pick_tasks(panels: dict[str, Any], tasks: list[str] | None, sources: list[Path]) -> dict[str, Any]:
    """``panels`` restricted to ``tasks``, in that order (all of them when None).

    Raises:
        ResultsError: A task that no results file has a run of.
    """
    if tasks is None:
        return panels
    missing = [t for t in tasks if t not in panels]
    if missing:
        raise ResultsError(
            f"no finished runs of {', '.join(missing)} in {', '.join(map(str, sources))}; "
            f"the files hold runs of {', '.join(panels)}"
        )
    return {t: panels[t] for t in tasks}


def panel_axes(plt: Any, panels: int, columns: int) -> tuple[Any, np.ndarray]:
    """A figure with one axes per panel, ``columns`` (at most ``panels``) to a row."""
    columns = max(1, min(columns, panels))
    rows = math.ceil(panels / columns)
    return plt.subplots(rows, columns, figsize=(3.4 * columns, 2.6 * rows), dpi=110, squeeze=False)


def plot_overview(sources: list[Path], out: Path, columns: int = 4, tasks: list[str] | None = None) -> list[str]:
    """Write the figure to ``out`` (its suffix picks the format); return the panels'
    titles, one per task, in drawing order. ``tasks`` picks the panels and their order
    (default: every task, in the order the results files first name them); a task that
    no file has a run of raises :class:`ResultsError`."""
    panels, targets = collect(sources)
    panels = pick_tasks(panels, tasks, sources)
    every = sorted({s for settings in panels.values() for s in settings})
    label = _labeller(every)
    colour = {s: f"C{i % 10}" for i, s in enumerate(every)}  # one setting, one colour, in every panel
    plt = pyplot()
    fig, axes = panel_axes(plt, len(panels), columns)
    titles = []
    for ax, (task, settings) in zip(axes.flat, panels.items()):
        for setting, runs in sorted(settings.items()):
            steps, mean, low, high = curve_band(runs)
            ax.plot(steps, mean, marker="o", ms=2, lw=1.2, color=colour[setting], label=label(setting, len(runs)))
            if np.isfinite(low).any():
                ax.fill_between(steps, low, high, color=colour[setting], alpha=0.2, linewidth=0)
        for level in sorted({v for (t, _), v in targets.items() if t == task}):
            ax.axhline(level, color="0.4", linestyle="--", linewidth=1, label=f"target {level:.2f}")
        title = task.split("/")[-1]
        titles.append(title)
        ax.set_title(title, fontsize=9)
        ax.set_ylim(-0.02, 1.02)
        ax.xaxis.set_major_formatter(lambda x, _: f"{x / 1000:g}k")
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6, loc="best")
    for ax in list(axes.flat)[len(panels) :]:
        ax.set_visible(False)
    x = steps_label(r for settings in panels.values() for runs in settings.values() for r in runs)
    fig.supxlabel(x, fontsize=9)
    fig.supylabel("success rate", fontsize=9)
    band = interval_label(len(runs) for settings in panels.values() for runs in settings.values())
    fig.suptitle(f"Evaluation success against {x} (mean over seeds, shaded: {band})", fontsize=10)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out)
    plt.close(fig)
    return titles
