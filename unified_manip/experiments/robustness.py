"""``unified-manip robustness BENCH``: every finished run's final policy evaluated again
under observation noise and delay, and on test distributions of domain randomisation
(``default``, ``in-range``, ``extreme``: Packer et al. 2018), without retraining.

Each (run, condition) is evaluated with :func:`~unified_manip.training.evaluation.evaluate`
on the run's ``final_model.zip`` (the policy the run ended with, not its best checkpoint),
its own env settings otherwise, and written to ``BENCH/robustness.csv`` atomically as soon as
it is done, so an interrupted pass resumes where it stopped. The report reads the file
(:func:`robustness_section`). Noise is a standard deviation in each observation group's own
units (metres for positions, radians for joint angles); a condition's noise and delay replace
the run's own, and the rest of its design (groups, distractors) stays. A condition's test
distribution replaces the run's training randomisation
(:func:`~unified_manip.training.evaluation.evaluated_randomization`: the ranges come from
``--randomization`` or the run's own preset); without one the run's own stays. Each row
records the run's training randomisation, the distribution and the randomisation it was
tested under; a ``robustness.csv`` written before these columns reads as ``none``.
"""

from __future__ import annotations

import csv
import os
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np

from unified_manip.envs.randomization import TEST_DISTRIBUTIONS, randomization_label
from unified_manip.experiments.generalisation import distribution_lines
from unified_manip.experiments.results import collect_row

FILE = "robustness.csv"
COLUMNS = (
    "run",
    "task",
    "action_mode",
    "observation",
    "algo",
    "seed",
    "randomization",
    "noise",
    "delay",
    "distribution",
    "tested",
    "episodes",
    "successes",
    "success_rate",
    "ci_low",
    "ci_high",
)
#: The default conditions: observation noise of 0, 0.5 and 1 cm, and a one-step delay.
NOISES = (0.0, 0.005, 0.01)
DELAYS = (1,)


class RobustnessError(ValueError):
    """A bench directory that cannot be evaluated (one-line error)."""


@dataclass(frozen=True)
class Condition:
    noise: float
    delay: int
    distribution: str = ""  # a test distribution (TEST_DISTRIBUTIONS); "": the run's own randomisation

    @property
    def label(self) -> str:
        if self.delay:
            perturbation = f"delay {self.delay}" + (f", noise {self.noise:g}" if self.noise else "")
        else:
            perturbation = f"noise {self.noise:g}"
        if not self.distribution:
            return perturbation
        return self.distribution + (f", {perturbation}" if self.delay or self.noise else "")

    @property
    def order(self) -> tuple:
        """Where the condition's column goes: by distribution, then no delay first, by noise."""
        return (_DISTRIBUTION_ORDER.index(self.distribution), self.delay, self.noise)


_DISTRIBUTION_ORDER = ("", *TEST_DISTRIBUTIONS)


def conditions(
    noises: tuple[float, ...] = NOISES, delays: tuple[int, ...] = DELAYS, distributions: tuple[str, ...] = ("",)
) -> list[Condition]:
    """On each test distribution (``""``: the run's own randomisation), each noise level
    without delay, then each delay without noise."""
    bad = [n for n in noises if not n >= 0.0] + [d for d in delays if d < 1]
    if bad:
        raise RobustnessError(f"noise levels must be >= 0 and delays >= 1 step; got {bad[0]!r}")
    unknown = [d for d in distributions if d not in _DISTRIBUTION_ORDER]
    if unknown:
        raise RobustnessError(
            f"unknown test distribution {unknown[0]!r}; expected one of {', '.join(TEST_DISTRIBUTIONS)}"
        )
    return [
        c
        for z in distributions
        for c in [Condition(float(n), 0, z) for n in noises] + [Condition(0.0, int(d), z) for d in delays]
    ]


def read_robustness(path: Path) -> list[dict[str, Any]]:
    """The rows of a ``robustness.csv``, typed (none if there is no file)."""
    if not Path(path).is_file():
        return []
    with Path(path).open(newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        r["randomization"] = r.get("randomization") or "none"  # files from before randomisation
        r["distribution"] = r.get("distribution") or ""
        r["tested"] = r.get("tested") or r["randomization"]
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
        for row in sorted(rows, key=lambda r: (r["run"], _condition(r).order, r["tested"])):
            writer.writerow({k: row[k] for k in COLUMNS})
    os.replace(tmp, path)


def evaluate_bench(
    bench: Path,
    wanted: list[Condition],
    episodes: int = 50,
    seed: int = 123,
    progress: Callable[[str], None] | None = None,
    randomization: str | None = None,
) -> Path:
    """Evaluate every finished run of ``bench`` under each condition not yet in its
    ``robustness.csv``; return the file's path. ``randomization``: the preset whose ranges
    the test distributions take (default: each run's own training preset)."""
    from unified_manip.training.evaluation import evaluate, evaluated_randomization
    from unified_manip.training.request import TrainError
    from unified_manip.training.rundir import read_config

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
    done = {(r["run"], r["noise"], r["delay"], r["distribution"], r["tested"]) for r in rows}
    todo = []
    for d, row in finished:  # every run's test distributions resolve before any evaluation
        trained = read_config(d)["env_kwargs"].get("randomization")
        for c in wanted:
            try:
                tested = evaluated_randomization(trained, randomization, c.distribution or None)
            except TrainError as err:
                raise RobustnessError(f"{d.name}: {err}") from None
            if (d.name, c.noise, c.delay, c.distribution, randomization_label(tested)) not in done:
                todo.append((d, row, c, tested))
    for i, (run_dir, row, c, tested) in enumerate(todo, 1):
        if progress:
            progress(f"[{i}/{len(todo)}] {run_dir.name}: {c.label}")
        try:
            result = evaluate(
                run_dir / "final_model.zip",
                episodes,
                seed=seed,
                observation_noise=c.noise,
                observation_delay=c.delay,
                randomization=tested,
            )
        except TrainError as err:  # a preset none of whose terms the run's task takes
            raise RobustnessError(f"{run_dir.name}: {err}") from None
        rows.append(
            {
                **{k: row[k] for k in ("run", "task", "action_mode", "observation", "algo", "seed", "randomization")},
                "noise": c.noise,
                "delay": c.delay,
                "distribution": c.distribution,
                "tested": randomization_label(tested),
                **{k: getattr(result, k) for k in ("episodes", "successes", "success_rate", "ci_low", "ci_high")},
            }
        )
        _write(path, rows)
    if not path.is_file():
        _write(path, rows)
    return path


def _condition(row: dict[str, Any]) -> Condition:
    return Condition(row["noise"], row["delay"], row["distribution"])


def _cells(rows: list[dict[str, Any]]) -> tuple[dict, list[Condition], list[str]]:
    """``task -> (design, mode, training randomisation) -> condition -> [success per seed]``,
    the conditions in order (by distribution, no delay first, by noise) and their column heads."""
    cells: dict[str, dict[tuple[str, str, str], dict[Condition, list[float]]]] = defaultdict(
        lambda: defaultdict(lambda: defaultdict(list))
    )
    for r in rows:
        cells[r["task"]][(r["observation"], r["action_mode"], r["randomization"])][_condition(r)].append(
            r["success_rate"]
        )
    keys = sorted({_condition(r) for r in rows}, key=lambda c: c.order)
    return cells, keys, [c.label for c in keys]


def robustness_tables(path: Path) -> dict[str, list[str]]:
    """Per task of ``robustness.csv``: Markdown lines of a table with each design's mean
    success over seeds (and the seeds' range) under each condition. Empty without the file."""
    return _tables(*_cells(read_robustness(path)))


def _tables(cells: dict, keys: list[Condition], heads: list[str]) -> dict[str, list[str]]:
    """A randomisation column only where some run was trained under one."""
    randomized = any(k[2] != "none" for designs in cells.values() for k in designs)
    tables = {}
    for task, designs in sorted(cells.items()):
        extra = ("randomization | ", "---|") if randomized else ("", "")
        lines = [
            f"| observation design | mode | {extra[0]}" + " | ".join(heads) + " |",
            f"|---|---|{extra[1]}" + "---|" * len(heads),
        ]
        for (design, mode, rand), by_condition in sorted(designs.items()):
            cells_ = " | ".join(_cell(by_condition.get(k, [])) for k in keys)
            lines.append(f"| {design} | {mode} | {f'{rand} | ' if randomized else ''}{cells_} |")
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
        *distribution_lines(rows),
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
    for (design, mode, rand), by_condition in sorted(designs.items()):
        values = [by_condition.get(k, []) for k in keys]
        mean = np.array([np.mean(v) if v else np.nan for v in values])
        trained = "" if rand == "none" else f", trained under {rand}"
        (line,) = ax.plot(x, mean, marker="o", ms=4, label=f"{design} ({mode}{trained}, n={max(map(len, values))})")
        low = np.array([min(v) if v else np.nan for v in values])
        high = np.array([max(v) if v else np.nan for v in values])
        ax.fill_between(x, low, high, color=line.get_color(), alpha=0.15, linewidth=0)
    ax.set_xticks(x, heads, fontsize=8)
    ax.set_ylabel("success rate of the final policy")
    ax.set_title(
        f"{task}: final policies under {'test distributions, ' if any(k.distribution for k in keys) else ''}"
        "observation noise and delay\n(mean over seeds, range shaded)",
        fontsize=9,
    )
    return save_success_figure(fig, ax, out / f"{task.split('/')[-1]}_robustness.png")


def _cell(values: list[float]) -> str:
    if not values:
        return "—"
    if len(values) == 1:
        return f"{values[0]:.2f}"
    return f"{np.mean(values):.2f} [{min(values):.2f}, {max(values):.2f}]"
