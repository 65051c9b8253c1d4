"""The ``unified-manip`` command line."""

from __future__ import annotations

import argparse
import json
import shlex
import signal
import sys
from pathlib import Path

from rich.console import Console
from rich.table import Table

from .config import REWARD_TYPES
from .devices import DEVICES
from .registry import TASKS, get_task
from .vector.factory import VEC_KINDS


class _Parser(argparse.ArgumentParser):
    """argparse, but errors are one line naming the valid choices, exit code 2."""

    def error(self, message: str) -> None:  # noqa: D102
        self.exit(2, f"{self.prog}: error: {message}\n")


def _task_ids(value: str | None) -> list[str] | None:
    if value is None:
        return None
    ids = [v.strip() for v in value.split(",") if v.strip()]
    for v in ids:
        try:
            get_task(v)  # the registry's error
        except ValueError as err:
            raise argparse.ArgumentTypeError(str(err)) from None
    return ids


def cmd_list(args: argparse.Namespace) -> int:
    console = Console(width=args.width)
    if args.doc:
        console.print(TASKS[args.doc].doc, markup=False, highlight=False)
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
    from . import speed

    results = speed.run(args.env, args.modes, steps=args.steps, repeats=args.repeats)
    table = Table(title=f"env steps/s vs raw physics (median of {args.repeats} x {args.steps} steps)")
    for col in ("ID", "action mode", "env steps/s", "raw physics steps/s", "env / raw", "overhead µs/step", "mode / joint_position"):
        table.add_column(col, justify="right")
    by_key = {(r.task_id, r.action_mode): r for r in results}
    for r in results:
        jp = by_key.get((r.task_id, "joint_position"))
        rel = f"{r.env_steps_per_s / jp.env_steps_per_s:.2f}" if jp else "-"
        table.add_row(
            r.task_id,
            r.action_mode,
            f"{r.env_steps_per_s:,.0f}",
            f"{r.raw_steps_per_s:,.0f}",
            f"{r.ratio_to_raw:.2f}",
            f"{r.overhead_us:.0f}",
            rel,
        )
    console = Console(width=args.width)
    console.print(table)
    document = {"modes": [r.as_dict() for r in results]}
    ids = args.env or list(TASKS)
    wrapped = [t for t in ids if TASKS[t].upstream_id]
    if wrapped and not args.no_upstream:
        up = Table(title="native mode against the upstream env, same actions, one step of each in turn")
        for col in ("ID", "upstream", "ours steps/s", "upstream steps/s", "ours / upstream", "ours resets/s", "upstream resets/s"):
            up.add_column(col, justify="right")
        rows = [speed.compare_upstream(t, steps=args.steps) for t in wrapped]
        for r in rows:
            up.add_row(
                r.task_id, r.upstream, f"{r.ours_steps_per_s:,.0f}", f"{r.upstream_steps_per_s:,.0f}", f"{r.ratio:.3f}",
                f"{r.ours_resets_per_s:,.0f}", f"{r.upstream_resets_per_s:,.1f}",
            )
        console.print(up)
        document["upstream"] = [r.as_dict() for r in rows]
    if args.train:
        tr = Table(title="SAC+HER training steps/s, native mode against the upstream env")
        for col in ("ID", "upstream", "ours steps/s", "upstream steps/s", "ours / upstream"):
            tr.add_column(col, justify="right")
        rows = [speed.train_speed(t, steps=args.train_steps) for t in args.train]
        for r in rows:
            tr.add_row(r.task_id, r.upstream, f"{r.ours_steps_per_s:,.1f}", f"{r.upstream_steps_per_s:,.1f}", f"{r.ratio:.3f}")
        console.print(tr)
        document["training"] = [r.as_dict() for r in rows]
    if args.json:
        Path(args.json).write_text(json.dumps(document, indent=2))
    return 0


def cmd_demo(args: argparse.Namespace) -> int:
    from . import demo

    successes = demo.run(Path(args.out), seed=args.seed, frames=args.frames, size=args.size, task_ids=args.env)
    for tid, ok in successes.items():
        print(f"{tid}: {'success' if ok else 'failure'}")
    print(f"wrote {args.out}")
    return 0


def cmd_train(args: argparse.Namespace) -> int:
    from .train import TrainRequest, train

    req = TrainRequest(
        env=args.env,
        action_mode=args.action_mode,
        reward_type=args.reward_type,
        algo=args.algo,
        steps=args.steps,
        seed=args.seed,
        n_envs=args.n_envs,
        vec=args.vec,
        run_dir=Path(args.run_dir) if args.run_dir else None,
        overrides=tuple(args.set or ()),
        env_kwargs=dict(args.env_kwarg or ()),
        device=args.device,
        restart=args.restart,
    )
    try:
        train(req, argv=["unified-manip", *sys.argv[1:]], progress=not args.no_progress)
    except KeyboardInterrupt:
        return 130
    return 0


def cmd_eval(args: argparse.Namespace) -> int:
    from .train import evaluate

    result = evaluate(
        Path(args.target),
        args.episodes,
        action_mode=args.action_mode,
        reward_type=args.reward_type,
        seed=args.seed,
        video=Path(args.video) if args.video else None,
        device=args.device,
    )
    print(
        f"success rate {result.success_rate:.3f} (95% CI {result.ci_low:.3f}-{result.ci_high:.3f}, "
        f"{result.successes}/{result.episodes} episodes); mean return {result.mean_return:.2f} ± {result.std_return:.2f}"
    )
    if args.json:
        Path(args.json).write_text(json.dumps(result.as_dict(), indent=2))
    if args.video:
        print(f"wrote {args.video}")
    return 0


def cmd_bench(args: argparse.Namespace) -> int:
    from .bench import load_grid, run_grid

    grid = load_grid(Path(args.grid))
    out = Path(args.out) if args.out else Path("baselines") / "results" / grid.name
    # Ctrl-C stops the bench cleanly even when it was started with SIGINT ignored.
    signal.signal(signal.SIGINT, signal.default_int_handler)
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
        )
    except KeyboardInterrupt:
        # Runs in progress wrote a checkpoint on the way out; finished runs are in results.
        print(f"bench interrupted; run the same command again to resume (finished runs are kept in {out})")
        return 130
    print(
        f"{summary['finished']}/{summary['runs']} runs finished, {len(summary['failed'])} failed; "
        f"results in {summary['results']}"
    )
    for name in summary["failed"]:
        print(f"failed: {name} (see failures.jsonl)")
    return 0 if not summary["failed"] else 1


def cmd_report(args: argparse.Namespace) -> int:
    from .report import build_report
    from .yamlfile import load_mapping

    results = Path(args.results)
    if not results.is_file():
        raise FileNotFoundError(f"{results} not found; expected a bench's results.csv")
    claims = load_mapping(Path(args.claims), "a mapping of claim labels") if args.claims else None
    out = Path(args.out) if args.out else results.parent / "report"
    path = build_report(results, out, command=shlex.join(["unified-manip", *sys.argv[1:]]),
                        dense_check=not args.no_dense_check, claims=claims)
    print(f"wrote {path}")
    return 0


def _env_kwarg(value: str) -> tuple[str, object]:
    import yaml

    if "=" not in value:
        raise argparse.ArgumentTypeError(f"expected key=value, got {value!r}")
    key, raw = value.split("=", 1)
    try:
        return key, yaml.safe_load(raw)
    except yaml.YAMLError:
        raise argparse.ArgumentTypeError(f"{value!r}: {raw!r} is not a YAML literal") from None


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="unified-manip", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("list", help="table of every registered ID")
    p.add_argument("--doc", choices=list(TASKS), metavar="ID", help="print one task's documentation")
    p.add_argument("--width", type=int, default=200, help="table width in characters")
    p.set_defaults(func=cmd_list)

    p = sub.add_parser("speed", help="env steps/s per ID x action mode, against the raw physics limit")
    p.add_argument("--env", type=_task_ids, help="comma-separated IDs (default: all)")
    p.add_argument("--modes", type=lambda s: s.split(","), help="comma-separated action modes (default: all)")
    p.add_argument("--steps", type=_positive_int, default=2000, help="steps per measurement")
    p.add_argument("--repeats", type=_positive_int, default=3, help="measurements per figure (median)")
    p.add_argument("--no-upstream", action="store_true", help="skip the comparison with wrapped upstream envs")
    p.add_argument("--train", type=_task_ids, help="also time SAC+HER training on these IDs against their upstream envs")
    p.add_argument("--train-steps", type=_positive_int, default=1500, help="training steps per timed round")
    p.add_argument("--json", help="also write the results to this JSON file")
    p.add_argument("--width", type=int, default=200)
    p.set_defaults(func=cmd_speed)

    from .config import ACTION_MODES
    from .hyperparams import ALGOS

    p = sub.add_parser("train", help="train a Stable-Baselines3 baseline on one task")
    p.add_argument("--env", required=True, choices=list(TASKS), metavar="ID", help="registered task ID")
    p.add_argument("--action-mode", default="native", choices=ACTION_MODES)
    p.add_argument("--reward-type", default="sparse", choices=REWARD_TYPES)
    p.add_argument("--algo", required=True, choices=list(ALGOS))
    p.add_argument("--steps", type=_positive_int, required=True, help="total environment steps")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--n-envs", type=_positive_int, help="parallel envs (see --vec; default: the hyperparameter file's n_envs, else 1)")
    p.add_argument("--vec", choices=VEC_KINDS, default="auto",
                   help="how the envs are stepped: native (the native vector env, on threads), dummy, subproc, or auto: "
                        "native where the ID has one and --n-envs > 1, else dummy for one env and subproc for more")
    p.add_argument("--run-dir", help="run directory (default: runs/<task>__<mode>__<reward>__<algo>__s<seed>)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a hyperparameter (repeatable)")
    p.add_argument("--env-kwarg", action="append", type=_env_kwarg, metavar="KEY=VALUE", help="extra env keyword argument")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--device", choices=DEVICES, help="auto (CUDA when torch sees a GPU), cpu or cuda; default: the hyperparameter file's device key, else auto")
    p.add_argument("--restart", action="store_true", help="start the run over from step 0 (discards its checkpoints, logs and models)")
    p.set_defaults(func=cmd_train)

    p = sub.add_parser("eval", help="evaluate a trained run: success rate with a 95%% CI, mean return, video")
    p.add_argument("target", help="run directory, or a model .zip inside one")
    p.add_argument("--episodes", type=_positive_int, default=50)
    p.add_argument("--action-mode", choices=ACTION_MODES, help="default: the run's own (a different one is an error)")
    p.add_argument("--reward-type", choices=REWARD_TYPES, help="default: the run's own")
    p.add_argument("--seed", type=int, default=123, help="episode k is reset with seed + k")
    p.add_argument("--video", help="write the first episodes to this .mp4 or .gif")
    p.add_argument("--json", help="also write the result to this JSON file")
    p.add_argument("--device", choices=DEVICES, default="auto", help="auto (CUDA when torch sees a GPU), cpu or cuda")
    p.set_defaults(func=cmd_eval)

    p = sub.add_parser("bench", help="run a grid of training runs (resumable)")
    p.add_argument("grid", help="grid YAML file, e.g. baselines/grids/action_spaces.yaml")
    p.add_argument("--out", help="bench directory (default: baselines/results/<grid name>)")
    p.add_argument("--executor", choices=("local", "ray"), default="local")
    p.add_argument("--address", help="Ray cluster address (with --executor ray); default: start a local Ray")
    p.add_argument("--workers", type=_positive_int, help="runs at a time (default: CPU cores)")
    p.add_argument("--retries", type=int, default=1, help="retries of a crashed run")
    p.add_argument("--device", choices=DEVICES, help="device of every run: auto, cpu or cuda (default: each hyperparameter file's device key, else auto)")
    p.add_argument("--only", action="append", metavar="KEY=VALUE",
                   help="train only the runs matching this (task, action_mode, reward_type, algo or seed; repeatable: "
                        "values of one key are alternatives, keys must all match); results keep every finished run")
    p.add_argument("--no-progress", action="store_true")
    p.set_defaults(func=cmd_bench)

    p = sub.add_parser("report", help="Markdown + PNG report from a bench's results.csv")
    p.add_argument("results", help="results.csv written by unified-manip bench")
    p.add_argument("--out", help="output directory (default: <results dir>/report)")
    p.add_argument("--claims", help="YAML of claimed results to set beside the measured ones")
    p.add_argument("--no-dense-check", action="store_true", help="skip the dense-reward sanity check")
    p.set_defaults(func=cmd_report)

    p = sub.add_parser("demo", help="roll out each task's scripted policy and write a picture strip")
    p.add_argument("--out", default="demo.png", help="output PNG")
    p.add_argument("--env", type=_task_ids, help="comma-separated IDs (default: all with a scripted policy)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--frames", type=_positive_int, default=6, help="pictures per task")
    p.add_argument("--size", type=_positive_int, default=200, help="picture size in pixels")
    p.set_defaults(func=cmd_demo)
    return parser


def _positive_int(value: str) -> int:
    try:
        n = int(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value!r}") from None
    if n <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value!r}")
    return n


def main(argv: list[str] | None = None) -> int:
    from .bench import GridError, ResultsError
    from .hyperparams import HyperparameterError
    from .runlock import DirectoryInUse
    from .train import TrainError
    from .yamlfile import YamlFileError

    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except (TrainError, HyperparameterError, GridError, ResultsError, YamlFileError, DirectoryInUse, FileNotFoundError) as err:
        parser.exit(2, f"unified-manip {args.command}: error: {err}\n")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
