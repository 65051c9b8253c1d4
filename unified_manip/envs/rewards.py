"""Reward designs as named, weighted, vectorised terms.

Every reward is a sum of terms. A term is a pure function of

* ``distance``: the task's goal distance between achieved and desired goal, shape ``(B,)``;
* ``success``: the task's success flag for the same goals, shape ``(B,)``;
* a few per-step quantities that do not depend on the goal, read from ``info`` so
  that hindsight relabelling (which changes only the goals) stays exact:

  ===================  ===========================================================
  ``info`` key         meaning
  ===================  ===========================================================
  ``grip_to_object``   distance from the gripper to the object, metres
  ``grasped``          1.0 while the object is held, else 0.0
  ``dropped``          1.0 on the step a held object was let go, else 0.0
  ``action_sq``        sum of squares of the (clipped) action
  ===================  ===========================================================

The designs (``reward_type``):

* ``sparse``: ``success - 1``, i.e. 0 on success and -1 otherwise.
* ``dense``: phased shaping (reach, then place, then a bonus). ``reach = 1 - tanh(5 d_reach)``
  where ``d_reach`` is the gripper-object distance (or the goal distance on tasks
  without an object); ``place = 5 * gate * (1 - tanh(5 d_goal))`` where ``gate`` is
  ``grasped`` on tasks that need a grasp and 1 on tasks that push; ``success = 10``
  on success.
* ``dense_penalized``: ``dense`` plus ``action = -0.01 * sum(a^2)`` and
  ``drop = -10`` on the step a held object is dropped.

Which dense terms a task gets is its *shaping* template (:data:`SHAPINGS`, the
``TaskSpec.shaping`` of the task): ``reach`` (no object), ``push`` (an object, no grasp
gate) or ``grasp`` (the place term gated by the grasp).

The numbers above are named in a :class:`RewardConfig` (MuJoCo Playground's
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


#: Shaping templates: which terms the dense rewards use (``TaskSpec.shaping``).
SHAPINGS: tuple[str, ...] = ("reach", "push", "grasp")

#: The ``info`` keys the reward terms read.
INFO_KEYS: tuple[str, ...] = ("grip_to_object", "grasped", "dropped", "action_sq")

TermFn = Callable[[np.ndarray, np.ndarray, Mapping[str, np.ndarray]], np.ndarray]


@dataclass(frozen=True)
class RewardScales:
    """The scale of every term (what it is multiplied by in the reward).

    Attributes:
        sparse: ``success - 1``.
        reach: ``1 - tanh(g d_reach)``.
        place: ``gate (1 - tanh(g d_goal))``.
        success: 1 on success.
        action: ``-sum(a^2)`` (``dense_penalized``).
        drop: -1 on the step a held object is let go (``dense_penalized``).
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
        of: ``"distance"`` (the goal distance) or an :data:`INFO_KEYS` quantity.
        gate: An :data:`INFO_KEYS` quantity to multiply by (``"grasped"``), or ``None``.
    """

    gain: float
    of: str = "distance"
    gate: str | None = None

    def __call__(self, distance, success, ctx):
        x = distance if self.of == "distance" else ctx[self.of]
        value = 1.0 - np.tanh(self.gain * x)
        return value if self.gate is None else ctx[self.gate] * value


def _sparse(distance, success, ctx):
    return success - 1.0


def _success(distance, success, ctx):
    return success


def _action(distance, success, ctx):
    return -ctx["action_sq"]


def _drop(distance, success, ctx):
    return -ctx["dropped"]


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


def make_reward_spec(reward_type: str, shaping: str, config: RewardConfig | None = None) -> RewardSpec:
    """The reward design ``reward_type`` for a task of shaping template ``shaping``,
    with the numbers of ``config`` (the defaults if ``None``)."""
    validate_reward_type(reward_type)
    if shaping not in SHAPINGS:
        raise ValueError(f"unknown shaping {shaping!r}; expected one of {', '.join(map(repr, SHAPINGS))}")
    config = config or RewardConfig()
    k, g = config.scales, config.distance_gain
    if reward_type == "sparse":
        return RewardSpec("sparse", (Term("sparse", _sparse, k.sparse),))
    dense: tuple[Term, ...]
    penalties: tuple[Term, ...]
    if shaping == "reach":
        dense = (Term("reach", Shaped(g), k.reach), Term("success", _success, k.success))
        penalties = (Term("action", _action, k.action),)
    else:
        dense = (
            Term("reach", Shaped(g, of="grip_to_object"), k.reach),
            Term("place", Shaped(g, gate="grasped" if shaping == "grasp" else None), k.place),
            Term("success", _success, k.success),
        )
        penalties = (Term("action", _action, k.action), Term("drop", _drop, k.drop))
    return RewardSpec(reward_type, dense + penalties if reward_type == "dense_penalized" else dense)


def info_arrays(info: Any, batch_shape: tuple[int, ...]) -> dict[str, np.ndarray]:
    """Collect the reward inputs from one info dict or a batch of them.

    Args:
        info: A single ``info`` dict, or a sequence / object array of them (as
            Stable-Baselines3's ``HerReplayBuffer`` passes).
        batch_shape: The leading shape of the goals, ``()`` or ``(B,)``.

    Returns:
        A dict mapping every key in :data:`INFO_KEYS` to a float array of
        ``batch_shape``. Missing keys read as 0.
    """
    if isinstance(info, Mapping):
        out = {k: np.full(batch_shape, float(info.get(k, 0.0))) for k in INFO_KEYS}
        return out
    infos: Sequence[Mapping[str, Any]] = list(np.asarray(info, dtype=object).reshape(-1))
    n = int(np.prod(batch_shape)) if batch_shape else 1
    if len(infos) != n:
        raise ValueError(f"got {len(infos)} infos for a batch of {n} goals")
    return {
        k: np.fromiter((float(i.get(k, 0.0)) for i in infos), np.float64, n).reshape(batch_shape) for k in INFO_KEYS
    }
