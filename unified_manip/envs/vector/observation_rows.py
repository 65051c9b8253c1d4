"""The observation design of a native vector env: each env's stream (its groups and
sensor model, drawn from that env's generator) and camera, one row per env."""

from __future__ import annotations

from typing import Any, Callable, Sequence

import numpy as np

from unified_manip.envs.cameras import ImageSensor, image_sensor
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.observations import build_stream, reattach
from unified_manip.envs.vector.batched import BatchedBackend


class ObservationRows:
    """The design's observations of ``batched``'s N envs, as the single env builds them.

    Args:
        config: The env options (the observation design, its sensor model, cameras).
        task: The task's spec (its cameras).
        batched: The family's batched backend.
        task_id: The registered ID, for error messages.
    """

    def __init__(self, config: EnvConfig, task: Any, batched: BatchedBackend, task_id: str) -> None:
        self._batched = batched
        self._streams = [build_stream(config, batched.backend(i), task_id) for i in range(batched.num_envs)]
        self._exact = self._streams[0].exact
        # One camera per env (each env's model holds its own goal marker), drawn in this
        # thread: a GL context is current in one thread at a time.
        sensors = [image_sensor(config, task.cameras, task_id) for _ in range(batched.num_envs)]
        self._images: list[ImageSensor] | None = [s for s in sensors if s is not None] or None

    def raw(self, obs: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """``obs`` with ``observation`` holding the design's groups of every env, before
        the sensor model (the batched backend's own vector where the design is the default),
        and the design's images of every env."""
        if not self._exact:
            obs["observation"] = np.stack([s.raw(self._batched.backend(i)) for i, s in enumerate(self._streams)])
        if self._images is not None:
            frames = [
                s.read(self._batched.backend(i).model, self._batched.backend(i).data)
                for i, s in enumerate(self._images)
            ]
            for key in frames[0]:
                obs[key] = np.stack([f[key] for f in frames])
        return obs

    def start_all(self, raw: np.ndarray, np_random: np.random.Generator) -> np.ndarray:
        """Every env's first observation vector from ``raw``, drawn from ``np_random`` (at
        construction, to size the space)."""
        return np.stack([s.start(raw[i], np_random) for i, s in enumerate(self._streams)])

    def sense(
        self,
        raw: np.ndarray,
        last: np.ndarray,
        starting: np.ndarray | Sequence[int],
        advancing: np.ndarray | Sequence[int],
        rng: Callable[[int], np.random.Generator],
    ) -> np.ndarray:
        """The sensor model (distractors, noise, delay) on the rows of envs that start an
        episode or advance one, each from its own generator ``rng(i)`` as the single env
        does; the other rows keep ``last``. ``raw`` itself where there is no sensor model."""
        if self._streams[0].passthrough:
            return raw
        out = last.copy()
        for i in starting:
            out[i] = self._streams[i].start(raw[i], rng(int(i)))
        for i in advancing:
            out[i] = self._streams[i].advance(raw[i], rng(int(i)))
        return out

    @property
    def layout(self) -> dict[str, slice]:
        """Each group of the design, in order, with its slice of ``observation``."""
        return dict(self._streams[0].layout)

    @property
    def goal_layout(self) -> dict[str, slice]:
        """The groups of :attr:`layout` that depend on the goal."""
        return dict(self._streams[0].goal_layout)

    def reattach(self) -> None:
        """Point every stream back at its env's backend (after unpickling)."""
        for i, stream in enumerate(self._streams):
            reattach(stream, self._batched.backend(i))

    def close(self) -> None:
        for sensor in self._images or ():
            sensor.close()
