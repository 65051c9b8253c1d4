"""Reward designs as named, weighted, vectorised terms.

Every reward is a sum of terms. A term is a pure function of

* ``distance``: the task's goal distance between achieved and desired goal, shape ``(B,)``;
* ``success``: the task's success flag for the same goals, shape ``(B,)``;
* ``ctx``: the task's per-step reward inputs, which do not depend on the goal, read from
  ``info`` so that hindsight relabelling (which changes only the goals) stays exact.
  Which inputs a task has is its term set's business
  (:class:`unified_manip.envs.termsets.TermSet`); every task has ``action_sq``, the sum
  of squares of the (clipped) action.

The designs (``reward_type``):

* ``sparse``: ``success - 1``, i.e. 0 on success and -1 otherwise, on every task.
* ``dense``: the task's shaped terms plus a success bonus (its term set's ``dense``).
* ``dense_penalized``: ``dense`` plus the task's penalties (its term set's
  ``penalties``), at least ``action = -0.01 * sum(a^2)``.

This module holds what every task shares: the designs' names, the numbers
(:class:`RewardConfig`), the generic terms (:class:`Shaped`, ``success``, ``action``) and
the batched evaluation (:class:`RewardSpec`).

The numbers are named in a :class:`RewardConfig` (MuJoCo Playground's
``reward_config.scales``): ``gym.make(ID, reward_type="dense",
reward_config=RewardConfig(scales=RewardScales(place=2.0)))`` changes one.
``info["reward_terms"]`` holds each term already multiplied by its scale, so the terms
add up to the step reward; the raw, unscaled terms come from
``env.unwrapped.compute_reward_terms(..., raw=True)`` (batched, like
``compute_reward``) or, per step in ``info["reward_terms_raw"]``, from the
:class:`unified_manip.envs.wrappers.RawRewardTerms` wrapper.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

import numpy as np

#: Every reward design the interface knows.
REWARD_TYPES: tuple[str, ...] = ("sparse", "dense", "dense_penalized")


def validate_reward_type(reward_type: str) -> None:
    """``ValueError`` naming the valid choices unless ``reward_type`` is one of :data:`REWARD_TYPES`."""
    if reward_type not in REWARD_TYPES:
        choices = ", ".join(repr(v) for v in REWARD_TYPES)
        raise ValueError(f"unknown reward_type {reward_type!r}; expected one of {choices}")


TermFn = Callable[[np.ndarray, np.ndarray, Mapping[str, np.ndarray]], np.ndarray]


@dataclass(frozen=True)
class RewardScales:
    """The scale of every term (what it is multiplied by in the reward).

    The names are those of the terms the tasks' term sets build; a term set reads the
    scales of its own terms.

    Attributes:
        sparse: ``success - 1``.
        reach: the shaped approach term ``1 - tanh(g d)``.
        place: the shaped goal term ``gate (1 - tanh(g d_goal))``.
        success: 1 on success.
        action: ``-sum(a^2)`` (``dense_penalized``).
        drop: -1 on the step an object is let go (``dense_penalized``).
    """

    sparse: float = 1.0
    reach: float = 1.0
    place: float = 5.0
    success: float = 10.0
    action: float = 0.01
    drop: float = 10.0

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not isinstance(value, (int, float)) or isinstance(value, bool) or not np.isfinite(value):
                raise ValueError(f"RewardScales.{name} must be a finite number, got {value!r}")


@dataclass(frozen=True)
class RewardConfig:
    """The reward designs' numbers, named.

    Attributes:
        scales: Each term's scale.
        distance_gain: ``g`` of the shaped terms ``1 - tanh(g d)``, per metre (per
            radian on goals that are angles).
    """

    scales: RewardScales = field(default_factory=RewardScales)
    distance_gain: float = 5.0

    def __post_init__(self) -> None:
        if not isinstance(self.scales, RewardScales):
            raise TypeError(f"RewardConfig.scales must be a RewardScales, got {type(self.scales).__name__}")
        if not isinstance(self.distance_gain, (int, float)) or not self.distance_gain > 0:
            raise ValueError(f"RewardConfig.distance_gain must be positive, got {self.distance_gain!r}")


@dataclass(frozen=True)
class Shaped:
    """The shaped term ``gate * (1 - tanh(gain * x))`` (picklable, unlike a closure).

    Attributes:
        gain: ``g`` of ``1 - tanh(g x)``.
        of: ``"distance"`` (the goal distance) or the name of a reward input.
        gate: The name of a reward input to multiply by, or ``None``.
    """

    gain: float
    of: str = "distance"
    gate: str | None = None

    def __call__(self, distance, success, ctx):
        x = distance if self.of == "distance" else ctx[self.of]
        value = 1.0 - np.tanh(self.gain * x)
        return value if self.gate is None else ctx[self.gate] * value


def sparse(distance, success, ctx):
    """``success - 1``."""
    return success - 1.0


def success_bonus(distance, success, ctx):
    """1 on success, else 0."""
    return success


def action_penalty(distance, success, ctx):
    """``-sum(a^2)`` of the clipped action."""
    return -ctx["action_sq"]


@dataclass(frozen=True)
class Term:
    """One named reward term and its scale."""

    name: str
    fn: TermFn
    scale: float


@dataclass(frozen=True)
class RewardSpec:
    """A reward design: the terms whose scaled sum is the reward.

    Attributes:
        reward_type: The design's name, one of ``REWARD_TYPES``.
        terms: The terms, in the order they appear in ``info["reward_terms"]``.
    """

    reward_type: str
    terms: tuple[Term, ...]

    @property
    def term_names(self) -> tuple[str, ...]:
        return tuple(t.name for t in self.terms)

    def terms_batch(
        self, distance: np.ndarray, success: np.ndarray, ctx: Mapping[str, np.ndarray]
    ) -> dict[str, np.ndarray]:
        """Scaled value of every term, each shaped like ``distance``."""
        return {t.name: t.scale * t.fn(distance, success, ctx) for t in self.terms}

    def total(self, distance: np.ndarray, success: np.ndarray, ctx: Mapping[str, np.ndarray]) -> np.ndarray:
        """The reward: the sum of the scaled terms."""
        out = np.zeros(np.shape(distance), dtype=np.float64)
        for t in self.terms:
            out = out + t.scale * t.fn(distance, success, ctx)
        return out

    def raw_batch(
        self, distance: np.ndarray, success: np.ndarray, ctx: Mapping[str, np.ndarray]
    ) -> dict[str, np.ndarray]:
        """Unscaled value of every term, each shaped like ``distance``."""
        return {t.name: t.fn(distance, success, ctx) for t in self.terms}


def sparse_terms(config: RewardConfig) -> tuple[Term, ...]:
    """The ``sparse`` design's one term, the same on every task."""
    return (Term("sparse", sparse, config.scales.sparse),)


def info_arrays(info: Any, batch_shape: tuple[int, ...], keys: Sequence[str]) -> dict[str, np.ndarray]:
    """Collect the reward inputs ``keys`` from one info dict or a batch of them.

    Args:
        info: A single ``info`` dict, or a sequence / object array of them (as
            Stable-Baselines3's ``HerReplayBuffer`` passes).
        batch_shape: The leading shape of the goals, ``()`` or ``(B,)``.
        keys: The task's reward inputs (``TermSet.info_keys``).

    Returns:
        A dict mapping every key to a float array of ``batch_shape``. Missing keys read as 0.
    """
    if isinstance(info, Mapping):
        return {k: np.full(batch_shape, float(info.get(k, 0.0))) for k in keys}
    infos: Sequence[Mapping[str, Any]] = list(np.asarray(info, dtype=object).reshape(-1))
    n = int(np.prod(batch_shape)) if batch_shape else 1
    if len(infos) != n:
        raise ValueError(f"got {len(infos)} infos for a batch of {n} goals")
    return {k: np.fromiter((float(i.get(k, 0.0)) for i in infos), np.float64, n).reshape(batch_shape) for k in keys}
