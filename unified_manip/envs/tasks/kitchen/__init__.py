"""The kitchen family: gymnasium-robotics' FrankaKitchen-v1, goal-conditioned on its subtasks.

The backend wraps the real upstream env object (its model, fixed initial state and noisy
observation). The goal is the task's subtasks' joints and their targets, flattened in a
fixed order, and the goal distance the largest subtask error, so that success is
upstream's completion of every subtask (:mod:`.subtasks`). Action modes: ``native``
(upstream's joint-velocity control), the joint modes and the end-effector modes through
mink, on a copy of the model with gravity compensation (:mod:`.rig`).

The registered ID, ``FrankaKitchen-v0``, takes D4RL's four subtasks (microwave, kettle,
light switch, slide cabinet). Another set is one spec away, registered under a name of
your own, e.g. all seven::

    from unified_manip.envs.registry import register_task
    from unified_manip.envs.tasks.kitchen.specs import kitchen_spec
    from unified_manip.envs.tasks.kitchen.subtasks import QPOS_INDICES

    register_task(kitchen_spec("FrankaKitchenAll", tuple(QPOS_INDICES)))

Modules: :mod:`.subtasks` (goals and distance), :mod:`.terms`, :mod:`.rig`,
:mod:`.controllers`, :mod:`.observations`, :mod:`.entities`, :mod:`.cameras`,
:mod:`.backend` (imports gymnasium-robotics and MuJoCo), :mod:`.docs`, :mod:`.specs`.
"""

from unified_manip.envs.tasks.kitchen.specs import SPECS

__all__ = ["SPECS"]
