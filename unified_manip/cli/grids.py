"""The subcommands of ``unified-manip`` for grids of runs: ``bench``, ``report``,
``aggregate``, ``robustness`` (:mod:`.robustness`) and ``plot``, each with its arguments
beside it."""

from __future__ import annotations

import argparse
import shlex
import signal
import sys
from pathlib import Path

from unified_manip.cli.args import figure_path, positive_int, task_ids
from unified_manip.cli.robustness import add_robustness
from unified_manip.training.devices import DEVICES


def add_commands(sub) -> None:
    """Add ``bench``, ``report``, ``aggregate``, ``robustness`` and ``plot`` to the subparsers ``sub``."""
    p = sub.add_parser("bench", help="run a grid of training runs (resumable)")
    p.add_argument("grid", help="grid YAML file, e.g. baselines/grids/action_spaces.yaml")
    p.add_argument("--out", help="bench directory (default: results/<grid name>)")
    p.add_argument(
        "--executor", choices=("local", "ray"), default="local", help="local: a process pool; ray: a Ray cluster"
    )
    p.add_argument("--address", help="Ray cluster address (with --executor ray); default: start a local Ray")
    p.add_argument("--workers", type=positive_int, help="runs at a time (default: CPU cores)")
    p.add_argument("--retries", type=int, default=1, help="retries of a crashed run")
    p.add_argument(
        "--device",
        choices=DEVICES,
        help="device of every run: auto, cpu or cuda (default: each hyperparameter file's device key, else auto)",
    )
    p.add_argument(
        "--only",
        action="append",
        metavar="KEY=VALUE",
        help="train only the runs matching this (task, action_mode, reward_type, algo, seed, observation or "
        "randomization, as run names show them; repeatable: "
        "values of one key are alternatives, keys must all match); results keep every finished run",
    )
    p.add_argument(
        "--collect",
        action="store_true",
        help="start no run: write results.csv from the finished runs in --out (e.g. copied in from another "
        "bench directory)",
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_bench)

    p = sub.add_parser("report", help="Markdown + PNG report from a bench's results.csv")
    p.add_argument("results", help="results.csv written by unified-manip bench")
    p.add_argument("--out", help="output directory (default: <results dir>/report)")
    p.add_argument("--claims", help="YAML of claimed results to set beside the measured ones")
    p.add_argument("--no-dense-check", action="store_true", help="skip the dense-reward sanity check")
    p.set_defaults(func=cmd_report)

    p = sub.add_parser(
        "aggregate", help="cross-task aggregates (IQM, profiles, improvement) over several benches' results"
    )
    p.add_argument("results", nargs="+", help="results.csv files written by unified-manip bench")
    p.add_argument("--out", required=True, help="output directory for aggregate.md and its figures")
    p.set_defaults(func=cmd_aggregate)

    add_robustness(sub)

    p = sub.add_parser(
        "plot", help="one figure of success against steps (or demonstrations) over benches, a panel per task"
    )
    p.add_argument("results", nargs="+", help="results.csv files written by unified-manip bench")
    p.add_argument("--out", required=True, type=figure_path, help="output figure (.png, .svg or .pdf)")
    p.add_argument("--columns", type=positive_int, default=4, help="panels per row")
    p.add_argument(
        "--tasks",
        type=task_ids,
        help="comma-separated IDs: the panels, in this order (default: every task in the files)",
    )
    p.add_argument(
        "--against",
        choices=("steps", "demonstrations"),
        default="steps",
        help="x axis: evaluation success against environment steps (default), or final success against "
        "the demonstration episodes each run learned from (benches of one grid at several dataset sizes)",
    )
    p.set_defaults(func=cmd_plot)


def cmd_bench(args: argparse.Namespace) -> int:
    from unified_manip.experiments.bench import run_grid
    from unified_manip.experiments.grid import load_grid

    grid = load_grid(Path(args.grid), datasets=not args.collect)  # collecting reads finished runs
    out = Path(args.out) if args.out else Path("results") / grid.name
    # Ctrl-C, `kill` and a hang-up stop the bench cleanly (its runs checkpoint and stop),
    # Ctrl-C even when the bench was started with SIGINT ignored; a hang-up stays ignored
    # under nohup.
    stops: list[int] = []

    def stop(signum, frame):
        stops.append(signum)
        raise KeyboardInterrupt

    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        if sig != signal.SIGHUP or signal.getsignal(sig) is signal.SIG_DFL:
            signal.signal(sig, stop)
    try:
        summary = run_grid(
            grid,
            out,
            executor=args.executor,
            workers=args.workers,
            address=args.address,
            retries=args.retries,
            progress=not args.no_progress,
            command=shlex.join(["unified-manip", *sys.argv[1:]]),
            device=args.device,
            select=tuple(args.only or ()),
            collect=args.collect,
        )
    except KeyboardInterrupt:
        # Runs in progress wrote a checkpoint on the way out; finished runs are in results.
        print(f"bench interrupted; run the same command again to resume (finished runs are kept in {out})")
        return 128 + (stops[0] if stops else signal.SIGINT)
    print(
        f"{summary['finished']}/{summary['runs']} runs finished, {len(summary['failed'])} failed; "
        f"results in {summary['results']}"
    )
    for name in summary["failed"]:
        print(f"failed: {name} (see failures.jsonl)")
    return 0 if not summary["failed"] else 1


def cmd_report(args: argparse.Namespace) -> int:
    from unified_manip.experiments.report import build_report
    from unified_manip.training.yamlfile import load_mapping

    (results,) = _results_files([args.results])
    claims = load_mapping(Path(args.claims), "a mapping of claim labels") if args.claims else None
    out = Path(args.out) if args.out else results.parent / "report"
    path = build_report(
        results,
        out,
        command=shlex.join(["unified-manip", *sys.argv[1:]]),
        dense_check=not args.no_dense_check,
        claims=claims,
    )
    print(f"wrote {path}")
    return 0


def cmd_aggregate(args: argparse.Namespace) -> int:
    from unified_manip.experiments.joined import build_aggregate

    path = build_aggregate(
        _results_files(args.results), Path(args.out), command=shlex.join(["unified-manip", *sys.argv[1:]])
    )
    print(f"wrote {path}")
    return 0


def cmd_plot(args: argparse.Namespace) -> int:
    from unified_manip.experiments.plot import plot_overview

    paths = _results_files(args.results)
    if args.against == "demonstrations":
        from unified_manip.experiments.scaling import plot_against_demonstrations as draw
    else:
        draw = plot_overview
    titles = draw(paths, Path(args.out), columns=args.columns, tasks=args.tasks)
    print(f"wrote {args.out} ({len(titles)} panels: {', '.join(titles)})")
    return 0


def _results_files(names: list[str]) -> list[Path]:
    """The given results.csv paths, each checked to exist (FileNotFoundError: one line)."""
    paths = [Path(n) for n in names]
    for path in paths:
        if not path.is_file():
            raise FileNotFoundError(f"{path} not found; expected a bench's results.csv")
    return paths
