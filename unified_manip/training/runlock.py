"""Exclusive ownership of a directory: one process at a time trains a run or runs a bench.

The owner holds an OS lock (``fcntl.flock``) on ``<directory>/.lock`` for as long as it
works there. The kernel drops the lock when the process ends, however it ends, so a
``kill -9`` leaves no stale lock behind. The lock file also names its owner (pid, host
and start time), which is what a refused second process reports::

    run directory runs/reach is in use by pid 4242 on host lab-3 (started 2026-11-24 10:15:02)

The file stays after its owner is gone (removing a lock file races with the next
owner); only the lock on it matters. On shared storage (NFS), Linux maps ``flock`` to
POSIX byte-range locks, which the NFS lock manager arbitrates between machines.
"""

from __future__ import annotations

import fcntl
import json
import os
import socket
import time
from pathlib import Path

LOCK_FILE = ".lock"


class DirectoryInUse(RuntimeError):
    """Another live process owns the directory (reported as one line, exit 2)."""


class DirectoryLock:
    """The lock on one directory, held from :meth:`acquire` until :meth:`release`.

    Args:
        directory: The directory to own; created if missing.
        what: How the directory is named in the refusal, e.g. ``"run directory"``.

    Use it as a context manager, or call :meth:`acquire` and :meth:`release`.
    """

    def __init__(self, directory: Path, what: str = "run directory") -> None:
        self.directory = Path(directory)
        self.what = what
        self._fd: int | None = None

    @property
    def path(self) -> Path:
        return self.directory / LOCK_FILE

    def acquire(self, wait_s: float = 0.0, poll_s: float = 0.5) -> "DirectoryLock":
        """Take the lock, waiting up to ``wait_s`` seconds for a live owner to finish.

        Raises:
            DirectoryInUse: another process still holds it after ``wait_s``.
        """
        if self._fd is not None:
            return self
        self.directory.mkdir(parents=True, exist_ok=True)
        fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        deadline = time.monotonic() + wait_s
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except BlockingIOError:
                if time.monotonic() >= deadline:
                    os.close(fd)
                    raise DirectoryInUse(self._refusal()) from None
                time.sleep(poll_s)
        # Ours now: say who we are (read by the next process that is refused).
        owner = {"pid": os.getpid(), "host": socket.gethostname(), "started": time.time()}
        os.ftruncate(fd, 0)
        os.pwrite(fd, json.dumps(owner).encode(), 0)
        self._fd = fd
        return self

    def release(self) -> None:
        if self._fd is not None:
            fcntl.flock(self._fd, fcntl.LOCK_UN)
            os.close(self._fd)
            self._fd = None

    @property
    def held(self) -> bool:
        return self._fd is not None

    def __enter__(self) -> "DirectoryLock":
        return self.acquire()

    def __exit__(self, *exc) -> None:
        self.release()

    def _refusal(self) -> str:
        owner = read_owner(self.directory)
        if owner is None:  # the owner has not written its name yet
            return f"{self.what} {self.directory} is in use by another process"
        started = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(owner["started"]))
        return (
            f"{self.what} {self.directory} is in use by pid {owner['pid']} on host {owner['host']} (started {started})"
        )


def read_owner(directory: Path) -> dict | None:
    """``{"pid", "host", "started"}`` of the last process that took the lock, or ``None``.

    The owner may have ended since: only :meth:`DirectoryLock.acquire` tells whether the
    lock is still held.
    """
    try:
        owner = json.loads((Path(directory) / LOCK_FILE).read_text())
    except (OSError, ValueError):
        return None
    return owner if isinstance(owner, dict) and {"pid", "host", "started"} <= owner.keys() else None
