"""The cost of one gradient update of the recipe, and levers that keep the algorithm:
``python -m benchmarks.update_speed``.

The recipe (``baselines/tqc_her.yaml``, the 8-env CPU entry) spends about 80% of its
training time in TQC's update. This times SB3's *real* update, ``model.train``, on a
replay buffer filled by the recipe's own envs, with each lever switched on and off on the
same model (same weights, same buffer):

* ``fused``: Adam's fused CPU kernel (``optimizer_kwargs={"fused": True}``);
* ``compile``: ``torch.compile`` of the actor's and critics' forward passes (the
  modules, their parameters and their ``state_dict`` stay as they are);
* ``quantile``: ``torch.compile`` of sb3-contrib's quantile Huber loss;
* ``all``: the three together.

Variants run in interleaved rounds (every variant once per round), so a change of load
on the machine touches them alike; the figure is the median over rounds of milliseconds
per update, and each variant's ratio to ``baseline`` in the same run. Whether a lever
also *learns* the same is a question for full runs (``unified-manip bench``), not this.
"""

from __future__ import annotations

import contextlib
import json
import statistics
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Iterator

from benchmarks.parser import ToolParser

#: The levers, each a set of switches; ``baseline`` is SB3's update as it ships.
VARIANTS: dict[str, tuple[str, ...]] = {
    "baseline": (),
    "fused": ("fused",),
    "compile": ("compile",),
    "quantile": ("quantile",),
    "all": ("fused", "compile", "quantile"),
}


@dataclass(frozen=True)
class UpdateTime:
    """One variant's update time: median over rounds, and its ratio to ``baseline``."""

    variant: str
    ms_per_update: float
    speedup: float
    rounds: tuple[float, ...]


def build_model(task_id: str, n_envs: int, warmup: int, seed: int):
    """The recipe's TQC+HER model on ``task_id``, its buffer filled by ``warmup`` env steps
    of random actions (no update is done: ``learning_starts`` is past the warm-up)."""
    from unified_manip.training.hyperparams import resolve
    from unified_manip.training.run_envs import make_vec_env

    sets = ("batch_size=512", "tau=0.05", "train_freq=1", "gradient_steps=2", "policy_kwargs.net_arch=[256, 256, 256]")
    params = resolve("tqc_her", task_id, sets + (f"learning_starts={warmup * 10}", "buffer_size=100000"))
    from sb3_contrib import TQC
    from stable_baselines3 import HerReplayBuffer

    env = make_vec_env(task_id, {"action_mode": "ee_delta", "reward_type": "sparse"}, n_envs, seed, None)
    model = TQC(
        "MultiInputPolicy",
        env,
        learning_rate=params["learning_rate"],
        buffer_size=params["buffer_size"],
        batch_size=params["batch_size"],
        tau=params["tau"],
        gamma=params["gamma"],
        learning_starts=params["learning_starts"],
        replay_buffer_class=HerReplayBuffer,
        replay_buffer_kwargs=params["replay_buffer_kwargs"],
        policy_kwargs=params["policy_kwargs"],
        device="cpu",
        seed=seed,
    )
    model.learn(warmup)
    return model


def _optimizers(model) -> list[Any]:
    opts = [model.actor.optimizer, model.critic.optimizer]
    if getattr(model, "ent_coef_optimizer", None) is not None:
        opts.append(model.ent_coef_optimizer)
    return opts


@contextlib.contextmanager
def switched(model, switches: tuple[str, ...], compiled: dict[str, Any]) -> Iterator[None]:
    """The model with ``switches`` on for the duration; everything restored after."""
    import sb3_contrib.tqc.tqc as tqc_module

    original_loss = tqc_module.quantile_huber_loss
    try:
        if "fused" in switches:
            for opt in _optimizers(model):
                for group in opt.param_groups:
                    group["fused"] = True
        if "compile" in switches:
            for name in ("actor", "critic", "critic_target"):
                module = getattr(model, name)
                module.forward = compiled[name]
            model.actor.action_log_prob = compiled["action_log_prob"]
        if "quantile" in switches:
            tqc_module.quantile_huber_loss = compiled["quantile"]
        yield
    finally:
        for opt in _optimizers(model):
            for group in opt.param_groups:
                group["fused"] = None
        for name in ("actor", "critic", "critic_target"):
            vars(getattr(model, name)).pop("forward", None)
        vars(model.actor).pop("action_log_prob", None)
        tqc_module.quantile_huber_loss = original_loss


def compiled_functions(model) -> dict[str, Any]:
    """``torch.compile`` of the forward passes and of the quantile loss (built lazily by
    torch on their first call)."""
    import sb3_contrib.tqc.tqc as tqc_module
    import torch

    out = {name: torch.compile(getattr(model, name).forward) for name in ("actor", "critic", "critic_target")}
    out["action_log_prob"] = torch.compile(model.actor.action_log_prob)
    out["quantile"] = torch.compile(tqc_module.quantile_huber_loss)
    return out


def measure(
    task_id: str = "UnifiedManip/FetchPickAndPlace-v0",
    variants: tuple[str, ...] = tuple(VARIANTS),
    rounds: int = 5,
    updates: int = 40,
    warmup: int = 2000,
    n_envs: int = 8,
    seed: int = 0,
    log=print,
) -> list[UpdateTime]:
    """Median milliseconds per ``model.train`` gradient step of each variant, in
    interleaved rounds of ``updates`` steps each, after one untimed round (compilation)."""
    import torch

    unknown = [v for v in variants if v not in VARIANTS]
    if unknown:
        raise ValueError(f"unknown variant {unknown[0]!r}; expected one of {', '.join(VARIANTS)}")
    if "baseline" not in variants:
        variants = ("baseline", *variants)
    model = build_model(task_id, n_envs, warmup, seed)
    compiled = compiled_functions(model)
    times: dict[str, list[float]] = {v: [] for v in variants}
    for r in range(rounds + 1):
        for v in variants:
            with switched(model, VARIANTS[v], compiled):
                start = time.perf_counter()
                model.train(gradient_steps=updates, batch_size=model.batch_size)
                elapsed = (time.perf_counter() - start) / updates * 1000
            if r:  # round 0 compiles and warms the caches
                times[v].append(elapsed)
        if r:
            log(f"round {r}: " + ", ".join(f"{v} {times[v][-1]:.1f} ms" for v in variants))
    base = statistics.median(times["baseline"])
    log(f"torch {torch.__version__}, {torch.get_num_threads()} thread(s)")
    return [
        UpdateTime(v, statistics.median(t), base / statistics.median(t), tuple(round(x, 2) for x in t))
        for v, t in times.items()
    ]


def main(argv: list[str] | None = None) -> None:
    parser = ToolParser("benchmarks.update_speed", __doc__)
    parser.add_argument("--env", default="UnifiedManip/FetchPickAndPlace-v0")
    parser.add_argument("--variants", default=",".join(VARIANTS), help="comma-separated, from " + ", ".join(VARIANTS))
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--updates", type=int, default=40, help="gradient steps per timed round")
    parser.add_argument("--warmup", type=int, default=2000, help="env steps that fill the buffer")
    parser.add_argument("--json", help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    import torch

    torch.set_num_threads(1)
    rows = measure(args.env, tuple(args.variants.split(",")), args.rounds, args.updates, args.warmup)
    for row in rows:
        print(f"{row.variant:>9}: {row.ms_per_update:6.1f} ms per update  x{row.speedup:.2f}")
    if args.json:
        Path(args.json).write_text(json.dumps({"env": args.env, "rows": [asdict(r) for r in rows]}, indent=2))


if __name__ == "__main__":
    main()
