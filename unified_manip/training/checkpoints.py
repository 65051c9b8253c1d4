"""Resumable checkpoints of a training run: atomic files, a manifest written last, and
verification with a fall-back on resume.

Layout, one directory per checkpoint, named by its step count::

    checkpoints/000000004000/model.zip           the SB3 model (step count, optimiser state)
                            replay_buffer.pkl   off-policy runs: the filled part of the buffer
                            vecnormalize.pkl    normalize runs: observation statistics
                            manifest.json       written last: step, and size + SHA-256 of each file

Each file is written under a temporary name, flushed to disk and renamed. A checkpoint
exists only once its manifest does: a writer killed half-way leaves a directory
without one, which is never read and is removed by the next writer. The last
:data:`KEEP` checkpoints are kept, so one damaged by anything after its manifest
(a truncated copy, a bad disk) still leaves an older one to resume from.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

from unified_manip.training import replay_buffers

CHECKPOINTS = "checkpoints"
MANIFEST = "manifest.json"
MODEL, REPLAY_BUFFER, VECNORMALIZE = "model.zip", "replay_buffer.pkl", "vecnormalize.pkl"
KEEP = 2
#: Test hook: with this set to N, the N-th checkpoint this process writes pauses after
#: its model file, creating ``PAUSED`` in its directory and waiting until that file is
#: removed (the fault-injection tests kill the writer there, or hold it while a second
#: process tries the same directory).
PAUSE_ENV = "UNIFIED_MANIP_TEST_PAUSE_CHECKPOINT"
_written = 0


class CheckpointError(Exception):
    """A checkpoint that cannot be loaded; the message names the file and why."""


@dataclass(frozen=True)
class Checkpoint:
    """One published checkpoint.

    Attributes:
        directory: Where it lives.
        step: Its step count.
        files: :data:`MODEL`, :data:`REPLAY_BUFFER`, :data:`VECNORMALIZE` -> path (the
            ones it has).
        digests: The manifest's ``size`` and ``sha256`` of each file.
        legacy: The one-checkpoint layout of earlier versions (``latest.json``,
            ``model_<step>.zip``, SB3's whole-buffer pickle), read so that runs started
            before it changed still resume; it has no digests.
    """

    directory: Path
    step: int
    files: dict[str, Path]
    digests: dict[str, dict[str, Any]]
    legacy: bool = False

    def path(self, key: str) -> Path | None:
        """The checkpoint's :data:`MODEL`, :data:`REPLAY_BUFFER` or :data:`VECNORMALIZE`
        file, or ``None`` if it has none."""
        return self.files.get(key)


# ---------------------------------------------------------------------- writing
def _fsync_dir(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _publish_file(tmp: Path, final: Path) -> dict[str, Any]:
    """fsync ``tmp``, rename it to ``final``; return its size and SHA-256."""
    with open(tmp, "rb") as f:
        os.fsync(f.fileno())
        digest = hashlib.file_digest(f, "sha256").hexdigest()
    os.replace(tmp, final)
    return {"size": final.stat().st_size, "sha256": digest}


def write(model, run_dir: Path, off_policy: bool) -> Checkpoint:
    """Write a checkpoint of ``model`` at its current step and keep the last :data:`KEEP`.

    A checkpoint already published at this step is kept as it is.
    """
    global _written
    root = Path(run_dir) / CHECKPOINTS
    step = int(model.num_timesteps)
    existing = {c.step: c for c in published(run_dir) if not c.legacy}
    if step in existing:
        return existing[step]
    directory = root / f"{step:012d}"
    shutil.rmtree(directory, ignore_errors=True)  # an unpublished attempt at this step
    directory.mkdir(parents=True)
    _written += 1
    files = {}
    model.save(directory / "model.tmp.zip")
    files[MODEL] = _publish_file(directory / "model.tmp.zip", directory / MODEL)
    if os.environ.get(PAUSE_ENV) == str(_written):
        marker = directory / "PAUSED"
        marker.touch()
        while marker.exists():
            time.sleep(0.05)
    if off_policy:
        rows = replay_buffers.save_trimmed(model.replay_buffer, directory / "replay_buffer.tmp")
        files[REPLAY_BUFFER] = _publish_file(directory / "replay_buffer.tmp", directory / REPLAY_BUFFER)
        files[REPLAY_BUFFER]["rows"] = rows
    if model.get_vec_normalize_env() is not None:
        model.get_vec_normalize_env().save(str(directory / "vecnormalize.tmp"))
        files[VECNORMALIZE] = _publish_file(directory / "vecnormalize.tmp", directory / VECNORMALIZE)
    manifest = {"num_timesteps": step, "files": files, "written": time.time()}
    tmp = directory / "manifest.tmp"
    tmp.write_text(json.dumps(manifest, indent=2))
    _publish_file(tmp, directory / MANIFEST)
    _fsync_dir(directory)
    prune(run_dir)
    return Checkpoint(directory, step, {k: directory / k for k in files}, files)


def prune(run_dir: Path, keep: int = KEEP) -> None:
    """Remove all but the newest ``keep`` published checkpoints, and every unpublished
    directory (a writer that was killed). Only the run's lock holder may call this."""
    root = Path(run_dir) / CHECKPOINTS
    if not root.is_dir():
        return
    kept: set[Path] = set()
    for c in published(run_dir)[:keep]:
        kept |= {root / "latest.json", *c.files.values()} if c.legacy else {c.directory}
    for entry in root.iterdir():
        if entry not in kept:
            shutil.rmtree(entry) if entry.is_dir() else entry.unlink()


# ---------------------------------------------------------------------- reading
def published(run_dir: Path) -> list[Checkpoint]:
    """Every checkpoint with a readable manifest, newest first."""
    root = Path(run_dir) / CHECKPOINTS
    found = []
    if root.is_dir():
        for directory in root.iterdir():
            try:
                manifest = json.loads((directory / MANIFEST).read_text())
                digests = {k: dict(v) for k, v in manifest["files"].items()}
                found.append(
                    Checkpoint(directory, int(manifest["num_timesteps"]), {k: directory / k for k in digests}, digests)
                )
            except (OSError, ValueError, KeyError, TypeError, AttributeError):
                continue
        legacy = _legacy(root)
        if legacy is not None:
            found.append(legacy)
    return sorted(found, key=lambda c: c.step, reverse=True)


def _legacy(root: Path) -> Checkpoint | None:
    try:
        entry = json.loads((root / "latest.json").read_text())
        files = {MODEL: root / entry["model"]}
        if "replay_buffer" in entry:
            files[REPLAY_BUFFER] = root / entry["replay_buffer"]
        if "vecnormalize" in entry:
            files[VECNORMALIZE] = root / entry["vecnormalize"]
        return Checkpoint(root, int(entry["num_timesteps"]), files, {}, legacy=True)
    except (OSError, ValueError, KeyError, TypeError):
        return None


def newest(run_dir: Path) -> Checkpoint | None:
    found = published(run_dir)
    return found[0] if found else None


def verify(ckpt: Checkpoint) -> None:
    """Check every file against the manifest's size and SHA-256.

    Raises:
        CheckpointError: naming the first file that is missing, truncated or altered.
    """
    for key, path in ckpt.files.items():
        if not path.is_file():
            raise CheckpointError(f"{path}: missing")
        expected = ckpt.digests.get(key)
        if expected is None:  # the legacy layout
            continue
        size = path.stat().st_size
        if size != expected["size"]:
            raise CheckpointError(
                f"{path}: {size} bytes, the manifest says {expected['size']} (truncated or overwritten)"
            )
        with open(path, "rb") as f:
            if hashlib.file_digest(f, "sha256").hexdigest() != expected["sha256"]:
                raise CheckpointError(f"{path}: contents differ from the manifest's SHA-256 (corrupted)")


def restore_replay_buffer(model, ckpt: Checkpoint) -> None:
    """Fill ``model``'s own (full-capacity) replay buffer from the checkpoint, as SB3's
    ``load_replay_buffer`` would: a HER buffer gets the env and its last, unfinished
    episode is closed (training goes on with a fresh episode)."""
    from stable_baselines3 import HerReplayBuffer

    path = ckpt.path(REPLAY_BUFFER)
    if ckpt.legacy:
        model.load_replay_buffer(path)
        return
    try:
        replay_buffers.restore(model.replay_buffer, path)
    except (replay_buffers.ReplayBufferMismatch, OSError, EOFError, ValueError) as err:
        raise CheckpointError(f"{path}: {err}") from None
    if isinstance(model.replay_buffer, HerReplayBuffer):
        import warnings

        with warnings.catch_warnings():  # SB3 warns that it closes the last episode: that is the intent
            warnings.simplefilter("ignore")
            model.replay_buffer.truncate_last_trajectory()


def load_first_good(
    candidates: list[Checkpoint], load: Callable[[Checkpoint], Any], warn: Callable[[str], None]
) -> tuple[Any, Checkpoint]:
    """Load the newest checkpoint that verifies and loads, falling back one at a time.

    ``load`` builds whatever the caller needs from a verified checkpoint (raising
    :class:`CheckpointError` or any exception if it cannot). Each checkpoint that fails
    is reported with one line through ``warn`` and removed, so training resumes from the
    one that loaded and never mixes its new checkpoints with a damaged one.

    Raises:
        CheckpointError: none loads; the message lists every file and why.
    """
    reasons = []
    for i, ckpt in enumerate(candidates):
        try:
            verify(ckpt)
            result = load(ckpt)
        except CheckpointError as err:
            why = str(err)
        except Exception as err:  # a file that verifies but does not load (e.g. another SB3 version)
            why = f"{ckpt.directory}: {type(err).__name__}: {str(err).splitlines()[0] if str(err) else ''}"
        else:
            for bad in candidates[:i]:
                if bad.legacy:
                    for path in bad.files.values():
                        path.unlink(missing_ok=True)
                    (bad.directory / "latest.json").unlink(missing_ok=True)
                else:
                    shutil.rmtree(bad.directory, ignore_errors=True)
            return result, ckpt
        reasons.append(why)
        if i + 1 < len(candidates):
            warn(
                f"warning: checkpoint at step {ckpt.step} cannot be loaded ({why}); "
                f"falling back to the checkpoint at step {candidates[i + 1].step}"
            )
    raise CheckpointError("; ".join(reasons))
