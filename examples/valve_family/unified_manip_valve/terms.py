"""The valve task's term set: its quantities, its reward terms and their scales.

The backend provides two quantities (:meth:`ValveBackend.quantities`), neither of which
depends on the goal:

* ``fingertip_to_handle``: the distance from the fingertip to the handle, m;
* ``valve_speed``: how fast the valve turns, ``|d angle / dt|``, rad/s.

The dense design, with ``g`` the reward config's ``distance_gain`` and ``d`` the goal
distance (the wrapped angle to the target, rad):

* ``approach = 1 - tanh(g fingertip_to_handle)`` (scale ``reach``);
* ``turn = 1 - tanh(g d)`` (scale ``place``);
* ``success``: 1 within the threshold (scale ``success``).

``dense_penalized`` adds ``action = -sum(a^2)`` (scale ``action``) and
``spin = -max(0, valve_speed - SPIN_LIMIT)`` (scale :data:`SPIN_SCALE`): a valve flicked
round faster than a hand would turn it costs reward.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from unified_manip.envs.rewards import RewardConfig, Shaped, Term, action_penalty, success_bonus
from unified_manip.envs.termsets import TermSet

FINGERTIP_TO_HANDLE = "fingertip_to_handle"
VALVE_SPEED = "valve_speed"
#: Valve speeds up to this are free under ``dense_penalized``, rad/s.
SPIN_LIMIT = 3.0
#: The spin penalty's scale, per rad/s over the limit. ``RewardScales`` names the built-in
#: terms' scales; a term of a family of its own carries its scale here.
SPIN_SCALE = 0.5


@dataclass(frozen=True)
class Spin:
    """``-max(0, valve_speed - limit)``: a term is a picklable callable ``(distance, success, ctx)``."""

    limit: float

    def __call__(self, distance, success, ctx):
        return -np.maximum(ctx[VALVE_SPEED] - self.limit, 0.0)


def _dense(config: RewardConfig) -> tuple[Term, ...]:
    k, g = config.scales, config.distance_gain
    return (
        Term("approach", Shaped(g, of=FINGERTIP_TO_HANDLE), k.reach),
        Term("turn", Shaped(g), k.place),
        Term("success", success_bonus, k.success),
    )


def _penalties(config: RewardConfig) -> tuple[Term, ...]:
    return (Term("action", action_penalty, config.scales.action), Term("spin", Spin(SPIN_LIMIT), SPIN_SCALE))


TURN = TermSet(
    "valve",
    inputs=(FINGERTIP_TO_HANDLE, VALVE_SPEED),
    dense=_dense,
    penalties=_penalties,
    # What the dense-reward sanity check sweeps: the finger reaches 0.28 m; the valve
    # seldom turns faster than 10 rad/s.
    ranges={FINGERTIP_TO_HANDLE: (0.0, 0.5), VALVE_SPEED: (0.0, 10.0)},
    doc="approach = 1 - tanh(g |fingertip - handle|), turn = 1 - tanh(g d), a success bonus",
)
