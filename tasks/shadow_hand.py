"""The Shadow Hand family: gymnasium-robotics' HandReach-v3 and HandManipulateBlock-v1.

The backend wraps the real upstream env object (model, reset, goal sampling,
observation), like the Fetch family. Two action modes, both 20 joint-position
targets through the hand's own position actuators:

* ``native``: upstream's absolute targets, ``ctrl = centre + a * half_range`` of each
  actuator's control range, by upstream's own ``_set_action``.
* ``joint_delta``: upstream's ``relative_control=True``: ``ctrl = q + a * half_range``,
  where ``q`` is the actuated joint's angle (plus the coupled distal joint J0 for the
  FF/MF/RF/LF J1 actuators), clipped to the control range. Upstream's own
  implementation of it calls mujoco-py APIs (``data.get_joint_qpos``) and raises
  ``AttributeError`` under the ``mujoco`` bindings, so this backend computes the same
  formula from precomputed ``qpos`` addresses.

Everything else (observation vector, goals, success) is upstream's unchanged.
"""

from __future__ import annotations

import math
from functools import partial
from typing import Any

import numpy as np
from gymnasium_robotics.envs.shadow_dexterous_hand.hand_env import DEFAULT_CAMERA_CONFIG
from gymnasium_robotics.envs.shadow_dexterous_hand.manipulate_block import MujocoHandBlockEnv
from gymnasium_robotics.envs.shadow_dexterous_hand.reach import MujocoHandReachEnv

from unified_manip.backend import Backend
from unified_manip.config import EnvConfig
from unified_manip.control import bad_state_warnings
from unified_manip.registry import TaskSpec, register_task, euclidean

from unified_manip.rendering import LazyRenderer

from ._upstream import pickle_upstream, unpickle_upstream, upstream_reset

ACTION_MODES = ("joint_delta", "native")

#: Upstream's block success: position within 1 cm and rotation within 0.1 rad.
BLOCK_POSITION_THRESHOLD = 0.01
BLOCK_ROTATION_THRESHOLD = 0.1
#: Rotation error is folded into the goal distance at this many metres per radian, so
#: that ``distance < 0.01`` is exactly upstream's "position < 0.01 and rotation < 0.1".
ROTATION_WEIGHT = BLOCK_POSITION_THRESHOLD / BLOCK_ROTATION_THRESHOLD


def block_goal_distance(achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
    """``max(d_pos, 0.1 m/rad * d_rot)`` over goals ``(..., 7)`` = (x, y, z, qw, qx, qy, qz).

    ``d_pos`` is the Euclidean position error (m) and ``d_rot = 2 arccos(clip(<qa, qd>))``
    upstream's rotation error (rad): the real part of ``qa * conj(qd)`` is the dot
    product of the two quaternions.
    """
    a = np.asarray(achieved_goal)
    b = np.asarray(desired_goal)
    diff = a[..., :3] - b[..., :3]
    d_pos = np.sqrt((diff * diff).sum(axis=-1))
    w = (a[..., 3:] * b[..., 3:]).sum(axis=-1)
    d_rot = 2.0 * np.arccos(np.clip(w, -1.0, 1.0))
    return np.maximum(d_pos, ROTATION_WEIGHT * d_rot)


class HandBackend(Backend):
    """One Shadow Hand task under ``native`` or ``joint_delta``."""

    def __init__(self, config: EnvConfig, upstream_cls: type, kind: str) -> None:
        if config.options:
            raise TypeError(f"Shadow Hand tasks take no extra options, got {sorted(config.options)}")
        self.kind = kind
        width, height = config.render_width, config.render_height
        up = upstream_cls(reward_type="sparse", width=width, height=height)
        up.mujoco_renderer = None  # we render with our own renderer (see render())
        self._up = up
        self.dt = up.dt
        self.action_dim = 20
        self._relative = config.action_mode == "joint_delta"
        m = up.model
        self._ctrl_low = m.actuator_ctrlrange[:, 0].copy()
        self._ctrl_high = m.actuator_ctrlrange[:, 1].copy()
        self._half_range = (self._ctrl_high - self._ctrl_low) / 2.0
        # joint_delta: the qpos address of each actuator's joint (upstream: the actuator
        # name with ":A_" replaced by ":"), and of the coupled J0 for the J1 actuators.
        names = [m.actuator(i).name for i in range(m.nu)]
        self._act_qadr = np.array([m.jnt_qposadr[m.joint(n.replace(":A_", ":")).id] for n in names])
        self._coupled_act = np.array([names.index(f"robot0:A_{f}J1") for f in ("FF", "MF", "RF", "LF")])
        self._coupled_qadr = np.array([m.jnt_qposadr[m.joint(f"robot0:{f}J0").id] for f in ("FF", "MF", "RF", "LF")])
        if kind != "reach":
            self._palm = m.body("robot0:palm").id
            self._obj_q = int(m.jnt_qposadr[m.joint("object:joint").id])
        self._obs: dict[str, np.ndarray] | None = None
        self._unstable = False
        self._renderer = LazyRenderer(config.render_mode, width, height, camera_config=DEFAULT_CAMERA_CONFIG)

    @property
    def model(self):
        return self._up.model

    @property
    def data(self):
        return self._up.data

    def reset(self, np_random: np.random.Generator) -> None:
        upstream_reset(self._up, np_random)
        self._obs = self._up._get_obs()
        self._unstable = False

    def step(self, action: np.ndarray) -> dict[str, Any]:
        up = self._up
        before = bad_state_warnings(up.data)
        a = action.astype(np.float32)  # upstream's action-space dtype
        if self._relative:
            q = up.data.qpos
            centre = q[self._act_qadr]
            centre[self._coupled_act] += q[self._coupled_qadr]
            up.data.ctrl[:] = np.clip(centre + a * self._half_range, self._ctrl_low, self._ctrl_high)
        else:
            up._set_action(a)
        up._mujoco_step(a)
        up._step_callback()
        self._unstable = bad_state_warnings(up.data) > before
        self._obs = up._get_obs()
        return {}

    def physics_step(self) -> None:
        self._up._mujoco_step(None)

    def unstable(self) -> bool:
        return self._unstable

    def observation(self) -> np.ndarray:
        return self._obs["observation"]

    def achieved_goal(self) -> np.ndarray:
        return self._obs["achieved_goal"]

    def desired_goal(self) -> np.ndarray:
        return self._obs["desired_goal"]

    def reward_state(self) -> tuple[float, float]:
        """Block: (palm-to-block distance, 1 while the block is still on the hand, i.e.
        its centre above z = 0.04 m, upstream's reset criterion)."""
        if self.kind == "reach":
            return 0.0, 0.0
        d = self._up.data
        obj = d.qpos[self._obj_q : self._obj_q + 3]
        return math.dist(d.xpos[self._palm], obj), float(obj[2] > 0.04)

    def render(self) -> np.ndarray | None:
        up = self._up
        up._render_callback()  # upstream: show the goal
        return self._renderer.render(up.model, up.data)

    def close(self) -> None:
        self._renderer.close()

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        state["_up"] = pickle_upstream(self._up)
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        state["_up"] = unpickle_upstream(state["_up"])
        self.__dict__.update(state)


_MODES = """Action modes (20 entries in [-1, 1], one per actuator, upstream's order: WRJ1, WRJ0,
FFJ3-1, MFJ3-1, RFJ3-1, LFJ4-1, THJ4-0):
    native       upstream's absolute targets: ctrl = centre + a * half range of each
                 actuator's control range (rad).
    joint_delta  upstream's relative_control: ctrl = q + a * half range, q the joint's
                 current angle (J1 + J0 for the coupled finger joints), clipped.
Other modes raise ValueError: the hand has no end effector or torque interface."""

REACH_DOC = f"""HandReach: move the Shadow Hand's five fingertips to goal positions
(gymnasium-robotics HandReach-v3).

With probability 0.1 the goal is the initial fingertip layout; otherwise one finger's
tip must meet the thumb's tip over the palm, the others keep their initial positions.
Success: Euclidean distance over the 15 goal coordinates < 0.01 m (upstream's
criterion); sparse reward = success - 1 = upstream's. 50 steps of 40 ms.

Observation (63,), upstream's vector exactly:
    0-23   joint angles (24 joints, upstream's order)             rad
    24-47  joint velocities                                       rad/s
    48-62  fingertip positions (ff, mf, rf, lf, th; x, y, z)      m
Goal (15,): achieved = fingertip positions, desired = their targets, m.

{_MODES}
Dense reward: kind "reach": reach = 1 - tanh(5 d), success bonus 10.
Version history: v0 initial (over HandReach-v3, gymnasium-robotics 1.4.2).
"""

BLOCK_DOC = f"""HandManipulateBlock: move and rotate a block held on the Shadow Hand's palm
to a goal pose (gymnasium-robotics HandManipulateBlock-v1: random target position
and full xyz target rotation).

The block starts on the palm with a random rotation and a 5 mm position jitter; the
goal position is the block's position plus an offset in x [-0.04, 0.04], y [-0.06,
0.02], z [0, 0.06] m; the goal rotation is uniformly random. Success (upstream's):
position error < 0.01 m and rotation error < 0.1 rad. 100 steps of 40 ms.

Observation (61,), upstream's vector exactly:
    0-23   joint angles                                           rad
    24-47  joint velocities                                       rad/s
    48-53  block linear and angular velocity                      m/s, rad/s
    54-60  block pose: position, quaternion (w, x, y, z)          m, -
Goal (7,): achieved = block pose, desired = goal pose (position m, unit quaternion).
Goal distance = max(position error, 0.1 m/rad x rotation error), threshold 0.01, so
success is exactly upstream's position-and-rotation criterion; sparse reward =
success - 1 = upstream's sparse reward.

{_MODES}
Dense reward: kind "push" (an object, no grasp gate): reach = 1 - tanh(5 |palm -
block|) keeps the block near the palm, place = 5 (1 - tanh(5 d)), success bonus 10;
``grasped`` is 1 while the block is on the hand (centre above z = 0.04 m, upstream's
reset check), so dense_penalized's drop penalty (-10) fires when it falls off.
Version history: v0 initial (over HandManipulateBlock-v1, gymnasium-robotics 1.4.2).
"""

#: Random steps per mode in the stability test (the hand steps at a few hundred/s).
STABILITY_STEPS = 1_000


def _register() -> None:
    common = dict(family="shadow_hand", action_modes=ACTION_MODES, render_fps=25, stability_steps=STABILITY_STEPS)
    register_task(
        TaskSpec(
            name="HandReach",
            kind="reach",
            make_backend=partial(HandBackend, upstream_cls=MujocoHandReachEnv, kind="reach"),
            goal_dim=15,
            max_episode_steps=50,
            distance_threshold=0.01,
            doc=REACH_DOC,
            goal_distance=euclidean,
            upstream_id="HandReach-v3",
            **common,
        )
    )
    register_task(
        TaskSpec(
            name="HandManipulateBlock",
            kind="push",
            make_backend=partial(HandBackend, upstream_cls=MujocoHandBlockEnv, kind="push"),
            goal_dim=7,
            max_episode_steps=100,
            distance_threshold=BLOCK_POSITION_THRESHOLD,
            doc=BLOCK_DOC,
            goal_distance=block_goal_distance,
            upstream_id="HandManipulateBlock-v1",
            **common,
        )
    )


_register()
