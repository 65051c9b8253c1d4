"""How straight a held action moves the hand: ``python -m benchmarks.line_tracking``.

An incremental end-effector action held at full scale on one axis commands a straight
line. This plays it, per task, mode and axis, from the reset of seed 0 for ``--steps``
steps, then zero actions for ``--settle`` steps (zero means "stay" in these modes), and
reports the hand's displacement along the axis and off it (the norm of the
perpendicular part), after the held steps and after settling. The hand is the achieved
goal, so the tasks are reach tasks (MetaWorldReach-v0, FetchReach-v0, Arm4Reach-v0); it
is read so in every mode, a source's own ``native`` included. A converted demonstration
follows a recorded path step by step, so a mode whose lines bend cannot follow a path
recorded in a mode whose lines do not (docs/datasets.md, Limits).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from benchmarks.parser import ToolParser

#: The held actions: a unit action on each of the first three entries (x, y, z).
AXES = {"+x": (0, 1.0), "+y": (1, 1.0), "-z": (2, -1.0)}


def line(task_id: str, mode: str, axis: str, steps: int, settle: int) -> dict[str, float]:
    """The hand's displacement (m) along ``axis`` and off it, after ``steps`` held full
    actions and after ``settle`` zero actions more."""
    import gymnasium as gym

    env = gym.make(task_id, action_mode=mode)
    try:
        obs, _ = env.reset(seed=0)
        start = obs["achieved_goal"].astype(np.float64)
        index, sign = AXES[axis]
        action = np.zeros(env.action_space.shape, dtype=np.float32)
        action[index] = sign
        direction = np.zeros(3)
        direction[index] = sign
        out = {}
        for label, act, n in (("held", action, steps), ("settled", np.zeros_like(action), settle)):
            for _ in range(n):
                obs = env.step(act)[0]
            moved = obs["achieved_goal"].astype(np.float64) - start
            along = float(moved @ direction)
            out[f"{label}_along_m"] = along
            out[f"{label}_off_m"] = float(np.linalg.norm(moved - along * direction))
        return out
    finally:
        env.close()


def main(argv: list[str] | None = None) -> None:
    parser = ToolParser("benchmarks.line_tracking", __doc__)
    parser.add_argument("--env", required=True, help="comma-separated task IDs")
    parser.add_argument("--modes", default="ee_delta,ee_target_delta", help="comma-separated action modes")
    parser.add_argument("--steps", type=int, default=20, help="held full-action steps")
    parser.add_argument("--settle", type=int, default=40, help="zero-action steps after them")
    parser.add_argument("--json", help="write the results here")
    args = parser.parse_args(argv)
    for name in ("steps", "settle"):
        if getattr(args, name) < 1:
            parser.error(f"--{name}: expected a positive integer, got {getattr(args, name)}")
    from unified_manip.envs.registry import get_task

    cases = [(t, m) for t in args.env.split(",") for m in args.modes.split(",")]
    try:
        for task_id, mode in cases:
            spec = get_task(task_id)
            if mode not in spec.action_modes:
                raise ValueError(
                    f"{task_id} has no action_mode {mode!r}; expected one of {', '.join(spec.action_modes)}"
                )
    except ValueError as err:
        parser.error(str(err))
    rows = [
        {"task": t, "mode": m, "axis": axis, **line(t, m, axis, args.steps, args.settle)}
        for t, m in cases
        for axis in AXES
    ]
    print(f"| task | mode | axis | along, cm ({args.steps} steps) | off, cm | settled along, cm | settled off, cm |")
    print("|---|---|---|---:|---:|---:|---:|")
    for r in rows:
        cells = [100 * r[k] for k in ("held_along_m", "held_off_m", "settled_along_m", "settled_off_m")]
        print(
            f"| {r['task'].split('/')[-1]} | `{r['mode']}` | {r['axis']} | "
            + " | ".join(f"{c:.1f}" for c in cells)
            + " |"
        )
    if args.json:
        doc = {
            "command": "python -m benchmarks.line_tracking "
            + " ".join(argv if argv is not None else __import__("sys").argv[1:]),
            "steps": args.steps,
            "settle": args.settle,
            "rows": rows,
        }
        Path(args.json).write_text(json.dumps(doc, indent=2) + "\n")


if __name__ == "__main__":
    main()
