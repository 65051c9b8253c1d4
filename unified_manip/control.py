"""Action modes on MuJoCo models: how a ``Box(-1, 1)`` action becomes control.

Every mode is real physics: the arm is driven through MuJoCo actuators whose gains
are set once, when the env is built, for the chosen mode. Nothing writes ``qpos``.

=================  =========================================================  ==============
mode               arm part of the action (``a`` in [-1, 1] per joint)         actuator as
=================  =========================================================  ==============
joint_torque       torque ``a * max_torque`` (N m)                             motor
joint_position     absolute target ``lower + (a + 1) / 2 * (upper - lower)``   PD servo
joint_delta        target ``q + a * max_delta`` (rad), clipped to the range    PD servo
joint_velocity     target velocity ``a * max_velocity`` (rad/s)                velocity servo
ee_delta           grip-site target ``p + a[:3] * ee_step`` (m), solved to     PD servo
                   joint targets by mink differential IK
=================  =========================================================  ==============

The last action entry always commands the gripper: -1 closed, +1 open.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import daqp
import mink
import mujoco
import numpy as np

from .physics import bad_state_warnings  # noqa: F401  (re-exported: it lived here)

JOINT_MODES: tuple[str, ...] = ("joint_torque", "joint_position", "joint_delta", "joint_velocity")
#: Modes whose arm actuators act as position servos.
SERVO_MODES: tuple[str, ...] = ("joint_position", "joint_delta", "ee_delta")


@dataclass(frozen=True)
class ArmGains:
    """Per-family scales of the action modes (scalars or one value per arm joint).

    The position-servo gains and the torque limits are not here: they are read from
    the model's arm actuators (``gainprm[0]`` = kp, ``-biasprm[2]`` = kv,
    ``forcerange`` = torque limit), so the MJCF stays the one place they are set.

    Attributes:
        kv_velocity: Velocity-servo gain in ``joint_velocity``, N m s / rad.
        max_velocity: Joint speed at ``|a| = 1`` in ``joint_velocity``, rad/s.
        max_delta: Target change at ``|a| = 1`` in ``joint_delta``, rad per step.
        ee_step: Grip-site displacement at ``|a| = 1`` in ``ee_delta``, m per step.
    """

    kv_velocity: Any
    max_velocity: Any
    max_delta: float = 0.05
    ee_step: float = 0.05

    def __post_init__(self) -> None:
        for name in ("kv_velocity", "max_velocity", "max_delta", "ee_step"):
            if np.any(np.asarray(getattr(self, name), dtype=float) <= 0):
                raise ValueError(f"ArmGains.{name} must be positive, got {getattr(self, name)!r}")


class ArmRig:
    """Indices of an arm and its gripper inside a MuJoCo model.

    Args:
        model: The model; its arm actuators must be force-limited ``general``
            position servos on the arm joints, in the same order as ``joints``. Their
            gains and force limits are the servo gains and torque limits of every mode.
        data: The data the env steps.
        joints: Names of the arm joints.
        actuators: Names of the arm actuators, one per joint.
        gripper_actuators: Names of the gripper's position actuators.
        gripper_closed: Gripper ctrl at action -1.
        gripper_open: Gripper ctrl at action +1.
        site: Name of the end-effector site (IK frame, reach goal).
        gains: The action modes' scales.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        joints: tuple[str, ...],
        actuators: tuple[str, ...],
        gripper_actuators: tuple[str, ...],
        gripper_closed: float,
        gripper_open: float,
        site: str,
        gains: ArmGains,
    ) -> None:
        self.model, self.data = model, data
        self.joint_names = joints
        jids = np.array([model.joint(j).id for j in joints])
        self.qpos_adr = model.jnt_qposadr[jids].copy()
        self.dof_adr = model.jnt_dofadr[jids].copy()
        self.lower = model.jnt_range[jids, 0].copy()
        self.upper = model.jnt_range[jids, 1].copy()
        self.actuator_ids = np.array([model.actuator(a).id for a in actuators])
        self.gripper_ids = np.array([model.actuator(a).id for a in gripper_actuators])
        self.gripper_closed = float(gripper_closed)
        self.gripper_span = float(gripper_open) - float(gripper_closed)
        self.site_name = site
        self.site_id = model.site(site).id
        self.gains = gains
        n = len(joints)
        self.n = n
        ids = self.actuator_ids
        if not np.all(model.actuator_forcelimited[ids]) or np.any(model.actuator_gainprm[ids, 0] <= 0):
            raise ValueError("arm actuators must be force-limited position servos (gainprm[0] = kp > 0)")
        self.kp = model.actuator_gainprm[ids, 0].copy()
        self.kv = -model.actuator_biasprm[ids, 2].copy()
        self.max_torque = model.actuator_forcerange[ids, 1].copy()
        self.kv_velocity = np.broadcast_to(np.asarray(gains.kv_velocity, float), (n,)).copy()
        self.max_velocity = np.broadcast_to(np.asarray(gains.max_velocity, float), (n,)).copy()

    def configure(self, mode: str) -> None:
        """Set the arm actuators' gains, bias and ctrl range for ``mode``."""
        m, ids = self.model, self.actuator_ids
        m.actuator_gaintype[ids] = mujoco.mjtGain.mjGAIN_FIXED
        m.actuator_biastype[ids] = mujoco.mjtBias.mjBIAS_AFFINE
        m.actuator_gainprm[ids, :] = 0.0
        m.actuator_biasprm[ids, :] = 0.0
        m.actuator_forcelimited[ids] = 1
        m.actuator_forcerange[ids, 0] = -self.max_torque
        m.actuator_forcerange[ids, 1] = self.max_torque
        m.actuator_ctrllimited[ids] = 1
        if mode == "joint_torque":
            m.actuator_gainprm[ids, 0] = 1.0
            m.actuator_ctrlrange[ids, 0] = -self.max_torque
            m.actuator_ctrlrange[ids, 1] = self.max_torque
        elif mode == "joint_velocity":
            # force = (kv + d) v_cmd - kv qdot: the feed-forward d v_cmd cancels the
            # joint's passive damping d, so the joint settles at exactly v_cmd.
            m.actuator_gainprm[ids, 0] = self.kv_velocity + m.dof_damping[self.dof_adr]
            m.actuator_biasprm[ids, 2] = -self.kv_velocity
            m.actuator_ctrlrange[ids, 0] = -self.max_velocity
            m.actuator_ctrlrange[ids, 1] = self.max_velocity
        elif mode in SERVO_MODES:
            m.actuator_gainprm[ids, 0] = self.kp
            m.actuator_biasprm[ids, 1] = -self.kp
            m.actuator_biasprm[ids, 2] = -self.kv
            m.actuator_ctrlrange[ids, 0] = self.lower
            m.actuator_ctrlrange[ids, 1] = self.upper
        else:
            raise ValueError(f"ArmRig cannot drive action mode {mode!r}")

    def hold_current_pose(self) -> None:
        """Set servo targets to the current joint positions (after a reset)."""
        self.data.ctrl[self.actuator_ids] = self.data.qpos[self.qpos_adr]

    def set_gripper(self, command: float) -> None:
        self.data.ctrl[self.gripper_ids] = self.gripper_closed + (command + 1.0) * 0.5 * self.gripper_span


@dataclass(frozen=True)
class IKJoints:
    """The joints and site :class:`MinkIK` works on, for models whose arm is not
    driven through :class:`ArmRig` (e.g. a simulator with its own joint controllers).

    Attributes:
        joint_names: The active joints.
        qpos_adr: Their ``qpos`` addresses.
        dof_adr: Their ``qvel`` addresses.
        lower: Lower range ends, rad.
        upper: Upper range ends, rad.
        site_name: The IK site.
    """

    joint_names: tuple[str, ...]
    qpos_adr: np.ndarray
    dof_adr: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    site_name: str

    @property
    def n(self) -> int:
        return len(self.joint_names)

    @classmethod
    def from_model(
        cls, model: mujoco.MjModel, joints, site: str, unlimited_range: tuple[float, float]
    ) -> "IKJoints":
        """Read addresses and ranges from ``model``; joints without limits get ``unlimited_range``."""
        jids = np.array([model.joint(j).id for j in joints])
        limited = model.jnt_limited[jids].astype(bool)
        lower = np.where(limited, model.jnt_range[jids, 0], unlimited_range[0])
        upper = np.where(limited, model.jnt_range[jids, 1], unlimited_range[1])
        return cls(
            tuple(joints), model.jnt_qposadr[jids].copy(), model.jnt_dofadr[jids].copy(), lower, upper, site
        )


class JointControl:
    """``joint_torque``, ``joint_position``, ``joint_delta`` or ``joint_velocity``.

    The action is ``n`` arm entries plus one gripper entry.
    """

    def __init__(self, rig: ArmRig, mode: str) -> None:
        if mode not in JOINT_MODES:
            raise ValueError(f"JointControl drives {JOINT_MODES}, not {mode!r}")
        self.rig, self.mode = rig, mode
        self.action_dim = rig.n + 1
        rig.configure(mode)
        g = rig.gains
        if mode == "joint_torque":
            self._scale, self._offset = rig.max_torque, np.zeros(rig.n)
        elif mode == "joint_velocity":
            self._scale, self._offset = rig.max_velocity, np.zeros(rig.n)
        elif mode == "joint_position":
            self._scale = 0.5 * (rig.upper - rig.lower)
            self._offset = 0.5 * (rig.upper + rig.lower)
        else:
            self._scale, self._offset = np.full(rig.n, g.max_delta), None

    def reset(self) -> None:
        if self.mode in SERVO_MODES:
            self.rig.hold_current_pose()
        else:
            self.rig.data.ctrl[self.rig.actuator_ids] = 0.0

    def __call__(self, action: np.ndarray) -> dict[str, Any]:
        rig = self.rig
        arm = action[: rig.n] * self._scale
        if self._offset is None:  # joint_delta: relative to the measured position
            arm = np.minimum(np.maximum(rig.data.qpos[rig.qpos_adr] + arm, rig.lower), rig.upper)
        else:
            arm = arm + self._offset
        rig.data.ctrl[rig.actuator_ids] = arm
        rig.set_gripper(action[rig.n])
        return {}


class SitePoseTask(mink.Task):
    r"""A mink task placing a site at a position with a preferred rotation.

    mink's ``FrameTask`` computes its error on SE(3) with Python Lie-group code,
    about 0.17 ms per evaluation here: more than the 10 physics substeps it controls.
    This task keeps mink's task interface and QP objective (weighted least squares
    with Levenberg-Marquardt damping) but uses the small-angle orientation error

    .. math::  e_p = p - p^*, \qquad e_R = -\tfrac12 \sum_i r_i \times r_i^*,
               \qquad J = [J_p; J_R]

    with :math:`r_i`, :math:`r_i^*` the columns of the current and target rotation
    matrices, straight from ``mj_jacSite``.
    """

    k = 6

    def __init__(self, site: str, position_cost: float, orientation_cost: float, lm_damping: float = 0.0):
        cost = np.array([position_cost] * 3 + [orientation_cost] * 3, dtype=float)
        super().__init__(cost=cost, gain=1.0, lm_damping=lm_damping)
        self.site = site
        self._site_id: int | None = None
        self.position = np.zeros(3)
        self.rotation = np.eye(3)
        self._jac = None

    def set_target(self, position: np.ndarray, rotation: np.ndarray) -> None:
        self.position = np.asarray(position, dtype=float)
        self.rotation = np.asarray(rotation, dtype=float)

    def compute_error(self, configuration: mink.Configuration) -> np.ndarray:
        if self._site_id is None:
            self._site_id = configuration.model.site(self.site).id
        data = configuration.data
        current = data.site_xmat[self._site_id].reshape(3, 3)
        # sum_i r_i x r*_i = vee(R* R^T - R R*^T), without numpy's slow np.cross.
        m = self.rotation @ current.T
        e_rot = -0.5 * np.array((m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1]))
        return np.concatenate((data.site_xpos[self._site_id] - self.position, e_rot))

    def compute_jacobian(self, configuration: mink.Configuration) -> np.ndarray:
        if self._site_id is None:
            self._site_id = configuration.model.site(self.site).id
        if self._jac is None:
            self._jac = np.zeros((6, configuration.model.nv))
        mujoco.mj_jacSite(configuration.model, configuration.data, self._jac[:3], self._jac[3:], self._site_id)
        return self._jac


class MinkIK:
    """Differential IK with mink on a subset of joints; the other joints stay frozen.

    The mink ``Configuration`` and task are built once. Each call runs ``iterations``
    Gauss-Newton steps: mink supplies the task's QP objective, the QP is restricted
    to the active degrees of freedom (which freezes every other joint, e.g. a mobile
    base or a torso that starts outside its range) and solved with daqp under the
    joint-range bounds (mink's ``ConfigurationLimit`` formula, restricted the same way).

    Args:
        model: The MuJoCo model.
        rig: Supplies the active joints, their ranges and the IK site (an
            :class:`ArmRig` or an :class:`IKJoints`).
        orientation_cost: Weight of the orientation error relative to position
            (0 ignores orientation).
        max_joint_step: Largest joint change per call, rad.
        iterations: Gauss-Newton steps per call.
        limit_gain: Fraction of the distance to a joint limit one step may cover.
        damping: Tikhonov regularisation of the QP.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        rig: ArmRig | IKJoints,
        orientation_cost: float = 0.1,
        max_joint_step: float = 0.5,
        iterations: int = 2,
        limit_gain: float = 0.95,
        damping: float = 1e-4,
    ) -> None:
        self.configuration = mink.Configuration(model)
        self.task = SitePoseTask(rig.site_name, 1.0, orientation_cost, lm_damping=1e-6)
        self.rig = rig
        self._dofs = np.ix_(rig.dof_adr, rig.dof_adr)
        self._damping = damping * np.eye(rig.n)
        self._no_rows = np.zeros((0, rig.n))
        self._max_step = max_joint_step
        self._iterations = iterations
        self._limit_gain = limit_gain
        self._site_id = model.site(rig.site_name).id

    def solve(self, q: np.ndarray, position: np.ndarray, rotation: np.ndarray) -> tuple[np.ndarray, float, bool]:
        """Joint targets that bring the site to ``position`` with ``rotation``.

        Args:
            q: Full ``qpos`` of the model.
            position: Target site position, world frame, m.
            rotation: Target site rotation matrix, world frame.

        Returns:
            ``(arm_targets, residual_m, limit_active)``: targets for the active joints,
            the remaining position error of the solution in metres, and whether a
            joint range bound the solution.
        """
        rig = self.rig
        cfg = self.configuration
        q = q.copy()
        self.task.set_target(position, rotation)
        limit_active = False
        for _ in range(self._iterations):
            cfg.update(q)
            H, c = self.task.compute_qp_objective(cfg)
            qa = q[rig.qpos_adr]
            # np.minimum/np.maximum: np.clip's Python wrapper costs more than the QP.
            lo = np.minimum(np.maximum(self._limit_gain * (rig.lower - qa), -self._max_step), 0.0)
            hi = np.maximum(np.minimum(self._limit_gain * (rig.upper - qa), self._max_step), 0.0)
            dq, _, flag, _ = daqp.solve(H[self._dofs] + self._damping, c[rig.dof_adr], self._no_rows, hi, lo)
            if flag < 1:  # numerically infeasible: stay put rather than jump
                dq = np.zeros(rig.n)
            at_range = ((dq <= lo + 1e-9) & (lo > -self._max_step)) | ((dq >= hi - 1e-9) & (hi < self._max_step))
            limit_active = limit_active or bool(at_range.any())
            q[rig.qpos_adr] = qa + dq
        cfg.update(q)
        residual = float(np.linalg.norm(cfg.data.site_xpos[self._site_id] - position))
        return q[rig.qpos_adr], residual, limit_active


class EndEffectorControl:
    """``ee_delta``: a grip-site position delta plus gripper, solved by :class:`MinkIK`.

    Args:
        rig: The arm.
        target_rotation: Maps the target position to the rotation the IK should hold
            (e.g. "pointing down"); a soft preference weighted by ``orientation_cost``.
        orientation_cost: See :class:`MinkIK`.
    """

    def __init__(
        self,
        rig: ArmRig,
        target_rotation: Callable[[np.ndarray], np.ndarray],
        orientation_cost: float = 0.1,
        iterations: int = 2,
    ) -> None:
        self.rig = rig
        self.action_dim = 4
        rig.configure("ee_delta")
        self.ik = MinkIK(rig.model, rig, orientation_cost=orientation_cost, iterations=iterations)
        self._target_rotation = target_rotation
        self._step = rig.gains.ee_step

    def reset(self) -> None:
        self.rig.hold_current_pose()

    def __call__(self, action: np.ndarray) -> dict[str, Any]:
        rig = self.rig
        target = rig.data.site_xpos[rig.site_id] + action[:3] * self._step
        q_arm, residual, limit_active = self.ik.solve(rig.data.qpos, target, self._target_rotation(target))
        rig.data.ctrl[rig.actuator_ids] = q_arm
        rig.set_gripper(action[3])
        return {"ik_residual": residual, "ik_limit_active": limit_active}


def make_mujoco_control(rig: ArmRig, mode: str, target_rotation: Callable[[np.ndarray], np.ndarray], **ik_kwargs):
    """Build the controller for ``mode`` on ``rig`` (``native`` is the family's job)."""
    if mode == "ee_delta":
        return EndEffectorControl(rig, target_rotation, **ik_kwargs)
    return JointControl(rig, mode)
