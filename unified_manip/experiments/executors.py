"""Where a bench's runs train: :class:`LocalExecutor` (spawned processes on this machine)
or :class:`RayExecutor` (Ray tasks), each running :func:`run_one`.

An executor submits runs, waits for the first to end, and hands back its results row or
its error; :func:`unified_manip.experiments.bench.run_grid` schedules and records them.
"""

from __future__ import annotations

import traceback
from pathlib import Path
from typing import Any

from unified_manip.experiments.grid import RunSpec
from unified_manip.experiments.results import collect_row

#: How long a run waits for its directory when another process still owns it (an
#: earlier attempt on a Ray node that has not noticed it was given up on, or a stray
#: ``train``) before it is refused and counted as a failed attempt.
RUN_LOCK_WAIT_S = 60.0


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


class LocalExecutor:
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


class RayExecutor:
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
