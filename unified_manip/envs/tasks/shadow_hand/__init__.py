"""The Shadow Hand family: gymnasium-robotics' HandReach-v3 and HandManipulateBlock-v1.

The backend wraps the real upstream env object (model, reset, goal sampling,
observation), like the Fetch family. Two action modes, both 20 joint-position
targets through the hand's own position actuators:

* ``native``: upstream's absolute targets, ``ctrl = centre + a * half_range`` of each
  actuator's control range, by upstream's own ``_set_action``.
* ``joint_delta``: upstream's ``relative_control=True``: ``ctrl = q + a * half_range``,
  where ``q`` is the actuated joint's angle (plus the coupled distal joint J0 for the
  FF/MF/RF/LF J1 actuators), clipped to the control range. Upstream's own
  implementation of it calls mujoco-py APIs (``data.get_joint_qpos``) and raises
  ``AttributeError`` under the ``mujoco`` bindings, so this backend computes the same
  formula from precomputed ``qpos`` addresses.

Everything else (observation vector, goals, success) is upstream's unchanged.

Modules: :mod:`.goals` (the block's goal distance), :mod:`.backend` (imports
gymnasium-robotics), :mod:`.docs`, :mod:`.specs`. Their names can also be imported from
this package, as when the family was one module.
"""

from unified_manip.envs.lazy import reexport
from unified_manip.envs.tasks.shadow_hand.specs import SPECS

__all__ = ["SPECS"]

__getattr__, __dir__ = reexport(__name__, ("goals", "controllers", "rig", "backend", "docs", "specs"))
