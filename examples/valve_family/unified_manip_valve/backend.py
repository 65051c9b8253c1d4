"""The valve task's MuJoCo backend: what the shared env needs from a family.

Imported on the first ``gym.make`` of a valve ID (the spec names it lazily), so
``import unified_manip`` does not load MuJoCo.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import mujoco
import numpy as np

from unified_manip.envs.backend import Backend
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.controllers import ControllerConfig
from unified_manip.envs.controllers.rig import MujocoRig
from unified_manip.envs.observations import ObservationGroup
from unified_manip.envs.physics import bad_state_warnings
from unified_manip.envs.rendering import Renderer, SceneOptions
from unified_manip_valve import observations as obs
from unified_manip_valve.scene import ASSET, HANDLE_RADIUS, LINKS, SUBSTEPS, VALVE_AXIS, sample_episode, wrap
from unified_manip_valve.terms import FINGERTIP_TO_HANDLE, VALVE_SPEED

#: How the scene is drawn: from above, through the model's ``top`` camera.
SCENE = SceneOptions(camera="top")


class FingerRig(MujocoRig):
    """:class:`MujocoRig` for a robot without a gripper: the action is the joints alone."""

    has_gripper = False

    def command(self, arm: np.ndarray, gripper: float | None) -> None:
        self.data.ctrl[self.actuator_ids] = arm


class ValveBackend(Backend):
    """The finger and the valve in MuJoCo, under one action mode.

    Args:
        config: The validated env config (``gym.make``'s keyword arguments).
        controller: The action mode's controller config; it drives the finger through
            :class:`FingerRig`.
    """

    def __init__(self, config: EnvConfig, controller: ControllerConfig) -> None:
        if config.options:
            raise TypeError(f"valve tasks take no extra options, got {sorted(config.options)}")
        self.model = mujoco.MjModel.from_xml_path(str(ASSET))
        self.data = mujoco.MjData(self.model)
        self.dt = SUBSTEPS * self.model.opt.timestep
        self.rig = FingerRig(
            self.model,
            self.data,
            joints=("j0", "j1"),
            actuators=("a_j0", "a_j1"),
            gripper_actuators=(),
            gripper_closed=0.0,
            gripper_open=0.0,
            site="fingertip",
            dt=self.dt,
        )
        self.control = controller.build(self.rig)
        self.action_dim = self.control.action_dim
        m = self.model
        self.handle_site = m.site("handle").id
        self._goal_site = m.site("goal").id
        self.valve_q = int(m.jnt_qposadr[m.joint("valve").id])
        self.valve_dof = int(m.jnt_dofadr[m.joint("valve").id])
        self._goal = 0.0
        self._check_layout()
        self._unstable = False
        self._renderer = Renderer(config.render_mode, config.render_width, config.render_height, SCENE)

    def _check_layout(self) -> None:
        """The scripted policy and the docs use scene.py's numbers and the group sizes of
        observations.py: the model must have them."""
        m = self.model
        sizes = {n: int(np.size(obs.GROUPS[n].read(self))) for n in obs.DEFAULT}
        if sizes != obs.SIZES:
            raise RuntimeError(f"the observation groups have sizes {sizes}; observations.SIZES says {obs.SIZES}")
        links = (float(m.body("link2").pos[0]), float(m.site("fingertip").pos[0]))
        axis, handle = m.body("valve").pos[:2], float(np.linalg.norm(m.site("handle").pos[:2]))
        if not (np.allclose(links, LINKS) and np.allclose(axis, VALVE_AXIS) and math.isclose(handle, HANDLE_RADIUS)):
            raise RuntimeError(f"{ASSET.name} disagrees with scene.py: links {links}, axis {axis}, handle {handle}")

    # -------------------------------------------------------------- episode
    def reset(self, np_random: np.random.Generator) -> None:
        m, d = self.model, self.data
        mujoco.mj_resetData(m, d)
        q, valve, self._goal = sample_episode(np_random)
        d.qpos[self.rig.qpos_adr] = q
        d.qpos[self.valve_q] = valve
        m.site_pos[self._goal_site, :2] = VALVE_AXIS + HANDLE_RADIUS * np.array(
            [math.cos(self._goal), math.sin(self._goal)]
        )
        mujoco.mj_forward(m, d)
        self.control.reset()
        self._unstable = False

    def step(self, action: np.ndarray) -> dict[str, Any]:
        diagnostics = self.control(action)
        before = bad_state_warnings(self.data)
        self.physics_step()
        self._unstable = bad_state_warnings(self.data) > before  # MuJoCo reset a diverged state
        mujoco.mj_kinematics(self.model, self.data)  # site positions of the state now
        return diagnostics

    def physics_step(self) -> None:
        mujoco.mj_step(self.model, self.data, nstep=SUBSTEPS)

    def unstable(self) -> bool:
        return self._unstable

    # -------------------------------------------------------------- what the env reads
    def valve_angle(self) -> float:
        """The valve's angle, rad, wrapped to ``[-pi, pi)``."""
        return float(wrap(self.data.qpos[self.valve_q]))

    def observation(self) -> np.ndarray:
        return np.concatenate([np.asarray(obs.GROUPS[n].read(self), dtype=np.float64) for n in obs.DEFAULT])

    def observation_groups(self) -> Mapping[str, ObservationGroup]:
        return obs.GROUPS

    def default_observation(self) -> tuple[str, ...]:
        return obs.DEFAULT

    def achieved_goal(self) -> np.ndarray:
        return np.array([self.valve_angle()])

    def desired_goal(self) -> np.ndarray:
        return np.array([self._goal])

    def quantities(self) -> dict[str, float]:
        d = self.data
        return {
            FINGERTIP_TO_HANDLE: math.dist(d.site_xpos[self.rig.site_id], d.site_xpos[self.handle_site]),
            VALVE_SPEED: abs(float(d.qvel[self.valve_dof])),
        }

    # -------------------------------------------------------------- rendering
    def render(self) -> np.ndarray | None:
        return self._renderer.render(self.model, self.data)

    def close(self) -> None:
        self._renderer.close()
