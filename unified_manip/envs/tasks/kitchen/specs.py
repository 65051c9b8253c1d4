"""The kitchen task specs (registered by ``unified_manip.envs.tasks``)."""

from __future__ import annotations

from unified_manip.envs.lazy import lazy
from unified_manip.envs.registry import TaskSpec
from unified_manip.envs.tasks.kitchen.cameras import CAMERAS
from unified_manip.envs.tasks.kitchen.controllers import CONTROLLERS
from unified_manip.envs.tasks.kitchen.docs import kitchen_doc
from unified_manip.envs.tasks.kitchen.entities import ENTITIES
from unified_manip.envs.tasks.kitchen.subtasks import BONUS_THRESH, D4RL_SUBTASKS, SubtaskDistance
from unified_manip.envs.tasks.kitchen.terms import KITCHEN

_BACKEND = "unified_manip.envs.tasks.kitchen.backend:KitchenBackend"
UPSTREAM_ID = "FrankaKitchen-v1"

#: Random steps per mode in the stability test (the kitchen steps at about a hundred/s).
STABILITY_STEPS = 100


def kitchen_spec(name: str, subtasks: tuple[str, ...]) -> TaskSpec:
    """The spec of a kitchen task whose goal is ``subtasks``, in that order."""
    distance = SubtaskDistance(subtasks)
    return TaskSpec(
        name=name,
        family="kitchen",
        terms=KITCHEN,
        make_backend=lazy(_BACKEND, distance=distance),
        controllers=CONTROLLERS,
        goal_dim=distance.goal_dim,
        max_episode_steps=280,
        distance_threshold=BONUS_THRESH,
        doc=kitchen_doc(name, distance),
        goal_distance=distance,
        render_fps=12,
        cameras=CAMERAS,
        entities=ENTITIES,
        stability_steps=STABILITY_STEPS,
        upstream_id=UPSTREAM_ID,
        make_upstream=lazy(
            "gymnasium:make",
            f"gymnasium_robotics:{UPSTREAM_ID}",
            tasks_to_complete=list(subtasks),
            disable_env_checker=True,
        ),
    )


SPECS: tuple[TaskSpec, ...] = (kitchen_spec("FrankaKitchen", D4RL_SUBTASKS),)
