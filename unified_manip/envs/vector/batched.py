"""The one abstract base a family implements to run natively in the vector env.

A *batched backend* owns N simulations of one task under one action mode and steps any
subset of them in one call. The shared :class:`~unified_manip.envs.vector.env.NativeVectorEnv`
turns it into a Gymnasium vector env (validation, time limits, rewards, success,
autoreset, info arrays) without looking at which family it is. Its contract is the
single env's: env ``i`` of a batched backend, reset with the same generator and given
the same actions, produces exactly what the family's :class:`~unified_manip.envs.backend.Backend`
produces, bit for bit.

Arrays hold one row per env. Rows of envs that were not part of the last ``step`` or
``reset`` keep their previous values.
"""

from __future__ import annotations

import abc
from typing import Any, Mapping

import numpy as np

from unified_manip.envs.backend import Backend
from unified_manip.envs.vector.pool import PhysicsPool


class BatchedBackend(abc.ABC):
    """N simulations of one task under one action mode, each one of the family's backends.

    A subclass fills ``_backends`` and ``_num_threads``, sets ``_quantities = {}``, and
    calls :meth:`_attach`, which builds what is not pickled (the thread pool, and whatever
    the subclass adds).

    Attributes:
        num_envs: N.
        action_dim: Length of one env's ``Box(-1, 1)`` action.
    """

    num_envs: int
    action_dim: int
    _backends: list[Backend]
    _num_threads: int
    _pool: PhysicsPool
    _quantities: dict[str, np.ndarray]
    _unstable: np.ndarray
    #: Attributes :meth:`_attach` rebuilds after unpickling.
    _transient: tuple[str, ...] = ("_pool",)

    @abc.abstractmethod
    def reset(self, index: int, np_random: np.random.Generator) -> dict[str, np.ndarray]:
        """Start a new episode in env ``index`` from ``np_random`` (as ``Backend.reset``).

        Returns:
            The family's extra reset-info entries for that env (``Backend.extra_info``),
            as scalars; usually empty.
        """

    @abc.abstractmethod
    def step(self, actions: np.ndarray, indices: np.ndarray) -> dict[str, np.ndarray]:
        """Apply validated, clipped actions to the envs in ``indices`` and advance them.

        Args:
            actions: float64 ``(N, action_dim)`` in [-1, 1]; rows outside ``indices``
                are ignored.
            indices: Sorted int array of the envs to step.

        Returns:
            The mode's diagnostics and the family's extra info (``Backend.step``'s and
            ``Backend.extra_info``'s entries), each an ``(N,)`` array valid at ``indices``,
            float64 for float values and bool for bool values.
        """

    @abc.abstractmethod
    def observations(self) -> dict[str, np.ndarray]:
        """``observation``, ``achieved_goal``, ``desired_goal`` (and any extra entries),
        float32 ``(N, ...)`` arrays, exactly as the single env's observation dict."""

    def backend(self, index: int) -> Backend:
        """Env ``index``'s own backend, holding its current state (to read observation groups)."""
        return self._backends[index]

    def quantities(self) -> dict[str, np.ndarray]:
        """Every env's quantities (``Backend.quantities``), each a float64 ``(N,)`` array,
        as :meth:`_keep_quantities` stored them."""
        return {k: v.copy() for k, v in self._quantities.items()}

    def _keep_quantities(self, i: int, values: Mapping[str, float]) -> None:
        """Store env ``i``'s quantities in row ``i`` (the arrays are made on first sight)."""
        for key, value in values.items():
            if key not in self._quantities:
                self._quantities[key] = np.zeros(self.num_envs)
            self._quantities[key][i] = value

    def unstable(self) -> np.ndarray:
        """bool ``(N,)``: the physics of the env diverged during its last step (``_unstable``)."""
        return self._unstable.copy()

    def render(self, index: int) -> np.ndarray | None:
        """Env ``index``'s frame (``Backend.render``)."""
        return self._backends[index].render()

    def close(self) -> None:
        """Stop the thread pool and release every simulation; idempotent."""
        self._pool.shutdown()
        for b in self._backends:
            b.close()

    def _attach(self) -> None:
        self._pool = PhysicsPool(self._num_threads)

    def __getstate__(self) -> dict[str, Any]:
        return {k: v for k, v in self.__dict__.items() if k not in self._transient}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._attach()
