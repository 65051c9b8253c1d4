"""``unified-manip bench``: a grid of training runs, on this machine or a Ray cluster.

A grid file (``baselines/grids/*.yaml``) lists tasks x action modes x reward types x
algorithms x seeds, the budget and the evaluation schedule::

    name: action_spaces
    tasks: [UnifiedManip/Arm4Reach-v0, UnifiedManip/FetchReach-v0]
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
import traceback
from pathlib import Path
from typing import Any, Callable

import yaml

from unified_manip.experiments.grid import Grid, GridError, RunSpec, selected
from unified_manip.experiments.results import collect_row, write_results
from unified_manip.training.runlock import DirectoryLock

#: How long a run waits for its directory when another process still owns it (an
#: earlier attempt on a Ray node that has not noticed it was given up on, or a stray
#: ``train``) before it is refused and counted as a failed attempt.
RUN_LOCK_WAIT_S = 60.0


# ---------------------------------------------------------------------- one run
def run_one(spec: RunSpec, out_dir: str, threads: int = 1, device: str | None = None) -> dict[str, Any]:
    """Train one run (resuming if needed) and return its results row. Runs in a worker."""
    from unified_manip.training.train import TrainRequest, train

    run_dir = Path(out_dir) / "runs" / spec.name
    req = TrainRequest(
        env=spec.task,
        action_mode=spec.action_mode,
        reward_type=spec.reward_type,
        algo=spec.algo,
        steps=spec.steps,
        seed=spec.seed,
        n_envs=spec.n_envs,
        run_dir=run_dir,
        overrides=spec.overrides,
        device=device,
        env_kwargs=spec.env_kwargs,
    )
    train(req, argv=None, progress=False, log=lambda msg: None, threads=threads, lock_wait_s=RUN_LOCK_WAIT_S)
    row = collect_row(run_dir)
    if row is None:
        raise RuntimeError(f"{run_dir} did not finish")
    return row


# ---------------------------------------------------------------------- executors
class _LocalExecutor:
    """Runs on this machine, one spawned process per worker."""

    def __init__(self, workers: int):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        self.pool = ProcessPoolExecutor(
            max_workers=workers, mp_context=multiprocessing.get_context("spawn"), initializer=_ignore_sigint
        )

    def submit(self, *args):
        return self.pool.submit(run_one, *args)

    def wait(self, handles: list) -> list:
        from concurrent.futures import FIRST_COMPLETED, wait

        return list(wait(handles, return_when=FIRST_COMPLETED)[0])

    def result(self, handle) -> dict[str, Any]:
        return handle.result()

    def describe(self, err: Exception) -> str:
        return "".join(traceback.format_exception_only(type(err), err)).strip()

    def close(self) -> None:
        self.pool.shutdown(cancel_futures=True)


class _RayExecutor:
    """Runs as Ray tasks of one CPU each, on the cluster at ``address`` (or a local Ray)."""

    def __init__(self, address: str | None):
        import ray

        if not ray.is_initialized():
            ray.init(address=address, include_dashboard=False, log_to_driver=False, configure_logging=False)
        self.ray = ray
        self.remote = ray.remote(num_cpus=1, max_retries=0)(run_one)

    def submit(self, *args):
        return self.remote.remote(*args)

    def wait(self, handles: list) -> list:
        return self.ray.wait(handles, num_returns=1)[0]

    def result(self, handle) -> dict[str, Any]:
        return self.ray.get(handle)

    def describe(self, err: Exception) -> str:
        cause = getattr(err, "cause", None) or err
        return f"{type(cause).__name__}: {cause}".splitlines()[0]

    def close(self) -> None:
        pass


def _ignore_sigint() -> None:
    """Idle pool workers ignore Ctrl-C (the bench handles it); ``train`` turns it back on
    while a run learns, so a running run still checkpoints and stops."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _schedule(executor, todo: list[RunSpec], workers: int, args: tuple, done, postfix) -> None:
    """Keep ``workers`` runs going until every run of ``todo`` has finished or given up.

    ``done(spec, row, error)`` records an attempt and says whether to retry it (at the
    end of the queue); a crashed run never stops the grid."""
    queue = list(todo)
    pending: dict[Any, RunSpec] = {}
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
    (out_dir / "grid.yaml").write_text(yaml.safe_dump(grid.source, sort_keys=False))
    if command:
        (out_dir / "command.txt").write_text(command + "\n")
    rows = {r["run"]: r for r in (collect_row(out_dir / "runs" / s.name) for s in grid.runs) if r}
    todo = [s for s in grid.runs if s.name not in rows and (chosen is None or s.name in chosen)]
    failures: dict[str, str] = {}
    attempts = {s.name: 0 for s in todo}
    write_results(out_dir, list(rows.values()))
    workers = workers or max(1, os.cpu_count() or 1)

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

    if executor == "local":
        runner = _LocalExecutor(workers)
    elif executor == "ray":
        runner = _RayExecutor(address)
    else:
        raise GridError(f"unknown executor {executor!r}; expected 'local' or 'ray'")
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
