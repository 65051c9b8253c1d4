"""The robosuite family: Lift, Stack, PickPlaceCan, NutAssemblyRound and Door (robosuite 1.5.2).

The backend owns one real robosuite env, built with ``robosuite.make`` exactly as a
robosuite user would (:func:`make_upstream`), and drives its ``step``/``reset``.

* **Seeding.** robosuite draws every random number of a reset (object placement, the
  robot's initial-joint noise) from one ``numpy.random.Generator``, ``env.rng``, which
  its placement samplers and robots share by reference. At every reset the backend
  draws a 63-bit seed from the env's ``np_random`` and sets ``env.rng``'s bit-generator
  state *in place* to ``default_rng(seed)``'s, then runs robosuite's reset; the desired
  goal is then drawn from ``np_random``. Same seed, same episode, on any instance.
* **One model.** robosuite samples a few model properties while building the model
  (Lift's cube size); the env is built with ``seed=0`` so every instance has the same
  model. With soft resets those properties stay fixed for the env's lifetime.
* **Fast resets.** The env is built with ``hard_reset=False`` (robosuite resets the
  existing simulator instead of recompiling the model: ~360 resets/s here instead of
  ~5/s). With the in-place reseeding above this is exactly as deterministic.
* **Pickling.** robosuite envs hold closures and their pickles are ~170 MB, so a
  backend pickles as its config, the reset seed and goal of the current episode and
  the actions played since; unpickling rebuilds the env and replays them, which is
  exact because the rollouts are deterministic (and costs one step per step replayed).
* **Rendering** (``render_mode="rgb_array"``, and the ``image`` observation with
  ``camera_obs=True``) uses ``mujoco.Renderer`` on robosuite's model and data
  (``MUJOCO_GL=egl`` headless), from robosuite's ``frontview`` and ``agentview`` cameras.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import partial
from typing import Any, Callable

import mujoco
import numpy as np
import robosuite
from robosuite.controllers import load_composite_controller_config, load_part_controller_config

from unified_manip.backend import Backend
from unified_manip.config import ACTION_MODES, EnvConfig
from unified_manip.control import IKJoints, MinkIK, bad_state_warnings
from unified_manip.registry import TaskSpec, register_task

#: Robots accepted by the ``robot`` option (single-arm robots tested on every task's Lift).
ROBOTS: tuple[str, ...] = ("Panda", "Sawyer", "UR5e", "IIWA", "Kinova3", "Jaco")

#: Options the family accepts, with their defaults.
DEFAULT_OPTIONS: dict[str, Any] = {"robot": "Panda", "camera_obs": False, "camera_width": 84, "camera_height": 84}

#: Keyword arguments of ``robosuite.make`` used for every task (besides the env name,
#: robot and controller config): low-dim observations only, no robosuite renderer,
#: robosuite never ends the episode itself (our TimeLimit does), fast resets, and a
#: fixed construction seed: robosuite samples some model properties when it builds
#: the model (e.g. Lift's cube half-size in [2.0, 2.2] cm), so every instance must
#: build the same model.
UPSTREAM_KWARGS: dict[str, Any] = dict(
    seed=0,
    has_renderer=False,
    has_offscreen_renderer=False,
    use_camera_obs=False,
    use_object_obs=True,
    ignore_done=True,
    hard_reset=False,
    control_freq=20,
)

#: JOINT_POSITION gains of the joint-position-based modes (robosuite's default kp is 50,
#: too soft for an IK-driven end effector at 20 Hz). Torques are kp * M(q) e + ... .
JOINT_KP = 150.0
#: Largest joint-target change per step in ``joint_delta``, rad.
MAX_DELTA = 0.05
#: Joint speed at |a| = 1 in ``joint_velocity``, rad/s, and how far the integrated
#: target may lead the measured position, rad.
MAX_VELOCITY = 1.0
MAX_LEAD = 0.1
#: Grip-site displacement at |a| = 1 in ``ee_delta``, m per step (as OSC_POSE's 5 cm).
EE_STEP = 0.05
#: ee_delta IK: weight of the held gripper orientation against position, and the
#: position residual, m, beyond which the orientation yields (a second solve with
#: ``EE_YIELD_ORIENTATION_COST``) so the arm can tilt the gripper to reach further.
EE_ORIENTATION_COST = 0.3
EE_YIELD_RESIDUAL = 0.005
EE_YIELD_ORIENTATION_COST = 0.01
#: Command range of joints without limits (Kinova3's continuous joints), rad.
UNLIMITED_RANGE = (-math.pi, math.pi)


def controller_config(mode: str, robot: str) -> dict:
    """The robosuite composite-controller config for an action mode."""
    cfg = load_composite_controller_config(controller="BASIC", robot=robot)
    if mode == "native":
        return cfg
    if mode == "joint_torque":
        arm = load_part_controller_config(default_controller="JOINT_TORQUE")
    else:
        arm = load_part_controller_config(default_controller="JOINT_POSITION")
        arm["kp"] = JOINT_KP
        if mode == "joint_delta":
            arm["input_type"] = "delta"
            arm["output_max"], arm["output_min"] = MAX_DELTA, -MAX_DELTA
        else:  # joint_position, joint_velocity, ee_delta: absolute targets in rad
            arm["input_type"] = "absolute"
    arm["gripper"] = {"type": "GRIP"}
    cfg["body_parts"] = {"right": arm}
    return cfg


def make_upstream(env_name: str, robot: str, mode: str):
    """The robosuite env, built with ``robosuite.make`` as a robosuite user would."""
    return robosuite.make(env_name, robots=robot, controller_configs=controller_config(mode, robot), **UPSTREAM_KWARGS)


def validate_options(options: dict[str, Any]) -> dict[str, Any]:
    unknown = sorted(set(options) - set(DEFAULT_OPTIONS))
    if unknown:
        raise TypeError(f"robosuite tasks got unknown options {unknown}; expected some of {sorted(DEFAULT_OPTIONS)}")
    opts = {**DEFAULT_OPTIONS, **options}
    if opts["robot"] not in ROBOTS:
        raise ValueError(f"unknown robot {opts['robot']!r}; expected one of {', '.join(repr(r) for r in ROBOTS)}")
    if not isinstance(opts["camera_obs"], bool):
        raise TypeError(f"camera_obs must be a bool, got {type(opts['camera_obs']).__name__}")
    for key in ("camera_width", "camera_height"):
        if not isinstance(opts[key], int) or opts[key] <= 0:
            raise ValueError(f"{key} must be a positive int, got {opts[key]!r}")
    return opts


# ------------------------------------------------------------------ task definitions
@dataclass(frozen=True)
class RobosuiteTask:
    """How one robosuite env becomes a goal task.

    Attributes:
        env_name: robosuite's env name.
        achieved: The achieved goal from the upstream env.
        sample_goal: ``(upstream env, np_random) -> desired goal``, called after reset.
        object_pos: The object the gripper must reach (for ``grip_to_object``).
        grasp_object: The robosuite object whose grasp ``grasped`` reports, or None.
        ee_turn: The gripper orientation ``ee_delta`` holds: the grip site's orientation
            at reset turned by this rotation (a rotation vector in the world frame, rad).
            Zero holds the reset orientation (gripper pointing down).
    """

    env_name: str
    achieved: Callable[[Any], np.ndarray]
    sample_goal: Callable[[Any, np.random.Generator], np.ndarray]
    object_pos: Callable[[Any], np.ndarray]
    grasp_object: Callable[[Any], Any] | None
    ee_turn: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def held_rotation(self, reset_rotation: np.ndarray) -> np.ndarray:
        """The grip-site rotation matrix ``ee_delta`` holds, given the one at reset."""
        turn = np.asarray(self.ee_turn, dtype=np.float64)
        angle = float(np.linalg.norm(turn))
        if angle == 0.0:
            return reset_rotation.copy()
        quat, mat = np.zeros(4), np.zeros(9)
        mujoco.mju_axisAngle2Quat(quat, turn / angle, angle)
        mujoco.mju_quat2Mat(mat, quat)
        return mat.reshape(3, 3) @ reset_rotation


def _body_pos(attr: str):
    def get(up) -> np.ndarray:
        return up.sim.data._data.xpos[getattr(up, attr)]

    return get


def _obj_body_pos(name: str):
    def get(up) -> np.ndarray:
        return up.sim.data._data.xpos[up.obj_body_id[name]]

    return get


#: Lift: table top height and the desired-goal box above it.
LIFT_XY, LIFT_Z = 0.1, (0.10, 0.20)


def _lift_goal(up, rng: np.random.Generator) -> np.ndarray:
    top = up.model.mujoco_arena.table_offset[2]
    return np.array([rng.uniform(-LIFT_XY, LIFT_XY), rng.uniform(-LIFT_XY, LIFT_XY), top + rng.uniform(*LIFT_Z)])


#: PickPlaceCan: margin kept from the quadrant's walls, and the goal height above the bin floor.
CAN_MARGIN, CAN_Z = 0.05, 0.05


def _can_quadrant(up) -> tuple[float, float, float, float]:
    """x/y bounds of the can's quadrant of bin 2, as robosuite's ``not_in_bin``."""
    bin_id = up.object_to_id["can"]
    x_low, y_low = up.bin2_pos[0], up.bin2_pos[1]
    if bin_id in (0, 2):
        x_low -= up.bin_size[0] / 2
    if bin_id < 2:
        y_low -= up.bin_size[1] / 2
    return x_low, x_low + up.bin_size[0] / 2, y_low, y_low + up.bin_size[1] / 2


def _can_goal(up, rng: np.random.Generator) -> np.ndarray:
    x0, x1, y0, y1 = _can_quadrant(up)
    m = CAN_MARGIN
    return np.array([rng.uniform(x0 + m, x1 - m), rng.uniform(y0 + m, y1 - m), up.bin2_pos[2] + CAN_Z])


#: Stack: cube half-sizes (robosuite: A 2 cm, B 2.5 cm).
STACK_HEIGHT = 0.02 + 0.025


def _stack_goal(up, rng: np.random.Generator) -> np.ndarray:
    return up.sim.data._data.xpos[up.cubeB_body_id] + np.array([0.0, 0.0, STACK_HEIGHT])


#: NutAssemblyRound: the nut body's height above the table when it rests around the
#: peg, and the sampled extra height along the peg.
NUT_REST_Z, NUT_Z_RANGE = 0.0, (0.005, 0.02)


def _nut_goal(up, rng: np.random.Generator) -> np.ndarray:
    peg = up.sim.data._data.xpos[up.peg2_body_id]
    return np.array([peg[0], peg[1], up.table_offset[2] + NUT_REST_Z + rng.uniform(*NUT_Z_RANGE)])


#: Door: the target hinge angle range, rad (the hinge's range is [0, 0.4]).
DOOR_GOAL = (0.35, 0.40)


def _door_goal(up, rng: np.random.Generator) -> np.ndarray:
    return np.array([rng.uniform(*DOOR_GOAL)])


def _door_angle(up) -> np.ndarray:
    return up.sim.data._data.qpos[up.hinge_qpos_addr : up.hinge_qpos_addr + 1]


def _door_handle(up) -> np.ndarray:
    return up.sim.data._data.site_xpos[up.door_handle_site_id]


TASK_DEFS: dict[str, RobosuiteTask] = {
    "Lift": RobosuiteTask("Lift", _body_pos("cube_body_id"), _lift_goal, _body_pos("cube_body_id"), lambda up: up.cube),
    "Stack": RobosuiteTask("Stack", _body_pos("cubeA_body_id"), _stack_goal, _body_pos("cubeA_body_id"), lambda up: up.cubeA),
    "PickPlaceCan": RobosuiteTask(
        "PickPlaceCan", _obj_body_pos("Can"), _can_goal, _obj_body_pos("Can"), lambda up: up.objects[up.object_id]
    ),
    "NutAssemblyRound": RobosuiteTask(
        "NutAssemblyRound", _obj_body_pos("RoundNut"), _nut_goal, _obj_body_pos("RoundNut"), lambda up: up.nuts[1]
    ),
    # The gripper points at the door (a quarter turn about world x), its fingers one above
    # the other: pointing down, the hand hits the door panel and the handle's base.
    "Door": RobosuiteTask("Door", _door_angle, _door_goal, _door_handle, None, ee_turn=(-math.pi / 2, 0.0, 0.0)),
}


# ------------------------------------------------------------------ backend
class RobosuiteBackend(Backend):
    """One robosuite task under one action mode (see the module docstring)."""

    def __init__(self, config: EnvConfig, task: str) -> None:
        if config.render_mode == "human":
            raise ValueError("robosuite tasks render with render_mode None or 'rgb_array', not 'human'")
        self.config = config
        self.task_name = task
        self.options = validate_options(dict(config.options))
        self.task = TASK_DEFS[task]
        self.mode = config.action_mode
        up = make_upstream(self.task.env_name, self.options["robot"], self.mode)
        self._up = up
        self.dt = float(up.control_timestep)
        self._substeps = int(round(up.control_timestep / up.model_timestep))
        self.model: mujoco.MjModel = up.sim.model._model
        self.data: mujoco.MjData = up.sim.data._data
        robot = up.robots[0]
        self._robot = robot
        self._gripper = robot.gripper["right"]
        self._grip_site = self.model.site(self._gripper.important_sites["grip_site"]).id
        self.joints = IKJoints.from_model(
            self.model, robot.robot_joints, self._gripper.important_sites["grip_site"], UNLIMITED_RANGE
        )
        self._grasp_object = self.task.grasp_object(up) if self.task.grasp_object else None
        n = self.joints.n
        self.action_dim = {"native": up.action_dim, "ee_delta": 4}.get(self.mode, n + 1)
        self._command = np.zeros(up.action_dim)
        self._mid = 0.5 * (self.joints.upper + self.joints.lower)
        self._half = 0.5 * (self.joints.upper - self.joints.lower)
        if self.mode == "ee_delta":
            self.ik = MinkIK(self.model, self.joints, orientation_cost=EE_ORIENTATION_COST, iterations=2)
            self.ik_yield = MinkIK(self.model, self.joints, orientation_cost=EE_YIELD_ORIENTATION_COST, iterations=2)
        self._rotation = np.eye(3)
        self._target = np.zeros(n)
        self._goal = np.zeros(0)
        self._obs: dict[str, np.ndarray] = {}
        self._reward = 0.0
        self._unstable = False
        self._episode: tuple[int, np.ndarray] | None = None
        self._log: list[np.ndarray | None] = []
        self._renderers: dict[tuple[int, int], mujoco.Renderer] = {}
        for w, h in ((config.render_width, config.render_height), (self.options["camera_width"], self.options["camera_height"])):
            self.model.vis.global_.offwidth = max(self.model.vis.global_.offwidth, w)
            self.model.vis.global_.offheight = max(self.model.vis.global_.offheight, h)

    # -------------------------------------------------------------- episode
    def reset(self, np_random: np.random.Generator) -> None:
        seed = int(np_random.integers(2**63))
        self._reset_upstream(seed)
        self._goal = np.asarray(self.task.sample_goal(self._up, np_random), dtype=np.float64)
        self._episode = (seed, self._goal.copy())
        self._log = []

    def _reset_upstream(self, seed: int) -> None:
        up = self._up
        # In place: robosuite's placement samplers and robots hold this very generator.
        up.rng.bit_generator.state = np.random.default_rng(seed).bit_generator.state
        self._obs = up.reset()
        self._reward = 0.0
        self._unstable = False
        if self.mode == "joint_torque":
            # Controllers are rebuilt at every reset: map |a| = 1 to the actuator limits
            # (robosuite's JOINT_TORQUE default maps it to 0.1 N m).
            c = self._robot.part_controllers["right"]
            c.output_max, c.output_min = c.actuator_max.copy(), c.actuator_min.copy()
            c.action_scale = None
        q = self.data.qpos[self.joints.qpos_adr]
        self._target = q.copy()
        self._rotation = self.task.held_rotation(self.data.site_xmat[self._grip_site].reshape(3, 3))

    def step(self, action: np.ndarray) -> dict[str, Any]:
        self._log.append(action.copy())
        return self._step(action)

    def _step(self, action: np.ndarray) -> dict[str, Any]:
        diagnostics: dict[str, Any] = {}
        if self.mode == "native":
            command = action
        else:
            command = self._command.copy()
            command[-1] = -action[-1]  # robosuite's GRIP: -1 open, +1 closed
            arm = action[:-1]
            j = self.joints
            if self.mode == "joint_position":
                command[:-1] = self._mid + arm * self._half
            elif self.mode in ("joint_delta", "joint_torque"):
                command[:-1] = arm
            elif self.mode == "joint_velocity":
                q = self.data.qpos[j.qpos_adr]
                target = self._target + arm * (MAX_VELOCITY * self.dt)
                target = np.minimum(np.maximum(target, q - MAX_LEAD), q + MAX_LEAD)
                self._target = np.minimum(np.maximum(target, j.lower), j.upper)
                command[:-1] = self._target
            else:  # ee_delta
                goal = self.data.site_xpos[self._grip_site] + arm * EE_STEP
                q_arm, residual, limit_active = self.ik.solve(self.data.qpos, goal, self._rotation)
                if residual > EE_YIELD_RESIDUAL:  # out of reach holding the orientation: tilt
                    q_arm, residual, limit_active = self.ik_yield.solve(self.data.qpos, goal, self._rotation)
                command[:-1] = q_arm
                diagnostics = {"ik_residual": residual, "ik_limit_active": limit_active}
        before = bad_state_warnings(self.data)
        self._obs, self._reward, _, _ = self._up.step(command)
        self._unstable = bad_state_warnings(self.data) > before
        return diagnostics

    def physics_step(self) -> None:
        self._log.append(None)
        mujoco.mj_step(self.model, self.data, self._substeps)

    def unstable(self) -> bool:
        return self._unstable

    # -------------------------------------------------------------- observation
    def observation(self) -> np.ndarray:
        return np.concatenate((self._obs["robot0_proprio-state"], self._obs["object-state"]))

    def achieved_goal(self) -> np.ndarray:
        return self.task.achieved(self._up).copy()

    def desired_goal(self) -> np.ndarray:
        return self._goal

    def grip_to_object(self) -> float:
        rel = self.task.object_pos(self._up) - self.data.site_xpos[self._grip_site]
        return math.sqrt(float(rel @ rel))

    def reward_state(self) -> tuple[float, float]:
        dist = self.grip_to_object()
        if self._grasp_object is None or dist > 0.08:  # skip the contact scan when far
            return dist, 0.0
        return dist, float(self._up._check_grasp(gripper=self._gripper, object_geoms=self._grasp_object))

    def extra_info(self) -> dict[str, Any]:
        return {"native_success": float(self._up._check_success()), "native_reward": float(self._reward)}

    def extra_observations(self) -> dict[str, np.ndarray]:
        if not self.options["camera_obs"]:
            return {}
        return {"image": self._render(self.options["camera_width"], self.options["camera_height"], "agentview")}

    # -------------------------------------------------------------- rendering
    def _render(self, width: int, height: int, camera: str) -> np.ndarray:
        r = self._renderers.get((width, height))
        if r is None:
            r = self._renderers[(width, height)] = mujoco.Renderer(self.model, height, width)
        r.update_scene(self.data, camera=camera)
        return r.render()

    def render(self) -> np.ndarray | None:
        return self._render(self.config.render_width, self.config.render_height, "frontview")

    def close(self) -> None:
        for r in self._renderers.values():
            r.close()
        self._renderers = {}

    # -------------------------------------------------------------- pickling
    def __getstate__(self) -> dict[str, Any]:
        return {"config": self.config, "task": self.task_name, "episode": self._episode, "log": list(self._log)}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__init__(state["config"], state["task"])
        if state["episode"] is not None:
            seed, goal = state["episode"]
            self._reset_upstream(seed)
            self._goal, self._episode = goal.copy(), (seed, goal.copy())
            for action in state["log"]:
                if action is None:
                    self.physics_step()
                else:
                    self.step(action)


# ------------------------------------------------------------------ scripted policies
# Memoryless ee_delta policies (dx, dy, dz, gripper: -1 closed, +1 open) on the Panda
# observation layout: eef position at proprio 35-37, gripper finger qpos at 46-47.
EEF = slice(35, 38)
PROPRIO = 50


def _toward(delta: np.ndarray, gain: float = 10.0) -> np.ndarray:
    return np.clip(np.asarray(delta) * gain, -1.0, 1.0)


def _pick_and_carry(obs: dict[str, np.ndarray], lift_first: float = 0.0, release: bool = False) -> np.ndarray:
    """Above the object, descend open, close, then carry it to the goal (raising it
    ``lift_first`` m above the goal height before moving sideways, if set; letting go
    and backing up once there, if ``release``)."""
    o = obs["observation"]
    eef = o[EEF]
    obj = obs["achieved_goal"]
    goal = obs["desired_goal"]
    to_obj = obj - eef
    if release and np.linalg.norm(goal - obj) < 0.04:
        return np.array([0.0, 0.0, 0.5, 1.0])
    opening = o[46] - o[47]  # Panda finger opening, m (0.08 open)
    closing_speed = abs(o[48] - o[49])  # m/s
    xy = np.linalg.norm(to_obj[:2])
    if xy < 0.02 and abs(to_obj[2]) < 0.04 and opening < 0.07:
        if closing_speed > 0.02:  # still closing: wait
            return np.array([0.0, 0.0, 0.0, -1.0])
        # closed on the object: carry it
        to_goal = goal - obj
        if lift_first and np.linalg.norm(to_goal[:2]) > 0.04 and obj[2] < goal[2] + lift_first:
            to_goal = np.array([to_goal[0], to_goal[1], 3.0 * (goal[2] + lift_first + 0.02 - obj[2])])
        return np.append(_toward(to_goal), -1.0)
    if xy < 0.015 and abs(to_obj[2]) < 0.025:  # in place: close
        return np.array([0.0, 0.0, 0.0, -1.0])
    if np.linalg.norm(to_obj[:2]) > 0.01:  # line up above the object, open
        return np.append(_toward(to_obj + np.array([0.0, 0.0, 0.08])), 1.0)
    return np.append(_toward(to_obj), 1.0)


def lift_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    return _pick_and_carry(obs)


#: Height of the can's centre above the goal while carried, m (clears the bins' walls).
CAN_CARRY = 0.13


def can_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Grasp the can from above, lift it over the bins' walls, carry it at a moderate
    speed (it swings in the fingers), lower it to 3 cm above the goal, let go, back up."""
    o = obs["observation"]
    eef = o[EEF]
    can = obs["achieved_goal"]
    goal = obs["desired_goal"]
    to_can = can - eef
    to_goal = goal - can
    opening = o[46] - o[47]  # Panda finger opening, m (0.08 open, ~0.05 on the can)
    if np.linalg.norm(to_goal[:2]) < 0.045 and can[2] < goal[2] + 0.07:  # low over the goal: let go
        return np.array([0.0, 0.0, 0.5 if opening > 0.07 else 0.0, 1.0])  # back up once open
    closing_speed = abs(o[48] - o[49])  # m/s
    near = np.linalg.norm(to_can[:2]) < 0.04 and abs(to_can[2]) < 0.05
    if near and 0.03 < opening < 0.07:  # closing on, or holding, the can
        if closing_speed > 0.02:  # still closing: wait
            return np.array([0.0, 0.0, 0.0, -1.0])
        carry_z = goal[2] + CAN_CARRY
        if np.linalg.norm(to_goal[:2]) > 0.02:
            if can[2] < carry_z - 0.03:  # up first, then across
                move = np.array([0.3 * to_goal[0], 0.3 * to_goal[1], carry_z + 0.02 - can[2]])
            else:
                move = np.array([to_goal[0], to_goal[1], carry_z - can[2]])
            return np.append(_toward(move, 10.0) * 0.6, -1.0)
        return np.append(_toward(to_goal, 10.0) * 0.6, -1.0)
    xy = np.linalg.norm(to_can[:2])
    if xy < 0.015 and abs(to_can[2]) < 0.025 and opening >= 0.07:  # in place: close
        return np.array([0.0, 0.0, 0.0, -1.0])
    if xy > 0.01:  # line up above the can, open
        return np.append(_toward(to_can + np.array([0.0, 0.0, 0.08])), 1.0)
    return np.append(_toward(to_can), 1.0)


#: Door geometry (robosuite's door_lock.xml) in the door body's frame, m: the latch
#: joint's anchor (its axis is the door's y) and the hinge's (axis z); the handle site
#: in the latch's frame. The handle is a lever along the latch's x, 15 cm long, 3 cm
#: thick (y, centred 10 cm in front of the door) and 4 cm high; a positive latch angle
#: turns it down.
DOOR_LATCH = np.array([-0.175, 0.0, -0.025])
DOOR_HINGE = np.array([0.255, 0.0, 0.0])
DOOR_HANDLE_SITE = np.array([0.125, -0.10, 0.0])
#: Door object state (after the proprio): door body position, handle site, hinge angle, latch angle.
DOOR_POS, DOOR_HANDLE = slice(PROPRIO, PROPRIO + 3), slice(PROPRIO + 3, PROPRIO + 6)
DOOR_ANGLE, DOOR_LATCH_ANGLE = PROPRIO + 6, PROPRIO + 13
#: Where the grip site presses the lever, in the latch's frame, m: 12 cm out along the
#: lever, fingertips just past its back face (the hand clears the handle's base), the
#: closed fingers' lower edge on its top face.
DOOR_PRESS = np.array([0.12, -0.095, 0.05])
#: Latch angles, rad: how far ahead of the lever the press target leads, the angle it
#: presses towards, and the angle beyond which the latch clears the frame and the
#: policy pulls (the latch_joint's range ends at 1.57).
DOOR_LEAD, DOOR_HOLD, DOOR_PULL = 0.4, 1.6, 1.3
#: The pull aims this far past the goal angle (the door lags the gripper), rad.
DOOR_OVERSHOOT = 0.03


def _latch_turn(v: np.ndarray, angle: float) -> np.ndarray:
    """``v`` (latch frame) turned by the latch angle about the latch's y axis."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]])


def _yaw(angle: float) -> np.ndarray:
    """The rotation matrix of ``angle`` about z."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def door_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    """Press the lever down with the closed fingertips, then pull the door open by it.

    Needs ``ee_delta``'s Door orientation (gripper pointing at the door, fingers one
    above the other). Everything is computed in the door's frame, whose yaw follows from
    the door, handle and latch angle of the observation: from the front, rise above
    the press point, descend onto the lever and follow it down along its arc (the target
    leads the lever by ``DOOR_LEAD``); once the latch is past ``DOOR_PULL``, keep
    pressing and swing the press point about the hinge towards the goal angle (friction
    on the lever drags the door)."""
    o = obs["observation"]
    door, eef = o[DOOR_POS], o[EEF]
    latch, angle, goal = float(o[DOOR_LATCH_ANGLE]), float(o[DOOR_ANGLE]), float(obs["desired_goal"][0])
    handle_local = DOOR_LATCH + _latch_turn(DOOR_HANDLE_SITE, latch)
    handle = o[DOOR_HANDLE] - door
    rot = _yaw(math.atan2(handle[1], handle[0]) - math.atan2(handle_local[1], handle_local[0]))
    grip = rot.T @ (eef - door)  # grip site in the door's frame

    def press(latch_angle: float) -> np.ndarray:
        return DOOR_LATCH + _latch_turn(DOOR_PRESS, latch_angle)

    if latch < 0.15:  # lever up: get above the press point, then descend onto it
        point = press(0.0)
        above = point + np.array([0.0, 0.0, 0.04])
        if np.linalg.norm(point[:2] - grip[:2]) > 0.015:
            target = above
            if grip[2] < above[2] - 0.02:  # rise first, staying 6 cm in front of the lever
                step = 0.3 * (above - grip)
                target = np.array([grip[0] + step[0], min(grip[1] + step[1], above[1] - 0.06), above[2]])
        else:
            target = press(latch + DOOR_LEAD)
    else:
        target = press(min(latch + DOOR_LEAD, DOOR_HOLD))
        if latch > DOOR_PULL:  # unlatched: swing the press point about the hinge
            swing = float(np.clip(goal + DOOR_OVERSHOOT - angle, -0.1, 0.1))
            target = DOOR_HINGE + _yaw(swing) @ (target - DOOR_HINGE)
    return np.append(_toward(rot @ (target - grip)), -1.0)


def _scripted(policy: Callable[[dict[str, np.ndarray]], np.ndarray]):
    def factory(action_mode: str):
        if action_mode != "ee_delta":
            raise ValueError(
                f"the robosuite scripted policies emit ee_delta actions; got action_mode={action_mode!r}"
            )
        return lambda obs: policy(obs).astype(np.float32)

    return factory


# ------------------------------------------------------------------ registration
_OPTIONS = """Options: ``robot`` (default "Panda"; also "Sawyer", "UR5e", "IIWA", "Kinova3",
"Jaco"), ``camera_obs`` (default False: adds an ``image`` key, agentview RGB uint8 of
``camera_height`` x ``camera_width``, default 84 x 84), ``camera_width``,
``camera_height``. Unknown options raise TypeError, unknown robots ValueError."""

_MODES = """Action modes (action in [-1, 1]; n = the robot's arm joints, 7 on Panda; in every
mode but native the last entry commands the gripper, -1 closed, +1 open):
    native          robosuite's default BASIC composite controller, unchanged: OSC_POSE
                    (dx, dy, dz, droll, dpitch, dyaw; 5 cm and 0.5 rad per unit) + GRIP
                    with robosuite's sign (-1 open, +1 closed). Same seed and actions give
                    robosuite.make's observations and reward (``info["native_reward"]``).
    ee_delta        (dx, dy, dz, gripper): grip-site target 5 cm per unit, solved by
                    mink IK on the arm joints only (gripper orientation at reset held
                    as a soft preference, cost 0.3; on Door it is turned to point at
                    the door, see the task doc; where that leaves more than 5 mm of
                    position error the step is re-solved with orientation cost 0.01, so
                    the gripper tilts to reach further, e.g. PickPlaceCan's far bin),
                    sent as absolute targets to robosuite's
                    JOINT_POSITION controller (kp 150, critically damped, mass-matrix
                    and gravity compensated). ``ik_residual`` (m) and ``ik_limit_active``
                    go to ``info``.
    joint_position  n absolute targets over the joint ranges (+-pi on continuous
                    joints) + gripper, robosuite JOINT_POSITION (absolute input).
    joint_delta     n targets q + 0.05 a rad + gripper, robosuite JOINT_POSITION (delta input).
    joint_velocity  n joint velocities, 1 rad/s per unit + gripper. robosuite 1.5.2's
                    JOINT_VELOCITY controller is broken (AttributeError on
                    ``torque_compensation``), so this mode integrates the command into a
                    position target, target += a * 1 rad/s * 0.05 s per step, kept within
                    0.1 rad of the measured position (no wind-up) and the joint range, and
                    tracks it with the JOINT_POSITION controller (absolute input).
    joint_torque    n torques, a times the actuator limit (87/12 N m on Panda), plus
                    robosuite's gravity compensation, JOINT_TORQUE controller + gripper."""

_OBS = """Observation (float32): robosuite's ``robot0_proprio-state`` then ``object-state``.
Proprio (Panda: 50): joint pos (n, rad), cos, sin (n each), joint vel (n, rad/s), joint
acc (n, rad/s^2), eef position (3, m, world), eef quaternion xyzw (4), grip-site
quaternion (4), gripper finger qpos (2 on Panda, m) and qvel (2, m/s). Other robots:
Sawyer 50, UR5e 53, IIWA/Kinova3/Jaco 58 (grippers with more joints)."""

_INFO = """Info adds ``native_success`` (1.0/0.0, robosuite's ``_check_success()``) and
``native_reward`` (robosuite's own sparse reward for the step)."""

_HISTORY = "Version history: v0 initial (robosuite {env} 1.5.2, control_freq 20 Hz)."

LIFT_DOC = f"""Lift: pick up a cube (2 cm half-size) and hold it at a goal point above the table
(robosuite Lift).

The cube starts within 3 cm of the table centre (robosuite's placement). Goal: a
point x, y ~ U(-0.1, 0.1) m around the table centre, z ~ U(0.10, 0.20) m above the
table top (table top at z = 0.8 m, world frame). Success: the cube centre is within
5 cm of it. 100 steps of 50 ms.

{_OBS}
Object state (10): cube position (3, m), cube quaternion (4), grip site to cube (3, m).
Goal (3,): achieved = cube centre, desired = goal point, world frame, m.

Native success (robosuite): cube centre > 4 cm above the table top. Every goal is at
least 10 cm up, so is_success implies native success; native success is looser (any
lift counts).

{_MODES}
{_OPTIONS}
{_INFO}
Dense reward: kind "grasp" (reach, grasped-gated place, success bonus).
{_HISTORY.format(env="Lift")}
"""

STACK_DOC = f"""Stack: put cube A (2 cm half-size, red) on top of cube B (2.5 cm half-size, green)
(robosuite Stack).

Both cubes start in a 16 x 16 cm square at the table centre. Goal: cube B's centre at
reset plus 4.5 cm (the two half-sizes) in z: cube A resting on B. It is not sampled
beyond the scene, whose placement comes from the env's seed. Success: cube A's centre
within 2 cm of it. 200 steps of 50 ms.

{_OBS}
Object state (23): cube A position (3, m) and quaternion (4), cube B position (3) and
quaternion (4), A - B (3, m), grip to A (3, m), grip to B (3, m).
Goal (3,): achieved = cube A centre, desired = top of cube B at reset, m.

Native success (robosuite): A lifted, touching B and not grasped. Differences by
design: is_success does not require the gripper to let go, and is measured against
B's position at reset (if B is pushed away the goal stays); native success needs
contact with B wherever B is.

{_MODES}
{_OPTIONS}
{_INFO}
Dense reward: kind "grasp".
{_HISTORY.format(env="Stack")}
"""

CAN_DOC = f"""PickPlaceCan: pick up a can from the left bin and place it in its quadrant of the right
bin (robosuite PickPlaceCan).

The can starts anywhere in bin 1. Goal: a point in the can's quadrant of bin 2
(x in [0.10, 0.295], y in [0.28, 0.525] m) at least 5 cm from the quadrant's walls,
5 cm above the bin floor (z = 0.85 m). Success: the can's centre within 5 cm of it.
200 steps of 50 ms.

{_OBS}
Object state (14): can position (3, m), quaternion (4), can relative to the eef in
the eef frame: position (3, m) and quaternion (4).
Goal (3,): achieved = can centre, desired = goal point, m.

Native success (robosuite): the can's centre inside its quadrant, between the bin
floor and 10 cm above it, and the eef more than about 4.2 cm from the can (robosuite's
r_reach < 0.6: the can has been let go). The goal keeps 5 cm from the walls and its z
ball stays in (0.80, 0.90), so once the can is released, is_success implies native
success; native success also counts any other point of the quadrant. Difference by
design: is_success does not require letting go (a can held within 5 cm of the goal
counts).

Reach: the quadrant is the far one from the robot (Panda base at (-0.56, 0)); most of
it is out of reach with the gripper pointing straight down, so ee_delta tilts the
gripper there (see ee_delta below). Even tilted, the Panda cannot carry the can to the
goals of the far corner (x > ~0.22 and y > ~0.45 m, more than ~0.91 m from the base in
x-y): the scripted ee_delta policy fails there (about 6% of goals). The goal
distribution is left as is: those goals are in the bin, and other robots reach further.

{_MODES}
{_OPTIONS}
{_INFO}
Dense reward: kind "grasp".
{_HISTORY.format(env="PickPlaceCan")}
"""

NUT_DOC = f"""NutAssemblyRound: put the round nut on the round peg (robosuite NutAssemblyRound).

The nut starts on the left of the table; the round peg is fixed at (0.23, -0.10) m.
Goal: the peg's axis, at a height U(0.005, 0.02) m above the table top (z = 0.82 m)
down the peg: the nut's body origin (ring centre) around the peg. Success: the nut's
centre within 2 cm of it. 200 steps of 50 ms.

{_OBS}
Object state (14): nut position (3, m), quaternion (4), nut relative to the eef
(3, m, and 4).
Goal (3,): achieved = nut body position, desired = point on the peg, m.

Native success (robosuite): the nut within 3 cm of the peg axis in x and y, below
5 cm above the table, and the gripper more than about 4 cm away. Differences by
design: is_success does not require the gripper to have let go.

{_MODES}
{_OPTIONS}
{_INFO}
Dense reward: kind "grasp".
{_HISTORY.format(env="NutAssemblyRound")}
"""

DOOR_DOC = f"""Door: turn the latch handle and open the door to a target angle (robosuite Door,
latch on).

The door frame is placed at robosuite's randomised position. Goal: a hinge angle
~ U(0.35, 0.40) rad (the hinge's range is [0, 0.4]). Success: |angle - goal| < 0.05 rad.
150 steps of 50 ms.

{_OBS}
Object state (14): door position (3, m), handle position (3, m), hinge angle (rad),
door - eef (3, m), handle - eef (3, m), handle (latch) angle (rad).
Goal (1,): achieved = hinge angle, desired = target angle, rad.

Native success (robosuite): hinge angle > 0.3 rad. Every goal is at least 0.35 rad,
so is_success implies native success.

The door opens towards the robot (+y) only once the latch is turned down past ~1.2 rad
(the latch_joint's range is [-1.57, 1.57]) and must be held there until the latch
clears the frame. ee_delta holds the gripper pointing at the door (-y) with its
fingers one above the other, instead of pointing down: a downward hand hits the door
panel and the handle's base. The scripted ee_delta policy closes the fingers, comes
over the lever from the front, presses it down along its arc with the fingertips to
~1.4 rad, then swings the pressed point about the hinge to the goal angle (friction on
the lever drags the door).

{_MODES}
{_OPTIONS}
{_INFO}
Dense reward: kind "push": reach = 1 - tanh(5 |grip - handle|), place = 5 (1 - tanh(5 d))
on the angle error d (rad) without a grasp gate, success bonus 10.
{_HISTORY.format(env="Door")}
"""

#: Random steps per mode in the stability test, and episodes of the scripted-policy
#: test: robosuite steps at ~100-200/s here.
STABILITY_STEPS = 300
SCRIPTED_EPISODES = 50


def _register() -> None:
    tasks = (
        # name, kind, goal_dim, steps, threshold, doc, policy, min success, episodes
        ("Lift", "grasp", 3, 100, 0.05, LIFT_DOC, lift_policy, 0.8),
        ("Stack", "grasp", 3, 200, 0.02, STACK_DOC, None, None),
        ("PickPlaceCan", "grasp", 3, 200, 0.05, CAN_DOC, can_policy, 0.8),
        ("NutAssemblyRound", "grasp", 3, 200, 0.02, NUT_DOC, None, None),
        ("Door", "push", 1, 150, 0.05, DOOR_DOC, door_policy, 0.8),
    )
    for name, kind, goal_dim, steps, threshold, doc, policy, min_success in tasks:
        register_task(
            TaskSpec(
                name=name,
                family="robosuite",
                kind=kind,
                make_backend=partial(RobosuiteBackend, task=name),
                action_modes=ACTION_MODES,
                goal_dim=goal_dim,
                max_episode_steps=steps,
                distance_threshold=threshold,
                doc=doc,
                scripted_policy=_scripted(policy) if policy else None,
                scripted_min_success=min_success,
                render_fps=20,
                scripted_episodes=SCRIPTED_EPISODES,
                stability_steps=STABILITY_STEPS,
                upstream_id=f"robosuite:{name}",
                make_upstream=partial(make_upstream, TASK_DEFS[name].env_name, "Panda", "native"),
            )
        )


_register()
