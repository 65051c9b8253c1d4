"""The ``unified-manip`` command line."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from rich.console import Console
from rich.table import Table

from unified_manip.cli.args import Parser, positive_int, task_id, task_ids
from unified_manip.cli.datasets import add_commands as add_dataset_commands
from unified_manip.cli.grids import add_commands as add_grid_commands
from unified_manip.cli.interrupts import exit_normally_after_interrupt, noting_ctrl_c
from unified_manip.cli.output import write_json
from unified_manip.cli.runs import add_commands as add_run_commands
from unified_manip.envs.registry import TASKS
from unified_manip.envs.rewards import REWARD_TYPES
from unified_manip.extras import MissingExtra, require


def cmd_list(args: argparse.Namespace) -> int:
    console = Console(width=args.width)
    if args.doc:
        from unified_manip.envs.observation_docs import observation_groups_doc

        console.print(TASKS[args.doc].doc, markup=False, highlight=False)
        console.print(observation_groups_doc(args.doc), markup=False, highlight=False)
        return 0
    table = Table(title="UnifiedManip tasks")
    for col in ("ID", "family", "action modes", "reward types", "goal dim", "episode steps"):
        table.add_column(col)
    for tid, spec in TASKS.items():
        table.add_row(
            tid,
            spec.family,
            ", ".join(spec.action_modes),
            ", ".join(REWARD_TYPES),
            str(spec.goal_dim),
            str(spec.max_episode_steps),
        )
    console.print(table)
    return 0


def cmd_speed(args: argparse.Namespace) -> int:
    from unified_manip.experiments import speed

    results = speed.run(args.env, args.modes, steps=args.steps, repeats=args.repeats)
    table = Table(title=f"env steps/s (median of {args.repeats} x {args.steps} steps, random actions)")
    for col in ("ID", "action mode", "env steps/s", "mode / joint_position"):
        table.add_column(col, justify="right")
    by_key = {(r.task_id, r.action_mode): r for r in results}
    for r in results:
        jp = by_key.get((r.task_id, "joint_position"))
        rel = f"{r.env_steps_per_s / jp.env_steps_per_s:.2f}" if jp else "-"
        table.add_row(r.task_id, r.action_mode, f"{r.env_steps_per_s:,.0f}", rel)
    Console(width=args.width).print(table)
    if args.json:
        write_json(args.json, {"modes": [r.as_dict() for r in results]})
    return 0


def cmd_demo(args: argparse.Namespace) -> int:
    from unified_manip.cli import demo

    successes = demo.run(
        Path(args.out),
        seed=args.seed,
        frames=args.frames,
        size=args.size,
        task_ids=args.env,
        progress=not args.no_progress,
    )
    for tid, ok in successes.items():
        print(f"{tid}: {'success' if ok else 'failure'}")
    print(f"wrote {args.out}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="unified-manip",
        description="Train, evaluate and compare RL baselines on goal-conditioned manipulation tasks, "
        "and record, replay and convert their demonstrations. Each command has its own --help.",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)

    p = sub.add_parser("list", help="table of every registered ID")
    p.add_argument("--doc", type=task_id, metavar="ID", help="print one task's documentation")
    p.add_argument("--width", type=int, default=200, help="table width in characters")
    p.set_defaults(func=cmd_list)

    p = sub.add_parser("speed", help="env steps/s per ID x action mode, random actions")
    p.add_argument("--env", type=task_ids, help="comma-separated IDs (default: all)")
    p.add_argument("--modes", type=lambda s: s.split(","), help="comma-separated action modes (default: all)")
    p.add_argument("--steps", type=positive_int, default=2000, help="steps per measurement")
    p.add_argument("--repeats", type=positive_int, default=3, help="measurements per figure (median)")
    p.add_argument("--json", help="also write the results to this JSON file")
    p.add_argument("--width", type=int, default=200, help="table width in characters")
    p.set_defaults(func=cmd_speed)

    add_run_commands(sub)  # train, eval
    add_grid_commands(sub)  # bench, report, aggregate, robustness, plot
    add_dataset_commands(sub)  # collect, replay, convert

    p = sub.add_parser("demo", help="roll out each task's scripted policy and write a picture strip")
    p.add_argument("--out", default="demo.png", help="output PNG")
    p.add_argument("--env", type=task_ids, help="comma-separated IDs (default: all with a scripted policy)")
    p.add_argument("--seed", type=int, default=0, help="reset seed of every task's episode")
    p.add_argument("--frames", type=positive_int, default=6, help="pictures per task")
    p.add_argument("--size", type=positive_int, default=200, help="picture size in pixels")
    p.add_argument("--no-progress", action="store_true", help="no progress bar (on stderr), as train and bench")
    p.set_defaults(func=cmd_demo)
    return parser


#: The extras each subcommand needs beyond the env library (see :mod:`unified_manip.extras`).
COMMAND_EXTRAS: dict[str, tuple[str, ...]] = {
    "train": ("train",),
    "eval": ("train",),
    "bench": ("train", "bench"),
    "report": ("bench",),
    "aggregate": ("bench",),
    "plot": ("bench",),
    "robustness": ("train", "bench"),
    "collect": ("datasets",),  # and train for --policy RUN_DIR (cli.datasets)
    "replay": ("datasets",),
    "convert": ("datasets",),
}


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    with noting_ctrl_c() as ctrl_c:
        try:
            return _run(parser, args)
        except BaseException as err:
            if not ctrl_c.caused(err):
                raise
    # Ctrl-C: one line and the shell's status for SIGINT. Every file a command writes is
    # written whole or not at all (datasets, checkpoints, results, reports, videos, JSON),
    # so what an interrupted command leaves reads as it did before, or is complete.
    print(f"unified-manip {args.command}: interrupted", file=sys.stderr)
    exit_normally_after_interrupt()
    return 130


def _run(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    extras = COMMAND_EXTRAS.get(args.command, ()) + (("ray",) if getattr(args, "executor", None) == "ray" else ())
    try:
        require(*extras, what=f"unified-manip {args.command}")
    except MissingExtra as err:
        parser.exit(2, f"unified-manip {args.command}: error: {err}\n")

    from unified_manip.envs.mujoco_version import UnsupportedMuJoCo
    from unified_manip.experiments.grid import GridError
    from unified_manip.experiments.results import ResultsError
    from unified_manip.experiments.robustness import RobustnessError
    from unified_manip.training.hyperparams import HyperparameterError
    from unified_manip.training.request import TrainError
    from unified_manip.training.runlock import DirectoryInUse
    from unified_manip.training.yamlfile import YamlFileError

    try:
        return args.func(args)
    except (
        TrainError,
        HyperparameterError,
        GridError,
        ResultsError,
        RobustnessError,
        YamlFileError,
        DirectoryInUse,
        FileNotFoundError,
        MissingExtra,
        UnsupportedMuJoCo,
    ) as err:
        parser.exit(2, f"unified-manip {args.command}: error: {err}\n")
