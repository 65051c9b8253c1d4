"""The domain randomisation of a native vector env: each env's own terms on its own
model, drawn from its own generator, as the single env draws them."""

from __future__ import annotations

from typing import Any, Callable, Mapping

import numpy as np

from unified_manip.envs.config import EnvConfig
from unified_manip.envs.randomization.randomizer import Randomizer, build_randomizer
from unified_manip.envs.vector import infos as vinfo
from unified_manip.envs.vector.batched import BatchedBackend

Drawn = dict[int, dict[str, float]]  # env index -> the values it drew


class RandomizerRows:
    """The randomisers of ``batched``'s N envs, one per env; inert under ``none``.

    Args:
        config: The env options (``randomization``).
        task: The task's spec (its entities).
        batched: The family's batched backend.
        task_id: The registered ID, for error messages.
    """

    def __init__(self, config: EnvConfig, task: Any, batched: BatchedBackend, task_id: str) -> None:
        self._batched = batched
        rows = [
            build_randomizer(config.randomization, task.entities, batched.backend(i), task_id)
            for i in range(batched.num_envs)
        ]
        self._rows: list[Randomizer] | None = None if rows[0] is None else rows  # type: ignore[assignment]

    def reset(self, i: int, rng: np.random.Generator, seeded: bool, drawn: Drawn) -> None:
        """Draw env ``i``'s reset values (before its backend resets, as the single env) into
        ``drawn[i]``."""
        if self._rows is not None:
            drawn[i] = self._rows[i].reset(self._batched.backend(i), rng, seeded)

    def step(self, stepping: np.ndarray, rng: Callable[[int], np.random.Generator]) -> Drawn:
        """The interval draws of the envs that step, before the physics (as the single env)."""
        drawn: Drawn = {}
        if self._rows is not None:
            for i in np.flatnonzero(stepping):
                values = self._rows[i].step(self._batched.backend(int(i)), rng(int(i)))
                if values is not None:
                    drawn[int(i)] = values
        return drawn

    def state(self, index: int) -> dict[str, float]:
        """Env ``index``'s randomised values in force; empty under ``none``."""
        return {} if self._rows is None else self._rows[index].state()

    def merge(self, info: dict[str, Any], drawn: Mapping[int, Mapping[str, float]]) -> dict[str, Any]:
        """``info`` with ``info["randomization"]`` of the envs in ``drawn``."""
        return vinfo.merge_rows(info, "randomization", drawn, self._batched.num_envs)
