"""The conversion table: per task, the share of recorded scripted episodes that still
succeed when ``convert`` re-executes them in each action mode, with the tracking error.

Run it as ``python -m benchmarks.conversion_table --env ID[,ID...] --episodes 50
--out DIR``. It records ``--episodes`` successful scripted episodes per task into
``DIR/<task>-<mode>-v0``, in the mode the scripted policy emits (``ee_delta``, or
Meta-World's ``native``), or in ``--source``'s mode, the policy translated live. It
converts them to every mode by ``--method`` (``search``, the default, or ``track``: open
loop), measuring only, with no datasets written, and prints a
Markdown table (and ``--json``'s document). For comparison it also plays the scripted
policy live in each mode from the same reset seeds, its actions translated one by one,
as a run's ``demonstrations`` do.
"""

from __future__ import annotations

import json
import os
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

from benchmarks.parser import ToolParser
from unified_manip.datasets import DatasetError
from unified_manip.datasets.convert import convert
from unified_manip.datasets.policies import scripted
from unified_manip.datasets.recording import collect
from unified_manip.datasets.store import metadata, open_dataset
from unified_manip.envs.registry import TASKS, get_task


def measure(
    task_id: str,
    episodes: int,
    out: Path,
    seed: int = 0,
    modes: list[str] | None = None,
    translated: bool = True,
    first: int | None = None,
    on_mode=None,
    progress: bool = False,
    method: str = "search",
    source: str | None = None,
) -> dict[str, Any]:
    """Record ``episodes`` successful scripted episodes of ``task_id`` in the mode its
    scripted policy emits (``ee_delta``; Meta-World's ``native``) and convert them to
    ``modes`` (default: every mode of the task); ``{mode: {...}}`` per mode.
    ``translated=False`` leaves out the live per-action translation (it doubles the time);
    ``first`` converts only the first episodes; ``on_mode(row)`` is called after each mode;
    ``progress`` shows the recording's and each conversion's progress bars; ``method`` is
    ``convert``'s; ``source`` records in that mode instead, the scripted actions translated
    live (Meta-World's servoed modes cannot follow its ``native`` recordings). A mode's
    ``success`` counts the episodes kept (a success within the tolerance), ``succeeded``
    those that succeed at all."""
    spec = get_task(task_id)
    # The version is in the name: Arm4Push-v0 and -v1 share a spec name, not their episodes.
    source = source or spec.scripted_mode
    path = Path(out) / f"{task_id.split('/')[-1]}-{source}-v0"
    start = time.perf_counter()
    if not path.exists():  # a recording of an earlier, interrupted measurement is reused
        collect(
            task_id,
            {"action_mode": source, "reward_type": "sparse"},
            scripted,
            "scripted",
            f"scripted policy of {task_id}",
            episodes,
            path,
            seed=seed,
            only_successful=True,
            progress=progress,
        )
    recorded = metadata(open_dataset(path))
    if recorded["env_id"] != task_id:
        raise DatasetError(
            f"{path} holds episodes of {recorded['env_id']}, not of {task_id}; remove it or pick another --out"
        )
    elapsed = time.perf_counter() - start
    row: dict[str, Any] = {"recorded": recorded, "source": source, "collect_s": elapsed, "modes": {}}
    for mode in modes or spec.action_modes:
        start = time.perf_counter()
        try:
            report = convert(path, mode, None, progress=progress, first=first, method=method)
        except DatasetError as err:
            row["modes"][mode] = {"error": str(err)}
            if on_mode is not None:
                on_mode(row)
            continue
        eps = report.episodes
        seeds = [int(m["seed"]) for m in _seeds(path)]
        row["modes"][mode] = {
            "method": method,
            "success": sum(e.kept for e in eps),
            "succeeded": sum(e.success_converted for e in eps),
            "kept_by": dict(Counter(e.replayed_by for e in eps if e.kept)),
            # Why the others were lost: the first step off the path, or no success on it.
            "lost_off_path_at": sorted(e.first_step_off for e in eps if e.first_step_off is not None),
            "lost_on_path": sum(not e.success_converted and e.first_step_off is None for e in eps),
            "episodes": len(eps),
            "tracking_error_mean_cm": sum(e.tracking_error_mean_cm for e in eps) / len(eps),
            "tracking_error_max_cm": max(e.tracking_error_max_cm for e in eps),
            "goal_error_mean": sum(e.goal_error_mean for e in eps) / len(eps),
            "goal_error_max": max(e.goal_error_max for e in eps),
            "seconds": time.perf_counter() - start,
            "translated_success": _translated_successes(task_id, mode, seeds) if translated else None,
        }
        if on_mode is not None:
            on_mode(row)
    return row


def _seeds(path: Path) -> list[dict[str, Any]]:
    dataset = open_dataset(path)
    return list(dataset.storage.get_episode_metadata(dataset.episode_indices))


def _translated_successes(task_id: str, mode: str, seeds: list[int]) -> int:
    """Successes of the scripted policy played live in ``mode`` from ``seeds``."""
    import gymnasium as gym

    from unified_manip.datasets.episodes import play

    env = gym.make(task_id, action_mode=mode)
    try:
        policy = scripted(env)
        return sum(play(env, policy, seed).success for seed in seeds)
    finally:
        env.close()


def overview(results: dict[str, dict[str, Any]]) -> str:
    """Markdown: one row per task, one column per action mode (the share of recorded
    episodes that still succeed converted, then in brackets the share that succeed with the
    scripted policy's actions translated live; ``—`` where the mode cannot be converted
    into), after the scripted recording's successes of the episodes it played."""
    from unified_manip.envs.config import ACTION_MODES

    modes = [m for m in ACTION_MODES if any(m in row["modes"] for row in results.values())]
    lines = [
        "| task | recorded: successful of played | " + " | ".join(f"`{m}`" for m in modes) + " |",
        "|---|---:|" + "---:|" * len(modes),
    ]
    for task_id, row in results.items():
        rec = row["recorded"]
        kept = rec["episodes_played"] - rec["dropped_episodes"]
        cells = []
        for mode in modes:
            m = row["modes"].get(mode)
            cells.append("" if m is None else "—" if "error" in m else _share(m))
        name, scripted_mode = task_id.split("/")[-1], get_task(task_id).scripted_mode
        if row.get("source", scripted_mode) != scripted_mode:  # older tables have no source
            name += f" (in `{row['source']}`)"
        lines.append(f"| {name} | {kept} of {rec['episodes_played']} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _share(m: dict[str, Any]) -> str:
    converted = f"{m['success'] / m['episodes']:.2f}"
    live = m.get("translated_success")
    return converted if live is None else f"{converted} ({live / m['episodes']:.2f})"


def _reason(error: str, task_id: str, mode: str) -> str:
    """Why a mode cannot be converted into, without the task and mode the row names and the
    list of valid modes (for a table row that names them already)."""
    reason = error.removeprefix(f"{task_id}'s action_mode {mode!r} ").split("; expected one of")[0]
    return reason.removeprefix("is ")


#: What keeps an episode, in the order the tries run (an episode's ``replayed_by``); the
#: search's retries with the target's lead weighted in (``search, lead W``, in the order of
#: their weights) run after the lockstep and before the open-loop guesses.
WAYS = ("search", "search, lockstep", "search, lead", "translated", "tracker")


def _way_order(way: str) -> tuple[int, float]:
    if way.startswith("search, lead "):
        return WAYS.index("search, lead"), -float(way.rsplit(" ", 1)[1])
    return WAYS.index(way), 0.0


def markdown(results: dict[str, dict[str, Any]]) -> str:
    """One row per task and mode: converted successes, what kept them (the search, or a
    retry: :func:`unified_manip.datasets.steps.steppers`), mean and worst tracking error,
    the live translation's successes and the wall time (conversion and live translation);
    a mode that cannot be converted into says why."""
    lines = [
        "| task | mode | converted success | kept by | tracking error, mean cm | worst step, cm | translated live "
        "| wall time |",
        "|---|---|---:|---|---:|---:|---:|---:|",
    ]
    for task_id, row in results.items():
        for mode, m in row["modes"].items():
            if "error" in m:
                lines.append(f"| {task_id} | {mode} | — {_reason(m['error'], task_id, mode)} | | | | — | |")
                continue
            share = m["success"] / m["episodes"]
            kept_by = m.get("kept_by", {})  # the tries in their order (older tables have none)
            by = "; ".join(f"{way} {kept_by[way]}" for way in sorted(kept_by, key=_way_order)) or "–"
            lines.append(
                f"| {task_id} | {mode} | {m['success']}/{m['episodes']} ({share:.2f}) | {by} | "
                f"{m['tracking_error_mean_cm']:.2f} | {m['tracking_error_max_cm']:.2f} | "
                f"{'–' if m['translated_success'] is None else m['translated_success']}/{m['episodes']} | "
                f"{m['seconds']:.0f} s |"
            )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = ToolParser("benchmarks.conversion_table", __doc__)
    parser.add_argument("--env", required=True, help="comma-separated task IDs")
    parser.add_argument("--episodes", type=int, default=50)
    parser.add_argument("--out", required=True, help="directory for the recorded datasets")
    parser.add_argument("--modes", help="comma-separated action modes (default: every mode of each task)")
    parser.add_argument("--no-translated", action="store_true", help="leave out the live per-action translation")
    parser.add_argument("--first", type=int, help="convert only the first recorded episodes")
    parser.add_argument(
        "--source", help="record in this mode, the scripted actions translated live (default: the mode they are in)"
    )
    parser.add_argument("--method", choices=("search", "track"), default="search", help="convert's method")
    parser.add_argument("--json", help="also write the results here (after every mode)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bars or per-mode lines on stderr")
    args = parser.parse_args(argv)
    for name in ("episodes", "first"):
        value = getattr(args, name)
        if value is not None and value < 1:
            parser.error(f"--{name}: expected a positive integer, got {value}")
    task_ids, modes = args.env.split(","), args.modes.split(",") if args.modes else None
    try:
        for task_id in task_ids:
            spec = get_task(task_id)
            if spec.scripted_policy is None:
                scripted_ids = ", ".join(t for t in TASKS if get_task(t).scripted_policy is not None)
                raise ValueError(f"{task_id} has no scripted policy to record; expected one of {scripted_ids}")
            for mode in (modes or []) + ([args.source] if args.source else []):
                if mode not in spec.action_modes:
                    raise ValueError(
                        f"{task_id} has no action_mode {mode!r}; expected one of {', '.join(spec.action_modes)}"
                    )
    except ValueError as err:
        parser.error(str(err))
    results: dict[str, Any] = {}

    def save(row: dict[str, Any]) -> None:
        results[task_id] = row
        if not args.no_progress:
            mode, m = next(reversed(row["modes"].items()))
            done = (
                _reason(m["error"], task_id, mode)
                if "error" in m
                else f"{m['success']}/{m['episodes']} converted"
                + (
                    ""
                    if m["translated_success"] is None
                    else f", {m['translated_success']}/{m['episodes']} translated live"
                )
            )
            print(f"{task_id} {mode}: {done}", file=sys.stderr, flush=True)
        if args.json:  # whole or not at all: a reader never sees a half-written file
            tmp = Path(f"{args.json}.tmp")
            tmp.write_text(json.dumps(results, indent=2))
            os.replace(tmp, args.json)

    for task_id in task_ids:
        try:
            results[task_id] = measure(
                task_id,
                args.episodes,
                Path(args.out),
                modes=modes,
                translated=not args.no_translated,
                first=args.first,
                on_mode=save,
                progress=not args.no_progress,
                method=args.method,
                source=args.source,
            )
        except ValueError as err:  # no scripted policy, or a recording of another task
            parser.error(str(err))
    print(overview(results) + "\n\n" + markdown(results))


if __name__ == "__main__":
    main()
