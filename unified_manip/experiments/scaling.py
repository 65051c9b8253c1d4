"""``unified-manip plot --against demonstrations``: final success against the number of
demonstration episodes a run learned from, a panel per task.

A study that repeats one grid at several dataset sizes (the cloning study of docs/results/cloning.md: 25, 100
and 400 episodes) is several benches, one per size. This figure puts them on one axis:
each *setting* (action mode, reward, algorithm) is a line through its mean final success
over seeds at each size, with whiskers over the seeds
(:func:`~unified_manip.experiments.stats.seed_interval`: their range below 5 seeds, the 95%
bootstrap CI from 5) and each seed as a dot. Runs without demonstrations sit at 0.
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.experiments.figures import interval_label, pyplot
from unified_manip.experiments.plot import collect, panel_axes, pick_tasks
from unified_manip.experiments.stats import seed_interval

Line = tuple[str, str, str]  # action mode, reward, algo


def demonstration_episodes(row: dict[str, Any]) -> int:
    """How many demonstration episodes a result row's run learned from (0 for none)."""
    demos = row.get("demonstrations")
    return int(demos["episodes"]) if demos else 0


def points(runs: list[dict[str, Any]]) -> dict[Line, dict[int, list[float]]]:
    """Final success by setting and demonstration episodes: ``line -> episodes -> finals``."""
    out: dict[Line, dict[int, list[float]]] = defaultdict(lambda: defaultdict(list))
    for r in runs:
        line = (r["action_mode"], r["reward_type"], r["algo"])
        out[line][demonstration_episodes(r)].append(float(r["final_success_rate"]))
    return out


def labelled_sizes(sizes: list[int], log: bool) -> list[int]:
    """The sizes that get a tick label: each at least 1.3 times the last labelled one on a
    log axis (or 5% of the whole span above it on a linear one), so that close sizes (a
    mode's 39 converted episodes beside another's 43) do not print over each other."""
    out: list[int] = []
    span = (max(sizes) - min(sizes)) if sizes else 0
    for n in sorted(sizes):
        if not out or (n >= out[-1] * 1.3 if log else n - out[-1] >= 0.05 * span):
            out.append(n)
    return out


def plot_against_demonstrations(
    sources: list[Path], out: Path, columns: int = 4, tasks: list[str] | None = None
) -> list[str]:
    """Write the figure to ``out`` (its suffix picks the format); return the panels'
    titles, one per task. ``tasks`` as in :func:`~unified_manip.experiments.plot.plot_overview`."""
    panels, _ = collect(sources)
    panels = pick_tasks(panels, tasks, sources)
    by_task = {task: points([r for runs in settings.values() for r in runs]) for task, settings in panels.items()}
    every = sorted({line for lines in by_task.values() for line in lines})
    varying = [i for i in range(3) if len({line[i] for line in every}) > 1] or [0]
    colour = {line: f"C{i % 10}" for i, line in enumerate(every)}
    plt = pyplot()
    fig, axes = panel_axes(plt, len(by_task), columns)
    titles, counts = [], []
    for ax, (task, lines) in zip(axes.flat, by_task.items()):
        sizes = sorted({n for by_size in lines.values() for n in by_size})
        for k, (line, by_size) in enumerate(sorted(lines.items())):
            xs = sorted(by_size)
            # Lines of one panel are nudged apart so their whiskers and dots do not overlap.
            nudge = 1 + 0.04 * (k - (len(lines) - 1) / 2)
            mean = [np.mean(by_size[n]) for n in xs]
            counts += [len(by_size[n]) for n in xs]
            label = " / ".join(line[i] for i in varying)
            ax.plot([n * nudge for n in xs], mean, marker="o", ms=3, lw=1.2, color=colour[line], label=label)
            for n in xs:
                iv = seed_interval(by_size[n])
                if np.isfinite(iv.low):
                    ax.vlines(n * nudge, iv.low, iv.high, color=colour[line], lw=1, alpha=0.6)
                ax.scatter([n * nudge] * len(by_size[n]), by_size[n], s=6, color=colour[line], alpha=0.5, lw=0)
        title = task.split("/")[-1]
        titles.append(title)
        ax.set_title(title, fontsize=9)
        log = 0 not in sizes
        if log:
            ax.set_xscale("log")
        ticks = labelled_sizes(sizes, log)
        ax.set_xticks(ticks, [str(n) for n in ticks])
        ax.minorticks_off()
        ax.set_ylim(-0.02, 1.02)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(by_task) :]:
        ax.set_visible(False)
    fig.supxlabel("demonstration episodes", fontsize=9)
    fig.supylabel("final success rate", fontsize=9)
    handles = {h.get_label(): h for ax in axes.flat for h in ax.get_lines()}  # one entry per setting
    fig.legend(handles.values(), handles.keys(), fontsize=7, loc="center left", bbox_to_anchor=(1, 0.5))
    band = interval_label(counts)
    fig.suptitle(f"Final success against demonstrations\n(mean over seeds; dots: seeds; whiskers: {band})", fontsize=9)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, bbox_inches="tight")
    plt.close(fig)
    return titles
