"""The Fetch task specs (registered by ``unified_manip.envs.tasks``)."""

from __future__ import annotations

from unified_manip.envs.lazy import lazy
from unified_manip.envs.registry import TaskSpec
from unified_manip.envs.tasks.fetch.cameras import CAMERAS
from unified_manip.envs.tasks.fetch.controllers import CONTROLLERS
from unified_manip.envs.tasks.fetch.docs import PICK_AND_PLACE_DOC, PUSH_DOC, REACH_DOC, SLIDE_DOC
from unified_manip.envs.tasks.fetch.entities import ENTITIES
from unified_manip.envs.tasks.fetch.policies import pick_and_place_policy, push_policy, reach_policy, slide_policy
from unified_manip.envs.tasks.gripper_terms import GRIPPER_TERM_SETS
from unified_manip.envs.tasks.scripted import EEDeltaPolicy

_BACKEND = "unified_manip.envs.tasks.fetch.backend:FetchBackend"
_UPSTREAM = "gymnasium_robotics.envs.fetch.{module}:MujocoFetch{name}Env"

#: Random steps per mode in the stability test: Fetch steps at ~300-400/s.
STABILITY_STEPS = 600

SPECS: tuple[TaskSpec, ...] = tuple(
    TaskSpec(
        name=f"Fetch{name}",
        family="fetch",
        terms=GRIPPER_TERM_SETS[term_set],
        make_backend=lazy(
            _BACKEND, upstream_cls=_UPSTREAM.format(module=module, name=name), has_object=name != "Reach"
        ),
        controllers=CONTROLLERS,
        goal_dim=3,
        max_episode_steps=50,
        distance_threshold=0.05,
        doc=doc,
        scripted_policy=EEDeltaPolicy("Fetch", policy),
        scripted_min_success=min_success,
        render_fps=25,
        cameras=CAMERAS,
        entities=ENTITIES[name],
        stability_steps=STABILITY_STEPS,
        upstream_id=f"Fetch{name}-v4",
        # gymnasium-robotics registers its IDs when imported: "module:ID" imports it.
        make_upstream=lazy("gymnasium:make", f"gymnasium_robotics:Fetch{name}-v4", disable_env_checker=True),
    )
    for name, module, term_set, doc, policy, min_success in (
        ("Reach", "reach", "reach", REACH_DOC, reach_policy, 0.9),
        ("Push", "push", "push", PUSH_DOC, push_policy, 0.9),
        ("Slide", "slide", "push", SLIDE_DOC, slide_policy, None),
        ("PickAndPlace", "pick_and_place", "grasp", PICK_AND_PLACE_DOC, pick_and_place_policy, 0.9),
    )
)
