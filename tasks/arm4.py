"""The 4-DOF arm family: the design document's arm, with its model corrected.

The model (``assets/arm4.xml``) keeps the design's kinematic layout: a yaw joint ``j0``
on a base 0.42 m above the floor, three pitch joints ``j1``-``j3`` on links of 0.30,
0.25 and 0.10 m, and a two-finger gripper. The corrections: angles in radians,
joint damping and armature, force-limited actuators, gravity compensation on the arm
links, and fingers that reach past the palm so a top-down grasp closes on the cube.

The table top is at z = 0.42 m; the cube (5 cm, 0.1 kg) rests with its centre at
z = 0.445 m. Control runs at 50 Hz (10 substeps of 2 ms). The ``native`` mode of this
family is ``joint_delta``, as in the design document.
"""

from __future__ import annotations

import math
from functools import partial
from pathlib import Path
from typing import Any, Callable

import mujoco
import numpy as np

from unified_manip.backend import Backend
from unified_manip.config import ACTION_MODES, EnvConfig
from unified_manip.control import ArmGains, ArmRig, bad_state_warnings, make_mujoco_control
from unified_manip.registry import TaskSpec, register_task
from unified_manip.rendering import LazyRenderer

ASSET = Path(__file__).parent / "assets" / "arm4.xml"

SUBSTEPS = 10
TABLE_Z = 0.42
CUBE_HALF = 0.025
CUBE_REST_Z = TABLE_Z + CUBE_HALF
#: Closed fingers sit at 0; a cube held between them keeps them near this opening.
FINGER_ON_CUBE = 0.01

GAINS = ArmGains(kv_velocity=(20.0, 20.0, 12.0, 6.0), max_velocity=2.0, max_delta=0.05, ee_step=0.025)

#: Arm posture at reset: grip site about 15 cm above the table, pointing down.
HOME_TARGET = np.array([0.45, 0.0, 0.58])

#: Reset distributions (world frame, metres).
OBJECT_XY_LOW, OBJECT_XY_HIGH = np.array([0.40, -0.10]), np.array([0.60, 0.10])
REACH_GOAL_LOW, REACH_GOAL_HIGH = np.array([0.30, -0.25, 0.46]), np.array([0.60, 0.25, 0.65])
PUSH_GOAL_XY_LOW, PUSH_GOAL_XY_HIGH = np.array([0.35, -0.15]), np.array([0.65, 0.15])
PLACE_GOAL_LOW, PLACE_GOAL_HIGH = np.array([0.30, 0.10, 0.50]), np.array([0.50, 0.30, 0.60])


def top_down(target: np.ndarray) -> np.ndarray:
    """Rotation of a grip site pointing straight down, facing away from the base.

    That is Rz(yaw) @ Ry(+90 deg) with yaw = atan2(y, x): the site's x axis points
    down and its z axis radially outwards.
    """
    r = math.hypot(target[0], target[1])
    c, s = (target[0] / r, target[1] / r) if r > 1e-9 else (1.0, 0.0)
    return np.array(((0.0, -s, c), (0.0, c, s), (-1.0, 0.0, 0.0)))


def _load_model(with_object: bool) -> mujoco.MjModel:
    spec = mujoco.MjSpec.from_file(str(ASSET))
    if not with_object:
        spec.delete(spec.body("object"))
    return spec.compile()


def _home_qpos(model: mujoco.MjModel, rig: ArmRig) -> np.ndarray:
    """Arm joint angles putting the grip site at HOME_TARGET, pointing down (IK, once)."""
    from unified_manip.control import MinkIK

    data = mujoco.MjData(model)
    ik = MinkIK(model, rig, orientation_cost=1.0, iterations=1)
    q = data.qpos.copy()
    q[rig.qpos_adr] = (0.0, 0.3, 1.0, 0.27)
    for _ in range(200):
        q[rig.qpos_adr], residual, _ = ik.solve(q, HOME_TARGET, top_down(HOME_TARGET))
        if residual < 1e-5:
            break
    return q[rig.qpos_adr].copy()


class Arm4Backend(Backend):
    """MuJoCo simulation of the 4-DOF arm for one of the three tasks."""

    def __init__(self, config: EnvConfig, kind: str) -> None:
        if config.options:
            raise TypeError(f"Arm4 tasks take no extra options, got {sorted(config.options)}")
        self.kind = kind
        self.model = _load_model(with_object=kind != "reach")
        self.data = mujoco.MjData(self.model)
        self.rig = ArmRig(
            self.model,
            self.data,
            joints=("j0", "j1", "j2", "j3"),
            actuators=("a_j0", "a_j1", "a_j2", "a_j3"),
            gripper_actuators=("a_fl", "a_fr"),
            gripper_closed=0.0,
            gripper_open=0.04,
            site="grip_site",
            gains=GAINS,
        )
        self._home = _home_qpos(self.model, self.rig)
        mode = "joint_delta" if config.action_mode == "native" else config.action_mode
        self.control = make_mujoco_control(self.rig, mode, top_down)
        self.action_dim = self.control.action_dim
        self.dt = SUBSTEPS * self.model.opt.timestep
        m = self.model
        self._arm_q = self.rig.qpos_adr
        self._arm_v = self.rig.dof_adr
        self._fingers_q = m.jnt_qposadr[[m.joint("finger_l").id, m.joint("finger_r").id]]
        self._fingers_v = m.jnt_dofadr[[m.joint("finger_l").id, m.joint("finger_r").id]]
        self._site = self.rig.site_id
        # observation() slices qpos/qvel directly: arm joints, fingers, then the cube.
        expected_nq = 6 if kind == "reach" else 13
        if m.nq != expected_nq or list(self._fingers_q) != [4, 5] or list(self._arm_q) != [0, 1, 2, 3]:
            raise RuntimeError(f"{ASSET.name}: unexpected joint layout (nq={m.nq}); update Arm4Backend.observation")
        self._goal_site = m.site("goal").id
        if kind != "reach":
            jnt = m.joint("obj_joint")
            self._obj_q = int(m.jnt_qposadr[jnt.id])
            self._obj_v = int(m.jnt_dofadr[jnt.id])
            self._obj_geom = m.geom("object_geom").id
            self._finger_geoms = (m.geom("finger_l_geom").id, m.geom("finger_r_geom").id)
        self._goal = np.zeros(3)
        self._unstable = False
        self._renderer = LazyRenderer(config.render_mode, config.render_width, config.render_height, camera_name="front")

    # -------------------------------------------------------------- episode
    def reset(self, np_random: np.random.Generator) -> None:
        m, d = self.model, self.data
        mujoco.mj_resetData(m, d)
        d.qpos[self._arm_q] = self._home
        d.qpos[self._fingers_q] = 0.04
        if self.kind != "reach":
            xy = np_random.uniform(OBJECT_XY_LOW, OBJECT_XY_HIGH)
            d.qpos[self._obj_q : self._obj_q + 3] = (xy[0], xy[1], CUBE_REST_Z)
            d.qpos[self._obj_q + 3 : self._obj_q + 7] = (1.0, 0.0, 0.0, 0.0)
        if self.kind == "reach":
            self._goal = np_random.uniform(REACH_GOAL_LOW, REACH_GOAL_HIGH)
        elif self.kind == "push":
            # Resample until the goal is not already solved.
            while True:
                gxy = np_random.uniform(PUSH_GOAL_XY_LOW, PUSH_GOAL_XY_HIGH)
                if np.linalg.norm(gxy - d.qpos[self._obj_q : self._obj_q + 2]) > 0.1:
                    break
            self._goal = np.array([gxy[0], gxy[1], CUBE_REST_Z])
        else:
            self._goal = np_random.uniform(PLACE_GOAL_LOW, PLACE_GOAL_HIGH)
        m.site_pos[self._goal_site] = self._goal
        mujoco.mj_forward(m, d)
        self.control.reset()
        self.rig.set_gripper(1.0)
        self._unstable = False

    def step(self, action: np.ndarray) -> dict[str, Any]:
        diagnostics = self.control(action)
        before = bad_state_warnings(self.data)
        self.physics_step()
        # MuJoCo checks qpos, qvel and qacc on every substep and resets a diverged
        # state itself, counting a warning: a new warning means this step blew up.
        self._unstable = bad_state_warnings(self.data) > before
        # Site positions for the observation (mj_step leaves them one substep behind).
        mujoco.mj_kinematics(self.model, self.data)
        return diagnostics

    def physics_step(self) -> None:
        mujoco.mj_step(self.model, self.data, nstep=SUBSTEPS)

    def unstable(self) -> bool:
        return self._unstable

    # -------------------------------------------------------------- observation
    def observation(self) -> np.ndarray:
        d = self.data
        grip = d.site_xpos[self._site]
        if self.kind == "reach":
            return np.concatenate((d.qpos[:6], d.qvel[:6], grip, self._goal - grip))
        obj = d.qpos[6:9]
        return np.concatenate((d.qpos, d.qvel, grip, obj - grip, self._goal - obj))

    def achieved_goal(self) -> np.ndarray:
        if self.kind == "reach":
            return self.data.site_xpos[self._site].copy()
        return self.data.qpos[self._obj_q : self._obj_q + 3].copy()

    def desired_goal(self) -> np.ndarray:
        return self._goal.copy()

    def reward_state(self) -> tuple[float, float]:
        if self.kind == "reach":
            return 0.0, 0.0
        d = self.data
        dist = math.dist(d.site_xpos[self._site], d.qpos[6:9])
        # A grasp needs the cube between the fingers: skip the contact scan otherwise.
        return dist, float(dist < 0.04 and self._fingers_touching())

    def _fingers_touching(self) -> bool:
        """Both fingers are in contact with the cube."""
        d = self.data
        if d.ncon < 2:
            return False
        pairs = d.contact.geom
        left, right = self._finger_geoms
        obj = self._obj_geom
        with_obj = (pairs == obj).any(axis=1)
        other = pairs[with_obj].ravel()
        return bool((other == left).any() and (other == right).any())

    # -------------------------------------------------------------- rendering
    def render(self) -> np.ndarray | None:
        return self._renderer.render(self.model, self.data)

    def close(self) -> None:
        self._renderer.close()


# ------------------------------------------------------------------ scripted policies
# Each maps an observation dict to an ee_delta action (dx, dy, dz, gripper), using the
# documented observation layout. They are memoryless, so they work from any state.

#: Slices of the push / pick-and-place observation (see the task docs).
OBS_FINGERS, OBS_CUBE, OBS_GRIP = slice(4, 6), slice(6, 9), slice(25, 28)
OBS_CUBE_REL, OBS_GOAL_REL = slice(28, 31), slice(31, 34)


def _toward(delta: np.ndarray, gain: float = 10.0) -> np.ndarray:
    return np.clip(delta * gain, -1.0, 1.0)


def reach_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Move the grip site straight to the goal."""
    move = _toward(obs["desired_goal"] - obs["achieved_goal"])
    return np.append(move, 1.0).astype(np.float32)


def pick_and_place_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Hover over the cube, descend open, close, then carry it to the goal."""
    o = obs["observation"]
    fingers = o[OBS_FINGERS]
    to_obj = o[OBS_CUBE_REL]
    to_goal = o[OBS_GOAL_REL]
    closed_on_cube = bool(np.all(fingers < FINGER_ON_CUBE + 0.006))
    if closed_on_cube and np.linalg.norm(to_obj) < 0.02:
        return np.append(_toward(to_goal), -1.0).astype(np.float32)
    if np.linalg.norm(to_obj[:2]) > 0.012:  # line up above the cube, then come down
        hover = to_obj + np.array([0.0, 0.0, 0.06])
        return np.append(_toward(hover), 1.0).astype(np.float32)
    if np.linalg.norm(to_obj) > 0.008:
        return np.append(_toward(to_obj), 1.0).astype(np.float32)
    return np.array([0.0, 0.0, 0.0, -1.0], dtype=np.float32)


PUSH_SPEED, PUSH_STEER, PUSH_LATERAL_TOL, PUSH_SLOWDOWN = 0.5, 20.0, 0.03, 10.0


def push_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Go behind the cube (seen from the goal), lower the closed gripper, push."""
    o = obs["observation"]
    grip = o[OBS_GRIP]
    obj = o[OBS_CUBE]
    to_goal = o[OBS_GOAL_REL]
    direction = to_goal[:2] / max(np.linalg.norm(to_goal[:2]), 1e-6)
    rel = grip[:2] - obj[:2]
    along = float(rel @ direction)  # negative: the gripper is behind the cube
    lateral = float(abs(rel[0] * direction[1] - rel[1] * direction[0]))
    push_z = obj[2] + 0.01
    remaining = float(np.linalg.norm(to_goal[:2]))
    if remaining < 0.015:  # close enough: stop, so the cube does not slide past
        return np.array([0.0, 0.0, 0.0, -1.0], dtype=np.float32)
    if along < -0.03 and lateral < PUSH_LATERAL_TOL and grip[2] < obj[2] + 0.03:
        # Steer back onto the line through the cube and the goal while pushing, and
        # slow down near the goal.
        correction = (obj[:2] - along * direction) - grip[:2]
        speed = min(PUSH_SPEED, PUSH_SLOWDOWN * remaining)
        steer = np.clip(correction * PUSH_STEER, -0.3, 0.3)
        move = np.append(direction * speed + steer, (push_z - grip[2]) * 20.0)
        return np.append(np.clip(move, -1, 1), -1.0).astype(np.float32)
    behind = np.append(obj[:2] - direction * 0.07, push_z)
    if np.linalg.norm(grip[:2] - behind[:2]) > 0.015:
        if grip[2] < obj[2] + 0.05 and np.linalg.norm(rel) < 0.1:  # rise clear of the cube first
            return np.array([0.0, 0.0, 1.0, -1.0], dtype=np.float32)
        above = behind.copy()
        above[2] = obj[2] + 0.07
        return np.append(_toward(above - grip, 20.0), -1.0).astype(np.float32)
    return np.append(_toward(behind - grip, 20.0), -1.0).astype(np.float32)


def _scripted(policy: Callable[[dict[str, np.ndarray]], np.ndarray]):
    def factory(action_mode: str):
        if action_mode != "ee_delta":
            raise ValueError(
                f"the Arm4 scripted policies emit ee_delta actions; got action_mode={action_mode!r}"
            )
        return policy

    return factory


# ------------------------------------------------------------------ registration
_TABLE_HEAD = """\
    =====  ==========================================  ==========
    index  content                                     units
    =====  ==========================================  ==========
"""
_TABLE_END = "    =====  ==========================================  ==========\n"

REACH_DOC = f"""Arm4Reach: bring the 4-DOF arm's grip site to a goal point.

The goal is sampled uniformly in x [0.30, 0.60], y [-0.25, 0.25], z [0.46, 0.65] m
(world frame; the table top is z = 0.42). There is no object. Success: the grip site
is within 5 cm of the goal. 50 steps of 20 ms.

Observation (18,):
{_TABLE_HEAD}    0-3    joint angles j0..j3                         rad
    4-5    finger openings (left, right), 0 = closed   m
    6-9    joint velocities j0..j3                     rad/s
    10-11  finger velocities                           m/s
    12-14  grip-site position (world)                  m
    15-17  goal - grip site                            m
{_TABLE_END}
Goal (3,): achieved = grip-site position, desired = goal point, m.
Action modes: {", ".join(ACTION_MODES)} (native = joint_delta).
Dense reward: reach = 1 - tanh(5 d), success bonus 10.
Version history: v0 initial.
"""

_OBJECT_TABLE = f"""{_TABLE_HEAD}    0-3    joint angles j0..j3                         rad
    4-5    finger openings (left, right), 0 = closed   m
    6-8    cube position (world)                       m
    9-12   cube orientation quaternion (w, x, y, z)
    13-16  joint velocities j0..j3                     rad/s
    17-18  finger velocities                           m/s
    19-21  cube linear velocity                        m/s
    22-24  cube angular velocity                       rad/s
    25-27  grip-site position (world)                  m
    28-30  cube - grip site                            m
    31-33  goal - cube                                 m
{_TABLE_END}"""

PUSH_DOC = f"""Arm4Push: push the cube across the table to a goal on the table.

The cube starts at rest at x [0.40, 0.60], y [-0.10, 0.10] m; the goal lies on the
table top (z = 0.445, the cube's resting height) at x [0.35, 0.65], y [-0.15, 0.15] m,
at least 10 cm from the cube. Success: the cube's centre is within 5 cm of the goal.
100 steps of 20 ms.

Observation (34,):
{_OBJECT_TABLE}
Goal (3,): achieved = cube centre, desired = goal point, m.
Action modes: {", ".join(ACTION_MODES)} (native = joint_delta).
Dense reward: reach = 1 - tanh(5 |grip - cube|), place = 5 (1 - tanh(5 d)) without a
grasp gate, success bonus 10.
Version history: v0 initial.
"""

PICK_AND_PLACE_DOC = f"""Arm4PickAndPlace: grasp the cube and carry it to a goal in the air.

The design document's task. The cube starts at rest at x [0.40, 0.60],
y [-0.10, 0.10] m; the goal is sampled in x [0.30, 0.50], y [0.10, 0.30],
z [0.50, 0.60] m, i.e. 5.5-15.5 cm above the cube's resting height, as in the design.
Success: the cube's centre is within 5 cm of the goal. 100 steps of 20 ms.

Observation (34,):
{_OBJECT_TABLE}
Goal (3,): achieved = cube centre, desired = goal point, m.
Action modes: {", ".join(ACTION_MODES)} (native = joint_delta).
Dense reward: reach = 1 - tanh(5 |grip - cube|), place = 5 grasped (1 - tanh(5 d)),
success bonus 10; ``grasped`` means both fingers touch the cube.
Version history: v0 initial.
"""


def _register() -> None:
    common = dict(
        family="arm4",
        action_modes=ACTION_MODES,
        goal_dim=3,
        distance_threshold=0.05,
        render_fps=50,
        scripted_min_success=0.9,
    )
    register_task(
        TaskSpec(
            name="Arm4Reach",
            kind="reach",
            make_backend=partial(Arm4Backend, kind="reach"),
            max_episode_steps=50,
            doc=REACH_DOC,
            scripted_policy=_scripted(reach_policy),
            **common,
        )
    )
    register_task(
        TaskSpec(
            name="Arm4Push",
            kind="push",
            make_backend=partial(Arm4Backend, kind="push"),
            max_episode_steps=100,
            doc=PUSH_DOC,
            scripted_policy=_scripted(push_policy),
            **common,
        )
    )
    register_task(
        TaskSpec(
            name="Arm4PickAndPlace",
            kind="grasp",
            make_backend=partial(Arm4Backend, kind="grasp"),
            max_episode_steps=100,
            doc=PICK_AND_PLACE_DOC,
            scripted_policy=_scripted(pick_and_place_policy),
            **common,
        )
    )


_register()
