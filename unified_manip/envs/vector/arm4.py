"""The 4-DOF arm, N at a time: action scaling, servo targets and observations as arrays.

:class:`VectorizedArm4` holds N of the family's own backends (``TaskSpec.make_backend``),
so each env keeps its own model, data, reset code and mink IK. A step:

1. computes the joint modes' controls for all N envs at once in numpy (the formulas of
   :mod:`unified_manip.envs.controllers.joint`, written over rows; the end-effector and
   target-relative modes run each env's own controller);
2. steps the physics of each env on the :class:`~.pool.PhysicsPool`. Per env, a worker
   writes the controls, runs the backend's ``physics_step`` (``mj_step`` releases the
   GIL), refreshes the site positions, copies ``qpos``/``qvel`` (one ``mj_getState``)
   and the grip site into row ``i`` of shared arrays, and asks the backend for its
   gripper-object distance and grasp (``math.dist`` and a contact scan: cheaper per env
   than any exact numpy form, and overlapped with the other threads' physics). Under
   ``ee_delta`` the calling thread runs each env's own mink IK (built once with its
   backend) and hands the env to a worker as soon as its IK is done, so that the IK's
   Python overlaps the physics instead of contending with it for the GIL;
3. builds the observations of all N envs at once from those arrays.

The observation layout is the one of ``Arm4Backend.observation``; the constructor
checks the two agree on every env, so a change of the family's layout fails loudly.
"""

from __future__ import annotations

from typing import Any, Sequence

import mujoco
import numpy as np

from unified_manip.envs.controllers.joint import (
    JointDeltaController,
    JointPositionController,
    JointTorqueController,
    JointVelocityController,
)
from unified_manip.envs.vector.batched import BatchedBackend

_QPOS_QVEL = int(mujoco.mjtState.mjSTATE_QPOS | mujoco.mjtState.mjSTATE_QVEL)
#: The warnings MuJoCo counts when it finds a diverged state and resets it (as
#: ``unified_manip.envs.physics.bad_state_warnings``).
_BAD_QPOS, _BAD_QVEL, _BAD_QACC = (
    int(mujoco.mjtWarning.mjWARN_BADQPOS),
    int(mujoco.mjtWarning.mjWARN_BADQVEL),
    int(mujoco.mjtWarning.mjWARN_BADQACC),
)
#: Observation layout (``Arm4Backend.observation``): reach tasks take the arm and finger
#: coordinates, object tasks all of qpos/qvel; the cube's position is qpos[6:9].
_ROBOT_Q = 6
_CUBE = slice(6, 9)


def _joint_scaling(control) -> tuple[np.ndarray, np.ndarray | None] | None:
    """``(scale, offset)`` of a stateless affine joint controller (``offset`` None:
    relative to the measured q, clipped to the range), or None for any other controller
    (the end-effector and target-relative modes), which then runs per env."""
    stateless = (JointTorqueController, JointPositionController, JointDeltaController, JointVelocityController)
    if not isinstance(control, stateless):
        return None
    if control.offset is None and not control.config.clip:
        return None
    return control.scale, control.offset


class VectorizedArm4(BatchedBackend):
    """N arm backends of one task and action mode, stepped together.

    Args:
        backends: The family's backends, one per env, all built from the same config.
        action_mode: The config's action mode (``native`` is ``joint_delta`` here).
        num_threads: Threads of the physics pool.
    """

    def __init__(self, backends: Sequence[Any], action_mode: str, num_threads: int) -> None:
        self._backends: list[Any] = list(backends)  # Arm4Backend: model, data, rig, control
        self.num_envs = n = len(self._backends)
        b0 = self._backends[0]
        self.kind = b0.scene
        self.action_dim = b0.action_dim
        scaling = _joint_scaling(b0.control)
        self._per_env = scaling is None  # the controller runs per env (IK, or a target it keeps)
        self._ik = b0.control.config.space == "ee"
        rig = b0.rig
        self._arm_cols = rig.actuator_ids
        self._grip_cols = rig.gripper_ids
        self._qpos_adr = rig.qpos_adr
        self._lower, self._upper = rig.lower, rig.upper
        self._grip_closed, self._grip_span = rig.gripper_closed, rig.gripper_span
        if scaling is not None:
            self._scale, self._offset = scaling
        m = b0.model
        self._nq = m.nq
        self._state = np.zeros((n, m.nq + m.nv))
        self._ctrl = np.zeros((n, m.nu))
        self._grip = np.zeros((n, 3))
        self._goal = np.zeros((n, 3))
        self._unstable = np.zeros(n, dtype=bool)
        self._quantities = {}
        self._residual = np.zeros(n)
        self._limit = np.zeros(n, dtype=bool)
        self._actions = np.zeros((n, self.action_dim))
        self._num_threads = num_threads
        self._attach()
        # Size and check: one reset of every env with a throwaway generator, as the
        # single env does when it is built.
        for i in range(n):
            self.reset(i, np.random.default_rng(0))
        self._check_layout()

    _transient = ("_pool", "_ctrl_views", "_warn_views", "_grip_views")

    def _attach(self) -> None:
        """Thread pool and live views into each env's MjData (rebuilt after unpickling)."""
        super()._attach()
        self._ctrl_views = [b.data.ctrl for b in self._backends]
        self._warn_views = [b.data.warning.number for b in self._backends]
        self._grip_views = [b.data.site_xpos[b.rig.site_id] for b in self._backends]

    def _check_layout(self) -> None:
        obs = self.observations()
        for i, b in enumerate(self._backends):
            single = {
                "observation": np.asarray(b.observation(), dtype=np.float32),
                "achieved_goal": np.asarray(b.achieved_goal(), dtype=np.float32),
                "desired_goal": np.asarray(b.desired_goal(), dtype=np.float32),
            }
            for key, value in single.items():
                if not np.array_equal(obs[key][i], value):
                    raise RuntimeError(
                        f"VectorizedArm4: {key} of env {i} differs from Arm4Backend's; "
                        "update unified_manip/envs/vector/arm4.py to the family's observation layout"
                    )

    # ------------------------------------------------------------------ episodes
    def reset(self, index: int, np_random: np.random.Generator) -> dict[str, Any]:
        b = self._backends[index]
        b.reset(np_random)
        self._goal[index] = b.desired_goal()
        self._ctrl[index] = self._ctrl_views[index]
        self._gather(index)
        return b.extra_info()

    def step(self, actions: np.ndarray, indices: np.ndarray) -> dict[str, np.ndarray]:
        if self._per_env:  # the controller (mink: Python) on the calling thread, overlapping the workers' physics
            self._actions[:] = actions
            self._pool.pipeline(self._control_one, self._advance, indices.tolist())
            if not self._ik:
                return {}
            return {"ik_residual": self._residual.copy(), "ik_limit_active": self._limit.copy()}
        n = self._scale.shape[0]
        arm = actions[:, :n] * self._scale
        if self._offset is None:  # joint_delta: relative to the measured position
            measured = self._state[:, self._qpos_adr]
            arm = np.minimum(np.maximum(measured + arm, self._lower), self._upper)
        else:
            arm = arm + self._offset
        self._ctrl[:, self._arm_cols] = arm
        self._ctrl[:, self._grip_cols] = (self._grip_closed + (actions[:, n] + 1.0) * 0.5 * self._grip_span)[:, None]
        self._pool.run(self._step_joint, indices.tolist())
        return {}

    # ------------------------------------------------------------------ per env, on the pool
    def _step_joint(self, i: int) -> None:
        np.copyto(self._ctrl_views[i], self._ctrl[i])
        self._advance(i)

    def _control_one(self, i: int) -> None:
        diagnostics = self._backends[i].control(self._actions[i])
        if self._ik:
            self._residual[i] = diagnostics["ik_residual"]
            self._limit[i] = diagnostics["ik_limit_active"]

    def _advance(self, i: int) -> None:
        b, w = self._backends[i], self._warn_views[i]
        before = int(w[_BAD_QPOS]) + int(w[_BAD_QVEL]) + int(w[_BAD_QACC])
        b.physics_step()
        # MuJoCo resets a diverged state itself and counts a warning (as Arm4Backend.step).
        self._unstable[i] = int(w[_BAD_QPOS]) + int(w[_BAD_QVEL]) + int(w[_BAD_QACC]) > before
        mujoco.mj_kinematics(b.model, b.data)
        self._gather(i)

    def _gather(self, i: int) -> None:
        b = self._backends[i]
        mujoco.mj_getState(b.model, b.data, self._state[i], _QPOS_QVEL)
        np.copyto(self._grip[i], self._grip_views[i])
        self._keep_quantities(i, b.quantities())

    # ------------------------------------------------------------------ batched reads
    def observations(self) -> dict[str, np.ndarray]:
        qpos, qvel = self._state[:, : self._nq], self._state[:, self._nq :]
        grip, goal = self._grip, self._goal
        if self.kind == "reach":
            obs = np.concatenate((qpos[:, :_ROBOT_Q], qvel[:, :_ROBOT_Q], grip, goal - grip), axis=1)
            achieved = grip
        else:
            cube = qpos[:, _CUBE]
            obs = np.concatenate((qpos, qvel, grip, cube - grip, goal - cube), axis=1)
            achieved = cube
        return {
            "observation": obs.astype(np.float32),
            "achieved_goal": achieved.astype(np.float32),
            "desired_goal": goal.astype(np.float32),
        }
