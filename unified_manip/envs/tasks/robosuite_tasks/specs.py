"""The robosuite task specs (registered by ``unified_manip.envs.tasks``)."""

from __future__ import annotations

from unified_manip.envs.lazy import lazy
from unified_manip.envs.registry import TaskSpec
from unified_manip.envs.tasks.gripper_terms import GRIPPER_TERM_SETS
from unified_manip.envs.tasks.robosuite_tasks.cameras import cameras_of
from unified_manip.envs.tasks.robosuite_tasks.controllers import CONTROLLERS
from unified_manip.envs.tasks.robosuite_tasks.docs import CAN_DOC, DOOR_DOC, LIFT_DOC, NUT_DOC, STACK_DOC
from unified_manip.envs.tasks.robosuite_tasks.entities import ENTITIES
from unified_manip.envs.tasks.robosuite_tasks.more_docs import (
    BREAD_DOC,
    CEREAL_DOC,
    MILK_DOC,
    SQUARE_NUT_DOC,
    TOOL_HANG_DOC,
    WIPE_DOC,
)
from unified_manip.envs.tasks.robosuite_tasks.more_policies import bread_policy, cereal_policy, milk_policy, nut_policy
from unified_manip.envs.tasks.robosuite_tasks.policies import can_policy, door_policy, lift_policy, stack_policy
from unified_manip.envs.tasks.robosuite_tasks.two_arm_docs import TWO_ARM_HANDOVER_DOC, TWO_ARM_LIFT_DOC
from unified_manip.envs.tasks.robosuite_tasks.two_arm_policies import two_arm_handover_policy, two_arm_lift_policy
from unified_manip.envs.tasks.scripted import EEDeltaPolicy

_PACKAGE = "unified_manip.envs.tasks.robosuite_tasks"

#: Random steps per mode in the stability test, and episodes of the scripted-policy
#: test: robosuite steps at ~100-200/s here, so 100 random steps per mode (x 8 modes x
#: 11 one-arm tasks) and 5 seeded episodes (up to 1,000 steps) per task keep the suite's
#: time; the policies' rates over more episodes are measured by ``unified-manip collect``
#: (docs/datasets.md). Seeds 1000-1004 gave 1.0 on every task with a minimum but
#: NutAssemblySquare (0.4, minimum 0.2) and PickPlaceBread (0.8, minimum 0.55).
STABILITY_STEPS = 100
SCRIPTED_EPISODES = 5
#: The two-arm tasks step two arms' controllers (two IKs in the ee modes): ~30-60 steps/s
#: here, so their stability test plays fewer steps in the same time.
TWO_ARM_STABILITY_STEPS = 60


def _spec(name, term_set, goal_dim, steps, threshold, doc, policy, min_success, robots=1) -> TaskSpec:
    return TaskSpec(
        name=name,
        family="robosuite",
        terms=GRIPPER_TERM_SETS[term_set],
        make_backend=lazy(f"{_PACKAGE}.backend:RobosuiteBackend", task=name),
        controllers=CONTROLLERS,
        goal_dim=goal_dim,
        max_episode_steps=steps,
        distance_threshold=threshold,
        doc=doc,
        scripted_policy=EEDeltaPolicy("robosuite", policy) if policy else None,
        scripted_min_success=min_success,
        render_fps=20,
        cameras=cameras_of(robots),
        entities=ENTITIES[name],
        scripted_episodes=SCRIPTED_EPISODES,
        stability_steps=STABILITY_STEPS if robots == 1 else TWO_ARM_STABILITY_STEPS,
        upstream_id=f"robosuite:{name}",
        make_upstream=lazy(f"{_PACKAGE}.suite:make_upstream", name, "Panda", "native", robots),
        extra="robosuite",
    )


SPECS: tuple[TaskSpec, ...] = tuple(
    _spec(*row)
    for row in (
        ("Lift", "grasp", 3, 100, 0.05, LIFT_DOC, lift_policy, 0.8),
        ("Stack", "grasp", 3, 200, 0.02, STACK_DOC, stack_policy, 0.8),
        ("PickPlaceCan", "grasp", 3, 200, 0.05, CAN_DOC, can_policy, 0.8),
        ("NutAssemblyRound", "grasp", 3, 200, 0.02, NUT_DOC, None, None),
        ("Door", "push", 1, 150, 0.05, DOOR_DOC, door_policy, 0.8),
        ("NutAssemblySquare", "grasp", 3, 200, 0.02, SQUARE_NUT_DOC, nut_policy, 0.2),
        ("PickPlaceMilk", "grasp", 3, 200, 0.05, MILK_DOC, milk_policy, 0.7),
        ("PickPlaceBread", "grasp", 3, 200, 0.05, BREAD_DOC, bread_policy, 0.55),
        ("PickPlaceCereal", "grasp", 3, 200, 0.05, CEREAL_DOC, cereal_policy, 0.25),
        # Wipe: success is every one of robosuite's 100 markers wiped: a fraction within
        # half a marker of 1. ToolHang: both stage flags set.
        ("Wipe", "push", 1, 500, 0.005, WIPE_DOC, None, None),
        ("ToolHang", "push", 2, 700, 0.5, TOOL_HANG_DOC, None, None),
        # Two Pandas: the pot to a point 16-22 cm up; the hammer's handover flags.
        ("TwoArmLift", "push", 3, 150, 0.05, TWO_ARM_LIFT_DOC, two_arm_lift_policy, None, 2),
        ("TwoArmHandover", "push", 3, 300, 0.5, TWO_ARM_HANDOVER_DOC, two_arm_handover_policy, None, 2),
    )
)
