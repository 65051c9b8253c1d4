"""The subcommands of ``unified-manip`` for one run: ``train`` and ``eval``, each with its
arguments beside it (grids of runs: :mod:`.grids`)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from unified_manip.cli.args import add_test_distribution, env_kwarg, positive_int, randomization_preset, task_id
from unified_manip.cli.output import write_json
from unified_manip.envs.config import ACTION_MODES
from unified_manip.envs.design_names import parse_observation
from unified_manip.envs.rewards import REWARD_TYPES
from unified_manip.envs.vector.factory import VEC_KINDS
from unified_manip.training.algorithms import ALGOS
from unified_manip.training.devices import DEVICES


def add_commands(sub) -> None:
    """Add ``train`` and ``eval`` to the subparsers ``sub``."""
    p = sub.add_parser("train", help="train a Stable-Baselines3 baseline on one task")
    p.add_argument("--env", required=True, type=task_id, metavar="ID", help="registered task ID")
    p.add_argument("--action-mode", default="native", choices=ACTION_MODES, help="how actions drive the robot")
    p.add_argument("--reward-type", default="sparse", choices=REWARD_TYPES, help="the reward design")
    p.add_argument(
        "--algo", required=True, choices=list(ALGOS), help="algorithm; its defaults come from baselines/<algo>.yaml"
    )
    p.add_argument("--steps", type=positive_int, required=True, help="total environment steps")
    p.add_argument("--seed", type=int, default=0, help="seed of the run: networks, exploration and env resets")
    p.add_argument(
        "--n-envs",
        type=positive_int,
        help="parallel envs (see --vec; default: the hyperparameter file's n_envs, else 1)",
    )
    p.add_argument(
        "--vec",
        choices=VEC_KINDS,
        default="auto",
        help="how the envs are stepped: native (the native vector env, on threads), dummy, subproc, or auto: "
        "native where the ID has one and --n-envs > 1, else dummy for one env and subproc for more",
    )
    p.add_argument("--run-dir", help="run directory (default: runs/<task>__<mode>__<reward>__<algo>__s<seed>)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a hyperparameter (repeatable)")
    p.add_argument(
        "--demonstrations",
        metavar="DATASET",
        help="a dataset (unified-manip collect or convert) for the replay buffer, or to clone with --algo bc "
        "(the same as --set demonstrations=DATASET)",
    )
    p.add_argument(
        "--env-kwarg",
        action="append",
        type=env_kwarg,
        metavar="KEY=VALUE",
        help="extra env keyword argument, a YAML value (repeatable), e.g. controller_options={band: 0.75}",
    )
    p.add_argument(
        "--observation",
        type=parse_observation,
        help="observation design: a preset (default, minimal, relative, full) or groups separated by commas "
        "(see unified-manip list --doc ID); a non-default design is part of the default run directory's name",
    )
    p.add_argument(
        "--randomization",
        type=randomization_preset,
        metavar="PRESET",
        help="domain randomisation of the training envs (the training distribution): none (the nominal task, "
        "the default), dynamics, objects, visual or all, joined by '+' (dynamics+objects); recorded in "
        "config.yaml's env_kwargs and, unless none, part of the default run directory's name",
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument(
        "--device",
        choices=DEVICES,
        help="auto (CUDA when torch sees a GPU), cpu or cuda; default: the hyperparameter file's device key, else auto",
    )
    p.add_argument(
        "--restart",
        action="store_true",
        help="start the run over from step 0 (discards its checkpoints, logs and models)",
    )
    p.set_defaults(func=cmd_train)

    p = sub.add_parser("eval", help="evaluate a trained run: success rate with a 95%% CI, mean return, video")
    p.add_argument("target", help="run directory, or a model .zip inside one")
    p.add_argument("--episodes", type=positive_int, default=50, help="evaluation episodes")
    p.add_argument("--action-mode", choices=ACTION_MODES, help="default: the run's own (a different one is an error)")
    p.add_argument("--reward-type", choices=REWARD_TYPES, help="default: the run's own")
    p.add_argument("--seed", type=int, default=123, help="episode k is reset with seed + k")
    p.add_argument(
        "--observation-noise",
        type=float,
        help="std of Gaussian noise on the observation vector, in its groups' units (robustness; default: the run's)",
    )
    p.add_argument(
        "--observation-delay", type=int, help="observe k steps late (robustness; default: the run's own, usually 0)"
    )
    add_test_distribution(p)
    p.add_argument("--video", help="write the first episodes to this .mp4 or .gif")
    p.add_argument("--json", help="also write the result to this JSON file")
    p.add_argument("--device", choices=DEVICES, default="auto", help="auto (CUDA when torch sees a GPU), cpu or cuda")
    p.set_defaults(func=cmd_eval)


def cmd_train(args: argparse.Namespace) -> int:
    from unified_manip.training.train import TrainRequest, train

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
        overrides=tuple(args.set or ()) + ((f"demonstrations={args.demonstrations}",) if args.demonstrations else ()),
        env_kwargs=_train_env_kwargs(args),
        device=args.device,
        restart=args.restart,
    )
    try:
        train(req, argv=["unified-manip", *sys.argv[1:]], progress=not args.no_progress)
    except KeyboardInterrupt:
        return 130
    return 0


def _train_env_kwargs(args: argparse.Namespace) -> dict:
    """``train``'s env keyword arguments: ``--env-kwarg``, then ``--observation`` and
    ``--randomization`` (``none`` is left out, so a nominal run's config.yaml reads as
    every run's from before randomisation)."""
    kwargs = {**dict(args.env_kwarg or ()), **({"observation": args.observation} if args.observation else {})}
    if args.randomization is not None:
        kwargs.pop("randomization", None)
        if args.randomization != "none":
            kwargs["randomization"] = args.randomization
    return kwargs


def cmd_eval(args: argparse.Namespace) -> int:
    from unified_manip.training.train import evaluate

    result = evaluate(
        Path(args.target),
        args.episodes,
        action_mode=args.action_mode,
        reward_type=args.reward_type,
        seed=args.seed,
        observation_noise=args.observation_noise,
        observation_delay=args.observation_delay,
        video=Path(args.video) if args.video else None,
        device=args.device,
        randomization=args.randomization,
        test_distribution=args.test_distribution,
    )
    world = result.randomization != "none" or result.test_distribution  # the nominal task says nothing more
    shown = f"; randomization {result.randomization}" if world else ""
    shown += f" ({result.test_distribution})" if result.test_distribution else ""
    print(
        f"success rate {result.success_rate:.3f} (95% CI {result.ci_low:.3f}-{result.ci_high:.3f}, "
        f"{result.successes}/{result.episodes} episodes); mean return {result.mean_return:.2f} ± {result.std_return:.2f}"
        f"{shown}"
    )
    if args.json:
        write_json(args.json, result.as_dict())
    if args.video:
        print(f"wrote {args.video}")
    return 0
