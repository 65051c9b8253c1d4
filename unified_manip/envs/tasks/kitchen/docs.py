"""The kitchen tasks' documentation pages (``unified-manip list --doc``)."""

from __future__ import annotations

from unified_manip.envs.controllers.docs import modes_section
from unified_manip.envs.tasks.kitchen.controllers import CONTROLLERS
from unified_manip.envs.tasks.kitchen.subtasks import BONUS_THRESH, D4RL_SUBTASKS, DESCRIPTIONS, SubtaskDistance


def _goal_layout(distance: SubtaskDistance) -> str:
    rows = []
    for name, s in zip(distance.subtasks, distance.slices):
        where = f"{s.start}" if s.stop - s.start == 1 else f"{s.start}-{s.stop - 1}"
        what, units = DESCRIPTIONS[name]
        rows.append(f"    {where:<6} {name + ': ' + what:<90} {units}")
    return "\n".join(rows)


def kitchen_doc(name: str, distance: SubtaskDistance) -> str:
    """The page of a kitchen task whose goal is ``distance.subtasks``."""
    subtasks = ", ".join(distance.subtasks)
    d4rl = ", D4RL's kitchen tasks" if distance.subtasks == D4RL_SUBTASKS else ""
    return f"""{name}: with the Franka arm in a kitchen, complete the subtasks {subtasks}
(gymnasium-robotics FrankaKitchen-v1 with tasks_to_complete={list(distance.subtasks)!r}{d4rl}).

Starting state: upstream's fixed initial state (the doors closed, the burners and the
light off, the kettle on the bottom left burner), the same every episode; the seed draws
only the observation noise.

Goal ({distance.goal_dim},): each subtask's joints one after another, achieved = their
positions now, desired = upstream's targets (the same every episode):
{_goal_layout(distance)}

Success: upstream completes a subtask when the norm of its joints' error is below
{BONUS_THRESH:g}; the goal distance is the largest of the subtasks' errors, threshold
{BONUS_THRESH:g}, so success is every subtask complete at once. Upstream's reward counts the
subtasks completed on a step, each once per episode, and ends the episode when all have
been (terminate_on_tasks_completed); that depends on the episode's past, which hindsight
relabelling cannot replay, so here success is the state's. A subtask's error is
env.unwrapped.task.goal_distance.errors(achieved_goal, desired_goal). Sparse reward =
success - 1. 280 steps of 80 ms.

Observation (59,), upstream's vector exactly, with upstream's uniform noise (0.01 of each
joint's amplitude on the robot, 0.0005 on the kitchen's joints), drawn from the env's
seeded generator:
    0-8    arm and finger joint positions                          rad, m
    9-17   arm and finger joint velocities                         rad/s, m/s
    18-38  the kitchen's qpos: knobs, burners, light, cabinets, microwave, kettle pose  rad, m, -
    39-58  the kitchen's qvel                                       rad/s, m/s

Action modes (native: 9 entries in [-1, 1], the 7 arm joints then the 2 fingers; the
other joint modes: 7 arm entries then one gripper entry, -1 closed, +1 open; the
end-effector modes: dx, dy, dz of the end-effector site, then the gripper; they hold the
site's orientation at reset):
{modes_section(CONTROLLERS)}
Every mode but native runs on a copy of the model with gravity compensation on the robot.

Rewards: term set "kitchen": progress = 1 - tanh(5 d) (scale place, 5) on the largest
subtask error d, success bonus 10; dense_penalized adds -0.01 sum(a^2).

Version history: v0 initial (over FrankaKitchen-v1, gymnasium-robotics 1.4.2).
"""
