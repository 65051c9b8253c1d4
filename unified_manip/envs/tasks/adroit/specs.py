"""The Adroit task specs (registered by ``unified_manip.envs.tasks``)."""

from __future__ import annotations

from unified_manip.envs.lazy import lazy
from unified_manip.envs.registry import TaskSpec
from unified_manip.envs.tasks.adroit.cameras import CAMERAS
from unified_manip.envs.tasks.adroit.controllers import CONTROLLERS
from unified_manip.envs.tasks.adroit.docs import DOOR_DOC, RELOCATE_DOC
from unified_manip.envs.tasks.gripper_terms import GRIPPER_TERM_SETS

_BACKEND = "unified_manip.envs.tasks.adroit.backend:AdroitBackend"
_UPSTREAM = "gymnasium_robotics.envs.adroit_hand"

#: Random steps per mode in the stability test (Adroit steps at a few hundred/s).
STABILITY_STEPS = 600

#: Door: success is |angle - 1.57| < 0.22 rad (:mod:`.tasks`).
DOOR_THRESHOLD = 0.22

SPECS: tuple[TaskSpec, ...] = tuple(
    TaskSpec(
        name=name,
        family="adroit",
        terms=GRIPPER_TERM_SETS[term_set],
        make_backend=lazy(_BACKEND, task=task, upstream_cls=f"{_UPSTREAM}.{upstream}"),
        controllers=CONTROLLERS,
        goal_dim=goal_dim,
        max_episode_steps=200,
        distance_threshold=threshold,
        doc=doc,
        render_fps=25,
        cameras=CAMERAS,
        stability_steps=STABILITY_STEPS,
        upstream_id=upstream_id,
        make_upstream=lazy("gymnasium:make", f"gymnasium_robotics:{upstream_id}", disable_env_checker=True),
    )
    for name, task, term_set, upstream, upstream_id, goal_dim, threshold, doc in (
        (
            "AdroitRelocate",
            "Relocate",
            "grasp",
            "adroit_relocate:AdroitHandRelocateEnv",
            "AdroitHandRelocate-v1",
            3,
            0.1,
            RELOCATE_DOC,
        ),
        (
            "AdroitDoor",
            "Door",
            "push",
            "adroit_door:AdroitHandDoorEnv",
            "AdroitHandDoor-v1",
            1,
            DOOR_THRESHOLD,
            DOOR_DOC,
        ),
    )
)
