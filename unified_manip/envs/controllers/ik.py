"""Differential IK with mink, for the end-effector modes (and the arm's home posture).

:class:`MinkIK` solves for the active joints of a rig (any object with ``n``,
``qpos_adr``, ``dof_adr``, ``lower``, ``upper`` and ``site_name``); :class:`IKJoints`
is such an object for models whose arm is driven by a simulator's own controllers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import daqp
import mink
import mujoco
import numpy as np


@dataclass(frozen=True)
class IKJoints:
    """The joints and site :class:`MinkIK` works on, for models whose arm is not
    driven through a :class:`~unified_manip.envs.controllers.rig.MujocoRig` (e.g. a simulator with its own
    joint controllers).

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
    def from_model(cls, model: mujoco.MjModel, joints, site: str, unlimited_range: tuple[float, float]) -> "IKJoints":
        """Read addresses and ranges from ``model``; joints without limits get ``unlimited_range``."""
        jids = np.array([model.joint(j).id for j in joints])
        limited = model.jnt_limited[jids].astype(bool)
        lower = np.where(limited, model.jnt_range[jids, 0], unlimited_range[0])
        upper = np.where(limited, model.jnt_range[jids, 1], unlimited_range[1])
        return cls(tuple(joints), model.jnt_qposadr[jids].copy(), model.jnt_dofadr[jids].copy(), lower, upper, site)


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
        self._jac: np.ndarray | None = None

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
        jac = self._jac
        mujoco.mj_jacSite(configuration.model, configuration.data, jac[:3], jac[3:], self._site_id)
        return jac


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
            :class:`~unified_manip.envs.controllers.rig.MujocoRig` or an :class:`IKJoints`).
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
        rig: Any,
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
