"""The in-hand term set: reorienting an object held on the Shadow Hand's palm (the egg
and the pen).

Its backend provides two quantities (:meth:`~unified_manip.envs.backend.Backend.quantities`):

* ``palm_to_object``: the distance from the palm body to the object's centre, m;
* ``on_palm``: 1.0 while the object's centre is above z = 0.04 m (upstream's check that
  the object is still on the hand, which its reset retries on), else 0.0;

and one event, ``dropped``: 1.0 on the step the object fell off the hand.

The dense design, with ``g`` the reward config's ``distance_gain`` and ``d`` the task's
pose distance (:mod:`~unified_manip.envs.tasks.shadow_hand.goals`):

* ``hold = 1 - tanh(g palm_to_object)`` (scale ``reach``): keep the object near the palm;
* ``pose = on_palm (1 - tanh(g d))`` (scale ``place``): the pose, paid only while the
  object is on the hand, so that a dropped object earns nothing for lying in the goal's
  orientation;
* ``success`` (scale ``success``).

``dense_penalized`` adds ``action = -sum(a^2)`` and ``drop = -dropped``.

A term reads the goal only through the one goal distance, so the dense terms cannot
weigh position and rotation apart (upstream's dense reward ``-(10 d_pos + d_rot)``): that
would need the task's goal distance to return its components, and the terms to receive
them.
"""

from __future__ import annotations

from unified_manip.envs.rewards import RewardConfig, Shaped, Term, action_penalty, success_bonus
from unified_manip.envs.tasks.gripper_terms import DROPPED, LetGo, drop_penalty
from unified_manip.envs.termsets import Event, TermSet

PALM_TO_OBJECT = "palm_to_object"
ON_PALM = "on_palm"


def _dense(config: RewardConfig) -> tuple[Term, ...]:
    k, g = config.scales, config.distance_gain
    return (
        Term("hold", Shaped(g, of=PALM_TO_OBJECT), k.reach),
        Term("pose", Shaped(g, gate=ON_PALM), k.place),
        Term("success", success_bonus, k.success),
    )


def _penalties(config: RewardConfig) -> tuple[Term, ...]:
    k = config.scales
    return (Term("action", action_penalty, k.action), Term("drop", drop_penalty, k.drop))


IN_HAND = TermSet(
    "in_hand",
    (PALM_TO_OBJECT, ON_PALM),
    _dense,
    (Event(DROPPED, LetGo(ON_PALM)),),
    _penalties,
    {PALM_TO_OBJECT: (0.0, 0.3)},  # the palm to the floor beneath the hand
    doc="hold = 1 - tanh(g |palm - object|), pose = on_palm (1 - tanh(g d)), a success bonus",
)
