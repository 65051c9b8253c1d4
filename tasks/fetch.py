"""The Fetch family: gymnasium-robotics' Fetch{Reach,Push,Slide,PickAndPlace}-v4.

The backend wraps the real upstream env object (its model, reset distribution, goal
sampling and observation code), so every task is exactly upstream's.

* ``native`` runs upstream's own mocap control, unchanged: its ``_set_action``,
  ``_mujoco_step`` and ``_step_callback`` on its own model. With the same seed and
  actions it reproduces ``gym.make("Fetch...-v4")`` (observation, sparse reward,
  ``is_success``); ``tests/test_fetch.py`` checks it.
* The other modes run on a modified copy of the model (built once per env with
  ``mujoco.MjSpec``), because the stock arm has no actuators: it follows a mocap weld.
  The copy **removes the weld**, adds force-limited ``general`` position-servo
  actuators on the 7 arm joints (the :class:`~unified_manip.control.ArmRig` reads
  their gains), turns on ``gravcomp`` for every body from the shoulder down (so zero
  torque holds the arm still), adds upstream's PickAndPlace finger actuators to the
  tasks that lack them, gives the three unlimited roll joints a +-pi command range,
  and **freezes the base slides and the torso** with joint equality constraints at
  their initial values (the torso starts at 0.0013 m, below its range
  [0.0386, 0.3861]; its range limit is switched off in the copy so the constraint and
  the limit do not fight). The layout of ``qpos`` is unchanged, so upstream's reset
  and observation code run on the copy unmodified.
"""

from __future__ import annotations

import math
from functools import partial
from typing import Any, Callable

import mujoco
import numpy as np
from gymnasium_robotics.envs.fetch.fetch_env import DEFAULT_CAMERA_CONFIG
from gymnasium_robotics.envs.fetch.pick_and_place import MujocoFetchPickAndPlaceEnv
from gymnasium_robotics.envs.fetch.push import MujocoFetchPushEnv
from gymnasium_robotics.envs.fetch.reach import MujocoFetchReachEnv
from gymnasium_robotics.envs.fetch.slide import MujocoFetchSlideEnv
from gymnasium_robotics.utils.mujoco_utils import MujocoModelNames

from unified_manip.backend import Backend
from unified_manip.config import ACTION_MODES, EnvConfig
from unified_manip.control import ArmGains, ArmRig, bad_state_warnings, make_mujoco_control
from unified_manip.registry import TaskSpec, register_task
from unified_manip.rendering import LazyRenderer

from ._upstream import pickle_upstream, unpickle_upstream, upstream_reset

ARM_JOINTS: tuple[str, ...] = tuple(
    f"robot0:{name}_joint"
    for name in ("shoulder_pan", "shoulder_lift", "upperarm_roll", "elbow_flex", "forearm_roll", "wrist_flex", "wrist_roll")
)
ARM_ACTUATORS: tuple[str, ...] = tuple(j.replace("_joint", "_servo") for j in ARM_JOINTS)
FINGER_JOINTS = ("robot0:l_gripper_finger_joint", "robot0:r_gripper_finger_joint")
FINGER_GEOMS = ("robot0:l_gripper_finger_link", "robot0:r_gripper_finger_link")
FROZEN_JOINTS = ("robot0:slide0", "robot0:slide1", "robot0:slide2", "robot0:torso_lift_joint")
UNLIMITED_ROLL_JOINTS = ("robot0:upperarm_roll_joint", "robot0:forearm_roll_joint", "robot0:wrist_roll_joint")

#: Arm servo gains and torque limits. The model's arm joints carry damping 50 N m s/rad
#: and armature 1 kg m^2 (far more than the real Fetch), so the limits are above the
#: real robot's efforts (33.8, 131.8, 76.9, 66.2, 29.4, 25.7, 7.4 N m) to let the
#: arm move at about 1 rad/s against that damping.
ARM_KP = np.array([3000.0, 3000.0, 3000.0, 3000.0, 1500.0, 1500.0, 1000.0])
ARM_KV = np.array([50.0, 50.0, 50.0, 50.0, 25.0, 25.0, 20.0])
ARM_TORQUE = np.array([150.0, 250.0, 150.0, 150.0, 80.0, 80.0, 60.0])
#: Upstream's PickAndPlace finger actuators (position servos, kp 30000, ctrl 0-0.2 m).
FINGER_KP, FINGER_CTRL_MAX, FINGER_OPEN = 30000.0, 0.2, 0.05

GAINS = ArmGains(kv_velocity=(50.0, 50.0, 50.0, 50.0, 20.0, 20.0, 10.0), max_velocity=1.0, max_delta=0.05, ee_step=0.05)

#: Observation entries appended in the joint modes: 7 arm angles and 7 arm velocities.
N_JOINT_OBS = 14


def _modified_model(path: str, initial_qpos: np.ndarray, width: int, height: int) -> mujoco.MjModel:
    """The Fetch model with arm actuators instead of the mocap weld (see module doc)."""
    spec = mujoco.MjSpec.from_file(path)
    for eq in list(spec.equalities):
        if eq.type == mujoco.mjtEq.mjEQ_WELD:
            spec.delete(eq)
    stack = [spec.body("robot0:shoulder_pan_link")]
    while stack:  # gravity compensation on the whole arm, gripper included
        body = stack.pop()
        body.gravcomp = 1.0
        stack.extend(body.bodies)
    for name in UNLIMITED_ROLL_JOINTS:
        spec.joint(name).range = [-math.pi, math.pi]  # command range; the joint stays unlimited
    for name in ARM_JOINTS:
        if spec.joint(name).limited == mujoco.mjtLimited.mjLIMITED_AUTO:
            spec.joint(name).limited = mujoco.mjtLimited.mjLIMITED_TRUE
    existing = {a.name for a in spec.actuators}
    for name in FINGER_JOINTS:
        if name not in existing:
            a = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
            a.set_to_position(kp=FINGER_KP)
            a.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
            a.ctrlrange = [0.0, FINGER_CTRL_MAX]
    for joint, actuator, kp, kv, tau in zip(ARM_JOINTS, ARM_ACTUATORS, ARM_KP, ARM_KV, ARM_TORQUE):
        a = spec.add_actuator(name=actuator, target=joint, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        a.set_to_position(kp=kp, kv=kv)
        a.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
        a.forcerange = [-tau, tau]
    spec.joint("robot0:torso_lift_joint").limited = mujoco.mjtLimited.mjLIMITED_FALSE
    model = spec.compile()
    for name in FROZEN_JOINTS:
        q0 = float(initial_qpos[model.jnt_qposadr[model.joint(name).id]])
        spec.add_equality(
            type=mujoco.mjtEq.mjEQ_JOINT, objtype=mujoco.mjtObj.mjOBJ_JOINT, name1=name,
            data=[q0] + [0.0] * 10,
        )
    model = spec.compile()
    model.vis.global_.offwidth = width
    model.vis.global_.offheight = height
    return model


class FixedRotation:
    """The IK's target rotation: always the grip site's initial one (a picklable callable)."""

    def __init__(self, rotation: np.ndarray) -> None:
        self.rotation = rotation

    def __call__(self, target: np.ndarray) -> np.ndarray:
        return self.rotation


class FetchBackend(Backend):
    """One Fetch task under one action mode (see the module docstring)."""

    def __init__(self, config: EnvConfig, upstream_cls: type, kind: str) -> None:
        if config.options:
            raise TypeError(f"Fetch tasks take no extra options, got {sorted(config.options)}")
        self.kind = kind
        self.mode = config.action_mode
        width, height = config.render_width, config.render_height
        up = upstream_cls(reward_type="sparse", width=width, height=height)
        up.mujoco_renderer = None  # we render with our own renderer (see render())
        self._up = up
        self.dt = up.dt
        self._native = self.mode == "native"
        if not self._native:
            model = _modified_model(up.fullpath, up.initial_qpos, width, height)
            up.model, up.data = model, mujoco.MjData(model)
            up._model_names = MujocoModelNames(model)
            mujoco.mj_resetData(up.model, up.data)
            up.data.qpos[:] = up.initial_qpos
            up.data.qvel[:] = up.initial_qvel
            mujoco.mj_forward(up.model, up.data)
            blocked = up.block_gripper  # Reach, Push, Slide: fingers held closed
            self.rig = ArmRig(
                up.model,
                up.data,
                joints=ARM_JOINTS,
                actuators=ARM_ACTUATORS,
                gripper_actuators=FINGER_JOINTS,
                gripper_closed=0.0,
                gripper_open=0.0 if blocked else FINGER_OPEN,
                site="robot0:grip",
                gains=GAINS,
            )
            rotation = up.data.site_xmat[self.rig.site_id].reshape(3, 3).copy()  # pointing down
            self.control = make_mujoco_control(self.rig, self.mode, FixedRotation(rotation))
            self.action_dim = self.control.action_dim
        else:
            self.action_dim = 4
        m = up.model
        self._arm_q = m.jnt_qposadr[[m.joint(j).id for j in ARM_JOINTS]]
        self._arm_v = m.jnt_dofadr[[m.joint(j).id for j in ARM_JOINTS]]
        if kind != "reach":
            self._obj_geom = m.geom("object0").id
            self._finger_geoms = tuple(m.geom(g).id for g in FINGER_GEOMS)
        self._obs: dict[str, np.ndarray] | None = None
        self._unstable = False
        self._renderer = LazyRenderer(config.render_mode, width, height, camera_config=DEFAULT_CAMERA_CONFIG)

    @property
    def model(self) -> mujoco.MjModel:
        return self._up.model

    @property
    def data(self) -> mujoco.MjData:
        return self._up.data

    # -------------------------------------------------------------- episode
    def reset(self, np_random: np.random.Generator) -> None:
        up = self._up
        upstream_reset(up, np_random)
        if not self._native:
            self.control.reset()
            self.rig.set_gripper(-1.0)  # ctrl 0, as upstream's reset leaves it
        self._obs = up._get_obs()
        self._unstable = False

    def step(self, action: np.ndarray) -> dict[str, Any]:
        up = self._up
        before = bad_state_warnings(up.data)
        if self._native:
            # Upstream clips in the action space's dtype (float32) and scales in it.
            a = action.astype(np.float32)
            up._set_action(a)
            up._mujoco_step(a)
            up._step_callback()
            diagnostics: dict[str, Any] = {}
        else:
            diagnostics = self.control(action)
            up._mujoco_step(action)
        self._unstable = bad_state_warnings(up.data) > before
        self._obs = up._get_obs()
        return diagnostics

    def physics_step(self) -> None:
        self._up._mujoco_step(None)

    def unstable(self) -> bool:
        return self._unstable

    # -------------------------------------------------------------- observation
    def observation(self) -> np.ndarray:
        obs = self._obs["observation"]
        if self._native or self.mode == "ee_delta":
            return obs
        d = self._up.data
        return np.concatenate((obs, d.qpos[self._arm_q], d.qvel[self._arm_v]))

    def achieved_goal(self) -> np.ndarray:
        return self._obs["achieved_goal"]

    def desired_goal(self) -> np.ndarray:
        return self._obs["desired_goal"]

    def reward_state(self) -> tuple[float, float]:
        if self.kind == "reach":
            return 0.0, 0.0
        rel = self._obs["observation"][6:9]  # object - grip, m
        dist = math.sqrt(float(rel @ rel))
        # Only a cube between the fingers can be held: skip the contact scan otherwise.
        return dist, float(dist < 0.05 and self._fingers_touching())

    def _fingers_touching(self) -> bool:
        """Both fingers touch the object."""
        d = self._up.data
        if d.ncon < 2:
            return False
        pairs = d.contact.geom
        other = pairs[(pairs == self._obj_geom).any(axis=1)].ravel()
        left, right = self._finger_geoms
        return bool((other == left).any() and (other == right).any())

    # -------------------------------------------------------------- rendering
    def render(self) -> np.ndarray | None:
        up = self._up
        up._render_callback()  # upstream: move the target marker to the goal
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
        if not self._native:  # the rig and its controller point at the same model/data
            self.rig.model, self.rig.data = self._up.model, self._up.data


# ------------------------------------------------------------------ scripted policies
# Each maps an observation dict to an ee_delta action (dx, dy, dz, gripper), using the
# upstream observation layout (see the task docs). They are memoryless.

#: Slices of the object tasks' observation.
OBS_GRIP, OBS_OBJ, OBS_REL, OBS_FINGERS = slice(0, 3), slice(3, 6), slice(6, 9), slice(9, 11)


def _toward(delta: np.ndarray, gain: float = 10.0) -> np.ndarray:
    return np.clip(delta * gain, -1.0, 1.0)


def reach_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Move the grip site straight to the goal."""
    return np.append(_toward(obs["desired_goal"] - obs["achieved_goal"]), -1.0).astype(np.float32)


def pick_and_place_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Hover over the cube, descend open, close, then carry it to the goal."""
    o = obs["observation"]
    to_obj = o[OBS_REL]
    to_goal = obs["desired_goal"] - obs["achieved_goal"]
    closed_on_cube = bool(np.all(o[OBS_FINGERS] < 0.03))
    if closed_on_cube and np.linalg.norm(to_obj) < 0.02:
        return np.append(_toward(to_goal), -1.0).astype(np.float32)
    if np.linalg.norm(to_obj[:2]) > 0.01:  # line up above the cube, then come down
        hover = to_obj + np.array([0.0, 0.0, 0.05])
        return np.append(_toward(hover), 1.0).astype(np.float32)
    if np.linalg.norm(to_obj) > 0.01:
        return np.append(_toward(to_obj), 1.0).astype(np.float32)
    return np.array([0.0, 0.0, 0.0, -1.0], dtype=np.float32)


#: Grip-site height above the object's centre while pushing, m. Lower, the fingertips
#: drag on the table and the servos stall.
PUSH_HEIGHT = 0.008
#: Grip site to the object's centre when a finger touches the cube's face, m.
PUSH_CONTACT = 0.04
#: While going around the object the grip site keeps this far from its centre, m (the
#: fingers clear the cube's corners).
PUSH_CLEARANCE = 0.065
#: Extra grip-site height while moving low around the object, m: a fast move near the
#: reach limit makes the arm dip, and fingertips on the table stall it.
APPROACH_LIFT = 0.02
#: Grip-site height above the object's centre from which the fingers clear its top, m.
CLEAR_HEIGHT = 0.05
#: Position gain of the approach and of height keeping: action per metre of error (20
#: asks for the whole error in one step of 5 cm per unit).
PUSH_GAIN = 20.0


def _around(rel: np.ndarray, spot: np.ndarray, radius: float, speed: float) -> np.ndarray:
    """xy action that takes the grip site, at ``rel`` from the object's centre, around the
    circle of ``radius`` towards ``spot`` (also from the centre), the shorter way round:
    towards the circle's tangent point from outside, along the circle and back out to it
    from inside."""
    dist = max(float(np.linalg.norm(rel)), 1e-6)
    radial = rel / dist
    side = 1.0 if radial[0] * spot[1] - radial[1] * spot[0] >= 0.0 else -1.0
    if dist > radius:  # the direction to the centre, turned by the tangent angle
        beta = side * math.asin(radius / dist)
        c, s = math.cos(beta), math.sin(beta)
        return -np.array([c * radial[0] + s * radial[1], c * radial[1] - s * radial[0]]) * speed
    xy = side * np.array([-radial[1], radial[0]]) * speed + radial * (radius - dist) * PUSH_GAIN
    return xy * min(1.0, speed / float(np.linalg.norm(xy)))


def _push(
    obs: dict[str, np.ndarray],
    speed: float,
    stop: float,
    slowdown: float,
    behind_by: float = 0.05,
    lateral_tol: float = 0.02,
    approach_speed: float = 0.8,
) -> np.ndarray:
    """Push the object along the line from it to the goal, re-deciding the contact point
    from the object-goal direction at every step (memoryless).

    * Pushing: the gripper is low, behind the object (seen from the goal) and within
      ``lateral_tol`` of that line: move along it at ``speed`` (``slowdown`` x the
      remaining distance near the goal, only as fast as the gripper is down at the
      object's height) and steer sideways back onto it, so the contact point follows
      the object as it turns or drifts.
    * Behind the object and on the line but high: come down onto it.
    * Otherwise go to the spot ``behind_by`` behind the object: straight if the way is
      clear of the object, straight over it if the fingers already clear its top, else
      around it, low, along the tangents of a circle of radius :data:`PUSH_CLEARANCE`
      (faster than over it: the arm is slow to rise and come down).

    Most of the remaining misses are cubes near the arm's reach with the goal towards
    the robot: the contact point is where the elbow is straight and the IK is slow.
    """
    o = obs["observation"]
    grip, obj = o[OBS_GRIP], o[OBS_OBJ]
    to_goal = (obs["desired_goal"] - obj)[:2]
    remaining = float(np.linalg.norm(to_goal))
    if remaining < stop:
        return np.zeros(4, dtype=np.float32)
    direction = to_goal / max(remaining, 1e-6)
    normal = np.array([-direction[1], direction[0]])
    rel = grip[:2] - obj[:2]
    along = float(rel @ direction)  # negative: the gripper is behind the object
    lateral = float(rel @ normal)
    height = float(grip[2] - obj[2])
    push_z = obj[2] + PUSH_HEIGHT  # grip site above the object's centre: fingertips clear the table
    touching = along > -PUSH_CONTACT - 0.01  # close enough to touch: a wider band keeps the push going
    if along < -0.02 and abs(lateral) < lateral_tol + 0.01 * touching and height < 0.03:
        low = float(np.clip(1.0 - (grip[2] - push_z - 0.01) / 0.02, 0.0, 1.0))
        v = min(speed, slowdown * remaining) * low
        steer = float(np.clip(-lateral * PUSH_GAIN, -0.3, 0.3))
        move = np.append(direction * v + normal * steer, (push_z - grip[2]) * PUSH_GAIN)
        return np.append(np.clip(move, -1.0, 1.0), -1.0).astype(np.float32)
    if along < -PUSH_CONTACT - 0.005 and abs(lateral) < lateral_tol + 0.005:  # on the line, high: come down
        spot = obj[:2] - direction * min(-along, behind_by)
        move = np.append((spot - grip[:2]) * PUSH_GAIN, (push_z - grip[2]) * PUSH_GAIN)
        return np.append(np.clip(move, -1.0, 1.0), -1.0).astype(np.float32)
    spot = -direction * behind_by  # from the object's centre
    to_spot = spot - rel
    dist = float(np.linalg.norm(to_spot))
    # How close the straight way to the spot passes by the object's centre.
    t = float(np.clip(-(rel @ to_spot) / max(dist * dist, 1e-9), 0.0, 1.0))
    clearance = float(np.linalg.norm(rel + t * to_spot))
    if clearance >= PUSH_CLEARANCE:  # the straight way is clear: low, or at the height it has
        xy = to_spot * PUSH_GAIN
        if dist < 0.03:
            z = push_z
        else:
            z = grip[2] if height > CLEAR_HEIGHT - 0.01 else push_z + APPROACH_LIFT
    elif height > CLEAR_HEIGHT - 0.01:  # above the object already: straight over it
        xy = to_spot * PUSH_GAIN
        if float(np.linalg.norm(rel)) < PUSH_CLEARANCE + 0.01:  # over it: slower while still rising
            xy *= min(1.0, (height - 0.02) / (CLEAR_HEIGHT - 0.02))
        z = obj[2] + CLEAR_HEIGHT + 0.01
    else:
        xy = _around(rel, spot, PUSH_CLEARANCE, approach_speed)
        z = push_z + APPROACH_LIFT
    norm = float(np.linalg.norm(xy))
    if norm > approach_speed:  # not faster than the arm follows without dipping
        xy *= approach_speed / norm
    move = np.append(xy, (z - grip[2]) * PUSH_GAIN)
    return np.append(np.clip(move, -1.0, 1.0), -1.0).astype(np.float32)


def push_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Push the cube to the goal, slowing down near it."""
    return _push(obs, speed=0.5, stop=0.01, slowdown=10.0)


def slide_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Line up behind the puck and push it towards the goal, letting it slide the rest."""
    return _push(obs, speed=1.0, stop=0.0, slowdown=4.0, lateral_tol=0.015)


def _scripted(policy: Callable[[dict[str, np.ndarray]], np.ndarray]):
    def factory(action_mode: str):
        if action_mode != "ee_delta":
            raise ValueError(
                f"the Fetch scripted policies emit ee_delta actions; got action_mode={action_mode!r}"
            )
        return policy

    return factory


# ------------------------------------------------------------------ registration
_MODES = """Action modes (action in [-1, 1]; the last entry commands the fingers, -1 closed,
+1 open, except on tasks whose gripper upstream blocks, where the fingers stay closed):
    native          upstream's mocap control, unchanged: (dx, dy, dz, gripper), the
                    mocap target moves 5 cm per unit; the gripper entry is upstream's
                    relative finger command. The action is cast to float32 first, as
                    upstream's action space does.
    ee_delta        (dx, dy, dz, gripper): grip-site target 5 cm per unit, solved by mink
                    IK on the 7 arm joints only (base and torso frozen), gripper kept
                    pointing down.
    joint_torque    7 arm torques (limits 150, 250, 150, 150, 80, 80, 60 N m) + gripper.
    joint_position  7 absolute arm targets over the joint ranges (+-pi on the three
                    unlimited roll joints) + gripper.
    joint_delta     7 arm targets q + 0.05 a rad + gripper.
    joint_velocity  7 arm velocities, 1 rad/s per unit + gripper.
The non-native modes run on a copy of the model without the mocap weld, with position
servos (kp 3000, 3000, 3000, 3000, 1500, 1500, 1000 N m/rad), gravity compensation on the arm and
the base slides and torso frozen by joint equality constraints (see ``tasks/fetch.py``).
In the joint modes the observation gains 14 entries: the 7 arm angles (rad, shoulder
pan, shoulder lift, upper-arm roll, elbow flex, forearm roll, wrist flex, wrist roll)
and their velocities (rad/s). native and ee_delta keep upstream's vector exactly."""

_OBJECT_OBS = """Observation (25,) in native and ee_delta (upstream's vector exactly; +14 in the joint
modes, see below). Velocities are upstream's: displacement per env step (m or rad
per 0.04 s).
    0-2    grip-site position (world)                         m
    3-5    object position (world)                            m
    6-8    object - grip site                                 m
    9-10   finger openings (right, left)                      m
    11-13  object rotation, Euler xyz                         rad
    14-16  object linear velocity relative to the grip site   m/step
    17-19  object angular velocity                            rad/step
    20-22  grip-site linear velocity                          m/step
    23-24  finger velocities                                  m/step
Goal (3,): achieved = object position, desired = goal point, m. Success: distance
< 0.05 m (upstream's criterion); sparse reward = success - 1 = upstream's -(d > 0.05)."""

_HISTORY = """Version history: v0 initial (over {upstream}, gymnasium-robotics 1.4.2)."""

REACH_DOC = f"""FetchReach: bring the Fetch gripper to a goal point (gymnasium-robotics FetchReach-v4).

The goal is the initial grip position (1.342, 0.749, 0.535) m plus a uniform offset in
[-0.15, 0.15] m on each axis. No object; the gripper is blocked closed. Success: the
grip site is within 5 cm of the goal. 50 steps of 40 ms (20 substeps of 2 ms).

Observation (10,) in native and ee_delta (upstream's vector exactly; +14 in the joint
modes). Velocities are displacement per env step.
    0-2    grip-site position (world)                         m
    3-4    finger openings (right, left)                      m
    5-7    grip-site linear velocity                          m/step
    8-9    finger velocities                                  m/step
Goal (3,): achieved = grip-site position, desired = goal point, m.

{_MODES}
Dense reward: kind "reach": reach = 1 - tanh(5 d), success bonus 10.
{_HISTORY.format(upstream="FetchReach-v4")}
"""

PUSH_DOC = f"""FetchPush: push a 5 cm cube (2 kg) across the table to a goal on the table
(gymnasium-robotics FetchPush-v4).

The cube starts within 15 cm (per axis) of the gripper's initial xy, at least 10 cm
from it; the goal is within 15 cm (per axis) of the gripper's initial xy at the cube's
resting height (z = 0.425). The gripper is blocked closed. 50 steps of 40 ms.

{_OBJECT_OBS}

{_MODES}
Dense reward: kind "push": reach = 1 - tanh(5 |grip - cube|), place = 5 (1 - tanh(5 d))
without a grasp gate, success bonus 10.
{_HISTORY.format(upstream="FetchPush-v4")}
"""

SLIDE_DOC = f"""FetchSlide: hit a puck so that it slides along a low-friction table to a goal
out of the arm's reach (gymnasium-robotics FetchSlide-v4).

The puck starts within 10 cm (per axis) of the gripper's initial xy; the goal is
0.4 m further in x plus a uniform offset within 30 cm (per axis), on the table
(z = 0.42). The gripper is blocked closed. 50 steps of 40 ms.

{_OBJECT_OBS}

{_MODES}
Dense reward: kind "push" (as FetchPush).
{_HISTORY.format(upstream="FetchSlide-v4")}
"""

PICK_AND_PLACE_DOC = f"""FetchPickAndPlace: grasp a 5 cm cube (2 kg) and carry it to a goal, in the air
half of the time (gymnasium-robotics FetchPickAndPlace-v4).

The cube starts as in FetchPush; the goal is within 15 cm (per axis) of the
gripper's initial xy at the cube's resting height, raised by U(0, 0.45) m with
probability 1/2. The gripper is free. 50 steps of 40 ms.

{_OBJECT_OBS}

{_MODES}
Dense reward: kind "grasp": reach = 1 - tanh(5 |grip - cube|), place = 5 grasped
(1 - tanh(5 d)), success bonus 10; ``grasped`` means both fingers touch the cube
(MuJoCo contacts) with the grip site within 5 cm of its centre.
{_HISTORY.format(upstream="FetchPickAndPlace-v4")}
"""

#: Random steps per mode in the stability test: Fetch steps at ~300-400/s.
STABILITY_STEPS = 1_000


def _register() -> None:
    common = dict(
        family="fetch",
        action_modes=ACTION_MODES,
        goal_dim=3,
        max_episode_steps=50,
        distance_threshold=0.05,
        render_fps=25,
        stability_steps=STABILITY_STEPS,
    )
    tasks = (
        ("FetchReach", "reach", MujocoFetchReachEnv, REACH_DOC, reach_policy, 0.9),
        ("FetchPush", "push", MujocoFetchPushEnv, PUSH_DOC, push_policy, 0.9),
        ("FetchSlide", "push", MujocoFetchSlideEnv, SLIDE_DOC, slide_policy, None),
        ("FetchPickAndPlace", "grasp", MujocoFetchPickAndPlaceEnv, PICK_AND_PLACE_DOC, pick_and_place_policy, 0.9),
    )
    for name, kind, cls, doc, policy, min_success in tasks:
        register_task(
            TaskSpec(
                name=name,
                kind=kind,
                make_backend=partial(FetchBackend, upstream_cls=cls, kind=kind),
                doc=doc,
                scripted_policy=_scripted(policy),
                scripted_min_success=min_success,
                upstream_id=f"{name}-v4",
                **common,
            )
        )


_register()
