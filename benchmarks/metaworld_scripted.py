"""Meta-World's own scripted policies (``metaworld.policies``) on the Meta-World IDs, in
``native``: success per task.

Run from the repository root, with the ``metaworld`` extra (not part of the wheel):

    python benchmarks/metaworld_scripted.py --episodes 5

Episode ``k`` is reset with seed ``k`` and runs the whole 500 steps. Three rates per task:
``last``, ``is_success`` on the last step (what ``unified-manip collect`` counts); ``any``,
``is_success`` on some step (Meta-World's own evaluation counts an episode so); and
``native_any``, Meta-World's own ``success`` on some step. Writes
``benchmarks/out/metaworld_scripted.json``.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

from unified_manip.cli.output import write_json

OUT = Path(__file__).resolve().parent / "out" / "metaworld_scripted.json"


def rates(task_id: str, episodes: int) -> dict[str, float]:
    import gymnasium as gym

    import unified_manip

    env = gym.make(task_id, action_mode="native")
    policy = unified_manip.TASKS[task_id].scripted_policy("native")
    state = env.unwrapped.state_observation
    last = any_ = native_any = 0
    for seed in range(episodes):
        env.reset(seed=seed)
        done, hit, native_hit = False, False, False
        while not done:
            _, _, terminated, truncated, info = env.step(policy(state()))
            hit |= info["is_success"] == 1.0
            native_hit |= info["native_success"] == 1.0
            done = terminated or truncated
        last += info["is_success"] == 1.0
        any_ += hit
        native_any += native_hit
    env.close()
    return {"last": last / episodes, "any": any_ / episodes, "native_any": native_any / episodes}


def main(argv: list[str] | None = None) -> int:
    from importlib.metadata import version

    import unified_manip

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=5)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    ids = [t for t, s in unified_manip.TASKS.items() if s.family == "metaworld"]
    rows = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Meta-World's policies warn that their gains clip
        for task_id in ids:
            rows[task_id] = rates(task_id, args.episodes)
            print(task_id, rows[task_id], flush=True)
    mean = {k: sum(r[k] for r in rows.values()) / len(rows) for k in ("last", "any", "native_any")}
    doc = {
        "command": f"python benchmarks/metaworld_scripted.py --episodes {args.episodes}",
        "episodes": args.episodes,
        "action_mode": "native",
        "versions": {p: version(p) for p in ("mujoco", "metaworld")},
        "mean": mean,
        "tasks": rows,
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    write_json(args.out, doc)
    print(f"wrote {args.out}: mean {mean}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
