"""Throughput of the native vector env against the alternatives, and its physics limit.

Run it as ``python -m benchmarks.vector_bench`` (``--help`` for the options). For
each action mode and number of envs N, every kind of vector env plays the same random
actions (env steps per second over all N envs; autoresets included, as in training):

=============  ================================================================
kind           what
=============  ================================================================
native         ``gym.make_vec`` (the native vector env, ``num_threads`` threads)
native-sb3     the same through the Stable-Baselines3 adapter (what ``train`` uses)
sync           Gymnasium's ``SyncVectorEnv`` over ``gym.make``
async          Gymnasium's ``AsyncVectorEnv`` (one process per env, forked)
subproc        SB3's ``SubprocVecEnv`` (one process per env, forked)
dummy          SB3's ``DummyVecEnv``
=============  ================================================================

The raw physics limit is measured in the same run: the single-thread rate of the
backend's ``physics_step`` (``mj_step``, the 10 substeps of one env step, nothing
else) on the states a random-action episode visits (``python -m benchmarks.speed``'s method),
times the number of threads. ``--physics`` adds a table of the physics alone on N
simulations: the thread pool against ``mujoco.rollout``'s persistent pool.
Kinds are measured in turn within each round (the order rotates) and each figure is
the median over rounds, so that load changes reach every kind alike. Compare ratios
within one run, not absolute rates across runs.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from typing import Any, Callable

import gymnasium as gym
import numpy as np

from benchmarks.parser import ToolParser

KINDS = ("native", "native-sb3", "sync", "async", "subproc", "dummy")


def _make(kind: str, task_id: str, mode: str, n: int, threads: int):
    """``(env, step)``: a vector env of ``kind`` and a function playing one batch of actions."""
    kwargs = dict(action_mode=mode, reward_type="dense")
    if kind in ("native", "sync", "async"):
        mode_name = {"native": "vector_entry_point", "sync": "sync", "async": "async"}[kind]
        extra: dict[str, Any] = {"num_threads": threads} if kind == "native" else {}
        vector_kwargs = {"context": "fork"} if kind == "async" else None
        env = gym.make_vec(
            task_id, num_envs=n, vectorization_mode=mode_name, vector_kwargs=vector_kwargs, **kwargs, **extra
        )
        env.reset(seed=0)
        return env, env.step
    if kind == "native-sb3":
        from gymnasium.vector import AutoresetMode

        from unified_manip.envs.vector.factory import make_vector_env
        from unified_manip.training.sb3_vec_env import NativeSB3VecEnv

        spec = gym.spec(task_id)
        env = NativeSB3VecEnv(
            make_vector_env(n, task_id, spec.max_episode_steps, AutoresetMode.SAME_STEP, threads, **kwargs)
        )
    else:
        from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

        fns = [lambda: gym.make(task_id, **kwargs)] * n
        env = SubprocVecEnv(fns, start_method="fork") if kind == "subproc" else DummyVecEnv(fns)
    env.seed(0)
    env.reset()
    return env, env.step


def vector_rate(kind: str, task_id: str, mode: str, n: int, threads: int, steps: int) -> float:
    """Env steps per second of ``kind`` with ``n`` envs over about ``steps`` env steps."""
    env, step = _make(kind, task_id, mode, n, threads)
    try:
        batches = max(steps // n, 20)
        rng = np.random.default_rng(0)
        actions = rng.uniform(-1, 1, (batches + 10, n, _action_dim(env))).astype(np.float32)
        for a in actions[:10]:  # warm-up
            step(a)
        start = time.perf_counter()
        for a in actions[10:]:
            step(a)
        return batches * n / (time.perf_counter() - start)
    finally:
        env.close()


def _action_dim(env) -> int:
    space = getattr(env, "single_action_space", None) or env.action_space
    return space.shape[-1]


def raw_rate(task_id: str, mode: str, steps: int) -> float:
    """Single-thread env steps per second of the physics alone (:func:`benchmarks.speed.measure`)."""
    from benchmarks.speed import measure

    return measure(task_id, mode, steps=steps).raw_steps_per_s


def physics_rates(task_id: str, mode: str, n: int, threads: int, steps: int) -> dict[str, float]:
    """Env steps per second of the physics alone on ``n`` simulations: the thread pool
    (``mj_step`` per env) against ``mujoco.rollout`` with a persistent pool of as many
    threads, from the states of one seeded reset each, with random controls."""
    import mujoco
    from mujoco import rollout

    from unified_manip.envs.setup import env_setup
    from unified_manip.envs.vector.pool import PhysicsPool

    setup = env_setup(task_id, action_mode=mode)
    backends = [setup.build_backend() for _ in range(n)]
    for i, b in enumerate(backends):
        b.reset(np.random.default_rng(i))
    models, datas = [b.model for b in backends], [b.data for b in backends]
    batches = max(steps // n, 20)
    nu = models[0].nu
    ctrl = np.random.default_rng(0).uniform(-0.3, 0.3, (batches, n, 1, nu))
    full = int(mujoco.mjtState.mjSTATE_FULLPHYSICS)
    state = np.zeros((n, mujoco.mj_stateSize(models[0], full)))
    for i in range(n):
        mujoco.mj_getState(models[i], datas[i], state[i], full)
    nstep = int(round(backends[0].dt / models[0].opt.timestep))
    pool = PhysicsPool(threads)
    k = [0]

    def one(i: int) -> None:
        datas[i].ctrl[:] = ctrl[k[0], i, 0]
        mujoco.mj_step(models[i], datas[i], nstep=nstep)

    start = time.perf_counter()
    for k[0] in range(batches):
        pool.run(one, range(n))
    pool_rate = batches * n / (time.perf_counter() - start)
    pool.shutdown()
    scratch = [mujoco.MjData(models[0]) for _ in range(threads)]
    with rollout.Rollout(nthread=threads if threads > 1 else 0) as r:
        start = time.perf_counter()
        for j in range(batches):
            out, _ = r.rollout(models, scratch, state, ctrl[j], nstep=nstep)
            state = out[:, -1]
        rollout_rate = batches * n / (time.perf_counter() - start)
    return {"thread pool": pool_rate, "mujoco.rollout": rollout_rate}


def run(
    task_id: str,
    modes,
    sizes,
    kinds,
    threads,
    steps: int,
    rounds: int,
    physics: bool,
    progress: Callable[[str], None] = lambda s: None,
) -> list[dict[str, Any]]:
    """Every mode x N x thread count x kind, plus the raw limit per mode: result rows.

    ``threads`` is a list of thread counts of the native env (the other kinds do not use
    threads; they are measured again beside each count)."""
    rows = []
    for mode in modes:
        raw = statistics.median(raw_rate(task_id, mode, steps) for _ in range(rounds))
        progress(f"{mode}: raw physics {raw:,.0f} env steps/s on one thread")
        for n in sizes:
            for t in threads:
                samples: dict[str, list[float]] = {k: [] for k in kinds}
                for r in range(rounds):
                    order = kinds[r % len(kinds) :] + kinds[: r % len(kinds)]
                    for kind in order:
                        samples[kind].append(vector_rate(kind, task_id, mode, n, t, steps))
                rates = {k: statistics.median(v) for k, v in samples.items()}
                row = {
                    "task": task_id,
                    "mode": mode,
                    "num_envs": n,
                    "threads": t,
                    "raw_one_thread": raw,
                    "raw_limit": raw * t,
                    **rates,
                }
                if physics:
                    row["physics"] = physics_rates(task_id, mode, n, t, steps)
                rows.append(row)
                progress(f"{mode} N={n} threads={t}: " + ", ".join(f"{k} {v:,.0f}" for k, v in rates.items()))
    return rows


def table(rows: list[dict[str, Any]]) -> str:
    """The results as a Markdown table (env steps/s, and the native env's ratios)."""
    kinds = [k for k in KINDS if k in rows[0]]
    head = ["mode", "N", "threads", *kinds]
    ratios = [(f"native / {k}", k) for k in ("sync", "subproc") if k in kinds and "native" in kinds]
    head += [name for name, _ in ratios] + (["native / raw limit"] if "native" in kinds else [])
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for row in rows:
        cells = [row["mode"], str(row["num_envs"]), str(row["threads"]), *(f"{row[k]:,.0f}" for k in kinds)]
        cells += [f"{row['native'] / row[k]:.2f}" for _, k in ratios]
        if "native" in kinds:
            cells.append(f"{row['native'] / row['raw_limit']:.2f}")
        lines.append("| " + " | ".join(cells) + " |")
    lines.append("")
    lines.append(
        "Raw limit = threads x the single-thread physics rate: "
        + ", ".join(sorted({f"{r['mode']} {r['raw_one_thread']:,.0f}/s" for r in rows}))
        + "."
    )
    if "physics" in rows[0]:
        lines += [
            "",
            "| mode | N | threads | physics: thread pool | mujoco.rollout | pool / rollout |",
            "|---|---|---|---|---|---|",
        ]
        for row in rows:
            p = row["physics"]
            lines.append(
                f"| {row['mode']} | {row['num_envs']} | {row['threads']} | {p['thread pool']:,.0f} | {p['mujoco.rollout']:,.0f} | "
                f"{p['thread pool'] / p['mujoco.rollout']:.2f} |"
            )
    return "\n".join(lines)


def _csv(kind: Callable[[str], Any]) -> Callable[[str], list]:
    def parse(text: str) -> list:
        try:
            return [kind(x) for x in text.split(",") if x]
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    return parse


def main(argv: list[str] | None = None) -> int:
    from unified_manip.envs.vector.pool import default_num_threads

    p = ToolParser("benchmarks.vector_bench", __doc__)
    p.add_argument("--env", default="UnifiedManip/Arm4PickAndPlace-v0", help="task ID")
    p.add_argument(
        "--modes", type=_csv(str), default=["joint_position", "ee_delta"], help="comma-separated action modes"
    )
    p.add_argument("--num-envs", type=_csv(int), default=[1, 2, 4, 8, 16, 32], help="comma-separated N")
    p.add_argument("--kinds", type=_csv(str), default=list(KINDS), help=f"comma-separated, from {','.join(KINDS)}")
    p.add_argument(
        "--threads",
        type=_csv(int),
        default=[default_num_threads()],
        help="comma-separated thread counts of the native env (default: the usable cores); several give the scaling",
    )
    p.add_argument("--steps", type=int, default=3000, help="env steps per measurement (over all N envs)")
    p.add_argument("--rounds", type=int, default=3, help="measurements per figure (the median is reported)")
    p.add_argument(
        "--physics", action="store_true", help="also time the physics alone: thread pool against mujoco.rollout"
    )
    p.add_argument("--json", help="also write the rows to this JSON file")
    args = p.parse_args(argv)
    import unified_manip

    bad = [k for k in args.kinds if k not in KINDS]
    problems = []
    if args.env not in unified_manip.TASKS:
        problems.append(f"unknown task {args.env!r}; expected one of {', '.join(unified_manip.TASKS)}")
    elif any(m not in unified_manip.TASKS[args.env].action_modes for m in args.modes):
        problems.append(
            f"--modes must be from {', '.join(unified_manip.TASKS[args.env].action_modes)}, got {','.join(args.modes)}"
        )
    if bad:
        problems.append(f"unknown kinds {bad}; expected from {', '.join(KINDS)}")
    if min(args.num_envs, default=0) < 1 or min(args.threads, default=0) < 1 or args.steps < 1 or args.rounds < 1:
        problems.append("--num-envs, --threads, --steps and --rounds must be positive")
    if problems:
        print(f"error: {problems[0]}", file=sys.stderr)
        return 2
    rows = run(
        args.env,
        args.modes,
        args.num_envs,
        list(args.kinds),
        args.threads,
        args.steps,
        args.rounds,
        args.physics,
        progress=lambda s: print(s, file=sys.stderr, flush=True),
    )
    print(table(rows))
    if args.json:  # written whole or not at all
        tmp = f"{args.json}.tmp"
        with open(tmp, "w") as f:
            json.dump(rows, f, indent=2)
        os.replace(tmp, args.json)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
