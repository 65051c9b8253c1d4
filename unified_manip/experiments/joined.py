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


def joined_rows(paths: list[Path]) -> dict[Path, list[dict[str, Any]]]:
    """The rows of every ``results.csv`` in ``paths``, by file.

    Raises:
        ResultsError: A file given twice, a file that is not a bench's, or one run (by
            :data:`RUN_KEYS`) in two files.
    """
    names = [Path(p).resolve() for p in paths]
    if len(set(names)) < len(names):
        raise ResultsError("aggregate was given the same results.csv twice; give each bench's file once")
    out: dict[Path, list[dict[str, Any]]] = {}
    seen: dict[tuple, Path] = {}
    for path in map(Path, paths):
        out[path] = read_results(path)
        for r in out[path]:
            key = tuple(r[k] for k in RUN_KEYS)
            if key in seen:
                raise ResultsError(
                    f"{path}: run {r['run']} is also in {seen[key]}; an aggregate takes each run from one bench, "
                    "so leave one of the two files out"
                )
            seen[key] = path
    return out


def _sources(by_file: dict[Path, list[dict[str, Any]]]) -> list[str]:
    """A table of where each task's runs come from: bench, tasks, runs, budget, seeds."""
    lines = ["| bench | tasks | runs | budget | seeds |", "|---|---|---:|---|---|"]
    for path, rows in by_file.items():
        tasks = sorted({r["task"].split("/")[-1] for r in rows})
        budgets = sorted({f"{r['steps']:,} {budget_unit(r)}" for r in rows})
        seeds = sorted({r["seed"] for r in rows})
        lines.append(
            f"| `{path}` | {', '.join(tasks)} | {len(rows)} | {', '.join(budgets)} | {', '.join(map(str, seeds))} |"
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

    by_file = joined_rows(paths)
    rows = [r for file_rows in by_file.values() for r in file_rows]
    out.mkdir(parents=True, exist_ok=True)
    section = aggregate_section(rows, out)
    if not section:
        tasks = sorted({r["task"].split("/")[-1] for r in rows})
        raise ResultsError(
            f"no aggregate: no algorithm and reward has two action modes (or observation designs) run on "
            f"every one of two tasks or more (the files hold {', '.join(tasks)})"
        )
    lines = [f"# Aggregate: {' + '.join(p.parent.name for p in by_file)}", "", "## How this was made", ""]
    for path in by_file:
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
        *_sources(by_file),
        "",
        *section,
    ]
    path = out / "aggregate.md"
    write_atomic(path, "\n".join(lines) + "\n")
    return path
