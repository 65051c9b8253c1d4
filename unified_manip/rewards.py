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
* ``dense``: the design document's phased shaping. ``reach = 1 - tanh(5 d_reach)``
  where ``d_reach`` is the gripper-object distance (or the goal distance on tasks
  without an object); ``place = 5 * gate * (1 - tanh(5 d_goal))`` where ``gate`` is
  ``grasped`` on tasks that need a grasp and 1 on tasks that push; ``success = 10``
  on success.
* ``dense_penalized``: ``dense`` plus ``action = -0.01 * sum(a^2)`` and
  ``drop = -10`` on the step a held object is dropped.

``info["reward_terms"]`` holds each term already multiplied by its scale, so the terms
add up to the step reward.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Mapping, Sequence

import numpy as np

#: Task kinds decide which terms the dense rewards use.
TASK_KINDS: tuple[str, ...] = ("reach", "push", "grasp")

#: The ``info`` keys the reward terms read.
INFO_KEYS: tuple[str, ...] = ("grip_to_object", "grasped", "dropped", "action_sq")

TermFn = Callable[[np.ndarray, np.ndarray, Mapping[str, np.ndarray]], np.ndarray]


def _shaped(distance: np.ndarray) -> np.ndarray:
    return 1.0 - np.tanh(5.0 * distance)


def _sparse(distance, success, ctx):
    return success - 1.0


def _reach_goal(distance, success, ctx):
    return _shaped(distance)


def _reach_object(distance, success, ctx):
    return _shaped(ctx["grip_to_object"])


def _place_grasped(distance, success, ctx):
    return ctx["grasped"] * _shaped(distance)


def _place_free(distance, success, ctx):
    return _shaped(distance)


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

    def total(
        self, distance: np.ndarray, success: np.ndarray, ctx: Mapping[str, np.ndarray]
    ) -> np.ndarray:
        """The reward: the sum of the scaled terms."""
        out = np.zeros(np.shape(distance), dtype=np.float64)
        for t in self.terms:
            out = out + t.scale * t.fn(distance, success, ctx)
        return out


def make_reward_spec(reward_type: str, task_kind: str) -> RewardSpec:
    """Build the reward design ``reward_type`` for a task of kind ``task_kind``."""
    if task_kind not in TASK_KINDS:
        raise ValueError(f"unknown task kind {task_kind!r}; expected one of {TASK_KINDS}")
    if reward_type == "sparse":
        return RewardSpec("sparse", (Term("sparse", _sparse, 1.0),))
    if task_kind == "reach":
        dense = (Term("reach", _reach_goal, 1.0), Term("success", _success, 10.0))
        penalties = (Term("action", _action, 0.01),)
    else:
        place = _place_grasped if task_kind == "grasp" else _place_free
        dense = (
            Term("reach", _reach_object, 1.0),
            Term("place", place, 5.0),
            Term("success", _success, 10.0),
        )
        penalties = (Term("action", _action, 0.01), Term("drop", _drop, 10.0))
    if reward_type == "dense":
        return RewardSpec("dense", dense)
    if reward_type == "dense_penalized":
        return RewardSpec("dense_penalized", dense + penalties)
    raise ValueError(
        f"unknown reward_type {reward_type!r}; "
        "expected one of 'sparse', 'dense', 'dense_penalized'"
    )


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
        k: np.fromiter((float(i.get(k, 0.0)) for i in infos), np.float64, n).reshape(
            batch_shape
        )
        for k in INFO_KEYS
    }
