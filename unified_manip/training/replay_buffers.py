"""Replay buffers saved trimmed to their filled part and restored to the same capacity.

Stable-Baselines3 preallocates every replay buffer at full capacity and
``save_replay_buffer`` pickles all of it: a 1e6-transition buffer is hundreds of MB on
disk after a few thousand steps. :func:`save_trimmed` writes only the rows that hold
transitions; :func:`restore` copies them into a freshly allocated buffer of the same
capacity (the one the model built from its hyperparameters), so training goes on
exactly as if the buffer had never left memory.

Per-row arrays are found by shape, not by name: every ndarray attribute of shape
``(buffer_size, n_envs, ...)``, and every dict of such arrays (``observations`` of a
``DictReplayBuffer``). That covers ``ReplayBuffer``, ``DictReplayBuffer`` and
``HerReplayBuffer`` (whose ``ep_start``, ``ep_length`` and ``infos`` are per row),
and subclasses that add per-row arrays. The other ndarray attributes (HER's
``_current_ep_start``) and ``pos`` / ``full`` are saved whole.
"""

from __future__ import annotations

import os
import pickle
from pathlib import Path
from typing import Any

import numpy as np

FORMAT = "unified_manip.trimmed_replay_buffer/1"


class ReplayBufferMismatch(ValueError):
    """A saved buffer does not fit the buffer it is restored into."""


def _rows_kept(buffer) -> int:
    if buffer.full:
        return buffer.buffer_size
    # With optimize_memory_usage the next observation of row pos-1 lives in row pos.
    extra = 1 if getattr(buffer, "optimize_memory_usage", False) else 0
    return min(buffer.pos + extra, buffer.buffer_size)


def _is_row_array(value: Any, buffer) -> bool:
    return isinstance(value, np.ndarray) and value.ndim >= 2 and value.shape[:2] == (buffer.buffer_size, buffer.n_envs)


def _is_row_dict(value: Any, buffer) -> bool:
    return isinstance(value, dict) and bool(value) and all(_is_row_array(v, buffer) for v in value.values())


def trimmed_state(buffer) -> dict[str, Any]:
    """What :func:`save_trimmed` writes: the filled rows and the buffer's small state."""
    keep = _rows_kept(buffer)
    rows: dict[str, Any] = {}
    small: dict[str, np.ndarray] = {}
    for name, value in vars(buffer).items():
        if _is_row_array(value, buffer):
            rows[name] = value[:keep]
        elif _is_row_dict(value, buffer):
            rows[name] = {k: v[:keep] for k, v in value.items()}
        elif isinstance(value, np.ndarray):
            small[name] = value
    return {
        "format": FORMAT,
        "class": f"{type(buffer).__module__}.{type(buffer).__qualname__}",
        "buffer_size": buffer.buffer_size,
        "n_envs": buffer.n_envs,
        "pos": buffer.pos,
        "full": buffer.full,
        "rows_kept": keep,
        "rows": rows,
        "small": small,
    }


def save_trimmed(buffer, path: Path) -> int:
    """Pickle the filled part of ``buffer`` to ``path``; return the number of rows kept.

    The caller makes the write atomic (this writes ``path`` directly).
    """
    state = trimmed_state(buffer)
    with open(path, "wb") as f:
        pickle.dump(state, f, protocol=pickle.HIGHEST_PROTOCOL)
        f.flush()
        os.fsync(f.fileno())
    return state["rows_kept"]


def restore(buffer, path: Path) -> None:
    """Fill ``buffer`` (freshly allocated, same capacity) from a :func:`save_trimmed` file.

    A buffer class may name, in ``restores_from``, other classes whose saves it takes
    (:class:`~unified_manip.training.her.GoalRelHerReplayBuffer` takes SB3's
    HerReplayBuffer's: the same rows).

    Raises:
        ReplayBufferMismatch: the file is not a trimmed buffer, or its class, capacity,
            env count or row layout differ from ``buffer``'s.
    """
    with open(path, "rb") as f:
        state = pickle.load(f)
    if not isinstance(state, dict) or state.get("format") != FORMAT:
        raise ReplayBufferMismatch(f"not a trimmed replay buffer (expected format {FORMAT})")
    cls = f"{type(buffer).__module__}.{type(buffer).__qualname__}"
    saved = _current_name(state["class"])
    if saved != cls and saved not in getattr(type(buffer), "restores_from", ()):
        raise ReplayBufferMismatch(f"saved from a {state['class']}, restoring into a {cls}")
    if (state["buffer_size"], state["n_envs"]) != (buffer.buffer_size, buffer.n_envs):
        raise ReplayBufferMismatch(
            f"capacity {state['buffer_size']} x {state['n_envs']} envs saved, "
            f"{buffer.buffer_size} x {buffer.n_envs} expected (buffer_size or n_envs changed)"
        )
    keep = state["rows_kept"]
    current = vars(buffer)
    for name, saved in state["rows"].items():
        target = current.get(name)
        if isinstance(saved, dict):
            if not _is_row_dict(target, buffer) or target.keys() != saved.keys():
                raise ReplayBufferMismatch(f"{name}: saved keys {sorted(saved)} do not match the buffer's")
            for key, rows in saved.items():
                _copy_rows(f"{name}[{key!r}]", target[key], rows, keep)
        else:
            if not _is_row_array(target, buffer):
                raise ReplayBufferMismatch(f"{name}: the buffer has no such per-row array")
            _copy_rows(name, target, saved, keep)
    for name, value in state["small"].items():
        target = current.get(name)
        if not isinstance(target, np.ndarray) or target.shape != value.shape:
            raise ReplayBufferMismatch(f"{name}: saved shape {value.shape} does not match the buffer's")
        target[...] = value
    buffer.pos = int(state["pos"])
    buffer.full = bool(state["full"])


#: Modules of this project's buffer classes that moved: the old dotted name -> the new.
RENAMED_MODULES: dict[str, str] = {"unified_manip.crossq": "unified_manip.training.crossq"}


def _current_name(class_path: str) -> str:
    """A saved buffer's class path under today's module names."""
    module, _, name = class_path.rpartition(".")
    return f"{RENAMED_MODULES.get(module, module)}.{name}"


def _copy_rows(name: str, target: np.ndarray, rows: np.ndarray, keep: int) -> None:
    if rows.shape != (keep,) + target.shape[1:] or rows.dtype != target.dtype:
        raise ReplayBufferMismatch(
            f"{name}: saved rows {rows.shape} {rows.dtype}, buffer rows {(keep,) + target.shape[1:]} {target.dtype}"
        )
    target[:keep] = rows
