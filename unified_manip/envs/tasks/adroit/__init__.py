"""The Adroit family: gymnasium-robotics' AdroitHandRelocate-v1 and AdroitHandDoor-v1.

The backend wraps the real upstream env object (its model, with upstream's actuator
gains, and its reset distribution); upstream's envs are not goal-conditioned, so each
task's goals, success and reward quantities are defined from its state in
:mod:`.tasks`, success being upstream's own ``success`` info. Three action modes,
all through the arm's and hand's position servos:

* ``native``: upstream's absolute controls, ``ctrl = centre + a * half_range``;
* ``joint_delta``, ``joint_target_delta``: targets relative to the measured or the last
  commanded position (:mod:`.rig`).

Modules: :mod:`.tasks` (goals, quantities, observation groups), :mod:`.rig`,
:mod:`.controllers`, :mod:`.backend` (imports gymnasium-robotics and MuJoCo),
:mod:`.docs`, :mod:`.specs`.
"""

from unified_manip.envs.tasks.adroit.specs import SPECS

__all__ = ["SPECS"]
