"""Throughput of ``rgb`` observations, against robosuite's own camera observations.

Run it as ``python -m benchmarks.camera_speed`` (``--help`` for the options). For
each task and image size it measures, in one run, with random actions and autoresets:

==============  ==================================================================
kind            what
==============  ==================================================================
physics         ``gym.make(ID)``: no camera, the baseline of the ``/physics`` column
single          ``gym.make(ID, observation=["default", "rgb"], image_size=S)``
decimated       the same with ``camera_meshes="decimated"``
collision       the same on Lift with ``camera="agentview_collision"`` (collision geoms)
vector          ``gym.make_vec`` of ``single``, N envs (native where the family has it)
robosuite       ``robosuite.make("Lift", use_camera_obs=True, ...)`` at S x S
                (``agentview``, robosuite's defaults otherwise), beside Lift only
robosuite-phys  the same with ``use_camera_obs=False``
==============  ==================================================================

Each figure is frames per second: env steps per second times the envs (one ``rgb`` frame per
env step). The kinds run in turn within each round and each figure is the median over
rounds, so load changes reach every kind alike; compare the ratios of one run, not rates
across runs. The ``/physics`` column is each kind's rate over its own no-camera rate
(``physics``, or ``robosuite-phys`` for robosuite's): what a frame costs against a step. The
last column is ``single`` (and ``collision``) over ``robosuite`` for Lift at the same size.
"""

from __future__ import annotations

import json
import statistics
import time
from typing import Any, Callable

import numpy as np

from benchmarks.parser import ToolParser

TASKS: tuple[str, ...] = (
    "UnifiedManip/Arm4PickAndPlace-v0",
    "UnifiedManip/FetchPickAndPlace-v0",
    "UnifiedManip/Lift-v0",
)
SIZES: tuple[int, ...] = (64, 84, 128)
ROBOSUITE_TASK = "UnifiedManip/Lift-v0"
#: The camera of the ``collision`` kind: robosuite's default view, collision geoms only.
COLLISION_CAMERA = "agentview_collision"
#: Unmeasured steps of each kind before the rounds.
WARMUP_STEPS = 5


def _rate(step: Callable[[], None], steps: int, frames_per_step: int) -> float:
    start = time.perf_counter()
    for _ in range(steps):
        step()
    return steps * frames_per_step / (time.perf_counter() - start)


def _single(
    task_id: str, size: int, camera: str | None = None, meshes: str = "full", images: bool = True
) -> tuple[Callable[[], None], Callable[[], None]]:
    import gymnasium as gym

    import unified_manip  # noqa: F401  (registers the IDs: this tool may run from outside the package)

    if images:
        env = gym.make(task_id, observation=["default", "rgb"], image_size=size, camera=camera, camera_meshes=meshes)
    else:
        env = gym.make(task_id)
    env.reset(seed=0)
    env.action_space.seed(0)

    def step() -> None:
        *_, terminated, truncated, _ = env.step(env.action_space.sample())
        if terminated or truncated:
            env.reset()

    return step, env.close


def _vector(task_id: str, size: int, n: int) -> tuple[Callable[[], None], Callable[[], None]]:
    import warnings

    import gymnasium as gym

    import unified_manip  # noqa: F401  (registers the IDs)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the fallback notice (robosuite): SyncVectorEnv is what runs
        env = gym.make_vec(task_id, num_envs=n, observation=["default", "rgb"], image_size=size)
    env.reset(seed=0)
    env.action_space.seed(0)
    return (lambda: env.step(env.action_space.sample())), env.close


def _robosuite(size: int, camera_obs: bool = True) -> tuple[Callable[[], None], Callable[[], None]]:
    import robosuite

    env = robosuite.make(
        "Lift",
        robots="Panda",
        has_renderer=False,
        has_offscreen_renderer=True,
        use_camera_obs=camera_obs,
        camera_names="agentview",
        camera_heights=size,
        camera_widths=size,
        hard_reset=False,
        ignore_done=True,
        control_freq=20,
    )
    env.reset()
    rng = np.random.default_rng(0)
    low, high = env.action_spec
    return (lambda: env.step(rng.uniform(low, high))), env.close


def measure(
    tasks: tuple[str, ...], sizes: tuple[int, ...], n: int, steps: int, rounds: int, decimated: bool = True
) -> list[dict[str, Any]]:
    """One row per task, size and kind: its frames/s (median over rounds); ``n=0`` leaves
    the vector env out, ``decimated=False`` the ``decimated`` kind."""
    rows = []
    for size in sizes:
        makers: dict[tuple[str, str], tuple[Callable[[], Any], int, int]] = {}
        for task in tasks:
            makers[(task, "physics")] = (lambda t=task: _single(t, size, images=False), steps, 1)
            makers[(task, "single")] = (lambda t=task: _single(t, size), steps, 1)
            if decimated:
                makers[(task, "decimated")] = (lambda t=task: _single(t, size, meshes="decimated"), steps, 1)
            if n:
                makers[(task, f"vector{n}")] = (lambda t=task: _vector(t, size, n), max(steps // n, 1), n)
        if ROBOSUITE_TASK in tasks:
            makers[(ROBOSUITE_TASK, "collision")] = (lambda: _single(ROBOSUITE_TASK, size, COLLISION_CAMERA), steps, 1)
            makers[("robosuite:Lift", "robosuite")] = (lambda: _robosuite(size), steps, 1)
            makers[("robosuite:Lift", "robosuite-phys")] = (lambda: _robosuite(size, False), steps, 1)
        built = {key: make() for key, (make, _, _) in makers.items()}
        for step, _ in built.values():  # warm up: first renders, numba's compilation (robosuite)
            for _ in range(WARMUP_STEPS):
                step()
        rates: dict[tuple[str, str], list[float]] = {key: [] for key in makers}
        keys = list(makers)
        for r in range(rounds):
            for key in keys[r % len(keys) :] + keys[: r % len(keys)]:  # rotate the order
                rates[key].append(_rate(built[key][0], makers[key][1], makers[key][2]))
        for step_close in built.values():
            step_close[1]()
        for (task, kind), values in rates.items():
            rows.append({"task": task, "size": size, "kind": kind, "frames_per_s": statistics.median(values)})
    return rows


def table(rows: list[dict[str, Any]]) -> str:
    """The rows as text, with each kind's rate over its no-camera rate, and ``single`` /
    ``robosuite`` ratios for Lift."""
    lines = [f"{'task':<36} {'size':>4} {'kind':<14} {'frames/s':>9} {'/physics':>8}  ratio"]
    upstream = {r["size"]: r["frames_per_s"] for r in rows if r["kind"] == "robosuite"}
    base = {(r["task"], r["size"]): r["frames_per_s"] for r in rows if r["kind"] in ("physics", "robosuite-phys")}
    for r in rows:
        ratio = ""
        if r["task"] == ROBOSUITE_TASK and r["size"] in upstream and r["kind"] != "physics":
            ratio = f"{r['frames_per_s'] / upstream[r['size']]:.1f}x robosuite"
        physics = base.get((r["task"], r["size"]))
        per = f"{r['frames_per_s'] / physics:.2f}" if physics and not r["kind"].startswith("vector") else ""
        lines.append(f"{r['task']:<36} {r['size']:>4} {r['kind']:<14} {r['frames_per_s']:>9.1f} {per:>8}  {ratio}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    p = ToolParser("benchmarks.camera_speed", __doc__)
    p.add_argument("--tasks", nargs="+", default=list(TASKS))
    p.add_argument("--sizes", nargs="+", type=int, default=list(SIZES))
    p.add_argument("--num-envs", type=int, default=8, help="N of the vector env (0: none)")
    p.add_argument("--steps", type=int, default=40, help="env steps per measurement (the vector env: steps / N)")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--json", help="also write the rows to this file")
    p.add_argument("--no-decimated", action="store_true", help="leave out the decimated kind (needs fast-camera)")
    args = p.parse_args(argv)
    rows = measure(
        tuple(args.tasks), tuple(args.sizes), args.num_envs, args.steps, args.rounds, decimated=not args.no_decimated
    )
    print(table(rows))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
