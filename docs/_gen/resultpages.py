"""Result tables, figures and commands, generated from the committed results.

Each committed experiment is a folder ``results/<name>/`` holding the bench's
``results.csv``, its ``grid.yaml`` (with the targets), ``command.txt`` (the commands
that trained it) and ``report/`` (the report and its PNG figures). The tables here are
computed from ``results.csv`` by the same functions ``unified-manip report`` uses, so a
page and the committed report agree to the digit.
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import numpy as np

from unified_manip.experiments.factors import factor_tables
from unified_manip.experiments.results import read_results
from unified_manip.experiments.robustness import FILE as ROBUSTNESS_FILE
from unified_manip.experiments.robustness import read_robustness
from unified_manip.experiments.robustness_report import robustness_tables
from unified_manip.experiments.stats import MIN_SEEDS_FOR_CI, seed_interval
from unified_manip.experiments.targets import benchmark_table, grid_targets

#: Where figures of ``results/<name>/report/`` are served, inside the site.
ASSETS = "assets/results"


def _demos(row) -> str:
    """The demonstrations a row's runs started with, and the levers on them (every setting
    under its own name, as :func:`~unified_manip.experiments.results.read_results` gives it)."""
    d = row.get("demonstrations")
    if not d:
        return "–"
    extra = []
    if d["bc_steps"]:
        extra.append(f"cloned {d['bc_steps']:,} steps")
    if d["offline_steps"]:
        extra.append(f"{d['offline_steps']:,} offline steps")
    if d["bc_weight"]:
        extra.append(
            f"cloning loss {d['bc_weight']:g}"
            + ("" if d["bc_q_filter"] else ", unfiltered")
            + (", sampled" if d["bc_sampled"] else "")
        )
    return f"{d['episodes']}" + (f" ({'; '.join(extra)})" if extra else "")


def final_table(paths: list[Path]) -> str:
    """Markdown: one row per setting (task, mode, observation design, reward, algorithm,
    demonstrations) of the given ``results.csv`` files, with the mean final success over
    seeds, its interval (:func:`seed_interval`, as in the report: the seeds' range below 5
    seeds, the 95% bootstrap CI from 5) and each seed's value. The design and the
    training randomisation each get a column only where some run has one other than the
    default, as in the report."""
    groups = defaultdict(list)
    for path in paths:
        for r in read_results(path):
            rand = r.get("randomization") or "none"
            key = (
                r["task"],
                r["action_mode"],
                r["observation"],
                rand,
                r["reward_type"],
                r["algo"],
                _demos(r),
                r["steps"],
            )
            groups[key].append(r)
    designs = any(key[2] != "default" for key in groups)  # a column only where some run has one
    rands = any(key[3] != "none" for key in groups)
    rows = [
        f"| task | mode |{' observation |' if designs else ''}{' randomization |' if rands else ''} reward | algo "
        "| demonstrations | budget | seeds | final success [interval] | per seed | wall time per run | steps/s |",
        "|---|---|"
        + ("---|" if designs else "")
        + ("---|" if rands else "")
        + "---|---|---|---:|---:|---|---|---:|---:|",
    ]
    for (task, mode, design, rand, reward, algo, demos, steps), runs in sorted(groups.items()):
        runs.sort(key=lambda r: r["seed"])
        finals = [r["final_success_rate"] for r in runs]
        interval = seed_interval(finals).text()
        interval = f" {interval}" if interval else ""
        seeds = ", ".join(f"{f:.2f} (s{r['seed']})" for f, r in zip(finals, runs))
        wall = float(np.median([r["wall_time_s"] for r in runs])) / 3600
        rate = float(np.median([r["steps_per_s"] for r in runs]))
        rows.append(
            f"| {task.split('/')[-1]} | `{mode}` |{f' {design} |' if designs else ''}{f' {rand} |' if rands else ''} "
            f"{reward} | {algo} | {demos} "
            f"| {steps:,} | {len(runs)} "
            f"| {np.mean(finals):.2f}{interval} | {seeds} | {wall:.2f} h | {rate:.0f} |"
        )
    return "\n".join(
        rows
        + [
            "",
            "Final success: the last evaluation of each run; the interval is the range (min–max) of the "
            f"seeds with fewer than {MIN_SEEDS_FOR_CI} seeds, the 95% percentile bootstrap of the mean from "
            f"{MIN_SEEDS_FOR_CI} on. Wall time and steps/s: medians over seeds.",
        ]
    )


def targets_table(path: Path) -> str:
    """The report's benchmark table (targets, steps and wall time to them) for one
    committed experiment, by the report's own function."""
    targets = grid_targets(path / "grid.yaml")
    return "\n".join(benchmark_table(read_results(path / "results.csv"), targets)).strip()


def figures(path: Path, name: str, depth: int) -> str:
    """Markdown embedding the report's figures: success against steps for each task, final
    success per setting, the cross-task aggregates where the report has them, and the
    training episodes' success and return in a collapsed block."""
    report = path / "report"
    up = "../" * depth
    success = sorted(report.glob("*_success.png"))
    training = sorted(report.glob("*_training.png"))
    final = sorted(report.glob("*_final.png"))
    panels = ("iqm", "profile", "improvement")  # the report's order
    aggregates = sorted(report.glob("aggregates_*.png"), key=lambda p: (p.stem.rsplit("_", 1)[0], _rank(p, panels)))
    out = []
    for png in success + final + aggregates:
        out += [f"![{png.stem}]({up}{ASSETS}/{name}/{png.name})", ""]
    if training:
        out += ['??? note "Training episodes: success and return against steps"', ""]
        out += [f"    ![{png.stem}]({up}{ASSETS}/{name}/{png.name})\n" for png in training]
    return "\n".join(out)


def robustness(path: Path, name: str, depth: int) -> str:
    """Markdown: per task, the final policies' success under observation noise and delay
    (``robustness.csv``, by the report's own table function) and the report's figure of it."""
    tables = robustness_tables(path / ROBUSTNESS_FILE)
    if not tables:
        raise ValueError(f"no {ROBUSTNESS_FILE} in {path}; run unified-manip robustness on its runs")
    return _with_figures(tables, name, depth, "robustness")


def factors(path: Path, name: str, depth: int) -> str:
    """Markdown: per task, each factor's drop in success alone shifted (the rows of
    ``robustness.csv`` that ``robustness --factors`` wrote, by the report's own table
    function) and the report's figure of it."""
    tables = factor_tables(read_robustness(path / ROBUSTNESS_FILE))
    if not tables:
        raise ValueError(f"no one-factor rows in {path / ROBUSTNESS_FILE}; run unified-manip robustness --factors")
    return _with_figures(tables, name, depth, "factors")


def _with_figures(tables: dict[str, list[str]], name: str, depth: int, kind: str) -> str:
    """Each task's table under its short name, then the report's ``<task>_<kind>.png``."""
    out = []
    for task, table in tables.items():
        short = task.split("/")[-1]
        figure = f"{'../' * depth}{ASSETS}/{name}/{short}_{kind}.png"
        out += [f"**{short}**:", "", *table, "", f"![{short} {kind}]({figure})", ""]
    return "\n".join(out)


def _rank(png: Path, panels: tuple[str, ...]) -> int:
    kind = png.stem.rsplit("_", 1)[-1]
    return panels.index(kind) if kind in panels else len(panels)


def conversion_tables(path: Path) -> str:
    """Markdown: the conversion table's ``conversion.json`` (``python -m
    benchmarks.conversion_table``), a task × mode overview, then every row."""
    import json

    from benchmarks.conversion_table import markdown, overview

    results = json.loads((path / "conversion.json").read_text())
    return overview(results) + "\n\n" + markdown(results).replace("UnifiedManip/", "")


def catalogue_table(path: Path) -> str:
    """Markdown: ``collect --all``'s ``catalogue.json`` per task (the datasets written, the
    modes skipped with their conversion success, size and time), then the whole set's totals."""
    import json

    entries = json.loads((path / "catalogue.json").read_text())
    by_task: dict[str, list[dict]] = defaultdict(list)
    for entry in entries.values():
        by_task[entry["task"]].append(entry)
    rows = [
        "| task | datasets (modes) | skipped: converted episodes, or why | size | wall time | CPU time |",
        "|---|---|---|---:|---:|---:|",
    ]
    for task, items in by_task.items():
        written = [f"`{e['mode']}`" for e in items if e["state"] == "written"]
        skipped = [
            f"`{e['mode']}` {e['converted']}" if "converted" in e else f"`{e['mode']}`: {e['reason']}"
            for e in items
            if e["state"] == "skipped"
        ]
        size = sum(e.get("bytes", 0) for e in items) / 1e6
        wall, cpu = (sum(e.get(k, 0.0) for e in items) / 60 for k in ("wall_s", "cpu_s"))
        rows.append(
            f"| {task.split('/')[-1]} | {len(written)}: {', '.join(written) or '–'} | {'; '.join(skipped) or '–'} "
            f"| {size:,.0f} MB | {wall:.1f} min | {cpu:.1f} min |"
        )
    every = list(entries.values())
    written = sum(e["state"] == "written" for e in every)
    size = sum(e.get("bytes", 0) for e in every) / 1e9
    wall, cpu = (sum(e.get(k, 0.0) for e in every) / 3600 for k in ("wall_s", "cpu_s"))
    rows += [
        "",
        f"**The whole set: {written} datasets of {len(every)} tried, {size:.2f} GB, {wall:.2f} h wall "
        f"({cpu:.2f} h CPU)** on one core. Sizes are the datasets' files; the conversion sources under "
        "`.sources/` are not counted. A conversion's time includes recording its source, where it did so.",
    ]
    return "\n".join(rows)


def command(path: Path) -> str:
    """The experiment's ``command.txt`` as a code block."""
    text = (path / "command.txt").read_text().strip()
    return f"```bash\n{text}\n```"
