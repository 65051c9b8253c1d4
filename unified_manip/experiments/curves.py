"""Training-episode curves of a bench's runs, read from their TensorBoard logs.

The report's success curves are deterministic evaluations. The policy that collects the
training data explores, and the two can tell different stories: a PPO run can succeed in
a tenth of its training episodes while its deterministic policy still fails every
evaluation. This module reads what the trainer logged, by env step, from
``<bench>/runs/<run>/tb``:

- ``rollout/success_rate``: success over the last 100 training episodes (SB3's for
  off-policy algorithms, :class:`~unified_manip.training.callbacks.SuccessRate`'s for PPO);
- ``rollout/ep_rew_mean``: SB3's mean return over the last 100 training episodes.

A resumed run has one event file per segment; a later segment's values replace the
earlier segment's from its first logged step on (the steps it trained again).
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.experiments.results import setting_label

#: The logged scalars plotted, with their axis labels.
TAGS: dict[str, str] = {
    "rollout/success_rate": "training success\n(last 100 episodes)",
    "rollout/ep_rew_mean": "training return\n(last 100 episodes)",
}


def _segments(run_dir: Path) -> list[Path]:
    """The run's event files in the order they were written (the name holds the start time)."""
    files = list((Path(run_dir) / "tb").rglob("events.out.tfevents.*"))
    return sorted(files, key=lambda p: (int(p.name.split(".")[3]), p.name))


def read_scalars(run_dir: Path, tags=tuple(TAGS)) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """``{tag: (steps, values)}`` for each of ``tags`` the run logged, steps increasing.

    The events are read as written (``LegacyEventFileLoader``): SB3 logs scalars as
    ``simple_value``, and tensorboard's conversion of each one into a tensor summary
    (``EventFileLoader``) took most of a report's time."""
    from tensorboard.backend.event_processing.event_file_loader import LegacyEventFileLoader
    from tensorboard.util import tensor_util

    values: dict[str, dict[int, float]] = {t: {} for t in tags}
    for path in _segments(run_dir):
        segment: dict[str, dict[int, float]] = {t: {} for t in tags}
        for event in LegacyEventFileLoader(str(path)).Load():
            for v in event.summary.value if event.HasField("summary") else ():
                if v.tag in segment:
                    x = v.simple_value if v.HasField("simple_value") else tensor_util.make_ndarray(v.tensor)
                    segment[v.tag][int(event.step)] = float(x)
        for tag, points in segment.items():
            if points:
                first = min(points)
                values[tag] = {s: x for s, x in values[tag].items() if s < first} | points
    return {t: (np.array(sorted(d)), np.array([d[s] for s in sorted(d)])) for t, d in values.items() if d}


def plot_training(
    task: str, groups: dict[tuple[str, str, str], list[dict[str, Any]]], runs_dir: Path, out: Path
) -> Path | None:
    """One figure per task: each tag against env steps, the mean over a setting's seeds with
    their range shaded. ``None`` when no run of the task has a log in ``runs_dir``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(TAGS), figsize=(11, 3.8), dpi=110)
    drawn = False
    for key, runs in sorted(groups.items()):
        curves = [read_scalars(runs_dir / r["run"]) for r in runs if (runs_dir / r["run"] / "tb").is_dir()]
        color = None
        for ax, tag in zip(axes, TAGS):
            series = [c[tag] for c in curves if tag in c]
            if not series:
                continue
            grid = np.linspace(0, max(int(s[-1]) for s, _ in series), 200)
            ys = np.array([np.interp(grid, s, v, left=np.nan, right=np.nan) for s, v in series])
            with warnings.catch_warnings():  # steps before any run's first log are all NaN: left blank
                warnings.simplefilter("ignore", RuntimeWarning)
                mean, low, high = np.nanmean(ys, axis=0), np.nanmin(ys, axis=0), np.nanmax(ys, axis=0)
            (line,) = ax.plot(grid, mean, color=color, label=f"{setting_label(key)} (n={len(series)})")
            color = line.get_color()
            if len(ys) > 1:
                ax.fill_between(grid, low, high, color=color, alpha=0.2)
            drawn = True
    if not drawn:
        plt.close(fig)
        return None
    for ax, label in zip(axes, TAGS.values()):
        ax.set_xlabel("environment steps")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].set_ylim(-0.02, 1.02)
    axes[-1].legend(fontsize=7)
    fig.suptitle(task.split("/")[-1])
    fig.tight_layout()
    path = Path(out) / f"{task.split('/')[-1]}_training.png"
    fig.savefig(path)
    plt.close(fig)
    return path
