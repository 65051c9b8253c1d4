"""How far the gripper overshoots one action step: ``python -m benchmarks.step_response``.

Issue 10 (3b) lists the arm's stiff servos, which overshoot a joint step by up to ~13%, as
one reason the arm might learn more slowly than Fetch. What an agent acting in an
incremental mode sees is the grip site's motion, so this measures that, per task and
mode, without training:

* play one step of the action ``e_axis`` (full scale on one action dimension), then hold
  with zero actions (in the incremental modes zero means "stay");
* play the same episode (same reset seed) with zero actions only, and take the
  difference of the grip-site positions, so that settling and gravity cancel out;
* report the peak and the settled displacement, the overshoot (peak / settled - 1) and
  the number of control steps until the site stays within 5% of where it settles.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from benchmarks.exploration import _grip_reader
from benchmarks.parser import ToolParser

#: Task ID and action mode of each compared case: the arm's incremental modes, which
#: re-target from where the arm is (``*_delta``) or from the last target (``*_target_delta``),
#: against Fetch's benchmark mode (``native``, mocap) and its ``ee_delta``.
DEFAULT_CASES = (
    *(
        (f"UnifiedManip/Arm4Push-v{v}", mode)
        for v in (0, 1)
        for mode in ("ee_delta", "ee_target_delta", "joint_delta", "joint_target_delta")
    ),
    ("UnifiedManip/FetchPush-v0", "native"),
    ("UnifiedManip/FetchPush-v0", "ee_delta"),
)

#: The settled band: within this fraction of the settled displacement.
BAND = 0.05


@dataclass(frozen=True)
class StepResponse:
    task_id: str
    action_mode: str
    axis: int
    episodes: int
    control_dt: float
    settled_cm: float
    peak_cm: float
    overshoot: float
    settle_steps: float


def _grip_path(env, seed: int, first: np.ndarray, steps: int) -> np.ndarray:
    env.reset(seed=seed)
    read = _grip_reader(env)
    zero = np.zeros(env.action_space.shape, dtype=env.action_space.dtype)
    path = []
    for i in range(steps):
        env.step(first if i == 0 else zero)
        path.append(read())
    return np.array(path)


def measure(task_id: str, action_mode: str, axis: int = 0, episodes: int = 5, steps: int = 15) -> StepResponse:
    """The grip site's response to one full step on action dimension ``axis``, averaged
    over ``episodes`` seeded resets."""
    import gymnasium as gym

    import unified_manip  # noqa: F401

    env = gym.make(task_id, action_mode=action_mode, reward_type="sparse")
    if not 0 <= axis < env.action_space.shape[0]:
        raise ValueError(f"axis {axis} is outside {task_id} {action_mode}'s {env.action_space.shape[0]} action dims")
    first = np.zeros(env.action_space.shape, dtype=env.action_space.dtype)
    first[axis] = 1.0
    settled, peak, settle = [], [], []
    for seed in range(episodes):
        moved = _grip_path(env, seed, first, steps) - _grip_path(env, seed, first * 0, steps)
        dist = np.linalg.norm(moved, axis=1)
        final = float(dist[-1])
        outside = np.flatnonzero(np.abs(dist - final) > BAND * final)
        settled.append(final)
        peak.append(float(dist.max()))
        settle.append(int(outside[-1]) + 2 if outside.size else 1)
    dt = float(env.unwrapped.backend.dt)
    env.close()
    s, p = float(np.mean(settled)), float(np.mean(peak))
    return StepResponse(
        task_id,
        action_mode,
        axis,
        episodes,
        dt,
        100 * s,
        100 * p,
        p / s - 1.0 if s > 0 else 0.0,
        float(np.mean(settle)),
    )


def main(argv: list[str] | None = None) -> int:
    parser = ToolParser("benchmarks.step_response", __doc__)
    parser.add_argument("--episodes", type=int, default=5)
    parser.add_argument(
        "--axes", type=int, nargs="+", default=[0, 1], help="the action dimensions stepped, one at a time (default 0 1)"
    )
    parser.add_argument("--json", help="write the results here")
    args = parser.parse_args(argv)
    rows = [measure(t, m, axis, args.episodes) for t, m in DEFAULT_CASES for axis in args.axes]
    print("| task | mode | axis | dt | settled displacement | peak | overshoot | steps to settle (±5%) |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(
            f"| {r.task_id.split('/')[-1]} | {r.action_mode} | {r.axis} | {r.control_dt * 1000:.0f} ms | "
            f"{r.settled_cm:.2f} cm | "
            f"{r.peak_cm:.2f} cm | {100 * r.overshoot:.1f}% | {r.settle_steps:.1f} |"
        )
    if args.json:
        Path(args.json).write_text(json.dumps([asdict(r) for r in rows], indent=2) + "\n")
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
