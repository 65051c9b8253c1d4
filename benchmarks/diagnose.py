"""What a run's policy did: ``python -m benchmarks.diagnose RUN_DIR ...``.

Issue 40 asks, for every action mode that fails on a task, what the mode did, measured
rather than guessed. For each run directory this reports:

* **demonstrations:** the episodes the run started with and their success
  (``demonstrations.json``), and, where they came from a dataset that is at hand (its path
  as the run recorded it, relative to the working directory), how much their actions change
  per step, to set beside the policy's;
* **training episodes:** the success of the agent's own episodes, over all of them and
  over the last tenth (the ``monitor/`` CSVs);
* **the policy,** played deterministically for ``--episodes`` seeded episodes: its
  success; its actions (mean ``|a|``, the share of components at the bounds, the mean
  change between steps); the closest approach of the grip site to the object (the
  ``object_rel`` group, cm, median over episodes; tasks without an object have none);
  how far the achieved goal got from where it started (the norm of its change, x100:
  cm where the goal is a position, as on the object tasks; median over episodes); how
  close it came to the desired goal, by the task's own goal distance, in units of its
  success threshold (below 1: the goal was reached at some step; median over episodes),
  beside that distance at reset;
  and the task's scalar quantities in ``info`` at each episode's end (mean over
  episodes, so a flag such as a dropped object gives the share of episodes).

The policy played is the run's final model (``--model final``, the default: the one whose
evaluation is the run's final success; a run still training plays its newest checkpoint),
or the best evaluated one (``--model best``, as ``unified-manip eval`` picks it). Committed
results carry no models, so for them only the first two are measured; run it where the runs
trained.
"""

from __future__ import annotations

import csv
import json
import sys
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import NamedTuple

import numpy as np

from benchmarks.parser import ToolParser

#: Seeds of the played episodes: 123, 124, ... (``unified-manip eval``'s).
FIRST_SEED = 123
#: An action component within this of a bound counts as saturated.
SATURATED = 0.99


@dataclass(frozen=True)
class Played:
    """The policy, played: see the module docstring."""

    model: str  # the model file played, relative to the run directory
    episodes: int
    success: float
    mean_abs_action: float
    saturated: float
    action_change: float
    closest_approach_cm: float | None
    goal_moved_cm: float
    closest_to_goal: float | None = None  # in success thresholds; None in files written before it
    goal_at_reset: float | None = None  # the same, at reset
    end_info: dict[str, float] = field(default_factory=dict)


class ActionStatistics(NamedTuple):
    """Actions over episodes: mean ``|a|``, the share of components at a bound
    (:data:`SATURATED`), and the mean change between consecutive steps of an episode."""

    mean_abs: float
    saturated: float
    change: float


def action_statistics(episodes: list[np.ndarray]) -> ActionStatistics:
    """:class:`ActionStatistics` of ``episodes``, each a ``steps x action dims`` array; a
    change is the mean over components of ``|a_t - a_{t-1}|``, averaged over every step
    after an episode's first."""
    a = np.abs(np.concatenate(episodes))
    changes = [np.abs(np.diff(e, axis=0)).mean(axis=1) for e in episodes if len(e) > 1]
    change = float(np.concatenate(changes).mean()) if changes else 0.0
    return ActionStatistics(float(a.mean()), float((a >= SATURATED).mean()), change)


def dataset_action_change(demos: dict) -> tuple[float | None, str]:
    """The demonstrations' action change per step (:func:`action_statistics`), from the
    dataset ``demonstrations.json`` names; None and why where there is none at hand."""
    path = demos.get("dataset")
    if not path:
        return None, ""
    if not Path(path).is_dir():
        return None, f"its dataset {path} is not at hand (from this working directory)"
    from unified_manip.datasets import store

    dataset = store.open_dataset(Path(path))
    episodes = [np.asarray(e.actions, dtype=np.float64) for e in dataset.iterate_episodes()]
    return action_statistics(episodes).change, ""


@dataclass(frozen=True)
class Diagnosis:
    run: str
    action_mode: str
    demonstrations: int
    demonstration_success: float | None
    demonstration_action_change: float | None
    training_episodes: int
    training_success: float | None
    training_success_last_tenth: float | None
    played: Played | None
    note: str = ""


def training_success(run_dir: Path) -> tuple[int, float | None, float | None]:
    """``(episodes, success over all, success over the last tenth)`` of the training
    episodes the run's monitor CSVs list, in the order they ended. A resumed run has one
    ``monitor/seg<k>`` per process; the episodes a process played after its last
    checkpoint count too (the agent played them, though training went on from the
    checkpoint)."""
    rows = []
    segments = sorted(Path(run_dir, "monitor").glob("seg*"), key=lambda p: int(p.name[3:] or 0))
    for k, segment in enumerate(segments):
        for path in sorted(segment.glob("*.monitor.csv")):
            with path.open() as f:
                f.readline()  # the JSON header
                rows += [(k, float(r["t"]), float(r["is_success"])) for r in csv.DictReader(f) if r.get("is_success")]
    if not rows:
        return 0, None, None
    success = np.array([s for *_, s in sorted(rows)])
    tail = success[-max(1, len(success) // 10) :]
    return len(success), float(success.mean()), float(tail.mean())


#: ``--model`` choices: which of a run's models :func:`play` plays.
MODELS = ("final", "best")


def model_to_play(run_dir: Path, which: str = "final") -> Path:
    """``final``: the run's final model, else its newest checkpoint (a run still training);
    ``best``: the model ``unified-manip eval`` picks (best, else final, else newest checkpoint)."""
    from unified_manip.training import checkpoints, rundir

    if which not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}; got {which!r}")
    if which == "best":
        return rundir.model_to_evaluate(run_dir, run_dir)
    ckpt = checkpoints.newest(run_dir)
    for path in (run_dir / "final_model.zip", ckpt.path(checkpoints.MODEL) if ckpt else None):
        if path is not None and path.is_file():
            return path
    best = " (--model best plays its best model)" if (run_dir / "best" / "best_model.zip").is_file() else ""
    raise rundir.RunDirectoryError(f"{run_dir} has no model yet (no final model or checkpoint){best}")


def play(run_dir: Path, episodes: int, which: str = "final") -> Played:
    """Play the run's model (:func:`model_to_play`) deterministically."""
    from unified_manip.training.evaluation import open_policy

    model = model_to_play(run_dir, which)
    policy = open_policy(model)
    env = policy.env
    backend = env.unwrapped.backend
    group = backend.observation_groups().get("object_rel")
    distance = (lambda: float(np.linalg.norm(group.read(backend)))) if group else (lambda: np.nan)
    task = env.unwrapped.task

    def to_goal(o: dict) -> float:  # in success thresholds
        return float(task.goal_distance(o["achieved_goal"], o["desired_goal"])) / task.distance_threshold

    actions, closest, moved, nearest_goal, at_reset, ends, successes = [], [], [], [], [], [], 0
    for ep in range(episodes):
        obs, info = env.reset(seed=FIRST_SEED + ep)
        start, done, taken = obs["achieved_goal"].copy(), False, []
        near, far, goal_near = distance(), 0.0, to_goal(obs)
        at_reset.append(goal_near)
        while not done:
            action = np.asarray(policy.act(obs), dtype=np.float64)
            obs, _, terminated, truncated, info = env.step(action)
            done = terminated or truncated
            taken.append(action)
            near = min(near, distance())
            far = max(far, float(np.linalg.norm(obs["achieved_goal"] - start)))
            goal_near = min(goal_near, to_goal(obs))
        actions.append(np.stack(taken))
        closest.append(near)
        moved.append(far)
        nearest_goal.append(goal_near)
        ends.append(end_quantities(info))
        successes += int(info.get("is_success", 0.0) > 0.5)
    policy.close()
    stats = action_statistics(actions)
    return Played(
        str(model.relative_to(run_dir)),
        episodes,
        successes / episodes,
        stats.mean_abs,
        stats.saturated,
        stats.change,
        100 * float(np.median(closest)) if group else None,
        100 * float(np.median(moved)),
        float(np.median(nearest_goal)),
        float(np.median(at_reset)),
        {k: float(np.mean([e.get(k, np.nan) for e in ends])) for k in sorted(set().union(*ends))},
    )


def end_quantities(info: dict) -> dict[str, float]:
    """The scalar numbers (and flags) of a step's ``info``, but its success, which
    :class:`Played` reports already."""
    return {
        k: float(v)
        for k, v in info.items()
        if k != "is_success" and isinstance(v, (bool, int, float, np.bool_, np.number)) and np.ndim(v) == 0
    }


def diagnose(run_dir: Path, episodes: int = 20, which: str = "final") -> Diagnosis:
    """Everything the module docstring lists that ``run_dir`` allows."""
    from unified_manip.training import rundir
    from unified_manip.training.request import TrainError
    from unified_manip.training.rundir import RunDirectoryError

    config = rundir.read_config(run_dir)
    demos_path = run_dir / "demonstrations.json"
    demos = json.loads(demos_path.read_text()) if demos_path.is_file() else {}
    n, success, last = training_success(run_dir)
    data_change, data_note = dataset_action_change(demos)
    played, note = None, ""
    try:
        played = play(run_dir, episodes, which)
    except (TrainError, RunDirectoryError) as err:
        note = str(err)
    return Diagnosis(
        run_dir.name,
        config["env_kwargs"]["action_mode"],
        int(demos.get("episodes", 0)),
        demos.get("success"),
        data_change,
        n,
        success,
        last,
        played,
        "; ".join(n for n in (data_note, note) if n),
    )


def _pct(value: float | None) -> str:
    return "–" if value is None else f"{value:.2f}"


def _change(value: float | None) -> str:
    return "–" if value is None else f"{value:.3f}"


def _num(value: float | None) -> str:
    return "–" if value is None else f"{value:.1f}"


def _ends(values: dict[str, float]) -> str:
    return ", ".join(f"{k} {v:.2f}" for k, v in values.items()) or "–"


def table(rows: list[Diagnosis]) -> str:
    """Markdown, one row per run."""
    lines = [
        "| run | mode | demonstrations (success) | their change per step | training episodes: success (last tenth) "
        "| played model | played: success | mean abs action | at bounds | change per step | closest approach, cm "
        "| goal moved, x100 (cm) | closest to goal (at reset), thresholds | at the end (mean) |",
        "|---|---|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for d in rows:
        p = d.played
        played = (
            f"{p.model} | {p.success:.2f} | {p.mean_abs_action:.2f} | {p.saturated:.2f} | {p.action_change:.2f} "
            f"| {_num(p.closest_approach_cm)} | {p.goal_moved_cm:.1f} | {_change(p.closest_to_goal)} ({_change(p.goal_at_reset)}) "
            f"| {_ends(p.end_info)}"
            if p
            else "– | – | – | – | – | – | – | – | –"
        )
        lines.append(
            f"| {d.run} | `{d.action_mode}` | {d.demonstrations} ({_pct(d.demonstration_success)}) "
            f"| {_change(d.demonstration_action_change)} "
            f"| {d.training_episodes} episodes: {_pct(d.training_success)} ({_pct(d.training_success_last_tenth)}) "
            f"| {played} |"
        )
    notes = [f"- {d.run}: {d.note}" for d in rows if d.note]
    return "\n".join(lines + ([""] + notes if notes else []))


def main(argv: list[str] | None = None) -> int:
    from unified_manip.training.rundir import RunDirectoryError

    parser = ToolParser("benchmarks.diagnose", __doc__)
    parser.add_argument("runs", nargs="+", type=Path, help="run directories")
    parser.add_argument("--episodes", type=int, default=20, help="episodes to play each policy (default 20)")
    parser.add_argument(
        "--model",
        choices=MODELS,
        default="final",
        help="the model to play: final (default; else newest checkpoint) or best",
    )
    parser.add_argument("--json", type=Path, help="also write the measurements here")
    args = parser.parse_args(argv)
    if args.episodes <= 0:
        parser.error(f"--episodes must be positive, got {args.episodes}")
    try:
        rows = [diagnose(run, args.episodes, args.model) for run in args.runs]
    except RunDirectoryError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    print(table(rows))
    if args.json:
        args.json.write_text(json.dumps([asdict(d) for d in rows], indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
