"""The 4-DOF arm's MuJoCo backend: model loading, home posture, reset, step, observation."""

from __future__ import annotations

import math
from typing import Any, Mapping

import mujoco
import numpy as np

from unified_manip.envs.backend import Backend
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.controllers import ControllerConfig
from unified_manip.envs.controllers.ik import MinkIK
from unified_manip.envs.controllers.rig import MujocoRig
from unified_manip.envs.mujoco_version import delete_element
from unified_manip.envs.observations import ObservationGroup
from unified_manip.envs.physics import bad_state_warnings
from unified_manip.envs.rendering import Renderer, SceneOptions
from unified_manip.envs.tasks.arm4 import observations as obs_groups
from unified_manip.envs.tasks.arm4.goals import PUSH_MIN_DISTANCE, sample_goal, sample_object_xy
from unified_manip.envs.tasks.arm4.scene import (
    ASSET,
    CUBE_REST_Z,
    FINGER_OPEN,
    GRASP_RADIUS,
    HOME_SITE,
    NQ_OBJECT,
    NQ_REACH,
    QPOS_ARM,
    QPOS_CUBE_POS,
    QPOS_FINGERS,
    ROBOT_Q,
    SUBSTEPS,
)
from unified_manip.envs.tasks.contacts import touches_both
from unified_manip.envs.tasks.gripper_terms import GRASPED, GRIP_TO_OBJECT

#: How the arm's scene is drawn: from the model's ``front`` camera, every geom group.
SCENE = SceneOptions(camera="front")

#: Arm posture at reset: grip site about 15 cm above the table, pointing down.
HOME_TARGET = np.array(HOME_SITE)


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
        delete_element(spec, spec.body("object"))
    return spec.compile()


def _home_qpos(model: mujoco.MjModel, rig: MujocoRig) -> np.ndarray:
    """Arm joint angles putting the grip site at HOME_TARGET, pointing down (IK, once)."""
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
    """MuJoCo simulation of the 4-DOF arm for one of the three tasks.

    Args:
        config: The validated env config.
        controller: The action mode's controller config (resolved by ``env_setup``).
        scene: ``"reach"`` (no cube), ``"push"`` or ``"pick_and_place"``: the model,
            the goal distribution and the observation layout.
        substeps: Physics substeps of 2 ms per env step (10: 50 Hz control).
        min_goal_distance: Push goals are at least this far from the cube at reset, m.
        table_goal_fraction: The share of pick-and-place goals on the table top.
    """

    SCENES = ("reach", "push", "pick_and_place")

    def __init__(
        self,
        config: EnvConfig,
        controller: ControllerConfig,
        scene: str,
        substeps: int = SUBSTEPS,
        min_goal_distance: float = PUSH_MIN_DISTANCE,
        table_goal_fraction: float = 0.0,
    ) -> None:
        if scene not in self.SCENES:
            raise ValueError(f"unknown Arm4 scene {scene!r}; expected one of {', '.join(map(repr, self.SCENES))}")
        if config.options:
            raise TypeError(f"Arm4 tasks take no extra options, got {sorted(config.options)}")
        self.scene = scene
        self.substeps = substeps
        self.min_goal_distance = min_goal_distance
        self.table_goal_fraction = table_goal_fraction
        self.model = _load_model(with_object=scene != "reach")
        self.data = mujoco.MjData(self.model)
        self.dt = substeps * self.model.opt.timestep
        self.rig = MujocoRig(
            self.model,
            self.data,
            joints=("j0", "j1", "j2", "j3"),
            actuators=("a_j0", "a_j1", "a_j2", "a_j3"),
            gripper_actuators=("a_fl", "a_fr"),
            gripper_closed=0.0,
            gripper_open=FINGER_OPEN,
            site="grip_site",
            dt=self.dt,
            ee_rotation=top_down,
        )
        self._home = _home_qpos(self.model, self.rig)
        self.control = controller.build(self.rig)
        self.action_dim = self.control.action_dim
        m = self.model
        self._arm_q = self.rig.qpos_adr
        self._fingers_q = m.jnt_qposadr[[m.joint("finger_l").id, m.joint("finger_r").id]]
        self._site = self.rig.site_id
        # observation() slices qpos/qvel by the layout of scene.py: check the model has it.
        if (
            m.nq != (NQ_REACH if scene == "reach" else NQ_OBJECT)
            or list(self._fingers_q) != list(range(QPOS_FINGERS.start, QPOS_FINGERS.stop))
            or list(self._arm_q) != list(range(QPOS_ARM.start, QPOS_ARM.stop))
        ):
            raise RuntimeError(f"{ASSET.name}: unexpected joint layout (nq={m.nq}); update arm4/scene.py")
        self._goal_site = m.site("goal").id
        if scene != "reach":
            jnt = m.joint("obj_joint")
            self._obj_q = int(m.jnt_qposadr[jnt.id])
            if self._obj_q != QPOS_CUBE_POS.start:
                raise RuntimeError(f"{ASSET.name}: the cube's joint moved; update arm4/scene.py")
            self._obj_geom = m.geom("object_geom").id
            self._finger_geoms = (m.geom("finger_l_geom").id, m.geom("finger_r_geom").id)
        self._goal = np.zeros(3)
        #: The height the cube's centre is placed at on reset (a resized cube rests on the table).
        self.object_rest_z = CUBE_REST_Z
        self._unstable = False
        self._renderer = Renderer(config.render_mode, config.render_width, config.render_height, SCENE)

    # -------------------------------------------------------------- episode
    def reset(self, np_random: np.random.Generator) -> None:
        m, d = self.model, self.data
        mujoco.mj_resetData(m, d)
        d.qpos[self._arm_q] = self._home
        d.qpos[self._fingers_q] = FINGER_OPEN
        xy = None
        if self.scene != "reach":
            xy = sample_object_xy(np_random)
            d.qpos[self._obj_q : self._obj_q + 3] = (xy[0], xy[1], self.object_rest_z)
            d.qpos[self._obj_q + 3 : self._obj_q + 7] = (1.0, 0.0, 0.0, 0.0)
        self._goal = sample_goal(self.scene, np_random, xy, self.min_goal_distance, self.table_goal_fraction)
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
        """The physics of one env step, ``substeps`` of ``mj_step`` with the controls as set:
        :meth:`step` runs it after the control law, and the native vector env runs it on its
        thread pool between the batched control and observation (:mod:`unified_manip.envs.vector.arm4`)."""
        mujoco.mj_step(self.model, self.data, nstep=self.substeps)

    def unstable(self) -> bool:
        return self._unstable

    # -------------------------------------------------------------- observation
    def observation(self) -> np.ndarray:
        d = self.data
        grip = d.site_xpos[self._site]
        if self.scene == "reach":
            return np.concatenate((d.qpos[ROBOT_Q], d.qvel[ROBOT_Q], grip, self._goal - grip))
        obj = d.qpos[QPOS_CUBE_POS]
        return np.concatenate((d.qpos, d.qvel, grip, obj - grip, self._goal - obj))

    def observation_groups(self) -> Mapping[str, ObservationGroup]:
        return obs_groups.REACH_GROUPS if self.scene == "reach" else obs_groups.OBJECT_GROUPS

    def default_observation(self) -> tuple[str, ...]:
        return obs_groups.REACH_DEFAULT if self.scene == "reach" else obs_groups.OBJECT_DEFAULT

    def achieved_goal(self) -> np.ndarray:
        if self.scene == "reach":
            return self.data.site_xpos[self._site].copy()
        return self.data.qpos[QPOS_CUBE_POS].copy()

    def desired_goal(self) -> np.ndarray:
        return self._goal.copy()

    def quantities(self) -> dict[str, float]:
        """``grip_to_object`` (grip site to cube, m) and ``grasped`` (both fingers touch the
        cube); 0 and 0 on the reach scene (:mod:`~unified_manip.envs.tasks.gripper_terms`)."""
        if self.scene == "reach":
            return {GRIP_TO_OBJECT: 0.0, GRASPED: 0.0}
        d = self.data
        dist = math.dist(d.site_xpos[self._site], d.qpos[QPOS_CUBE_POS])
        # A grasp needs the cube between the fingers: skip the contact scan otherwise.
        held = float(dist < GRASP_RADIUS and touches_both(d, self._obj_geom, *self._finger_geoms))
        return {GRIP_TO_OBJECT: dist, GRASPED: held}

    # -------------------------------------------------------------- rendering
    def render(self) -> np.ndarray | None:
        return self._renderer.render(self.model, self.data)

    def close(self) -> None:
        self._renderer.close()
