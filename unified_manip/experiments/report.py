"""``unified-manip report RESULTS``: Markdown and PNG figures from a bench's results.

Statistics come from libraries, not hand-rolled code. A cell's interval over seeds is
labelled as what it is (:func:`~unified_manip.experiments.stats.seed_interval`): the range
of its seeds below 5 seeds, a ``scipy.stats.bootstrap`` 95% percentile interval of the mean
from 5 on; the interquartile mean (IQM, with its stratified-bootstrap interval) and the
probability of improvement come from ``rliable``. The report states the budget, the seeds, the
package versions and the commands that produced it, and includes the dense-reward
sanity check of :mod:`unified_manip.experiments.sanity`.
"""

from __future__ import annotations

import json
import shlex
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from unified_manip.experiments.aggregate_report import aggregate_section
from unified_manip.experiments.figures import plot_final, plot_task
from unified_manip.experiments.rankings import Groups, config_rankings, design_rankings
from unified_manip.experiments.results import budget_unit, read_results, setting_key, steps_label
from unified_manip.experiments.robustness import FILE as ROBUSTNESS_FILE
from unified_manip.experiments.robustness_report import robustness_section
from unified_manip.experiments.stats import MIN_SEEDS_FOR_CI, iqm_with_ci, seed_interval
from unified_manip.experiments.targets import benchmark_table, grid_targets


def _group(rows: list[dict[str, Any]]) -> Groups:
    """Rows by task, then by setting (:func:`~unified_manip.experiments.results.setting_key`)."""
    out: Groups = defaultdict(lambda: defaultdict(list))
    for r in rows:
        out[r["task"]][setting_key(r)].append(r)
    return out


def _demonstrations_lines(demonstrated: list[dict], total: int) -> list[str]:
    """A line on the runs that fitted a dataset (``bc``: the data is what they learn from,
    within their budget) and one on the runs that started from demonstrations."""
    fitted = [r for r in demonstrated if r["algo"] == "bc"]
    started = [r for r in demonstrated if r["algo"] != "bc"]
    lines = [_demonstrations_line(started, total)] if started else []
    if fitted:
        records = [r["demonstrations"] for r in fitted]
        episodes = sorted({d["episodes"] for d in records})
        success = [d["success"] for d in records]
        lines.append(
            f"- Demonstrations: {len(fitted)} of {total} runs are behaviour cloning, fitted to "
            f"{', '.join(map(str, episodes))} episodes of {_sources(records)} "
            f"(their success {min(success):.2f}–{max(success):.2f}); their budget counts gradient steps on them."
        )
    return lines


def _demonstrations_line(demonstrated: list[dict], total: int) -> str:
    """What the runs that started from scripted demonstrations were given (a prior they
    did not collect, so the report says so). Each record holds every demonstration
    setting under its own name (:func:`~unified_manip.experiments.results.read_results`)."""
    records = [r["demonstrations"] for r in demonstrated]
    episodes = sorted({d["episodes"] for d in records})
    success = [d["success"] for d in records]
    cloned = [d["bc_steps"] for d in records if d["bc_steps"]]
    cloning = (
        f" The actor of {len(cloned)} of them was behaviour-cloned on them first "
        f"({', '.join(f'{c:,}' for c in sorted(set(cloned)))} gradient steps)."
        if cloned
        else ""
    )
    offline = [d["offline_steps"] for d in records if d["offline_steps"]]
    learned = (
        f" {len(offline)} of them took {', '.join(f'{s:,}' for s in sorted(set(offline)))} gradient steps of "
        "the algorithm's own update on them alone before the first rollout."
        if offline
        else ""
    )
    losses = [(d["bc_weight"], d["bc_q_filter"], d["bc_sampled"]) for d in records if d["bc_weight"]]
    loss = (
        f" {len(losses)} of them kept a cloning loss on them in every actor update ("
        + "; ".join(
            f"weight {w:g}, {'Q-filtered' if q else 'unfiltered'}{', on sampled actions' if a else ''}"
            for w, q, a in sorted(set(losses))
        )
        + ")."
        if losses
        else ""
    )
    return (
        f"- Demonstrations: {len(demonstrated)} of {total} runs started with "
        f"{', '.join(map(str, episodes))} episodes of "
        f"{_sources(records)} in the replay buffer "
        f"(their success {min(success):.2f}–{max(success):.2f}); they are not counted in the budget."
        f"{cloning}{learned}{loss}"
    )


def _sources(records: list[dict]) -> str:
    """Where the demonstrations came from: the task's scripted policy, or datasets."""
    datasets = sorted({d["dataset"] for d in records if d.get("dataset")})
    scripted = ["the task's scripted policy"] if any(not d.get("dataset") for d in records) else []
    named = [f"`{d}`" for d in datasets] if len(datasets) < 4 else [f"{len(datasets)} datasets"]
    return " or ".join(named + scripted)


def build_report(
    results: Path, out: Path, command: str | None = None, dense_check: bool = True, claims: dict | None = None
) -> Path:
    """Write ``report.md`` and figures for ``results`` into ``out``; return the Markdown path."""
    rows = read_results(results)
    out.mkdir(parents=True, exist_ok=True)
    by_task = _group(rows)
    lines: list[str] = []
    bench_dir = Path(results).parent
    title = bench_dir.name
    lines += [f"# Benchmark report: {title}", ""]
    lines += ["## How this was made", ""]
    bench_cmd = (bench_dir / "command.txt").read_text().strip() if (bench_dir / "command.txt").is_file() else None
    if bench_cmd:
        lines += ["Runs:", "", "```bash", bench_cmd, "```", ""]
    lines += [
        "This report:",
        "",
        "```bash",
        command or shlex.join(["unified-manip", "report", str(results)]),
        "```",
        "",
    ]
    budgets = sorted({(r["steps"], budget_unit(r)) for r in rows})
    seeds = sorted({r["seed"] for r in rows})
    versions = sorted({json.dumps(r["versions"], sort_keys=True) for r in rows})
    demonstrated = [r for r in rows if r.get("demonstrations")]
    grid_file = bench_dir / "grid.yaml"
    env_kwargs = (yaml.safe_load(grid_file.read_text()) or {}).get("env_kwargs") if grid_file.is_file() else None
    lines += [
        f"- Runs: {len(rows)} finished (rows of `{Path(results).name}`; unfinished runs are never included).",
        f"- Budget: {', '.join(f'{b:,} {unit}' for b, unit in budgets)} per run.",
        f"- Seeds: {', '.join(map(str, seeds))}.",
        f"- Wall time (sum over runs): {sum(r['wall_time_s'] for r in rows) / 3600:.2f} h; "
        f"median {np.median([r['steps_per_s'] for r in rows]):.0f} training steps/s per run.",
        *_demonstrations_lines(demonstrated, len(rows)),
        *(
            [
                f"- Env keyword arguments of every run (the grid's `env_kwargs`): `{json.dumps(env_kwargs, sort_keys=True)}`."
            ]
            if env_kwargs
            else []
        ),
        "- Success rate: deterministic evaluation episodes at each evaluation point (SB3 `EvalCallback`); "
        "final = the last evaluation.",
        f"- Intervals of one setting over seeds: with fewer than {MIN_SEEDS_FOR_CI} seeds, the range (min–max) "
        f"of the seeds, labelled so; from {MIN_SEEDS_FOR_CI} seeds, the 95% percentile bootstrap of the mean "
        f"(`scipy.stats.bootstrap`). IQM (rliable) only from {MIN_SEEDS_FOR_CI} seeds; probability of "
        "improvement from rliable.",
        "",
        "Package versions:",
        "",
    ]
    for v in versions:
        lines.append("- " + ", ".join(f"{k} {val}" for k, val in json.loads(v).items()))
    lines.append("")

    targets = grid_targets(grid_file)
    lines += ["## Final success rate", ""]
    designs = any(r["observation"] != "default" for r in rows)  # a column only where some run has one
    randomized = any(r["randomization"] != "none" for r in rows)
    lines += [
        f"| task | algo | action mode |{' observation |' if designs else ''} reward |"
        f"{' randomization |' if randomized else ''} seeds | mean | interval | IQM [95% CI] | per seed |",
        f"|---|---|---|{'---|' if designs else ''}---|{'---|' if randomized else ''}---:|---:|---|---|---|",
    ]
    for task, groups in by_task.items():
        for (algo, mode, reward, design, randomization), runs in sorted(groups.items()):
            vals = [r["final_success_rate"] for r in sorted(runs, key=lambda r: r["seed"])]
            iqm = iqm_with_ci(vals)
            iqm_s = f"{iqm[0]:.2f} [{iqm[1]:.2f}, {iqm[2]:.2f}]" if iqm else f"— (under {MIN_SEEDS_FOR_CI} seeds)"
            lines.append(
                f"| {task.split('/')[-1]} | {algo} | {mode} |{f' {design} |' if designs else ''} {reward} |"
                f"{f' {randomization} |' if randomized else ''} {len(vals)} | {np.mean(vals):.2f} | "
                f"{seed_interval(vals).text() or '—'} | {iqm_s} | {', '.join(f'{v:.2f}' for v in vals)} |"
            )
    lines.append("")
    for task, groups in by_task.items():
        if len(groups) > 1:
            fig = plot_final(task, groups, out, _task_targets(targets, task))
            lines += [f"![{task} final success per setting]({fig.name})", ""]

    if grid_file.is_file():
        lines += ["## Benchmark table", ""]
        lines += benchmark_table(rows, targets)

    lines += [f"## Success against {steps_label(rows)}", ""]
    for task, groups in by_task.items():
        fig = plot_task(task, groups, out, _task_targets(targets, task))
        lines += [f"![{task}]({fig.name})", ""]
    lines += _training_section(by_task, bench_dir / "runs", out)

    lines += design_rankings(by_task)
    lines += aggregate_section(rows, out)
    lines += config_rankings(by_task)

    lines += robustness_section(bench_dir / ROBUSTNESS_FILE, out)

    if claims:
        lines += ["## Against the claimed success rates", ""]
        lines += claims_section(rows, claims)

    if dense_check:
        from unified_manip.experiments.sanity import dense_reward_check

        tasks = sorted(by_task)
        lines += ["## Dense-reward sanity check", ""]
        lines += [
            "For each task, goals from seeded resets and achieved goals sampled at distances from 0 to 20 "
            "success thresholds, with every combination of the ends of the task's other reward inputs "
            "(a gripper's distance and grasp, the action, a drop). A dense reward is flagged if its best value outside "
            "the success region reaches its best value inside it.",
            "",
            "| task | reward | max inside success | max outside success | optimum in success region | flag |",
            "|---|---|---:|---:|---|---|",
        ]
        for task in tasks:
            for reward in ("dense", "dense_penalized"):
                c = dense_reward_check(task, reward)
                lines.append(
                    f"| {task.split('/')[-1]} | {reward} | {c.max_inside:.2f} | {c.max_outside:.2f} | "
                    f"{'yes' if c.optimum_in_success else 'NO'} | {'**FLAG**' if c.flagged else 'ok'} |"
                )
        lines.append("")

    path = out / "report.md"
    path.write_text("\n".join(lines) + "\n")
    return path


def _task_targets(targets: tuple, task: str) -> dict[str, float]:
    return {t.action_mode: t.success for t in targets if t.task == task}


def _training_section(by_task: dict, runs_dir: Path, out: Path) -> list[str]:
    """Training-episode curves from the runs' logs (:mod:`.training_curves`), where present."""
    from unified_manip.experiments.curves import plot_training

    figs = [(task, plot_training(task, groups, runs_dir, out)) for task, groups in by_task.items()]
    if not any(fig for _, fig in figs):
        return []
    lines = [
        "## Training episodes",
        "",
        "Success and return over the last 100 training episodes (the exploring policy, not the "
        "deterministic one evaluated above), from each run's TensorBoard log; mean over seeds, range "
        "shaded.",
        "",
    ]
    return lines + [line for task, fig in figs if fig for line in (f"![{task} training]({fig.name})", "")]


def claims_section(rows: list[dict[str, Any]], claims: dict) -> list[str]:
    """Measured final success beside claimed numbers (``claims``: label -> spec)."""
    lines = [
        "| run | claimed success (budget) | measured mean final success [interval] (budget, seeds) |",
        "|---|---|---|",
    ]
    for label, c in claims.items():
        vals = [
            r["final_success_rate"]
            for r in rows
            if r["algo"] == c["algo"] and r["reward_type"] == c["reward_type"] and r["task"] == c["task"]
        ]
        if not vals:
            lines.append(f"| {label} | {c['claimed']} ({c['claimed_budget']}) | not run |")
            continue
        interval = seed_interval(vals).text()  # none from one seed
        interval = f" {interval}" if interval else ""
        budget = sorted({r["steps"] for r in rows if r["algo"] == c["algo"] and r["reward_type"] == c["reward_type"]})
        lines.append(
            f"| {label} | {c['claimed']} ({c['claimed_budget']}) | {np.mean(vals):.2f}{interval} "
            f"({', '.join(f'{b:,}' for b in budget)} steps, {len(vals)} seed{'s' if len(vals) > 1 else ''}) |"
        )
    lines.append("")
    return lines
