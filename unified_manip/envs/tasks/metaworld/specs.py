"""The Meta-World task specs (registered by ``unified_manip.envs.tasks``), one per task
of :data:`.tasks.TASKS`, without importing Meta-World or MuJoCo."""

from __future__ import annotations

from unified_manip.envs.lazy import lazy
from unified_manip.envs.registry import TaskSpec
from unified_manip.envs.tasks.gripper_terms import GRIPPER_TERM_SETS
from unified_manip.envs.tasks.metaworld.cameras import CAMERAS
from unified_manip.envs.tasks.metaworld.controllers import CONTROLLERS
from unified_manip.envs.tasks.metaworld.docs import MAX_STEPS, task_doc
from unified_manip.envs.tasks.metaworld.policies import MetaWorldPolicy
from unified_manip.envs.tasks.metaworld.tasks import TASKS

#: Each version's wrist damping on the actuated copy, N m s/rad (None: the model's 10;
#: :mod:`.rig`). At 1, a wrist's 9 N m reaches 9 rad/s, above the Sawyer's rated
#: 3.49-4.55 rad/s. Version 1 changes only the joint and end-effector modes: native never
#: uses the copy.
WRIST_DAMPING = {0: None, 1: 1.0, 2: 1.0}

#: The versions whose joint modes observe the robot's joints (:data:`.observations.JOINT_MODE_EXTRA`,
#: as Fetch's do). Version 2 changes only the joint modes' observation.
JOINT_OBSERVATION = {0: False, 1: False, 2: True}

_BACKEND = "unified_manip.envs.tasks.metaworld.backend:MetaWorldBackend"

#: Random steps per mode in the stability test (a Meta-World step takes about a millisecond).
STABILITY_STEPS = 500

#: Episodes of the scripted-policy check (its success is reported, not asserted here).
SCRIPTED_EPISODES = 5

SPECS: tuple[TaskSpec, ...] = tuple(
    TaskSpec(
        name=task.name,
        version=version,
        family="metaworld",
        terms=GRIPPER_TERM_SETS[task.terms],
        make_backend=lazy(_BACKEND, task=env_name, wrist_damping=damping, joint_observation=JOINT_OBSERVATION[version]),
        controllers=CONTROLLERS,
        goal_dim=3,
        max_episode_steps=MAX_STEPS,
        distance_threshold=task.threshold,
        doc=task_doc(task, damping, JOINT_OBSERVATION[version]),
        goal_distance=task.distance,
        scripted_policy=MetaWorldPolicy(env_name),
        scripted_episodes=SCRIPTED_EPISODES,
        render_fps=80,
        cameras=CAMERAS,
        stability_steps=STABILITY_STEPS,
        upstream_id=f"metaworld:{env_name}",
        make_upstream=lazy("unified_manip.envs.tasks.metaworld.backend:make_upstream", env_name),
        extra="metaworld",
    )
    for version, damping in WRIST_DAMPING.items()
    for env_name, task in TASKS.items()
)
