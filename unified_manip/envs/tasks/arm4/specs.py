"""The 4-DOF arm's task specs (registered by ``unified_manip.envs.tasks``)."""

from __future__ import annotations

from dataclasses import replace

from unified_manip.envs.lazy import lazy
from unified_manip.envs.registry import TaskSpec
from unified_manip.envs.tasks.arm4.cameras import CAMERAS
from unified_manip.envs.tasks.arm4.controllers import CONTROLLERS, CONTROLLERS_25HZ
from unified_manip.envs.tasks.arm4.docs import (
    PICK_AND_PLACE_DOC,
    PICK_AND_PLACE_V1_DOC,
    PUSH_DOC,
    PUSH_V1_DOC,
    REACH_DOC,
)
from unified_manip.envs.tasks.arm4.entities import ENTITIES
from unified_manip.envs.tasks.arm4.policies import pick_and_place_policy, push_policy, push_policy_25hz, reach_policy
from unified_manip.envs.tasks.gripper_terms import GRIPPER_TERM_SETS
from unified_manip.envs.tasks.scripted import EEDeltaPolicy

_BACKEND = "unified_manip.envs.tasks.arm4.backend:Arm4Backend"

V0: tuple[TaskSpec, ...] = tuple(
    TaskSpec(
        name=name,
        family="arm4",
        terms=GRIPPER_TERM_SETS[term_set],
        make_backend=lazy(_BACKEND, scene=scene),
        controllers=CONTROLLERS,
        goal_dim=3,
        max_episode_steps=steps,
        distance_threshold=0.05,
        doc=doc,
        scripted_policy=EEDeltaPolicy("Arm4", policy),
        scripted_min_success=0.9,
        render_fps=50,
        cameras=CAMERAS,
        entities=ENTITIES[scene],
    )
    for name, scene, term_set, steps, doc, policy in (
        ("Arm4Reach", "reach", "reach", 50, REACH_DOC, reach_policy),
        ("Arm4Push", "push", "push", 100, PUSH_DOC, push_policy),
        ("Arm4PickAndPlace", "pick_and_place", "grasp", 100, PICK_AND_PLACE_DOC, pick_and_place_policy),
    )
)

#: Arm4Push with Fetch's timing and goal distribution (to test why the arm learns more
#: slowly than Fetch): v0's push task
#: with only these fields changed.
PUSH_V1 = replace(
    V0[1],
    version=1,
    make_backend=lazy(_BACKEND, scene="push", substeps=20, min_goal_distance=0.0),
    controllers=CONTROLLERS_25HZ,
    max_episode_steps=50,
    doc=PUSH_V1_DOC,
    scripted_policy=EEDeltaPolicy("Arm4", push_policy_25hz),
    render_fps=25,
)

#: Arm4PickAndPlace with Fetch's goal distribution (to test why the arm
#: learns more slowly than Fetch): half of the goals on
#: the table; v0's timing, so that one lever changes.
PICK_AND_PLACE_V1 = replace(
    V0[2],
    version=1,
    make_backend=lazy(_BACKEND, scene="pick_and_place", table_goal_fraction=0.5),
    doc=PICK_AND_PLACE_V1_DOC,
)

SPECS: tuple[TaskSpec, ...] = (*V0, PUSH_V1, PICK_AND_PLACE_V1)
