"""What random exploration gives HER on each task: ``python -m benchmarks.exploration``.

HER learns about the object only from episodes in which the object moved, and it gets a
free positive label whenever a goal is met by chance. This measures both under uniform
random actions (the start of every off-policy run), per task, side by side:

* ``chance success``: the goal is met at the first step, with nothing done;
* ``random success``: met at the last step of a random episode;
* ``object moved``: the object ended more than ``moved`` metres from where it started;
* ``gripper cm/step``: mean distance the grip site travels per control step, and per second.

No training: these are properties of the tasks, which is where issue 10's question "why
does the arm learn more slowly than Fetch" starts.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from benchmarks.parser import ToolParser

#: Task ID and action mode of each compared task (the benchmark's modes).
DEFAULT_TASKS = (
    ("UnifiedManip/Arm4Push-v0", "ee_delta"),
    ("UnifiedManip/Arm4Push-v1", "ee_delta"),
    ("UnifiedManip/FetchPush-v0", "native"),
    ("UnifiedManip/Arm4PickAndPlace-v0", "ee_delta"),
    ("UnifiedManip/Arm4PickAndPlace-v1", "ee_delta"),
    ("UnifiedManip/FetchPickAndPlace-v0", "native"),
)


@dataclass(frozen=True)
class Exploration:
    task_id: str
    action_mode: str
    episodes: int
    episode_steps: int
    control_dt: float
    chance_success: float
    random_success: float
    object_moved: float
    mean_object_displacement_m: float
    gripper_cm_per_step: float
    gripper_cm_per_s: float


#: Grip-site names of the compared families (the arm's, then Fetch's).
GRIP_SITES = ("grip_site", "robot0:grip")


def _grip_reader(env):
    """A function returning the grip-site position of ``env``'s simulation."""
    import mujoco

    backend = env.unwrapped.backend
    model, data = backend.model, backend.data
    for name in GRIP_SITES:
        site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, name)
        if site >= 0:
            return lambda: data.site_xpos[site].copy()
    raise ValueError(f"{env.spec.id} has none of the grip sites {', '.join(GRIP_SITES)}")


def measure(task_id: str, action_mode: str, episodes: int = 200, moved: float = 0.02, seed: int = 0) -> Exploration:
    import gymnasium as gym

    import unified_manip  # noqa: F401

    env = gym.make(task_id, action_mode=action_mode, reward_type="sparse")
    env.action_space.seed(seed)
    chance, final, moves, disp, travel, steps = 0, 0, 0, [], 0.0, 0
    for ep in range(episodes):
        obs, _ = env.reset(seed=seed + ep)
        start = obs["achieved_goal"].copy()
        chance += int(env.unwrapped.compute_reward(obs["achieved_goal"], obs["desired_goal"], {}) == 0.0)
        read = _grip_reader(env)  # (Fetch rebuilds its data on reset)
        grip, done, info = read(), False, {}
        while not done:
            obs, _, terminated, truncated, info = env.step(env.action_space.sample())
            done = terminated or truncated
            new = read()
            travel += float(np.linalg.norm(new - grip))
            grip, steps = new, steps + 1
        final += int(info.get("is_success", 0.0) > 0.5)
        d = float(np.linalg.norm(obs["achieved_goal"] - start))
        disp.append(d)
        moves += int(d > moved)
    spec = env.spec
    dt = float(env.unwrapped.backend.dt)
    env.close()
    per_step = 100.0 * travel / max(steps, 1)
    return Exploration(
        task_id,
        action_mode,
        episodes,
        int(spec.max_episode_steps),
        dt,
        chance / episodes,
        final / episodes,
        moves / episodes,
        float(np.mean(disp)),
        per_step,
        per_step / dt,
    )


def noisy_demonstrations(task_id: str, action_mode: str, sigma: float, episodes: int = 20, seed: int = 0) -> float:
    """Success of the task's scripted policy, played in ``action_mode`` as demonstrations
    are (:mod:`unified_manip.envs.controllers.translate`), with Gaussian noise of std ``sigma``
    added to every action in that mode's own units (then clipped to ``[-1, 1]``): how
    much the same exploration noise disturbs a good policy in each mode."""
    import gymnasium as gym

    import unified_manip  # noqa: F401
    from unified_manip.training.demonstrations import policy

    env = gym.make(task_id, action_mode=action_mode, reward_type="sparse")
    act = policy(task_id, action_mode, env)
    noise = np.random.default_rng(seed)
    successes = 0
    for ep in range(episodes):
        obs, _ = env.reset(seed=seed + ep)
        done, info = False, {}
        while not done:
            action = act(obs)
            action = np.clip(action + sigma * noise.standard_normal(action.shape), -1.0, 1.0).astype(np.float32)
            obs, _, terminated, truncated, info = env.step(action)
            done = terminated or truncated
        successes += int(info.get("is_success", 0.0) > 0.5)
    env.close()
    return successes / episodes


def footprint(task_id: str, action_mode: str, episodes: int = 20, seed: int = 0) -> tuple[np.ndarray, float]:
    """Where the task's scripted policy acts in ``action_mode``: the fraction of each action
    dimension's ``[-1, 1]`` that its actions span (max minus min, over ``episodes`` seeded
    episodes, halved), and the mean absolute change of an action component from one step
    to the next. A mode in which a solving policy uses a small part of the box asks a
    learner for precise actions there."""
    import gymnasium as gym

    import unified_manip  # noqa: F401
    from unified_manip.training.demonstrations import policy

    env = gym.make(task_id, action_mode=action_mode, reward_type="sparse")
    act = policy(task_id, action_mode, env)
    actions, changes = [], []
    for ep in range(episodes):
        obs, _ = env.reset(seed=seed + ep)
        done, episode = False, []
        while not done:
            episode.append(np.asarray(act(obs), dtype=np.float64))
            obs, _, terminated, truncated, _ = env.step(episode[-1].astype(np.float32))
            done = terminated or truncated
        episode = np.clip(np.array(episode), -1.0, 1.0)
        actions.append(episode)
        changes.append(np.abs(np.diff(episode, axis=0)))
    env.close()
    stacked = np.concatenate(actions)
    return (stacked.max(0) - stacked.min(0)) / 2.0, float(np.concatenate(changes).mean())


def _footprint_table(task_id: str, episodes: int) -> None:
    from unified_manip.training.demonstrations import demonstrable_modes

    print(f"{task_id}: the scripted policy's actions in each shared action mode ({episodes} episodes)")
    print("| action mode | span of each dimension's [-1, 1] used | mean change per step |")
    print("|---|---|---:|")
    for mode in demonstrable_modes(task_id):
        span, change = footprint(task_id, mode, episodes)
        print(f"| {mode} | {' / '.join(f'{v:.2f}' for v in span)} | {change:.3f} |")


def _noise_table(task_id: str, sigmas: list[float], episodes: int) -> None:
    from unified_manip.training.demonstrations import demonstrable_modes

    modes = demonstrable_modes(task_id)
    print(f"{task_id}: success of the scripted policy with action noise ({episodes} episodes per cell)")
    print("| action mode | " + " | ".join(f"σ = {s:g}" for s in sigmas) + " |")
    print("|---|" + "---:|" * len(sigmas))
    for mode in modes:
        print(
            f"| {mode} | "
            + " | ".join(f"{noisy_demonstrations(task_id, mode, s, episodes):.2f}" for s in sigmas)
            + " |"
        )


def main(argv: list[str] | None = None) -> int:
    parser = ToolParser("benchmarks.exploration", __doc__)
    parser.add_argument("--episodes", type=int, default=200)
    parser.add_argument("--json", help="write the results here")
    parser.add_argument(
        "--noise",
        type=float,
        nargs="+",
        metavar="SIGMA",
        help="instead: the scripted policy's success in every shared action mode of --task, with "
        "Gaussian action noise of each std SIGMA",
    )
    parser.add_argument(
        "--footprint",
        action="store_true",
        help="instead: the part of the action box the scripted policy of --task uses in every shared action mode",
    )
    parser.add_argument(
        "--task", default="UnifiedManip/Arm4PickAndPlace-v0", help="the task of --noise and --footprint"
    )
    args = parser.parse_args(argv)
    if args.footprint:
        _footprint_table(args.task, args.episodes)
        return 0
    if args.noise:
        _noise_table(args.task, args.noise, args.episodes)
        return 0
    rows = [measure(t, m, args.episodes) for t, m in DEFAULT_TASKS]
    print(
        "| task | mode | steps x dt | chance success | random success | object moved > 2 cm | "
        "mean object displacement | gripper cm/step | gripper cm/s |"
    )
    print("|---|---|---|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(
            f"| {r.task_id.split('/')[-1]} | {r.action_mode} | {r.episode_steps} x {r.control_dt * 1000:.0f} ms | "
            f"{r.chance_success:.3f} | {r.random_success:.3f} | {r.object_moved:.3f} | "
            f"{100 * r.mean_object_displacement_m:.1f} cm | {r.gripper_cm_per_step:.2f} | {r.gripper_cm_per_s:.1f} |"
        )
    if args.json:
        Path(args.json).write_text(json.dumps([asdict(r) for r in rows], indent=2) + "\n")
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
