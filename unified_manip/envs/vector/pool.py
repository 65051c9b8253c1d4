"""A persistent thread pool that runs one function over many env indices.

MuJoCo's ``mj_step`` releases the GIL, so N simulations stepped from T threads run up
to T times faster than from one, as long as the Python around each call is short. The
pool keeps ``num_threads - 1`` worker threads alive for the life of the vector env; the
calling thread is the last worker, so a call costs one wake-up and no thread start.
Indices are handed out one at a time from a shared iterator (``next`` on a list
iterator is atomic under the GIL), which balances envs whose steps cost different
amounts (contacts, IK) without any partitioning.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor, wait
from typing import Callable, Sequence


def default_num_threads() -> int:
    """The cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


class PhysicsPool:
    """``num_threads`` threads (the caller included) that run ``fn(i)`` for given ``i``.

    Args:
        num_threads: Threads to step on, at least 1; 1 runs everything on the caller.

    Raises:
        ValueError: ``num_threads`` is not a positive int.
    """

    def __init__(self, num_threads: int) -> None:
        if not isinstance(num_threads, int) or isinstance(num_threads, bool) or num_threads < 1:
            raise ValueError(f"num_threads must be a positive int, got {num_threads!r}")
        self.num_threads = num_threads
        self.closed = False
        self._executor: ThreadPoolExecutor | None = None
        if num_threads > 1:
            self._executor = ThreadPoolExecutor(max_workers=num_threads - 1, thread_name_prefix="unified-manip-physics")

    def run(self, fn: Callable[[int], None], indices: Sequence[int]) -> None:
        """Call ``fn(i)`` for every ``i`` in ``indices``, spread over the threads.

        Returns when all calls have finished. The first exception raised by any call is
        re-raised here (the other threads finish their current index and stop).

        Raises:
            RuntimeError: The pool was shut down.
        """
        if self.closed:
            raise RuntimeError("the physics thread pool is shut down (the vector env was closed)")
        executor = self._executor
        helpers = 0 if executor is None else min(self.num_threads - 1, len(indices) - 1)
        if executor is None or helpers <= 0:
            for i in indices:
                fn(i)
            return
        todo = iter(indices)
        failed: list[BaseException] = []

        def drain() -> None:
            for i in todo:
                if failed:
                    return
                try:
                    fn(i)
                except BaseException as exc:  # re-raised on the calling thread
                    failed.append(exc)
                    return

        futures = [executor.submit(drain) for _ in range(helpers)]
        drain()
        for f in futures:
            f.result()
        if failed:
            raise failed[0]

    def pipeline(self, prepare: Callable[[int], None], advance: Callable[[int], None], indices: Sequence[int]) -> None:
        """``prepare(i)`` then ``advance(i)`` for every ``i``: the calling thread runs every
        ``prepare`` in order and hands each ``advance`` to the worker threads as soon as
        its ``prepare`` is done.

        For steps whose first part is Python that holds the GIL (mink's IK) and whose
        second part is mostly ``mj_step`` (which releases it): the Python of one thread
        overlaps the physics of the others, where :meth:`run` would have two threads
        contend for the GIL. With one thread, runs both parts in turn.

        Raises:
            RuntimeError: The pool was shut down.
        """
        if self.closed:
            raise RuntimeError("the physics thread pool is shut down (the vector env was closed)")
        if self._executor is None:
            for i in indices:
                prepare(i)
                advance(i)
            return
        futures = []
        try:
            for i in indices:
                prepare(i)
                futures.append(self._executor.submit(advance, i))
        finally:
            wait(futures)
        for f in futures:
            f.result()  # re-raise the first failure

    def shutdown(self) -> None:
        """Stop the worker threads and wait for them; idempotent."""
        self.closed = True
        if self._executor is not None:
            self._executor.shutdown(wait=True)
            self._executor = None
