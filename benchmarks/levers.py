"""Training-throughput levers measured side by side: ``python -m benchmarks.levers``.

Each *lever* is one training setting: an algorithm key, ``--set`` overrides and a number
of envs (stepped in one process, so every setting gets the same single core). The
levers are timed in interleaved rounds, one after another in every round, so a change of
machine load touches them all alike; the figure is the median over rounds of training
env steps per second, after a warm-up that fills the buffer past ``learning_starts``.

Wall time to a success rate comes from full learning runs (``unified-manip bench``),
not from here; ``docs/training_speed.md`` puts both side by side.
"""

from __future__ import annotations

import json
import statistics
import time
from dataclasses import asdict, dataclass
from pathlib import Path

from benchmarks.parser import ToolParser


@dataclass(frozen=True)
class Lever:
    """One training setting.

    Attributes:
        name: Short label used in tables.
        algo: Algorithm key (``sac_her``, ``tqc_her``, ``crossq_her``, ...).
        overrides: ``key=value`` hyperparameter overrides on top of the task's entry.
        n_envs: Envs stepped together (a ``DummyVecEnv``: one process, one core).
        source: Where the setting comes from.
    """

    name: str
    algo: str
    overrides: tuple[str, ...] = ()
    n_envs: int = 1
    source: str = ""


_NET3 = "policy_kwargs.net_arch=[256, 256, 256]"
_HER_PAPER = ("batch_size=256", "tau=0.05", "gamma=0.98", _NET3)

#: The settings compared in docs/training_speed.md.
LEVERS: tuple[Lever, ...] = (
    Lever("zoo", "tqc_her", (), 1, "rl-baselines3-zoo tqc.yml FetchPush: batch 2048, [512]*3, 1 update/step"),
    Lever(
        "sac-256x2",
        "sac_her",
        ("batch_size=256", "policy_kwargs.net_arch=[256, 256]"),
        1,
        "SB3 SAC defaults: batch 256, [256, 256], 1 update/step",
    ),
    Lever(
        "her-paper",
        "sac_her",
        (*_HER_PAPER, "train_freq=100", "gradient_steps=40"),
        1,
        "HER paper: 40 updates of batch 256 per 2 episodes (0.4/step), [256]*3",
    ),
    Lever(
        "her-paper-2env",
        "sac_her",
        (*_HER_PAPER, "train_freq=50", "gradient_steps=40"),
        2,
        "as her-paper with 2 envs collecting together",
    ),
    Lever(
        "her-paper-0.2",
        "sac_her",
        (*_HER_PAPER, "train_freq=100", "gradient_steps=20"),
        1,
        "half the HER paper's updates (0.2/step)",
    ),
    Lever(
        "her-paper-b512",
        "sac_her",
        ("batch_size=512", "tau=0.05", "gamma=0.98", _NET3, "train_freq=100", "gradient_steps=20"),
        1,
        "0.2 updates/step of batch 512: the same samples per step as her-paper",
    ),
    Lever(
        "tqc-8env",
        "tqc_her",
        ("batch_size=512", "tau=0.05", "policy_kwargs.net_arch=[256, 256, 256]", "train_freq=1", "gradient_steps=2"),
        8,
        "TQC, 8 envs, 2 updates per 8 env steps, batch 512 (issue 10's early-learning runs)",
    ),
    Lever(
        "tqc-her-paper",
        "tqc_her",
        (
            "batch_size=256",
            "tau=0.05",
            "gamma=0.98",
            "policy_kwargs.net_arch=[256, 256, 256]",
            "train_freq=100",
            "gradient_steps=40",
        ),
        1,
        "TQC on the HER paper schedule",
    ),
    Lever("crossq", "crossq_her", (), 1, "sb3-contrib CrossQ defaults (pi [256,256], qf [1024,1024], 1 update/step)"),
    Lever(
        "crossq-0.4",
        "crossq_her",
        ("train_freq=100", "gradient_steps=40", "gamma=0.98"),
        1,
        "CrossQ on the HER paper schedule",
    ),
)


@dataclass(frozen=True)
class LeverRate:
    lever: Lever
    steps_per_s: float
    rounds: list[float]

    def as_dict(self) -> dict:
        return {**asdict(self.lever), "steps_per_s": self.steps_per_s, "rounds": self.rounds}


def _model(lever: Lever, task_id: str, action_mode: str, seed: int, warmup: int, device: str):
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import DummyVecEnv

    from unified_manip.training.algorithms import get_algo
    from unified_manip.training.hyperparams import resolve_run
    from unified_manip.training.run_envs import model_kwargs as _model_kwargs
    from unified_manip.training.run_envs import normalized as _normalized

    algo = get_algo(lever.algo)
    resolved = resolve_run(lever.algo, task_id, lever.overrides + (f"learning_starts={warmup}", "buffer_size=100000"))
    run, kwargs = resolved.run, resolved.algo_kwargs
    env = make_vec_env(
        task_id,
        n_envs=lever.n_envs,
        seed=seed,
        vec_env_cls=DummyVecEnv,
        env_kwargs={"action_mode": action_mode, "reward_type": "sparse"},
    )
    env = _normalized(env, run, None, training=True, gamma=float(kwargs.get("gamma", 0.99)))
    return algo.cls()(
        env=env,
        seed=seed,
        device=device,
        verbose=0,
        **_model_kwargs(lever.algo, kwargs, run, env),
    )


def measure(
    task_id: str,
    action_mode: str,
    levers: tuple[Lever, ...] = LEVERS,
    seconds: float = 30.0,
    rounds: int = 3,
    warmup: int = 1000,
    seed: int = 0,
    device: str = "cpu",
    log=print,
) -> list[LeverRate]:
    """Median training steps/s of each lever over ``rounds`` interleaved rounds.

    A round of a lever trains in chunks of 100 env steps (a whole update cycle of the
    HER-paper settings) until ``seconds`` have passed, at least one chunk."""
    import torch

    import unified_manip  # noqa: F401  (registers the IDs)

    torch.set_num_threads(1)
    from unified_manip.training.devices import resolve_device

    device = resolve_device(device)
    models = {lever.name: _model(lever, task_id, action_mode, seed, warmup, device) for lever in levers}
    for lever in levers:  # fill past learning_starts, and pay one-time costs
        models[lever.name].learn(total_timesteps=warmup + 200, reset_num_timesteps=False)
    rates: dict[str, list[float]] = {lever.name: [] for lever in levers}
    for r in range(rounds):
        for lever in levers:
            model = models[lever.name]
            start, before = time.perf_counter(), model.num_timesteps
            while True:
                model.learn(total_timesteps=100, reset_num_timesteps=False)
                if time.perf_counter() - start >= seconds:
                    break
            rates[lever.name].append((model.num_timesteps - before) / (time.perf_counter() - start))
            log(f"round {r + 1}/{rounds} {lever.name}: {rates[lever.name][-1]:.1f} steps/s")
    return [LeverRate(lever, statistics.median(rates[lever.name]), rates[lever.name]) for lever in levers]


def main(argv: list[str] | None = None) -> int:
    parser = ToolParser("benchmarks.levers", __doc__)
    parser.add_argument("--env", default="UnifiedManip/FetchPush-v0")
    parser.add_argument("--action-mode", default="native")
    parser.add_argument("--levers", help="comma-separated lever names (default: all)")
    parser.add_argument("--seconds", type=float, default=30.0, help="training time per lever per round")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--device", default="cpu", choices=("auto", "cpu", "cuda"))
    parser.add_argument("--json", help="write the results here")
    args = parser.parse_args(argv)
    chosen = LEVERS
    if args.levers:
        names = args.levers.split(",")
        unknown = [n for n in names if n not in {lv.name for lv in LEVERS}]
        if unknown:
            parser.error(f"unknown lever {unknown[0]!r}; expected one of {', '.join(lv.name for lv in LEVERS)}")
        chosen = tuple(lv for lv in LEVERS if lv.name in names)
    results = measure(args.env, args.action_mode, chosen, seconds=args.seconds, rounds=args.rounds, device=args.device)
    for r in results:
        print(f"{r.lever.name:>16}  {r.steps_per_s:7.1f} steps/s   {r.lever.source}")
    if args.json:
        doc = {
            "env": args.env,
            "action_mode": args.action_mode,
            "device": args.device,
            "seconds": args.seconds,
            "rounds": args.rounds,
            "levers": [r.as_dict() for r in results],
        }
        Path(args.json).write_text(json.dumps(doc, indent=2))
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
