"""One factor at a time: which randomised quantity hurts a final policy most.

``unified-manip robustness BENCH --test-distribution in-range extreme --factors`` tests each
run's final policy on every term of a shifted distribution alone (the object's mass, the
robot's damping, ...: the terms of the preset that apply to the run's task), beside the
distribution as a whole. Each such row of ``robustness.csv`` names its term in ``factor``.
The drop of a factor is success on the nominal task (``default``) minus success with that
factor alone shifted, per seed; :func:`factor_lines` tabulates and plots it.
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from unified_manip.envs.randomization import RandomizationTerm
from unified_manip.experiments.generalisation import SHIFTED, gap_cell

#: How the tables name a distribution's terms all together (the row without a factor).
TOGETHER = "all together"

Setting = tuple[str, str, str, str]  # task, observation design, action mode, training randomisation


def applied_terms(config: Mapping[str, Any], randomization: Any) -> tuple[RandomizationTerm, ...]:
    """The terms of ``randomization`` that apply to a run's env (``config``: its
    ``config.yaml``, read for ``env`` and ``env_kwargs``), in draw order: a preset's terms
    that its task cannot take are left out, as the env leaves them out."""
    import gymnasium as gym

    import unified_manip  # noqa: F401  (registers the IDs and the plugged-in families)

    env = gym.make(config["env"], **{**config.get("env_kwargs", {}), "randomization": randomization})
    try:
        randomizer = env.unwrapped.randomizer
        return () if randomizer is None else randomizer.terms
    finally:
        env.close()


def factor_drops(rows: list[dict[str, Any]]) -> dict[Setting, dict[str, dict[str, list[float]]]]:
    """``setting -> factor (or TOGETHER) -> shifted distribution -> [drop per seed]``, from
    the rows of ``robustness.csv`` (typed) without noise or delay: ``default`` success minus
    the shifted success, for the seeds evaluated on both. Settings without a factor row are
    left out."""
    plain = [r for r in rows if not r["noise"] and not r["delay"] and r["distribution"]]
    nominal = {_key(r): r["success_rate"] for r in plain if r["distribution"] == "default"}
    with_factors = {_key(r)[:-1] for r in plain if r["factor"]}
    drops: dict = defaultdict(lambda: defaultdict(lambda: defaultdict(list)))
    for r in sorted(plain, key=lambda r: r["seed"]):
        key = _key(r)
        if r["distribution"] in SHIFTED and key[:-1] in with_factors and key in nominal:
            drops[key[:-1]][r["factor"] or TOGETHER][r["distribution"]].append(nominal[key] - r["success_rate"])
    return {s: {f: dict(d) for f, d in by_factor.items()} for s, by_factor in drops.items()}


def factor_tables(rows: list[dict[str, Any]]) -> dict[str, list[str]]:
    """Per task, Markdown lines of a table of each factor's drop (mean over seeds, the
    seeds' range below 5 seeds): per setting, the distribution as a whole first and then
    the factors, worst on the extreme distribution first. Empty without factor rows."""
    return {task: _table(settings) for task, settings in _by_task(factor_drops(rows)).items()}


def factor_lines(rows: list[dict[str, Any]], out: Path) -> list[str]:
    """Markdown lines: the section of :func:`factor_tables`, each task's table with a
    figure of it written to ``out``. None without factor rows."""
    by_task = _by_task(factor_drops(rows))
    if not by_task:
        return []
    lines = [
        "## One factor at a time",
        "",
        "Each final policy tested with one randomised quantity alone shifted, the rest nominal "
        "(`unified-manip robustness --factors`). The drop is success on `default` minus success with the "
        "factor shifted, per seed; mean over seeds, the seeds' range in brackets below 5 seeds. Positive: "
        f"the factor costs success. `{TOGETHER}` is the distribution's every factor at once.",
        "",
    ]
    for task, settings in by_task.items():
        figure = _plot(task, settings, Path(out))
        lines += [f"**{task.split('/')[-1]}**:", "", *_table(settings), "", f"![{task} factors]({figure.name})", ""]
    return lines


def _by_task(drops: dict[Setting, dict]) -> dict[str, dict[Setting, dict]]:
    """``task -> setting -> factor drops``, tasks and settings sorted."""
    out: dict[str, dict[Setting, dict]] = {}
    for setting, by_factor in sorted(drops.items()):
        out.setdefault(setting[0], {})[setting] = by_factor
    return out


def _table(settings: dict[Setting, dict]) -> list[str]:
    lines = [
        "| observation design | mode | training randomization | seeds | factor | drop in-range | drop extreme |",
        "|---|---|---|---:|---|---:|---:|",
    ]
    for (_task, design, mode, rand), by_factor in settings.items():
        for factor in ordered_factors(by_factor):
            shifts = by_factor[factor]
            seeds = max(len(v) for v in shifts.values())
            cells = " | ".join(gap_cell(shifts.get(s, [])) for s in SHIFTED)
            lines.append(f"| {design} | {mode} | {rand} | {seeds} | {factor} | {cells} |")
    return lines


def ordered_factors(by_factor: Mapping[str, Mapping[str, list[float]]]) -> list[str]:
    """``TOGETHER`` first, then the factors by their mean drop on ``extreme`` (then
    ``in-range``), largest first, then by name."""

    def mean(factor: str, shift: str) -> float:
        values = by_factor[factor].get(shift, [])
        return float(np.mean(values)) if values else -np.inf

    factors = sorted(
        (f for f in by_factor if f != TOGETHER), key=lambda f: (-mean(f, "extreme"), -mean(f, "in-range"), f)
    )
    return ([TOGETHER] if TOGETHER in by_factor else []) + factors


def _key(r: dict[str, Any]) -> tuple:
    return (r["task"], r["observation"], r["action_mode"], r["randomization"], r["seed"])


def _plot(task: str, settings: dict[Setting, dict], out: Path) -> Path:
    """One panel per shifted distribution: each factor's drop, one bar per setting (mean
    over seeds, the seeds' range as an error bar). A colour per action mode (and design),
    solid after randomised training, pale after nominal; the legend below the panels."""
    from unified_manip.experiments.figures import pyplot

    plt = pyplot()
    factors = sorted({f for by_factor in settings.values() for f in by_factor if f != TOGETHER})
    names = [TOGETHER, *factors]
    height_in = 1.6 + max(0.42, 0.11 * len(settings)) * len(names)
    fig, axes = plt.subplots(1, len(SHIFTED), figsize=(9, height_in), dpi=110, sharey=True)
    colours = {key: f"C{i}" for i, key in enumerate(sorted({(s[1], s[2]) for s in settings}))}
    height = 0.8 / len(settings)
    for ax, shift in zip(axes, SHIFTED):
        for k, ((_, design, mode, rand), by_factor) in enumerate(settings.items()):
            values = [by_factor.get(f, {}).get(shift, []) for f in names]
            mean = np.array([np.mean(v) if v else np.nan for v in values])
            low = np.array([mean[i] - min(v) if v else 0.0 for i, v in enumerate(values)])
            high = np.array([max(v) - mean[i] if v else 0.0 for i, v in enumerate(values)])
            y = np.arange(len(names)) + (k - (len(settings) - 1) / 2) * height
            label = f"{mode}, {'nominal' if rand == 'none' else rand}" + ("" if design == "default" else f", {design}")
            ax.barh(y, mean, height=height, xerr=[low, high], label=label, color=colours[(design, mode)],
                    alpha=0.4 if rand == "none" else 1.0, capsize=2, error_kw={"lw": 0.7})  # fmt: skip
        ax.axvline(0.0, color="black", lw=0.6)
        ax.set_xlim(min(-0.1, ax.get_xlim()[0]), max(0.6, ax.get_xlim()[1]))  # a drop is at most 1
        ax.set_title(f"{shift}: drop in success vs default", fontsize=9)
        ax.set_xlabel("default success minus shifted success")
        ax.grid(axis="x", alpha=0.3)
    axes[0].set_yticks(np.arange(len(names)), names, fontsize=8)
    axes[0].invert_yaxis()
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=7, loc="lower center", ncol=min(4, len(labels)), frameon=False)
    fig.suptitle(f"{task}: one factor at a time, by action mode and training randomisation\n"
                 "(mean over seeds, range as bars)", fontsize=9)  # fmt: skip
    legend_in = 0.2 + 0.16 * -(-len(labels) // 4)  # inches: the legend's rows under the panels
    fig.tight_layout(rect=(0, legend_in / height_in, 1, 1))
    path = out / f"{task.split('/')[-1]}_factors.png"
    fig.savefig(path)
    plt.close(fig)
    return path
