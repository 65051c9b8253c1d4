"""The term sets of the families with a gripper: reach, push and grasp.

Their backends provide two quantities (:meth:`~unified_manip.envs.backend.Backend.quantities`):

* ``grip_to_object``: the distance from the gripper to the object, metres (0 on tasks
  without an object);
* ``grasped``: 1.0 while the object is held, else 0.0 (what "held" means is the task's
  own: two fingers in contact on the arm and Fetch, robosuite's grasp check, the block
  still on the palm for the Shadow Hand).

and one event, ``dropped``: 1.0 on the step a held object was let go.

The dense designs, with ``g`` the reward config's ``distance_gain`` and ``d`` the goal
distance:

* ``reach`` (no object): ``reach = 1 - tanh(g d)`` and a success bonus;
* ``push`` (an object, no grasp): ``reach = 1 - tanh(g grip_to_object)``,
  ``place = 1 - tanh(g d)`` and a success bonus;
* ``grasp``: as ``push``, with ``place`` multiplied by ``grasped``.

``dense_penalized`` adds ``action = -sum(a^2)`` to each, and ``drop = -dropped`` to the
two with an object.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from unified_manip.envs.rewards import RewardConfig, Shaped, Term, action_penalty, success_bonus
from unified_manip.envs.termsets import Event, Termination, TermSet

GRIP_TO_OBJECT = "grip_to_object"
GRASPED = "grasped"
DROPPED = "dropped"


@dataclass(frozen=True)
class LetGo:
    """Event: 1.0 on the step the quantity ``of`` went from held (> 0.5) to not (< 0.5)."""

    of: str

    def __call__(self, before: Mapping[str, np.ndarray], now: Mapping[str, np.ndarray]) -> np.ndarray:
        return np.logical_and(np.greater(before[self.of], 0.5), np.less(now[self.of], 0.5)).astype(np.float64)


def was_dropped(ctx: Mapping[str, np.ndarray]) -> np.ndarray:
    """Where a held object was let go this step."""
    return np.greater(ctx[DROPPED], 0.5)


def drop_penalty(distance, success, ctx):
    """``-dropped``: -1 on the step a held object is let go."""
    return -ctx[DROPPED]


def _reach_dense(config: RewardConfig) -> tuple[Term, ...]:
    k = config.scales
    return (Term("reach", Shaped(config.distance_gain), k.reach), Term("success", success_bonus, k.success))


def _reach_penalties(config: RewardConfig) -> tuple[Term, ...]:
    return (Term("action", action_penalty, config.scales.action),)


def _object_dense(config: RewardConfig, gate: str | None) -> tuple[Term, ...]:
    k, g = config.scales, config.distance_gain
    return (
        Term("reach", Shaped(g, of=GRIP_TO_OBJECT), k.reach),
        Term("place", Shaped(g, gate=gate), k.place),
        Term("success", success_bonus, k.success),
    )


def _push_dense(config: RewardConfig) -> tuple[Term, ...]:
    return _object_dense(config, None)


def _grasp_dense(config: RewardConfig) -> tuple[Term, ...]:
    return _object_dense(config, GRASPED)


def _object_penalties(config: RewardConfig) -> tuple[Term, ...]:
    k = config.scales
    return (Term("action", action_penalty, k.action), Term("drop", drop_penalty, k.drop))


_INPUTS = (GRIP_TO_OBJECT, GRASPED)
_EVENTS = (Event(DROPPED, LetGo(GRASPED)),)
#: Half a metre: farther than any gripper starts from its object.
_RANGES = {GRIP_TO_OBJECT: (0.0, 0.5)}
_DROP = (Termination(DROPPED, was_dropped, doc="a held object was let go"),)

REACH = TermSet(
    "reach",
    _INPUTS,
    _reach_dense,
    _EVENTS,
    _reach_penalties,
    _RANGES,
    doc="reach = 1 - tanh(g d) and a success bonus; no object",
)
PUSH = TermSet(
    "push",
    _INPUTS,
    _push_dense,
    _EVENTS,
    _object_penalties,
    _RANGES,
    _DROP,
    doc="reach = 1 - tanh(g |grip - object|), place = 1 - tanh(g d), a success bonus",
)
GRASP = TermSet(
    "grasp",
    _INPUTS,
    _grasp_dense,
    _EVENTS,
    _object_penalties,
    _RANGES,
    _DROP,
    doc="as push, with place multiplied by grasped",
)

#: The gripper term sets by name (what task pages and docs call them).
GRIPPER_TERM_SETS: dict[str, TermSet] = {t.name: t for t in (REACH, PUSH, GRASP)}
