"""The tasks' scripted ``ee_delta`` policies under a randomisation preset: success rates.

Run from the repository root (not part of the wheel):

    python benchmarks/scripted_success.py --randomization objects --episodes 20

Episode ``k`` is reset with seed ``k``; success is ``is_success`` on the last step, as
``unified-manip collect`` counts it. Tasks the preset has no term for, and tasks without
a scripted policy, are left out. Writes ``benchmarks/out/scripted_<preset>.json``.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path


def success_rate(task_id: str, randomization: str, episodes: int) -> float | None:
    import gymnasium as gym

    from unified_manip.datasets.policies import scripted

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            env = gym.make(task_id, action_mode="ee_delta", randomization=randomization)
        except ValueError:  # no term of the preset applies to this task
            return None
    try:
        policy = scripted(env)
        wins = 0
        for seed in range(episodes):
            obs, info = env.reset(seed=seed)
            done = False
            while not done:
                obs, _, terminated, truncated, info = env.step(policy(obs))
                done = terminated or truncated
            wins += info["is_success"] > 0.5
        return wins / episodes
    finally:
        env.close()


def main(argv: list[str] | None = None) -> int:
    import unified_manip  # noqa: F401  (registers the IDs)
    from unified_manip.envs.registry import TASKS

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--randomization", default="objects")
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument("--task", action="append", help="only these IDs")
    parser.add_argument("--out", type=Path)
    args = parser.parse_args(argv)
    ids = args.task or [i for i, s in TASKS.items() if s.scripted_policy is not None and "ee_delta" in s.action_modes]
    rows = {}
    for task_id in ids:
        for preset in ("none", args.randomization):
            rate = success_rate(task_id, preset, args.episodes)
            if rate is None:
                break
            rows.setdefault(task_id, {})[preset] = rate
            print(task_id, preset, rate, flush=True)
        else:
            continue
        rows.pop(task_id, None)
    out = args.out or Path(f"benchmarks/out/scripted_{args.randomization.replace(':', '_')}.json")
    result = {
        "command": "python benchmarks/scripted_success.py " + " ".join(argv if argv is not None else sys.argv[1:]),
        "episodes": args.episodes,
        "seeds": f"0..{args.episodes - 1}",
        "success": rows,
    }
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".partial")
    tmp.write_text(json.dumps(result, indent=2) + "\n")
    tmp.replace(out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
