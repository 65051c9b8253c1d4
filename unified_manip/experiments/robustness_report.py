"""The report of ``robustness.csv``: per task, each design's mean success over seeds (and the
seeds' range) under each condition, as a table and a figure, with the test distributions
and the generalisation gap (:mod:`~unified_manip.experiments.generalisation`) and the
factors varied one at a time (:mod:`~unified_manip.experiments.factors`)."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.experiments.factors import factor_lines
from unified_manip.experiments.generalisation import distribution_lines
from unified_manip.experiments.robustness import Condition, condition_of, read_robustness


def _cells(rows: list[dict[str, Any]]) -> tuple[dict, list[Condition], list[str]]:
    """``task -> (design, mode, training randomisation) -> condition -> [success per seed]``,
    the conditions in order (by distribution, no delay first, by noise) and their column heads."""
    cells: dict[str, dict[tuple[str, str, str], dict[Condition, list[float]]]] = defaultdict(
        lambda: defaultdict(lambda: defaultdict(list))
    )
    for r in rows:
        cells[r["task"]][(r["observation"], r["action_mode"], r["randomization"])][condition_of(r)].append(
            r["success_rate"]
        )
    keys = sorted({condition_of(r) for r in rows}, key=lambda c: c.order)
    return cells, keys, [c.label for c in keys]


def robustness_tables(path: Path) -> dict[str, list[str]]:
    """Per task of ``robustness.csv``: Markdown lines of a table with each design's mean
    success over seeds (and the seeds' range) under each condition. Empty without the file."""
    return _tables(*_cells([r for r in read_robustness(path) if not r["factor"]]))


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
    every = read_robustness(path)
    rows = [r for r in every if not r["factor"]]  # the factors alone have their own section
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
    return lines + factor_lines(every, Path(out))


def figure_panels(designs: dict) -> list[tuple[str, list[tuple[tuple[str, str, str], str, str]]]]:
    """The robustness figure's panels, ``(title, [(design key, label, colour)])``: with runs
    trained under more than one randomisation, a panel per action mode (and design), a line
    per training randomisation, so each panel shows what randomised training changes;
    otherwise one untitled panel, a line per design and mode."""
    trainings = sorted({r for _, _, r in designs}, key=lambda r: (r != "none", r))
    several = len({d for d, _, _ in designs}) > 1

    def name(design: str, mode: str) -> str:
        return f"{mode}, {design}" if several else mode

    def trained(rand: str) -> str:
        return "trained nominal" if rand == "none" else f"trained under {rand}"

    if len(trainings) > 1:
        pairs = sorted({(d, m) for d, m, _ in designs})
        return [(name(*p), [((*p, r), trained(r), f"C{trainings.index(r)}") for r in trainings]) for p in pairs]
    return [("", [(k, name(*k[:2]), f"C{i}") for i, k in enumerate(sorted(designs))])]


def _plot(task: str, designs: dict, keys: list, heads: list[str], out: Path) -> Path:
    """Success under each condition (:func:`figure_panels`): mean over seeds, the seeds'
    range shaded."""
    from unified_manip.experiments.figures import pyplot

    plt = pyplot()
    panels = figure_panels(designs)
    columns = min(4, len(panels))
    rows = -(-len(panels) // columns)
    fig, axes = plt.subplots(rows, columns, figsize=(max(6.5, 2.6 * columns + 1.2), 2.6 * rows + 1.2), dpi=110,
                             sharey=True, squeeze=False)  # fmt: skip
    x = np.arange(len(keys))
    for ax, (title, lines) in zip(axes.flat, panels):
        for key, label, colour in lines:
            values = [designs.get(key, {}).get(k, []) for k in keys]
            if not any(values):
                continue
            mean = np.array([np.mean(v) if v else np.nan for v in values])
            ax.plot(x, mean, marker="o", ms=4, color=colour, label=f"{label} (n={max(map(len, values))})")
            low = np.array([min(v) if v else np.nan for v in values])
            high = np.array([max(v) if v else np.nan for v in values])
            ax.fill_between(x, low, high, color=colour, alpha=0.15, linewidth=0)
        ax.set_xticks(x, heads, fontsize=7, rotation=30 if len(keys) > 4 else 0)
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6, loc="lower left" if len(panels) > 1 else "best")
    for ax in axes.flat[len(panels) :]:
        ax.set_visible(False)
    axes[0, 0].set_ylim(-0.02, 1.02)  # the panels share it
    for ax in axes[:, 0]:
        ax.set_ylabel("success of the final policy", fontsize=8)
    what = [w for w, on in (("test distributions", any(k.distribution for k in keys)),
                            ("observation noise", any(k.noise for k in keys)),
                            ("observation delay", any(k.delay for k in keys))) if on]  # fmt: skip
    fig.suptitle(f"{task.split('/')[-1]}: final policies under {', '.join(what) or 'no shift'}\n"
                 "(mean over seeds, range shaded)", fontsize=9)  # fmt: skip
    fig.tight_layout()
    path = out / f"{task.split('/')[-1]}_robustness.png"
    fig.savefig(path)
    plt.close(fig)
    return path


def _cell(values: list[float]) -> str:
    if not values:
        return "—"
    if len(values) == 1:
        return f"{values[0]:.2f}"
    return f"{np.mean(values):.2f} [{min(values):.2f}, {max(values):.2f}]"
