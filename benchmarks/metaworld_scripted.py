"""Meta-World's own scripted policies (``metaworld.policies``) on the Meta-World IDs:
success per task, in ``native`` or, translated live, in another action mode.

Run from the repository root, with the ``metaworld`` extra (not part of the wheel):

    python benchmarks/metaworld_scripted.py --episodes 5
    python benchmarks/metaworld_scripted.py --episodes 3 --tasks metaworld:MT10 --action-mode ee_delta

Episode ``k`` is reset with seed ``k`` and runs the whole 500 steps. Three rates per task:
``last``, ``is_success`` on the last step (what ``unified-manip collect`` counts); ``any``,
``is_success`` on some step (Meta-World's own evaluation counts an episode so); and
``native_any``, Meta-World's own ``success`` on some step. In a mode other than ``native``
the policy is ``collect``'s (:func:`unified_manip.datasets.policies.scripted`), which
translates its actions. ``--step`` sets the mode's ``step`` (``controller_options``).
Writes ``benchmarks/out/metaworld_scripted.json`` (native) or
``benchmarks/out/metaworld_scripted_<mode>.json``.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

from unified_manip.cli.output import write_json

OUT = Path(__file__).resolve().parent / "out"


def rates(task_id: str, episodes: int, action_mode: str, options: dict) -> dict[str, float]:
    import gymnasium as gym

    from unified_manip.datasets.policies import scripted

    env = gym.make(task_id, action_mode=action_mode, **({"controller_options": options} if options else {}))
    policy = scripted(env)
    last = any_ = native_any = 0
    for seed in range(episodes):
        obs, _ = env.reset(seed=seed)
        done, hit, native_hit = False, False, False
        while not done:
            obs, _, terminated, truncated, info = env.step(policy(obs))
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
    from unified_manip.envs.task_lists import expand_task_lists

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=5)
    parser.add_argument("--tasks", default="metaworld:MT50", help="a task list or comma-separated IDs")
    parser.add_argument("--action-mode", default="native")
    parser.add_argument("--step", type=float, help="the mode's step (controller_options)")
    parser.add_argument("--out", type=Path)
    args = parser.parse_args(argv if argv is not None else sys.argv[1:])
    ids = expand_task_lists(args.tasks.split(","))
    options = {} if args.step is None else {"step": args.step}
    rows = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Meta-World's policies warn that their gains clip
        for task_id in ids:
            rows[task_id] = rates(task_id, args.episodes, args.action_mode, options)
            print(task_id, rows[task_id], flush=True)
    mean = {k: sum(r[k] for r in rows.values()) / len(rows) for k in ("last", "any", "native_any")}
    spec = unified_manip.TASKS[ids[0]]
    controller = spec.controllers[args.action_mode]
    doc = {
        "command": "python benchmarks/metaworld_scripted.py " + " ".join(argv if argv is not None else sys.argv[1:]),
        "episodes": args.episodes,
        "seeds": f"0..{args.episodes - 1}",
        "tasks_list": args.tasks,
        "action_mode": args.action_mode,
        "controller": {**controller.parameters(), **options},
        "versions": {p: version(p) for p in ("mujoco", "metaworld", "mink")},
        "mean": mean,
        "tasks": rows,
    }
    suffix = "" if args.action_mode == "native" else f"_{args.action_mode}"
    out = args.out or OUT / f"metaworld_scripted{suffix}.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    write_json(out, doc)
    print(f"wrote {out}: mean {mean}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
