"""The Shadow Hand task specs (registered by ``unified_manip.envs.tasks``)."""

from __future__ import annotations

from unified_manip.envs.lazy import lazy
from unified_manip.envs.registry import TaskSpec, euclidean
from unified_manip.envs.tasks.gripper_terms import GRIPPER_TERM_SETS
from unified_manip.envs.tasks.shadow_hand.cameras import CAMERAS
from unified_manip.envs.tasks.shadow_hand.controllers import CONTROLLERS
from unified_manip.envs.tasks.shadow_hand.docs import BLOCK_DOC, REACH_DOC, in_hand_doc
from unified_manip.envs.tasks.shadow_hand.entities import ENTITIES
from unified_manip.envs.tasks.shadow_hand.goals import PEN_POSITION_THRESHOLD, PoseDistance, block_goal_distance
from unified_manip.envs.tasks.shadow_hand.terms import IN_HAND, ON_PALM, PALM_TO_OBJECT

_BACKEND = "unified_manip.envs.tasks.shadow_hand.backend:HandBackend"
_UPSTREAM = "gymnasium_robotics.envs.shadow_dexterous_hand"

#: Random steps per mode in the stability test (the hand steps at a few hundred/s).
STABILITY_STEPS = 600


def _spec(name, terms, upstream, upstream_id, goal_dim, steps, distance, threshold, doc, **backend) -> TaskSpec:
    return TaskSpec(
        name=name,
        family="shadow_hand",
        terms=terms,
        make_backend=lazy(_BACKEND, upstream_cls=f"{_UPSTREAM}.{upstream}", **backend),
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


#: The egg and pen tasks: (object, upstream module:class, its goal distance) x (full pose, Rotate).
_PEN = PoseDistance(PEN_POSITION_THRESHOLD, ignore_z=True)
_IN_HAND = (
    ("Egg", "manipulate_egg:MujocoHandEggEnv", PoseDistance()),
    ("Pen", "manipulate_pen:MujocoHandPenEnv", _PEN),
)
_ROTATE = {"target_position": "ignore"}


def _in_hand(obj: str, upstream: str, distance: PoseDistance, rotate: bool) -> TaskSpec:
    name = f"HandManipulate{obj}{'Rotate' if rotate else ''}"
    if rotate:
        distance = PoseDistance(distance.position_threshold, distance.rotation_threshold, False, distance.ignore_z)
    return _spec(
        name,
        IN_HAND,
        upstream,
        f"{name}-v1",
        7,
        100,
        distance,
        distance.threshold,
        in_hand_doc(obj.lower(), distance),
        held=obj.lower(),
        quantities=(PALM_TO_OBJECT, ON_PALM),
        upstream_kwargs=_ROTATE if rotate else None,
    )


SPECS: tuple[TaskSpec, ...] = (
    _spec(
        "HandReach",
        GRIPPER_TERM_SETS["reach"],
        "reach:MujocoHandReachEnv",
        "HandReach-v3",
        15,
        50,
        euclidean,
        0.01,
        REACH_DOC,
    ),
    _spec(
        "HandManipulateBlock",
        GRIPPER_TERM_SETS["push"],
        "manipulate_block:MujocoHandBlockEnv",
        "HandManipulateBlock-v1",
        7,
        100,
        block_goal_distance,
        block_goal_distance.threshold,
        BLOCK_DOC,
        held="block",
    ),
    *(_in_hand(*args, rotate) for args in _IN_HAND for rotate in (False, True)),
)
