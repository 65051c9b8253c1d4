"""The robosuite backend: one real robosuite env, driven through its ``step``/``reset``
(see the package docs for seeding, resets, pickling and rendering)."""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, Mapping

import mujoco
import numpy as np

from unified_manip.envs.backend import Backend, Checkpoint
from unified_manip.envs.config import EnvConfig
from unified_manip.envs.controllers import ControllerConfig
from unified_manip.envs.controllers.composite import build_controller, part_layout
from unified_manip.envs.controllers.ik import IKJoints
from unified_manip.envs.observations import ObservationGroup
from unified_manip.envs.physics import bad_state_warnings
from unified_manip.envs.rendering import Renderer
from unified_manip.envs.tasks.gripper_terms import GRASPED, GRIP_TO_OBJECT
from unified_manip.envs.tasks.robosuite_tasks.cameras import CAMERAS
from unified_manip.envs.tasks.robosuite_tasks.more_goals import TASKS
from unified_manip.envs.tasks.robosuite_tasks.observations import suite_groups
from unified_manip.envs.tasks.robosuite_tasks.options import validate_options
from unified_manip.envs.tasks.robosuite_tasks.rig import SuiteRig
from unified_manip.envs.tasks.robosuite_tasks.suite import UNLIMITED_RANGE, make_upstream

#: How robosuite scenes are drawn: robosuite's ``frontview`` camera, without the collision
#: geoms (group 0; robosuite's own renderer hides them too, and shows the visual meshes).
SCENE = CAMERAS["frontview"].scene

#: The grasp check runs only while the grip site is this close to the object, m.
GRASP_CHECK_RADIUS = 0.08


class RobosuiteBackend(Backend):
    """One robosuite task under one action mode (see the module docstring)."""

    #: Unpickling rebuilds robosuite's env and replays the episode on a nominal model.
    pickles_model = False

    def __init__(self, config: EnvConfig, controller: ControllerConfig, task: str) -> None:
        if config.render_mode == "human":
            raise ValueError("robosuite tasks render with render_mode None or 'rgb_array', not 'human'")
        self.config = config
        self.controller = controller
        self.task_name = task
        self.options = validate_options(dict(config.options))
        self.task = TASKS[task]
        self.mode = config.action_mode
        up = make_upstream(self.task.env_name, self.options["robot"], self.mode, self.task.robots)
        self._up = up
        self.dt = float(up.control_timestep)
        self.model: mujoco.MjModel = up.sim.model._model
        self.data: mujoco.MjData = up.sim.data._data
        self._grippers = [robot.gripper["right"] for robot in up.robots]
        sites = [g.important_sites["grip_site"] for g in self._grippers]
        self._grip_sites = [self.model.site(site).id for site in sites]
        self._grip_site = self._grip_sites[0]
        joints = [
            IKJoints.from_model(self.model, robot.robot_joints, site, UNLIMITED_RANGE)
            for robot, site in zip(up.robots, sites)
        ]
        self.joints = joints[0]
        self._reach = [(i, self._grip_sites[i], self._grippers[i]) for i in self.task.reachers]
        self._grasp_objects = self.task.grasp_objects(up)
        self._native = self.mode == "native"
        # Each robot's part of robosuite's action, in turn: arm, then gripper.
        dims = [robot.action_dim for robot in up.robots]
        grippers = [g.dof > 0 for g in self._grippers]
        self.action_layout = part_layout(dims, grippers) if len(dims) > 1 else ""
        if self._native:
            self.action_dim = up.action_dim
        else:
            self._command = np.zeros(up.action_dim)
            ends = np.cumsum(dims)
            self.rigs = [
                SuiteRig(up, j, self.task.held_rotation, i, self._command[e - d : e])
                for i, (j, d, e) in enumerate(zip(joints, dims, ends))
            ]
            self.rig = self.rigs[0]
            self.control = build_controller(controller, self.rigs)
            self.action_dim = self.control.action_dim
            self.action_layout = getattr(self.control, "layout", "")
        self._groups, self._default = suite_groups(up)
        self._goal = np.zeros(0)
        self._achieved: np.ndarray | None = None  # the achieved goal of the current state, once read
        self._obs: dict[str, np.ndarray] = {}
        self._reward = 0.0
        self._unstable = False
        self._episode: tuple[int, np.ndarray] | None = None
        self._log: list[np.ndarray] = []
        self._renderer = Renderer(config.render_mode, config.render_width, config.render_height, SCENE)

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
        self._achieved = None
        self._reward = 0.0
        self._unstable = False
        if not self._native:
            self.control.reset()

    def step(self, action: np.ndarray) -> dict[str, Any]:
        self._log.append(action.copy())
        return self._step(action)

    def _step(self, action: np.ndarray) -> dict[str, Any]:
        if self._native:
            command, diagnostics = action, {}
        else:
            diagnostics = self.control(action)
            command = self._command.copy()
        before = bad_state_warnings(self.data)
        self._obs, self._reward, _, _ = self._up.step(command)
        self._achieved = None
        self._unstable = bad_state_warnings(self.data) > before
        return diagnostics

    def unstable(self) -> bool:
        return self._unstable

    def checkpoint(self) -> Checkpoint:
        """Also each gripper's command, which robosuite moves toward the action's sign at
        a set speed (``current_action``)."""
        grippers = [g.current_action.copy() for r in self._up.robots for g in r.gripper.values()]
        return replace(super().checkpoint(), family=grippers)

    def restore(self, checkpoint: Checkpoint) -> None:
        """Also flag robosuite's part controllers to reread the simulator, as a step leaves
        them: each caches the joint state and reads it again only when flagged."""
        super().restore(checkpoint)
        grippers = [g for r in self._up.robots for g in r.gripper.values()]
        for gripper, action in zip(grippers, checkpoint.family):
            gripper.current_action = action.copy()
        for robot in self._up.robots:
            for part in robot.part_controllers.values():
                part.new_update = True

    # -------------------------------------------------------------- observation
    def observation(self) -> np.ndarray:
        """Each robot's ``robotI_proprio-state``, then ``object-state``."""
        obs = self._obs
        return np.concatenate([obs[f"robot{i}_proprio-state"] for i in range(self.task.robots)] + [obs["object-state"]])

    def observation_groups(self) -> Mapping[str, ObservationGroup]:
        return self._groups

    def default_observation(self) -> tuple[str, ...]:
        return self._default

    def achieved_goal(self) -> np.ndarray:
        self._achieved = self.task.achieved(self._up).copy()
        return self._achieved

    def desired_goal(self) -> np.ndarray:
        return self._goal

    def _reach_distances(self) -> list[float]:
        """Each reacher's grip-site distance to its row of the task's ``object_pos``, m."""
        targets = np.atleast_2d(self.task.object_pos(self._up))
        out = []
        for target, (_, site, _) in zip(targets, self._reach):
            rel = target - self.data.site_xpos[site]
            out.append(math.sqrt(float(rel @ rel)))
        return out

    def grip_to_object(self) -> float:
        return max(self._reach_distances())

    def quantities(self) -> dict[str, float]:
        """``grip_to_object`` (m; with several reachers, the farthest one's) and ``grasped``
        (robosuite's grasp check; with several reachers, 1 while each holds its own) of the
        task's object (:mod:`~unified_manip.envs.tasks.gripper_terms`)."""
        dists = self._reach_distances()
        dist = max(dists)
        if self._grasp_objects is None or dist > GRASP_CHECK_RADIUS:  # skip the contact scan when far
            return {GRIP_TO_OBJECT: dist, GRASPED: 0.0}
        check = self._up._check_grasp
        held = all(check(gripper=g, object_geoms=o) for (_, _, g), o in zip(self._reach, self._grasp_objects))
        return {GRIP_TO_OBJECT: dist, GRASPED: float(held)}

    def extra_info(self) -> dict[str, Any]:
        if self.task.goal_is_success:  # the env has read the achieved goal of this state
            achieved = self.achieved_goal() if self._achieved is None else self._achieved
            success = float(np.array_equal(achieved, self._goal))
        else:
            success = float(self._up._check_success())
        return {"native_success": success, "native_reward": float(self._reward)}

    # -------------------------------------------------------------- rendering
    def render(self) -> np.ndarray | None:
        return self._renderer.render(self.model, self.data)

    def close(self) -> None:
        self._renderer.close()
        # robosuite's env holds reference cycles, so its model and data (about 100 MB for
        # Lift) would wait for a full garbage collection. robosuite's own close() frees them
        # by running one (gc.collect, 0.2 s and more in a large process); dropping every
        # reference to them frees them at once instead.
        sim = self._up.sim
        if sim is not None:
            for name in ("_render_context_offscreen", "data", "model"):
                sim.__dict__.pop(name, None)
            self._up.sim = None
        # Each robot's model also keeps its own compiled MjModel, meshes included (about
        # 40 MB for the Panda), in the same cycles.
        for robot in self._up.robots:
            robot.robot_model.mujoco_model = None
        self.model = self.data = None  # type: ignore[assignment]
        self.rig = self.rigs = self.control = None  # they hold the model and data too

    # -------------------------------------------------------------- pickling
    def __getstate__(self) -> dict[str, Any]:
        return {
            "config": self.config,
            "controller": self.controller,
            "task": self.task_name,
            "episode": self._episode,
            "log": list(self._log),
        }

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__init__(state["config"], state["controller"], state["task"])
        if state["episode"] is not None:
            seed, goal = state["episode"]
            self._reset_upstream(seed)
            self._goal, self._episode = goal.copy(), (seed, goal.copy())
            for action in state["log"]:
                self.step(action)
