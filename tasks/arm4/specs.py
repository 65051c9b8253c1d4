"""The 4-DOF arm's task specs (registered by ``unified_manip.tasks``)."""

from __future__ import annotations

from unified_manip.lazy import lazy
from unified_manip.registry import TaskSpec

from ..scripted import EEDeltaPolicy
from .controllers import CONTROLLERS
from .docs import PICK_AND_PLACE_DOC, PUSH_DOC, REACH_DOC
from .policies import pick_and_place_policy, push_policy, reach_policy

_BACKEND = "unified_manip.tasks.arm4.backend:Arm4Backend"

SPECS: tuple[TaskSpec, ...] = tuple(
    TaskSpec(
        name=name,
        family="arm4",
        shaping=shaping,
        make_backend=lazy(_BACKEND, scene=scene),
        controllers=CONTROLLERS,
        goal_dim=3,
        max_episode_steps=steps,
        distance_threshold=0.05,
        doc=doc,
        scripted_policy=EEDeltaPolicy("Arm4", policy),
        scripted_min_success=0.9,
        render_fps=50,
    )
    for name, scene, shaping, steps, doc, policy in (
        ("Arm4Reach", "reach", "reach", 50, REACH_DOC, reach_policy),
        ("Arm4Push", "push", "push", 100, PUSH_DOC, push_policy),
        ("Arm4PickAndPlace", "pick_and_place", "grasp", 100, PICK_AND_PLACE_DOC, pick_and_place_policy),
    )
)
