"""A run directory's own state: who owns it, what run it holds, how far it got.

``config.yaml`` says what run a directory holds (a different run is refused),
``status.json`` how far it got, and ``.lock`` who works in it now (one process at a
time, :mod:`unified_manip.runlock`). The rest (checkpoints, logs, models) belongs to
training; :func:`clear_outputs` removes it for ``--restart``.
"""

from __future__ import annotations

import json
import os
import shutil
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator

from .runlock import LOCK_FILE, DirectoryInUse, DirectoryLock

STATUS = "status.json"
CONFIG = "config.yaml"
#: What a run writes besides config.yaml and the lock (what ``--restart`` removes).
OUTPUTS = ("checkpoints", "monitor", "eval", "best", "tb", "final_model.zip", "replay_buffer.pkl", "vecnormalize.pkl",
           STATUS)


class RunDirectoryError(ValueError):
    """A run directory that cannot be used for this run (one-line error, exit 2)."""


def write_atomic(path: Path, text: str) -> None:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def read_status(run_dir: Path) -> dict[str, Any] | None:
    path = Path(run_dir) / STATUS
    if not path.is_file():
        return None
    return json.loads(path.read_text())


def write_status(run_dir: Path, **status: Any) -> None:
    write_atomic(Path(run_dir) / STATUS, json.dumps({**status, "updated": time.time()}, indent=2))


def read_config(run_dir: Path) -> dict[str, Any]:
    from .yamlfile import YamlFileError, load_mapping

    try:
        return load_mapping(Path(run_dir) / CONFIG, "a run's settings (written by unified-manip train)")
    except YamlFileError as err:
        raise RunDirectoryError(str(err)) from None


def check_same_run(run_dir: Path, config: dict[str, Any], compared: tuple[str, ...]) -> None:
    """Refuse a directory whose ``config.yaml`` differs from ``config`` in a ``compared`` key."""
    if (Path(run_dir) / CONFIG).is_file():
        stored = read_config(run_dir)
        diff = [k for k in compared if stored.get(k) != config[k]]
        if diff:
            raise RunDirectoryError(
                f"{run_dir} holds a different run (it differs in {', '.join(diff)}); choose another --run-dir"
            )


def clear_outputs(run_dir: Path) -> None:
    """Remove everything the run wrote but its config.yaml (and the lock)."""
    for name in OUTPUTS:
        path = Path(run_dir) / name
        shutil.rmtree(path) if path.is_dir() else path.unlink(missing_ok=True)


@contextmanager
def owned(run_dir: Path, wait_s: float = 0.0) -> Iterator[Path]:
    """Own ``run_dir`` (created if missing) for the duration of the ``with`` block.

    A file, a directory of other files, or one that another process owns (after
    waiting ``wait_s`` seconds for it) is refused with :class:`RunDirectoryError`. A
    directory made here that holds nothing but the lock when the block fails is removed
    again, so a refused request leaves nothing behind.
    """
    run_dir = Path(run_dir)
    if run_dir.exists() and not run_dir.is_dir():
        raise RunDirectoryError(f"{run_dir} is a file; expected a run directory (choose another --run-dir)")
    if run_dir.is_dir() and not (run_dir / CONFIG).is_file() and any(p.name != LOCK_FILE for p in run_dir.iterdir()):
        raise RunDirectoryError(f"{run_dir} exists and is not a unified-manip run directory; choose another --run-dir")
    created = not run_dir.exists()
    lock = DirectoryLock(run_dir, "run directory")
    try:
        lock.acquire(wait_s=wait_s)
    except DirectoryInUse as err:
        raise RunDirectoryError(str(err)) from None
    try:
        yield run_dir
    except BaseException:
        if created and [p.name for p in run_dir.iterdir()] == [LOCK_FILE]:
            lock.path.unlink()
            run_dir.rmdir()
        raise
    finally:
        lock.release()
