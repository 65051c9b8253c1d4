"""The Meta-World family: the 50 tasks of Farama Meta-World 3.1.1 (its Sawyer arm with a
two-finger gripper), as goal tasks.

The backend wraps the real upstream env object (its model, its seeded reset
distribution, its observation, its own success and reward). Meta-World's envs are not
goal-conditioned; each task's goal is Meta-World's target and the point its success
reads (:mod:`.tasks`, :mod:`.goals`). Action modes: ``native`` (Meta-World's mocap
end-effector delta and gripper), and on an actuated copy of the model (:mod:`.rig`) the
joint modes over the Sawyer's 7 joints and ``ee_delta``/``ee_target_delta`` through mink.
Meta-World's scripted policies emit ``native``; :mod:`.translate` plays them in the others.

Modules: :mod:`.goals` (goal distances), :mod:`.tasks` (the 50 tasks' goals),
:mod:`.observations`, :mod:`.cameras`, :mod:`.rig`, :mod:`.controllers`, :mod:`.policies`
(Meta-World's scripted policies), :mod:`.translate`, :mod:`.backend` (imports Meta-World and MuJoCo),
:mod:`.docs`, :mod:`.specs`, :mod:`.benchmarks` (its MT10, MT50 and ML10 task lists).
"""

from unified_manip.envs.tasks.metaworld.benchmarks import LISTS
from unified_manip.envs.tasks.metaworld.specs import SPECS

#: Each task's newest ID (SPECS holds every version, oldest first).
_IDS = {spec.upstream_id.removeprefix("metaworld:"): spec.id for spec in SPECS}

#: Meta-World's benchmark lists as the newest IDs (``metaworld:MT10`` in a bench grid's tasks).
TASK_LISTS = {name: tuple(_IDS[n] for n in names) for name, names in LISTS.items()}

__all__ = ["SPECS", "TASK_LISTS"]
