"""The Fetch family: gymnasium-robotics' Fetch{Reach,Push,Slide,PickAndPlace}-v4.

The backend wraps the real upstream env object (its model, reset distribution, goal
sampling and observation code), so every task is exactly upstream's.

* ``native`` runs upstream's own mocap control, unchanged: its ``_set_action``,
  ``_mujoco_step`` and ``_step_callback`` on its own model. With the same seed and
  actions it reproduces ``gym.make("Fetch...-v4")`` (observation, sparse reward,
  ``is_success``); ``tests/envs/test_fetch.py`` checks it.
* The other modes run on a modified copy of the model (built once per env with
  ``mujoco.MjSpec``, :mod:`.model`), because the stock arm has no actuators: it follows
  a mocap weld. The copy **removes the weld**, adds force-limited ``general``
  position-servo actuators on the 7 arm joints (the
  :class:`~unified_manip.envs.controllers.rig.MujocoRig` reads their gains), turns on ``gravcomp`` for
  every body from the shoulder down (so zero torque holds the arm still), adds
  upstream's PickAndPlace finger actuators to the tasks that lack them, gives the three
  unlimited roll joints a +-pi command range, and **freezes the base slides and the
  torso** with joint equality constraints at their initial values (the torso starts at
  0.0013 m, below its range [0.0386, 0.3861]; its range limit is switched off in the
  copy so the constraint and the limit do not fight). The layout of ``qpos`` is
  unchanged, so upstream's reset and observation code run on the copy unmodified.

Modules: :mod:`.scene` (names, gains, observation layout), :mod:`.controllers`
(the action modes), :mod:`.model`,
:mod:`.backend` (imports gymnasium-robotics and MuJoCo), :mod:`.policies`,
:mod:`.docs`, :mod:`.specs`. Their names can also be imported from this package, as
when the family was one module; they are imported on first access.
"""

from unified_manip.envs.lazy import reexport
from unified_manip.envs.tasks.fetch.specs import SPECS

__all__ = ["SPECS"]

__getattr__, __dir__ = reexport(__name__, ("scene", "controllers", "model", "backend", "policies", "docs", "specs"))
