"""``unified-manip aggregate``: the cross-task aggregates of several benches at once.

One bench answers "which action mode is better across *its* tasks". A question across
suites (Meta-World's MT10 beside the pick-and-place tasks of another study) needs the runs
of several ``results.csv`` files in one aggregate: each task keeps the runs, budget and
recipe of the bench it came from, and the aggregate (:mod:`.aggregates`, rliable's IQM,
performance profiles and probability of improvement) treats every task alike. Only the
modes run on every task of a setting enter it; the others are named as left out.
"""

from __future__ import annotations

import shlex
from pathlib import Path
from typing import Any

from unified_manip.experiments.aggregate_report import aggregate_section
from unified_manip.experiments.results import ResultsError, budget_unit, read_results

#: What makes two rows the same run, whichever bench they come from.
RUN_KEYS = ("task", "action_mode", "observation", "randomization", "algo", "reward_type", "seed")


def joined_rows(paths: list[Path]) -> list[dict[str, Any]]:
    """The rows of every ``results.csv`` in ``paths``, each with ``suite`` (its bench
    directory's name).

    Raises:
        ResultsError: A file given twice, a file that is not a bench's, or one run (by
            :data:`RUN_KEYS`) in two files.
    """
    rows: list[dict[str, Any]] = []
    seen: dict[tuple, Path] = {}
    names = [Path(p).resolve() for p in paths]
    if len(set(names)) < len(names):
        raise ResultsError("aggregate was given the same results.csv twice; give each bench's file once")
    for path in map(Path, paths):
        for r in read_results(path):
            key = tuple(r[k] for k in RUN_KEYS)
            if key in seen:
                raise ResultsError(
                    f"{path}: run {r['run']} is also in {seen[key]}; an aggregate takes each run from one bench, "
                    "so leave one of the two files out"
                )
            seen[key] = path
            rows.append({**r, "suite": path.parent.name})
    return rows


def _sources(paths: list[Path], rows: list[dict[str, Any]]) -> list[str]:
    """A table of where each task's runs come from: bench, tasks, runs, budget, seeds."""
    lines = ["| bench | tasks | runs | budget | seeds |", "|---|---|---:|---|---|"]
    for path in map(Path, paths):
        mine = [r for r in rows if r["suite"] == path.parent.name]
        tasks = sorted({r["task"].split("/")[-1] for r in mine})
        budgets = sorted({f"{r['steps']:,} {budget_unit(r)}" for r in mine})
        seeds = sorted({r["seed"] for r in mine})
        lines.append(
            f"| `{path}` | {', '.join(tasks)} | {len(mine)} | {', '.join(budgets)} | {', '.join(map(str, seeds))} |"
        )
    return lines


def build_aggregate(paths: list[Path], out: Path, command: str | None = None) -> Path:
    """Write ``aggregate.md`` and its figures for the joined rows of ``paths`` into ``out``;
    return the Markdown path.

    Raises:
        ResultsError: As :func:`joined_rows`; or no setting (algorithm and reward) with
            two action modes (or observation designs) run on two tasks or more.
    """
    from unified_manip.training.rundir import write_atomic

    rows = joined_rows(paths)
    out.mkdir(parents=True, exist_ok=True)
    section = aggregate_section(rows, out)
    if not section:
        tasks = sorted({r["task"].split("/")[-1] for r in rows})
        raise ResultsError(
            f"no aggregate: no algorithm and reward has two action modes (or observation designs) run on "
            f"every one of two tasks or more (the files hold {', '.join(tasks)})"
        )
    lines = [f"# Aggregate: {' + '.join(Path(p).parent.name for p in paths)}", "", "## How this was made", ""]
    for path in map(Path, paths):
        command_file = path.parent / "command.txt"
        if command_file.is_file():
            lines += [f"`{path.parent}`:", "", "```bash", command_file.read_text().strip(), "```", ""]
    lines += [
        "This aggregate:",
        "",
        "```bash",
        command or shlex.join(["unified-manip", "aggregate", *map(str, paths)]),
        "```",
        "",
        "Each task's runs come from one bench, with that bench's recipe and budget:",
        "",
        *_sources(paths, rows),
        "",
        *section,
    ]
    path = out / "aggregate.md"
    write_atomic(path, "\n".join(lines) + "\n")
    return path
