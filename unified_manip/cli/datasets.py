"""The dataset subcommands of ``unified-manip``: ``collect``, ``replay`` and ``convert``
(:mod:`unified_manip.datasets`), each with its arguments beside it. Every error they
expect is one line on stderr and exit status 2."""

from __future__ import annotations

import argparse
import functools
import sys
from pathlib import Path
from typing import Callable

from rich.console import Console
from rich.table import Table

from unified_manip.cli.args import env_kwarg, positive_int, task_id
from unified_manip.cli.output import write_json
from unified_manip.datasets.search import METHODS, TOLERANCE_CM
from unified_manip.envs.config import ACTION_MODES
from unified_manip.envs.design_names import parse_observation
from unified_manip.envs.registry import TASKS
from unified_manip.envs.rewards import REWARD_TYPES


def add_commands(sub) -> None:
    """Add ``collect``, ``replay`` and ``convert`` to the subparsers ``sub``."""
    p = sub.add_parser("collect", help="record a policy's episodes as a Minari dataset, with simulator states")
    p.add_argument("--env", type=task_id, metavar="ID", help="registered task ID (with --all: only this task)")
    p.add_argument(
        "--all",
        action="store_true",
        help="every task with a scripted policy, in every mode conversion reaches (>= 80%%), N successful "
        "episodes each, into the directory --out (resumable)",
    )
    p.add_argument(
        "--policy",
        default="scripted",
        metavar="scripted|random|RUN_DIR",
        help="the task's scripted policy, uniform random actions, or a trained run (default: scripted)",
    )
    p.add_argument("--episodes", type=positive_int, help="episodes in the dataset (with --all: default 100)")
    p.add_argument("--action-mode", choices=ACTION_MODES, help="default: ee_delta, or the run's own mode")
    p.add_argument("--reward-type", choices=REWARD_TYPES, help="default: sparse, or the run's own")
    p.add_argument(
        "--env-kwarg",
        action="append",
        type=env_kwarg,
        metavar="KEY=VALUE",
        help="extra gym.make keyword argument, a YAML value (repeatable), e.g. observation=relative",
    )
    p.add_argument(
        "--out", required=True, help="dataset directory ROOT/NAME-vN (MINARI_DATASETS_PATH=ROOT); with --all: ROOT"
    )
    p.add_argument("--seed", type=int, default=0, help="episode k is reset with seed + k")
    p.add_argument("--only-successful", action="store_true", help="keep successful episodes only")
    p.add_argument("--overwrite", action="store_true", help="replace a dataset at --out")
    p.add_argument("--stochastic", action="store_true", help="sample a trained run's actions (default: its mean)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", help="also write the result to this JSON file")
    p.set_defaults(func=cmd_collect)

    p = sub.add_parser("replay", help="replay a dataset from its states (or actions) and report where it departs")
    p.add_argument("dataset", help="dataset directory (written by collect or convert)")
    p.add_argument("--actions", action="store_true", help="play the recorded actions from the reset instead")
    p.add_argument("--video", help="render the replayed episodes to this .mp4 or .gif")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", help="also write the report to this JSON file")
    p.set_defaults(func=cmd_replay)

    p = sub.add_parser("convert", help="re-execute a dataset's episodes in another action mode")
    p.add_argument("dataset", help="dataset directory (written by collect or convert)")
    p.add_argument("--action-mode", required=True, choices=ACTION_MODES, help="the action mode to convert into")
    p.add_argument("--out", required=True, help="new dataset directory ROOT/NAME-vN")
    p.add_argument(
        "--observation",
        type=parse_observation,
        help="record the converted episodes with this observation design (default: the dataset's)",
    )
    p.add_argument(
        "--env",
        help="play the episodes on this ID, another version of the recorded task (default: the recorded ID)",
    )
    p.add_argument(
        "--method",
        choices=METHODS,
        default=METHODS[0],
        help="search each step's action for the recorded next state, catching up where the mode lags, and "
        "retry a lost episode in lockstep and open loop (default); or play the recorded actions translated "
        "into the mode, open loop",
    )
    p.add_argument(
        "--tolerance",
        type=float,
        default=TOLERANCE_CM,
        metavar="CM",
        help=f"an episode whose grip site lands further than this from the recording fails (default {TOLERANCE_CM:g})",
    )
    p.add_argument(
        "--keep-failed", action="store_true", help="keep the episodes that no longer succeed or leave the tolerance"
    )
    p.add_argument("--overwrite", action="store_true", help="replace a dataset at --out")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", help="also write the report to this JSON file")
    p.set_defaults(func=cmd_convert)


def _one_line_errors(command: Callable[[argparse.Namespace], int]) -> Callable[[argparse.Namespace], int]:
    """Run ``command``; an expected error is one line on stderr and exit status 2."""

    @functools.wraps(command)
    def run(args: argparse.Namespace) -> int:
        from unified_manip.datasets import DatasetError
        from unified_manip.training.request import TrainError

        try:
            return command(args)
        except (DatasetError, TrainError) as err:
            print(f"unified-manip {args.command}: error: {err}", file=sys.stderr)
            return 2

    return run


@_one_line_errors
def cmd_collect(args: argparse.Namespace) -> int:
    from unified_manip.datasets import DatasetError
    from unified_manip.datasets.policies import BUILT_IN
    from unified_manip.datasets.recording import collect

    if args.all:
        from unified_manip.cli.collect_all import collect_all_command

        return collect_all_command(args)
    if args.env is None or args.episodes is None:
        raise DatasetError("collect needs --env ID and --episodes N (or --all)")

    kwargs = {"action_mode": args.action_mode or "ee_delta", "reward_type": args.reward_type or "sparse"}
    if args.policy in BUILT_IN:
        make_policy, source = BUILT_IN[args.policy], f"{args.policy} policy of {args.env}"
    else:
        from unified_manip.extras import MissingExtra, require

        try:
            require("train", what="unified-manip collect --policy RUN_DIR")
        except MissingExtra as err:
            raise DatasetError(str(err)) from None
        from unified_manip.training.played import run_policy, run_settings

        _, config = run_settings(Path(args.policy))
        if config["env"] != args.env:
            raise DatasetError(f"the run {args.policy} was trained on {config['env']}; it cannot play {args.env}")
        run_kwargs = dict(config["env_kwargs"])
        for key, value in (("action_mode", args.action_mode), ("reward_type", args.reward_type)):
            if value is not None and value != run_kwargs.get(key):
                raise DatasetError(
                    f"the run {args.policy} was trained with {key} {run_kwargs.get(key)!r}; it cannot act with {value!r}"
                )
        kwargs = run_kwargs
        make_policy = run_policy(Path(args.policy), deterministic=not args.stochastic)
        source = f"run {args.policy} ({'stochastic' if args.stochastic else 'deterministic'})"
    kwargs.update(dict(args.env_kwarg or []))
    try:
        TASKS[args.env].check_choices(kwargs["action_mode"], kwargs["reward_type"])
    except ValueError as err:
        raise DatasetError(str(err)) from None
    result = collect(
        args.env,
        kwargs,
        make_policy,
        policy=args.policy if args.policy in BUILT_IN else "run",
        source=source,
        episodes=args.episodes,
        out=Path(args.out),
        seed=args.seed,
        only_successful=args.only_successful,
        overwrite=args.overwrite,
        progress=not args.no_progress,
    )
    dropped = f", {result.dropped} failed {'one' if result.dropped == 1 else 'ones'} left out" if result.dropped else ""
    print(
        f"wrote {result.out}: {result.episodes} episodes of {result.played} played "
        f"(success rate {result.success_rate:.2f}{dropped})"
    )
    if args.json:
        write_json(args.json, result.as_dict())
    return 0


@_one_line_errors
def cmd_replay(args: argparse.Namespace) -> int:
    from unified_manip.datasets.replay import replay

    if args.video and Path(args.video).suffix.lower() not in (".mp4", ".gif"):
        from unified_manip.datasets import DatasetError

        raise DatasetError(f"unsupported video format {Path(args.video).suffix!r}; expected .mp4 or .gif")
    report = replay(Path(args.dataset), from_actions=args.actions, video=args.video, progress=not args.no_progress)
    if report.version_mismatches:
        print(f"warning: recorded under other versions: {'; '.join(report.version_mismatches)}", file=sys.stderr)
    table = Table(title=f"replay of {args.dataset} from {'actions' if args.actions else 'states'}")
    for col in ("episode", "steps", "max deviation", "first departure", "success recorded", "success replayed"):
        table.add_column(col, justify="right")
    for e in report.episodes:
        table.add_row(
            str(e.episode),
            str(e.steps),
            f"{e.max_deviation:.3g}",
            "-" if e.first_departure is None else str(e.first_departure),
            str(e.success_recorded),
            str(e.success_replayed),
        )
    Console(width=120).print(table)
    print("exact: every step replayed bit for bit" if report.exact else f"not exact: {report.departure()}")
    if args.video:
        print(f"wrote {args.video}")
    if args.json:
        write_json(args.json, report.as_dict())
    return 0 if report.exact else 1


@_one_line_errors
def cmd_convert(args: argparse.Namespace) -> int:
    from unified_manip.datasets.convert import convert

    report = convert(
        Path(args.dataset),
        args.action_mode,
        Path(args.out),
        keep_failed=args.keep_failed,
        overwrite=args.overwrite,
        progress=not args.no_progress,
        observation=args.observation,
        method=args.method,
        tolerance_cm=args.tolerance,
        env_id=args.env,
    )
    table = Table(title=f"{args.dataset} converted to {args.action_mode} ({args.method})")
    columns = "episode|steps|success recorded|success converted|grip site off cm (mean / max)|goal off (mean / max)"
    for col in columns.split("|") + ["first step off", "by", "s"]:
        table.add_column(col, justify="right")
    for e in report.episodes:
        table.add_row(
            str(e.episode),
            str(e.steps),
            str(e.success_recorded),
            str(e.success_converted),
            f"{e.tracking_error_mean_cm:.2f} / {e.tracking_error_max_cm:.2f}",
            f"{e.goal_error_mean:.4f} / {e.goal_error_max:.4f}",
            "-" if e.first_step_off is None else str(e.first_step_off),
            e.replayed_by,
            f"{e.seconds:.1f}",
        )
    Console(width=150).print(table)
    n = len(report.episodes)
    for e in report.episodes:
        if e.first_step_off is not None:
            print(f"episode {e.episode}: step {e.first_step_off} left the grip site beyond {args.tolerance:g} cm")
    print(f"converted success {report.success_rate:.2f} ({sum(e.kept for e in report.episodes)}/{n})")
    if args.json:
        write_json(args.json, report.as_dict())
    if report.out is None:
        print("no dataset written: no episode kept (--keep-failed keeps the failed ones)", file=sys.stderr)
        return 1
    print(f"wrote {report.out}: {report.kept} episodes")
    return 0
