"""``unified-manip robustness``: a bench's final policies evaluated again under observation
noise and delay, and on the test distributions of domain randomisation."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from unified_manip.cli.args import add_test_distribution, positive_int


def add_robustness(sub) -> None:
    """Add ``robustness`` to the subparsers ``sub``."""
    p = sub.add_parser(
        "robustness",
        help="evaluate a bench's final policies under observation noise and delay, and on test distributions",
    )
    p.add_argument("bench", help="a bench's output directory (its runs/ with their final models)")
    p.add_argument(
        "--noise", type=float, nargs="+", help="noise stds (default 0 .005 .01; with --test-distribution: 0)"
    )
    p.add_argument(
        "--delay", type=positive_int, nargs="*", help="delays in steps (default 1; with --test-distribution: none)"
    )
    add_test_distribution(p, several=True)
    p.add_argument(
        "--factors",
        action="store_true",
        help="with --test-distribution in-range or extreme: also each of its terms alone, one factor at a time",
    )
    p.add_argument(
        "--only",
        action="append",
        metavar="KEY=VALUE",
        help="evaluate only the finished runs matching this (task, action_mode, reward_type, algo, seed, "
        "observation or randomization; repeatable: values of one key are alternatives, keys must all match)",
    )
    p.add_argument("--episodes", type=positive_int, default=50, help="evaluation episodes per run and condition")
    p.add_argument("--seed", type=int, default=123, help="episode k is reset with seed + k")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_robustness)


def cmd_robustness(args: argparse.Namespace) -> int:
    from unified_manip.experiments.factors import SHIFTED
    from unified_manip.experiments.robustness import DELAYS, NOISES, RobustnessError, conditions, evaluate_bench

    if args.factors and not set(args.test_distribution or ()) & set(SHIFTED):
        raise RobustnessError("--factors needs --test-distribution in-range or extreme (the ranges it shifts)")
    distributions = tuple(args.test_distribution or ("",))  # "": each run's own randomisation
    shifted = bool(args.test_distribution)  # the distributions alone, unless noise or delay is asked for
    noises = args.noise if args.noise is not None else ((0.0,) if shifted else NOISES)
    delays = args.delay if args.delay is not None else (() if shifted else DELAYS)
    wanted = conditions(tuple(noises), tuple(delays), distributions)
    log = None if args.no_progress else (lambda line: print(line, file=sys.stderr, flush=True))
    path = evaluate_bench(
        Path(args.bench),
        wanted,
        args.episodes,
        args.seed,
        progress=log,
        randomization=args.randomization,
        factors=args.factors,
        select=tuple(args.only or ()),
    )
    print(f"wrote {path}")
    return 0
