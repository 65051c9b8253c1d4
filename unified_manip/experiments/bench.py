"""``unified-manip bench``: a grid of training runs, on this machine or a Ray cluster.

A grid file (``baselines/grids/*.yaml``) lists tasks x action modes x reward types x
algorithms x seeds, the budget and the evaluation schedule::

    name: action_spaces
    tasks: [UnifiedManip/Arm4Reach-v0, UnifiedManip/FetchReach-v0]   # or a named list: metaworld:MT10
    action_modes: all              # or a list; "all" = every mode each task supports
    reward_types: [sparse]
    algos: [sac_her]
    seeds: [0, 1, 2]
    steps: 10000                   # env steps per run, or {default: N, <task ID>: N, ...}
    n_envs: {default: 1, ppo: 8}   # optional: envs per run (or one number), by algorithm
                                   # (not given: the hyperparameter file's n_envs, else 1)
    eval_freq: 1000                # env steps between evaluations
    n_eval_episodes: 20
    overrides: {sac_her: [learning_starts=500]}   # optional, per algorithm
    env_kwargs: {controller_options: {band: 0.75}}  # optional: extra gym.make arguments, every run
    randomizations: [none, dynamics]  # optional: training randomisation presets crossed with the rest
    only:                          # optional: keep just the combinations matching an entry
      - {algo: ppo, reward_type: sparse}
    targets:                       # optional: final success the report checks
      - {task: UnifiedManip/Arm4Reach-v0, action_mode: ee_delta, success: 0.95}

Each run is the ``train`` command's run, in ``<out>/runs/<run name>``. Re-running a bench
skips finished runs and resumes unfinished ones from their checkpoints. One bench at a
time owns ``<out>`` (a second is refused), and the worker that trains a run owns that
run's directory, so a retried run never writes beside an attempt still alive. A run that
crashes is retried up to ``retries`` times and then recorded as failed with its error;
it never blocks the rest. ``<out>/results.csv`` gets one row per *finished* run, and is
rewritten atomically after every run, so it never holds a half-written run.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path
from typing import Any, Callable

import yaml

from unified_manip.experiments.executors import LocalExecutor, RayExecutor
from unified_manip.experiments.grid import Grid, GridError, RunSpec, selected
from unified_manip.experiments.results import collect_row, write_results
from unified_manip.training.runlock import DirectoryLock


def _schedule(executor, todo: list[RunSpec], workers: int, args: tuple, done, postfix) -> None:
    """Keep ``workers`` runs going until every run of ``todo`` has finished or given up.

    ``done(spec, row, error)`` records an attempt and says whether to retry it (at the
    end of the queue); a crashed run never stops the grid."""
    queue = list(todo)
    pending: dict[Any, RunSpec] = {}
    try:
        while queue or pending:
            while queue and len(pending) < workers:
                spec = queue.pop(0)
                pending[executor.submit(spec, *args)] = spec
            postfix(len(pending))
            for handle in executor.wait(list(pending)):
                spec = pending.pop(handle)
                try:
                    retry = done(spec, executor.result(handle), None)
                except Exception as err:  # a crashed run must not stop the grid
                    retry = done(spec, None, executor.describe(err))
                if retry:
                    queue.append(spec)
    except KeyboardInterrupt:
        executor.interrupt(list(pending))  # the runs in progress checkpoint and stop
        raise


def run_grid(
    grid: Grid,
    out_dir: Path,
    executor: str = "local",
    workers: int | None = None,
    address: str | None = None,
    retries: int = 1,
    progress: bool = True,
    command: str | None = None,
    on_event: Callable[[str, RunSpec], None] | None = None,
    device: str | None = None,
    select: tuple[str, ...] = (),
    collect: bool = False,
) -> dict[str, Any]:
    """Run every run of ``grid`` that is not finished yet; return a summary.

    ``device`` (auto, cpu or cuda) applies to every run; it is checked here, before any
    run starts, so ``cuda`` without a GPU fails once and not once per run. With
    ``collect``, no run starts: ``results.csv`` is written from the finished runs in
    ``out_dir/runs`` (copied in from another bench directory, say), and ``command.txt``,
    the command that trained them, is left as it is.

    Raises :class:`~unified_manip.training.runlock.DirectoryInUse` if another bench owns ``out_dir``.
    """
    if executor not in ("local", "ray"):
        raise GridError(f"unknown executor {executor!r}; expected 'local' or 'ray'")
    if address and executor != "ray":
        raise GridError(f"--address names a Ray cluster, for --executor ray; this bench's executor is {executor!r}")
    if collect and select:
        raise GridError("--only chooses runs to train and --collect trains none; give one or the other")
    if device is not None:
        from unified_manip.training.devices import DeviceError, resolve_device

        try:
            resolve_device(device)
        except DeviceError as err:
            raise GridError(str(err)) from None
    out_dir = Path(out_dir).resolve()
    with DirectoryLock(out_dir, "bench directory"):
        return _run_owned(
            grid,
            out_dir,
            executor,
            workers,
            address,
            retries,
            progress,
            None if collect else command,
            on_event,
            device,
            set() if collect else selected(grid, select),
        )


def _run_owned(
    grid: Grid,
    out_dir: Path,
    executor: str,
    workers: int | None,
    address: str | None,
    retries: int,
    progress: bool,
    command: str | None,
    on_event,
    device: str | None,
    chosen: set[str] | None = None,
) -> dict[str, Any]:
    rows = {r["run"]: r for r in (collect_row(out_dir / "runs" / s.name) for s in grid.runs) if r}
    todo = [s for s in grid.runs if s.name not in rows and (chosen is None or s.name in chosen)]
    workers = workers or max(1, os.cpu_count() or 1)
    # Started before anything is written: an executor that cannot start leaves the
    # directory as it was.
    runner = (LocalExecutor(workers) if executor == "local" else RayExecutor(address)) if todo else None
    (out_dir / "grid.yaml").write_text(yaml.safe_dump(grid.source, sort_keys=False))
    if command:
        (out_dir / "command.txt").write_text(command + "\n")
    failures: dict[str, str] = {}
    attempts = {s.name: 0 for s in todo}
    write_results(out_dir, list(rows.values()))

    from tqdm import tqdm

    bar = tqdm(
        total=len(grid.runs), initial=len(rows), unit="run", desc=grid.name, disable=not progress, dynamic_ncols=True
    )
    started = time.time()

    def done(spec: RunSpec, row: dict | None, error: str | None) -> bool:
        """Record a finished attempt; return True if the run should be retried."""
        attempts[spec.name] += 1
        if row is not None:
            rows[spec.name] = row
            failures.pop(spec.name, None)
            write_results(out_dir, list(rows.values()))
            bar.update(1)
            if on_event:
                on_event("finished", spec)
            return False
        failures[spec.name] = error or "unknown error"
        _record_failure(out_dir, spec, failures[spec.name], attempts[spec.name])
        if on_event:
            on_event("failed", spec)
        return attempts[spec.name] <= retries

    def postfix(running: int) -> None:
        bar.set_postfix(running=running, failed=len(failures), refresh=True)

    if runner is not None:
        try:
            _schedule(runner, todo, workers, (str(out_dir), 1, device), done, postfix)
        finally:
            runner.close()
    postfix(0)
    bar.close()
    return {
        "runs": len(grid.runs),
        "finished": len(rows),
        "failed": sorted(failures),
        "wall_time_s": time.time() - started,
        "results": str(out_dir / "results.csv"),
    }


def _record_failure(out_dir: Path, spec: RunSpec, error: str, attempt: int) -> None:
    with (Path(out_dir) / "failures.jsonl").open("a") as f:
        f.write(json.dumps({"run": spec.name, "attempt": attempt, "error": error, "time": time.time()}) + "\n")
