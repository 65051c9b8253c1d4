"""The kitchen's term set: the goal distance alone (no per-step quantities).

A kitchen goal is several subtasks at once (:mod:`.subtasks`); a term reads the goal only
through the one goal distance, the largest subtask error ``d``. The dense design, with
``g`` the reward config's ``distance_gain``:

* ``progress = 1 - tanh(g d)`` (scale ``place``): the subtask farthest from its target;
* ``success`` (scale ``success``): every subtask within upstream's threshold at once.

``dense_penalized`` adds ``action = -sum(a^2)``. There is no approach term: which handle
the gripper should go to next depends on the goal (the subtasks left), and a reward input
must not.
"""

from __future__ import annotations

from unified_manip.envs.rewards import RewardConfig, Shaped, Term, action_penalty, success_bonus
from unified_manip.envs.termsets import TermSet


def _dense(config: RewardConfig) -> tuple[Term, ...]:
    k = config.scales
    return (Term("progress", Shaped(config.distance_gain), k.place), Term("success", success_bonus, k.success))


def _penalties(config: RewardConfig) -> tuple[Term, ...]:
    return (Term("action", action_penalty, config.scales.action),)


KITCHEN = TermSet(
    "kitchen",
    (),
    _dense,
    penalties=_penalties,
    doc="progress = 1 - tanh(g d) on the largest subtask error d, a success bonus",
)
