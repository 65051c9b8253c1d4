"""``unified-manip robustness BENCH``: every finished run's final policy evaluated again
under observation noise and delay, without retraining (issue 41's study, item 5).

Each (run, condition) is evaluated with :func:`~unified_manip.training.evaluation.evaluate`
on the run's ``final_model.zip`` (the policy the run ended with, not its best checkpoint),
its own env settings otherwise, and written to ``BENCH/robustness.csv`` atomically as soon as
it is done, so an interrupted pass resumes where it stopped. The report reads the file
(:func:`robustness_section`). Noise is a standard deviation in each observation group's own
units (metres for positions, radians for joint angles); a condition's noise and delay replace
the run's own, and the rest of its design (groups, distractors) stays.
"""

from __future__ import annotations

import csv
import os
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np

from unified_manip.experiments.results import collect_row

FILE = "robustness.csv"
COLUMNS = (
    "run",
    "task",
    "action_mode",
    "observation",
    "algo",
    "seed",
    "noise",
    "delay",
    "episodes",
    "successes",
    "success_rate",
    "ci_low",
    "ci_high",
)
#: Issue 41's conditions: observation noise of 0, 0.5 and 1 cm, and a one-step delay.
NOISES = (0.0, 0.005, 0.01)
DELAYS = (1,)


class RobustnessError(ValueError):
    """A bench directory that cannot be evaluated (one-line error)."""


@dataclass(frozen=True)
class Condition:
    noise: float
    delay: int

    @property
    def label(self) -> str:
        if self.delay:
            return f"delay {self.delay}" + (f", noise {self.noise:g}" if self.noise else "")
        return f"noise {self.noise:g}"


def conditions(noises: tuple[float, ...] = NOISES, delays: tuple[int, ...] = DELAYS) -> list[Condition]:
    """Each noise level without delay, then each delay without noise."""
    bad = [n for n in noises if not n >= 0.0] + [d for d in delays if d < 1]
    if bad:
        raise RobustnessError(f"noise levels must be >= 0 and delays >= 1 step; got {bad[0]!r}")
    return [Condition(float(n), 0) for n in noises] + [Condition(0.0, int(d)) for d in delays]


def read_robustness(path: Path) -> list[dict[str, Any]]:
    """The rows of a ``robustness.csv``, typed (none if there is no file)."""
    if not Path(path).is_file():
        return []
    with Path(path).open(newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("seed", "delay", "episodes", "successes"):
            r[k] = int(r[k])
        for k in ("noise", "success_rate", "ci_low", "ci_high"):
            r[k] = float(r[k])
    return rows


def _write(path: Path, rows: list[dict[str, Any]]) -> None:
    tmp = path.with_name(path.name + ".tmp")
    with tmp.open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS)
        writer.writeheader()
        for row in sorted(rows, key=lambda r: (r["run"], r["delay"], r["noise"])):
            writer.writerow({k: row[k] for k in COLUMNS})
    os.replace(tmp, path)


def evaluate_bench(
    bench: Path,
    wanted: list[Condition],
    episodes: int = 50,
    seed: int = 123,
    progress: Callable[[str], None] | None = None,
) -> Path:
    """Evaluate every finished run of ``bench`` under each condition not yet in its
    ``robustness.csv``; return the file's path."""
    from unified_manip.training.evaluation import evaluate

    runs_dir = Path(bench) / "runs"
    if not runs_dir.is_dir():
        raise RobustnessError(f"{bench} has no runs/ directory; expected a bench's output directory")
    finished = [(d, row) for d in sorted(runs_dir.iterdir()) if (row := collect_row(d)) is not None]
    if not finished:
        raise RobustnessError(f"{runs_dir} holds no finished run")
    missing = [d.name for d, _ in finished if not (d / "final_model.zip").is_file()]
    if missing:
        raise RobustnessError(
            f"{runs_dir / missing[0]} has no final_model.zip (committed results carry no models); evaluate the "
            "bench directory the runs trained in"
        )
    path = Path(bench) / FILE
    rows = read_robustness(path)
    done = {(r["run"], r["noise"], r["delay"]) for r in rows}
    todo = [(d, row, c) for d, row in finished for c in wanted if (d.name, c.noise, c.delay) not in done]
    for i, (run_dir, row, c) in enumerate(todo, 1):
        if progress:
            progress(f"[{i}/{len(todo)}] {run_dir.name}: {c.label}")
        result = evaluate(
            run_dir / "final_model.zip",
            episodes,
            seed=seed,
            observation_noise=c.noise,
            observation_delay=c.delay,
        )
        rows.append(
            {
                **{k: row[k] for k in ("run", "task", "action_mode", "observation", "algo", "seed")},
                "noise": c.noise,
                "delay": c.delay,
                **{k: getattr(result, k) for k in ("episodes", "successes", "success_rate", "ci_low", "ci_high")},
            }
        )
        _write(path, rows)
    if not path.is_file():
        _write(path, rows)
    return path


def _cells(rows: list[dict[str, Any]]) -> tuple[dict, list[tuple[float, int]], list[str]]:
    """``task -> (design, mode) -> (noise, delay) -> [success per seed]``, the conditions in
    order (no delay first, by noise) and their column heads."""
    cells: dict[str, dict[tuple[str, str], dict[tuple[float, int], list[float]]]] = defaultdict(
        lambda: defaultdict(lambda: defaultdict(list))
    )
    for r in rows:
        cells[r["task"]][(r["observation"], r["action_mode"])][(r["noise"], r["delay"])].append(r["success_rate"])
    keys = sorted({(r["noise"], r["delay"]) for r in rows}, key=lambda k: (k[1], k[0]))
    return cells, keys, [Condition(n, d).label for n, d in keys]


def robustness_tables(path: Path) -> dict[str, list[str]]:
    """Per task of ``robustness.csv``: Markdown lines of a table with each design's mean
    success over seeds (and the seeds' range) under each condition. Empty without the file."""
    return _tables(*_cells(read_robustness(path)))


def _tables(cells: dict, keys: list[tuple[float, int]], heads: list[str]) -> dict[str, list[str]]:
    tables = {}
    for task, designs in sorted(cells.items()):
        lines = ["| observation design | mode | " + " | ".join(heads) + " |", "|---|---|" + "---|" * len(heads)]
        for (design, mode), by_condition in sorted(designs.items()):
            lines.append(f"| {design} | {mode} | " + " | ".join(_cell(by_condition.get(k, [])) for k in keys) + " |")
        tables[task] = lines
    return tables


def robustness_section(path: Path, out: Path) -> list[str]:
    """Markdown lines: per task, each design's mean success over seeds (and the seeds'
    range) under each condition (:func:`robustness_tables`), and a figure of it in ``out``.
    None when there is no ``robustness.csv``."""
    rows = read_robustness(path)
    if not rows:
        return []
    cells, keys, heads = _cells(rows)
    episodes = sorted({r["episodes"] for r in rows})
    lines = [
        "## Robustness of the final policies",
        "",
        f"Each run's final policy evaluated again ({', '.join(map(str, episodes))} episodes each) with Gaussian "
        "noise of this standard deviation added to its observation vector (in each group's own units: metres, "
        "radians) or observing one step late; goals stay exact. Mean over seeds, the seeds' range in "
        f"brackets. Made by `unified-manip robustness` into `{Path(path).name}`.",
        "",
    ]
    for task, table in _tables(cells, keys, heads).items():
        figure = _plot(task, cells[task], keys, heads, Path(out))
        lines += [f"**{task.split('/')[-1]}**:", "", *table, "", f"![{task} robustness]({figure.name})", ""]
    return lines


def _plot(task: str, designs: dict, keys: list, heads: list[str], out: Path) -> Path:
    """Success under each condition, one line per design: mean over seeds, range shaded."""
    from unified_manip.experiments.figures import pyplot, save_success_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.5, 3.8), dpi=110)
    x = np.arange(len(keys))
    for (design, mode), by_condition in sorted(designs.items()):
        values = [by_condition.get(k, []) for k in keys]
        mean = np.array([np.mean(v) if v else np.nan for v in values])
        (line,) = ax.plot(x, mean, marker="o", ms=4, label=f"{design} ({mode}, n={max(map(len, values))})")
        low = np.array([min(v) if v else np.nan for v in values])
        high = np.array([max(v) if v else np.nan for v in values])
        ax.fill_between(x, low, high, color=line.get_color(), alpha=0.15, linewidth=0)
    ax.set_xticks(x, heads, fontsize=8)
    ax.set_ylabel("success rate of the final policy")
    ax.set_title(
        f"{task}: final policies under observation noise and delay\n(mean over seeds, range shaded)", fontsize=9
    )
    return save_success_figure(fig, ax, out / f"{task.split('/')[-1]}_robustness.png")


def _cell(values: list[float]) -> str:
    if not values:
        return "—"
    if len(values) == 1:
        return f"{values[0]:.2f}"
    return f"{np.mean(values):.2f} [{min(values):.2f}, {max(values):.2f}]"
