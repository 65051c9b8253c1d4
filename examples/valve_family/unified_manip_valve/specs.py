"""The valve family's task specs: what ``unified_manip`` registers.

The ``unified_manip.families`` entry point in ``pyproject.toml`` names this module; it
defines :data:`SPECS`. Importing it must stay cheap: the backend (which imports MuJoCo) is
named lazily and loaded by the first ``gym.make``.
"""

from __future__ import annotations

import numpy as np

from unified_manip.envs import controllers as ctl
from unified_manip.envs.cameras import CameraConfig
from unified_manip.envs.controllers.docs import modes_section
from unified_manip.envs.lazy import lazy
from unified_manip.envs.registry import TaskSpec
from unified_manip.envs.rendering import SceneOptions
from unified_manip_valve.observations import GROUPS, SIZES, default_slices
from unified_manip_valve.scene import HANDLE_RADIUS, LINKS, TURN_HIGH, TURN_LOW, VALVE_AXIS, wrap
from unified_manip_valve.terms import SPIN_LIMIT, SPIN_SCALE, TURN

#: Success: the valve within this angle of the target, rad (about 6 degrees).
THRESHOLD = 0.1

#: Every mode the shared controllers can drive on a robot without a gripper. The
#: end-effector modes are left out: their action is (dx, dy, dz, gripper), and a planar
#: finger has neither a z axis to move along nor a gripper, so two of their four entries
#: would do nothing.
CONTROLLERS = {
    "joint_torque": ctl.JointTorque(),
    "joint_position": ctl.JointPosition(),
    "joint_delta": ctl.JointDelta(max_delta=0.05),
    "joint_target_delta": ctl.JointTargetDelta(max_delta=0.05),
    "joint_velocity": ctl.JointVelocity(max_velocity=2.5, kv=0.5),
    "native": ctl.JointDelta(max_delta=0.05),
}

#: The model's ``top`` camera, the view ``render()`` draws.
CAMERAS = {"top": CameraConfig(SceneOptions(camera="top"))}


def angle_distance(achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
    """The goal distance: the wrapped angle between the goals, rad, ``(..., 1) -> (...)``."""
    return np.abs(wrap(np.asarray(achieved_goal) - np.asarray(desired_goal)))[..., 0]


def _layout() -> str:
    """The default observation's table, from the groups (the layout is written once)."""
    rows = []
    for name, s in default_slices().items():
        index = f"{s.start}" if s.stop - s.start == 1 else f"{s.start}-{s.stop - 1}"
        rows.append(f"    {index:<7}{name:<13}{GROUPS[name].units}")
    return "\n".join(rows)


VALVE_TURN_DOC = f"""ValveTurn: a two-link finger turns a valve to a target angle.

The finger (links of {LINKS[0]} and {LINKS[1]} m, hinges j0 and j1 about the vertical,
base at the origin) and the valve (a wheel on a vertical hinge at x = {VALVE_AXIS[0]} m,
with damping and friction) lie in the horizontal plane. The handle stands on the wheel's
rim, {HANDLE_RADIUS} m from its axis; only the fingertip and the handle collide.

Starting state: the finger at rest; the valve's angle uniform in [-pi, pi); the target
{TURN_LOW}-{TURN_HIGH} rad from it, either way.

Success: the valve within {THRESHOLD} rad of the target (the wrapped angle difference).

Observation ({sum(SIZES.values())},):
    index  group        units
{_layout()}

Goal (1,): achieved = the valve's angle, desired = the target angle, rad, both wrapped to
[-pi, pi); the goal distance is the wrapped difference.
Action modes (action in [-1, 1], one entry per joint, no gripper; native is joint_delta;
no end-effector modes: a planar finger has no z axis and no gripper):
{modes_section(CONTROLLERS)}

Rewards: the term set "valve" reads fingertip_to_handle (m) and valve_speed (rad/s):
approach = 1 - tanh(5 |fingertip - handle|), turn = 5 (1 - tanh(5 d)), success bonus 10;
dense_penalized adds action = -0.01 sum(a^2) and
spin = -{SPIN_SCALE} max(0, valve_speed - {SPIN_LIMIT} rad/s).

Version history: v0 initial.
"""

SPECS = (
    TaskSpec(
        name="ValveTurn",
        family="valve",
        terms=TURN,
        make_backend=lazy("unified_manip_valve.backend:ValveBackend"),
        controllers=CONTROLLERS,
        goal_dim=1,
        max_episode_steps=100,
        distance_threshold=THRESHOLD,
        doc=VALVE_TURN_DOC,
        goal_distance=angle_distance,
        render_fps=50,
        stability_steps=2_000,
        cameras=CAMERAS,
    ),
)
