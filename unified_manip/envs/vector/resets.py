"""What ``NativeVectorEnv.reset`` is asked to do: which seed each env gets, and which envs
reset (Gymnasium's ``seed`` and ``options["reset_mask"]`` conventions), and which a
``step()`` resets (its ``AutoresetMode``)."""

from __future__ import annotations

from typing import Sequence

import numpy as np
from gymnasium.vector import AutoresetMode


def env_seeds(seed: int | Sequence[int | None] | None, n: int) -> list[int | None]:
    """Env ``i``'s seed: ``seed + i`` (an int), ``seed[i]`` (a list) or none (None)."""
    if seed is None:
        return [None] * n
    if isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
        return [int(seed) + i for i in range(n)]
    seeds = list(seed)  # type: ignore[arg-type]  # a sequence here (bools are ints)
    if len(seeds) != n:
        raise ValueError(f"seed must be None, an int or a list of num_envs={n} seeds, got {len(seeds)} seeds")
    return seeds


def reset_mask(options: dict | None, n: int) -> np.ndarray:
    """The envs to reset: ``options["reset_mask"]`` (a bool array of shape ``(n,)`` with a
    True) where given, else all of them."""
    if options is None or "reset_mask" not in options:
        return np.ones(n, dtype=bool)
    mask = options["reset_mask"]
    if not isinstance(mask, np.ndarray) or mask.shape != (n,) or mask.dtype != np.bool_ or not mask.any():
        raise ValueError(f"options['reset_mask'] must be a bool array of shape ({n},) with a True, got {mask!r}")
    return mask


def step_resets(mode: AutoresetMode, ended: np.ndarray) -> np.ndarray:
    """The envs a ``step()`` resets instead of stepping: under ``NEXT_STEP`` those whose
    episode ``ended`` on the last step, else none (``SAME_STEP`` reset them then;
    ``DISABLED`` refuses to step an ended env)."""
    if mode == AutoresetMode.NEXT_STEP:
        return ended.copy()
    if mode == AutoresetMode.DISABLED and ended.any():
        i = int(np.flatnonzero(ended)[0])
        raise ValueError(f"env {i} has ended its episode: reset it first (reset(options={{'reset_mask': ...}}))")
    return np.zeros(ended.shape, dtype=bool)
