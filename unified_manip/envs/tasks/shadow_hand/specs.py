"""The Shadow Hand task specs (registered by ``unified_manip.envs.tasks``)."""

from __future__ import annotations

from unified_manip.envs.lazy import lazy
from unified_manip.envs.registry import TaskSpec, euclidean
from unified_manip.envs.tasks.gripper_terms import GRIPPER_TERM_SETS
from unified_manip.envs.tasks.shadow_hand.cameras import CAMERAS
from unified_manip.envs.tasks.shadow_hand.controllers import CONTROLLERS
from unified_manip.envs.tasks.shadow_hand.docs import BLOCK_DOC, REACH_DOC
from unified_manip.envs.tasks.shadow_hand.entities import ENTITIES
from unified_manip.envs.tasks.shadow_hand.goals import BLOCK_POSITION_THRESHOLD, block_goal_distance

_BACKEND = "unified_manip.envs.tasks.shadow_hand.backend:HandBackend"
_UPSTREAM = "gymnasium_robotics.envs.shadow_dexterous_hand"

#: Random steps per mode in the stability test (the hand steps at a few hundred/s).
STABILITY_STEPS = 1_000

SPECS: tuple[TaskSpec, ...] = tuple(
    TaskSpec(
        name=name,
        family="shadow_hand",
        terms=GRIPPER_TERM_SETS[term_set],
        make_backend=lazy(_BACKEND, upstream_cls=f"{_UPSTREAM}.{upstream}", has_object=term_set != "reach"),
        controllers=CONTROLLERS,
        goal_dim=goal_dim,
        max_episode_steps=steps,
        distance_threshold=threshold,
        doc=doc,
        goal_distance=distance,
        render_fps=25,
        cameras=CAMERAS,
        entities=ENTITIES,
        stability_steps=STABILITY_STEPS,
        upstream_id=upstream_id,
        make_upstream=lazy("gymnasium:make", f"gymnasium_robotics:{upstream_id}", disable_env_checker=True),
    )
    for name, term_set, upstream, upstream_id, goal_dim, steps, threshold, doc, distance in (
        ("HandReach", "reach", "reach:MujocoHandReachEnv", "HandReach-v3", 15, 50, 0.01, REACH_DOC, euclidean),
        (
            "HandManipulateBlock",
            "push",
            "manipulate_block:MujocoHandBlockEnv",
            "HandManipulateBlock-v1",
            7,
            100,
            BLOCK_POSITION_THRESHOLD,
            BLOCK_DOC,
            block_goal_distance,
        ),
    )
)
