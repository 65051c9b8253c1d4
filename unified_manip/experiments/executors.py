"""Where a bench's runs train: :class:`LocalExecutor` (spawned processes on this machine)
or :class:`RayExecutor` (Ray tasks), each running :func:`run_one`.

An executor submits runs, waits for the first to end, and hands back its results row or
its error; :func:`unified_manip.experiments.bench.run_grid` schedules and records them.
"""

from __future__ import annotations

import os
import sys
import traceback
from pathlib import Path
from typing import Any

from unified_manip.experiments.grid import GridError, RunSpec
from unified_manip.experiments.results import collect_row

#: Linux: pool workers leave the bench's process group and are stopped with it
#: (see :func:`_worker_init`); elsewhere they share its group, and so its Ctrl-C.
OWN_GROUP = sys.platform.startswith("linux")

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
            max_workers=workers, mp_context=multiprocessing.get_context("spawn"), initializer=_worker_init
        )

    def submit(self, *args):
        return self.pool.submit(_run_in_worker, *args)

    def wait(self, handles: list) -> list:
        from concurrent.futures import FIRST_COMPLETED, wait

        return list(wait(handles, return_when=FIRST_COMPLETED)[0])

    def result(self, handle) -> dict[str, Any]:
        return handle.result()

    def describe(self, err: Exception) -> str:
        return "".join(traceback.format_exception_only(type(err), err)).strip()

    def interrupt(self, handles: list) -> None:
        """Pass a stop on to the runs in progress and wait while they checkpoint and stop
        (the pool knows its own; ``handles`` is for executors that do not).

        With :data:`OWN_GROUP` the workers hear of a stop only from here, once per
        interrupt of the bench: Ctrl-C, ``kill`` of the bench's pid or a hang-up. An
        interrupt while they stop is passed on too, and they then stop at once, resuming
        later from their last periodic checkpoint."""
        import multiprocessing
        import signal

        while True:
            if OWN_GROUP:
                for child in multiprocessing.active_children():
                    os.kill(child.pid, signal.SIGINT)  # an idle worker ignores it
            try:
                self.pool.shutdown(cancel_futures=True)
                return
            except KeyboardInterrupt:
                continue

    def close(self) -> None:
        self.pool.shutdown(cancel_futures=True)


class RayExecutor:
    """Runs as Ray tasks of one CPU each, on the cluster at ``address`` (or a local Ray)."""

    def __init__(self, address: str | None):
        import signal

        import ray

        if not ray.is_initialized():
            # ray.init puts its own SIGTERM handler (exit at once) in place of the
            # bench's clean stop; the bench's handlers are put back.
            kept = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)}
            try:
                ray.init(address=address, include_dashboard=False, log_to_driver=False, configure_logging=False)
            except Exception as err:  # a malformed or unreachable address, a node that does not start
                where = f"at --address {address}" if address else "on this machine"
                reason = (str(err).strip() or type(err).__name__).splitlines()[0]
                raise GridError(f"Ray did not start {where}: {reason}") from None
            for sig, handler in kept.items():
                signal.signal(sig, handler)
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

    def interrupt(self, handles: list) -> None:
        """Pass a stop on to the runs in progress (``handles``) and wait while they
        checkpoint and stop.

        ``ray.cancel`` interrupts a running task's main thread as SIGINT would, so
        ``train`` checkpoints and stops; a queued task never starts. An interrupt while
        they stop cancels them with ``force``, which ends their workers at once: those
        runs resume later from their last periodic checkpoint."""
        force = False
        while True:
            for ref in handles:
                self.ray.cancel(ref, force=force)
            try:
                self.ray.wait(handles, num_returns=len(handles))
                return
            except KeyboardInterrupt:
                force = True

    def close(self) -> None:
        pass


#: The bench's pid, in a pool worker (see :func:`_worker_init`).
_bench_pid: int | None = None


def _worker_init() -> None:
    """Set up a pool worker: idle, it ignores SIGINT; ``train`` handles it while a run
    learns, so a running run checkpoints and stops.

    With :data:`OWN_GROUP` the worker leaves the bench's process group, so a stop reaches
    it once, passed on by :meth:`LocalExecutor.interrupt`, and it is sent SIGINT when the
    bench dies (``PR_SET_PDEATHSIG``): a bench killed outright leaves its runs
    checkpointed and stopped, and its workers gone, not training on with no one to
    record them."""
    import ctypes
    import signal

    global _bench_pid
    _bench_pid = os.getppid()
    signal.signal(signal.SIGINT, _idle_sigint)
    if OWN_GROUP:
        pr_set_pdeathsig = 1
        if ctypes.CDLL(None, use_errno=True).prctl(pr_set_pdeathsig, int(signal.SIGINT), 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_SET_PDEATHSIG) failed")
        os.setpgrp()
        _exit_if_orphaned()  # the bench died before the prctl


def _idle_sigint(signum, frame) -> None:
    """SIGINT between runs: ignored, unless the bench has died (then the worker ends)."""
    _exit_if_orphaned()


def _exit_if_orphaned() -> None:
    if os.getppid() != _bench_pid:
        os._exit(1)  # no one is left to hand a run to it or to read its results


def _run_in_worker(spec: RunSpec, *args) -> dict[str, Any]:
    """:func:`run_one` in a pool worker, which ends after the run if the bench has died."""
    _exit_if_orphaned()
    try:
        return run_one(spec, *args)
    finally:
        _exit_if_orphaned()
