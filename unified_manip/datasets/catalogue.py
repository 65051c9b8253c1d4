"""``unified-manip collect --all``: a dataset of N successful episodes for every task with a
scripted policy, in ``ee_delta`` and in every other mode that conversion reaches.

Per task: the scripted policy's ``ee_delta`` episodes are recorded (``TASK-ee_delta-v0``,
seeds from 0, successful episodes only); a conversion source of ``ceil(N / THRESHOLD)``
successful episodes (the same seeds on) is recorded under ``.sources/``; each other
mode of the shared controllers is converted from it and kept, as ``TASK-MODE-v0`` with
its first N successful episodes, where at least :data:`THRESHOLD` of the converted
episodes succeed. A conversion stops early once that is out of reach. A task whose
scripted policy cannot give N successful episodes, or that has none, takes a trained
run's policy where the caller passes one (in the run's own mode only), else it is
skipped with its reason.

Resumable: a dataset already there is complete (datasets are published whole) and kept;
``catalogue.json`` in the output directory records every dataset written and every mode
skipped with its conversion success, so a second call redoes neither. Each entry this call
produced also holds its cost: ``wall_s`` and ``cpu_s`` (a conversion's include its source,
where it recorded that) and the dataset's ``bytes``, so the set's cost sums across calls.
"""

from __future__ import annotations

import json
import math
import os
import time
from pathlib import Path
from typing import Any, Callable

from unified_manip.datasets.errors import DatasetError

#: A mode gets a dataset where at least this fraction of the converted episodes succeed.
THRESHOLD = 0.8
MANIFEST = "catalogue.json"
#: Trained policies the caller found, by task ID: ``(make_policy, source, env_kwargs)``.
Trained = dict[str, tuple[Callable, str, dict[str, Any]]]


def dataset_name(task_id: str, mode: str) -> str:
    """``Arm4PickAndPlace-v0-ee_delta-v0`` for ``UnifiedManip/Arm4PickAndPlace-v0`` in ``ee_delta``."""
    return f"{task_id.split('/')[-1]}-{mode}-v0"


def plan(tasks: list[str] | None = None) -> list[tuple[str, str]]:
    """``(task ID, mode)`` of every dataset ``collect --all`` tries, ``ee_delta`` first per task."""
    from unified_manip.datasets.policies import shared_modes
    from unified_manip.envs.registry import TASKS

    out = []
    for task_id, spec in TASKS.items():
        if tasks is not None and task_id not in tasks:
            continue
        modes = shared_modes(spec) if spec.scripted_policy is not None else []
        out += [
            (task_id, m) for m in (["ee_delta"] if "ee_delta" in modes else []) + [m for m in modes if m != "ee_delta"]
        ]
        if not modes:
            out.append((task_id, "trained"))
    return out


def collect_all(
    root: Path,
    episodes: int = 100,
    tasks: list[str] | None = None,
    trained: Trained | None = None,
    progress: bool = True,
    log: Callable[[str], None] | None = None,
) -> dict[str, dict[str, Any]]:
    """Write the datasets of :func:`plan` under ``root``; return ``catalogue.json``'s entries.
    ``log`` gets a line per dataset (default: printed above the progress bar)."""
    from tqdm import tqdm

    log = log or tqdm.write
    if episodes <= 0:
        raise DatasetError(f"--episodes must be a positive number of episodes; got {episodes}")
    root = Path(root)
    root.mkdir(parents=True, exist_ok=True)
    manifest = _read(root)
    failed_tasks: dict[str, str] = {}
    items = plan(tasks)
    with tqdm(items, desc="collect --all", unit="dataset", disable=not progress) as bar:
        for task_id, mode in bar:
            bar.set_postfix_str(f"{task_id.split('/')[-1]} {mode}")
            name = dataset_name(task_id, mode)
            done = manifest.get(name, {})
            if task_id in failed_tasks:
                entry = {"task": task_id, "mode": mode, "state": "skipped", "reason": failed_tasks[task_id]}
            elif mode == "trained":
                entry = _trained_entry(root, manifest, task_id, episodes, (trained or {}).get(task_id), False)
            elif (root / name).is_dir():
                entry = done or {"task": task_id, "mode": mode, "state": "written", "episodes": episodes}
            elif done.get("state") == "skipped" and done.get("episodes") == episodes:
                entry = done
            else:
                entry = _timed(root, name, lambda: _one(root, task_id, mode, episodes))
            _record(root, manifest, entry.get("name", name), entry, log)
            if mode == "ee_delta" and entry["state"] == "skipped":
                failed_tasks[task_id] = f"no ee_delta dataset to convert: {entry['reason']}"
                if trained and task_id in trained:
                    run = _trained_entry(root, manifest, task_id, episodes, trained[task_id], True)
                    _record(root, manifest, run["name"], run, log)
    return manifest


def _timed(root: Path, name: str, make: Callable[[], dict[str, Any]]) -> dict[str, Any]:
    """``make()``'s entry with its wall and CPU seconds and, when written, the dataset's bytes."""
    wall, cpu = time.perf_counter(), time.process_time()
    entry = make()
    entry.update(wall_s=round(time.perf_counter() - wall, 3), cpu_s=round(time.process_time() - cpu, 3))
    if entry["state"] == "written":
        entry["bytes"] = sum(f.stat().st_size for f in (root / entry.get("name", name)).rglob("*") if f.is_file())
    return entry


def _one(root: Path, task_id: str, mode: str, episodes: int) -> dict[str, Any]:
    """Record (``ee_delta``) or convert (any other mode) one dataset; a skip says why."""
    from unified_manip.datasets.convert import convert
    from unified_manip.datasets.policies import scripted
    from unified_manip.datasets.recording import collect

    entry: dict[str, Any] = {"task": task_id, "mode": mode, "episodes": episodes}
    out = root / dataset_name(task_id, mode)
    kwargs = {"action_mode": "ee_delta", "reward_type": "sparse"}
    try:
        if mode == "ee_delta":
            result = collect(
                task_id,
                kwargs,
                scripted,
                "scripted",
                f"scripted policy of {task_id}",
                episodes,
                out,
                only_successful=True,
                progress=False,
            )
            return {**entry, "state": "written", "success": result.success_rate}
        source = root / ".sources" / f"{dataset_name(task_id, 'ee_delta')[:-3]}-source-v0"
        tries = math.ceil(episodes / THRESHOLD)
        if not source.is_dir():
            collect(
                task_id,
                kwargs,
                scripted,
                "scripted",
                f"scripted policy of {task_id}",
                tries,
                source,
                only_successful=True,
                progress=False,
            )
        report = convert(source, mode, out, progress=False, keep=episodes, max_failed=tries - episodes)
    except DatasetError as err:
        return {**entry, "state": "skipped", "reason": str(err)}
    converted = f"{sum(e.success_converted for e in report.episodes)}/{len(report.episodes)}"
    if report.out is None:
        reason = f"conversion succeeded in {converted} episodes, below {THRESHOLD:.0%}"
        return {**entry, "state": "skipped", "reason": reason, "converted": converted}
    return {**entry, "state": "written", "converted": converted}


def _record(root: Path, manifest: dict, name: str, entry: dict, log: Callable[[str], None]) -> None:
    manifest[name] = entry
    _write(root, manifest)
    log(f"{name}: {entry['state']}" + (f" ({entry['reason']})" if entry.get("reason") else ""))


def _trained_entry(
    root: Path, manifest: dict, task_id: str, episodes: int, run: tuple | None, scripted: bool
) -> dict[str, Any]:
    """:func:`_trained`'s entry with its cost (:func:`_timed`). A dataset already written is
    kept as recorded; a run found now replaces the ``TASK-trained-v0`` placeholder that an
    earlier call without one recorded."""
    placeholder = dataset_name(task_id, "trained")
    if run is not None:
        name = dataset_name(task_id, run[2]["action_mode"])
        done = manifest.get(name, {})
        if done.get("state") == "written" and (root / name).is_dir():
            return {"name": name, **done}
        manifest.pop(placeholder, None)
    return _timed(root, placeholder, lambda: _trained(root, task_id, episodes, run, scripted))


def _trained(root: Path, task_id: str, episodes: int, run: tuple | None, scripted: bool) -> dict[str, Any]:
    """The dataset of a trained run's policy on ``task_id``, in the run's mode; skipped without one."""
    from unified_manip.datasets.recording import collect

    if run is None:
        why = "the scripted policy cannot" if scripted else "no scripted policy to"
        return {
            "task": task_id,
            "mode": "trained",
            "name": dataset_name(task_id, "trained"),
            "state": "skipped",
            "reason": f"{why} collect it and no finished run with a final model under results/ "
            "(models are committed only in results/policies/)",
        }
    make_policy, source, kwargs = run
    name = dataset_name(task_id, kwargs["action_mode"])
    entry = {"task": task_id, "mode": kwargs["action_mode"], "name": name, "episodes": episodes, "source": source}
    if (root / name).is_dir():
        return {**entry, "state": "written"}
    try:
        result = collect(
            task_id, kwargs, make_policy, "run", source, episodes, root / name, only_successful=True, progress=False
        )
    except DatasetError as err:
        return {**entry, "state": "skipped", "reason": str(err)}
    return {**entry, "state": "written", "success": result.success_rate}


def _read(root: Path) -> dict[str, dict[str, Any]]:
    path = root / MANIFEST
    return json.loads(path.read_text()) if path.is_file() else {}


def _write(root: Path, manifest: dict) -> None:
    tmp = root / f".{MANIFEST}.tmp"
    tmp.write_text(json.dumps(manifest, indent=2) + "\n")
    os.replace(tmp, root / MANIFEST)
