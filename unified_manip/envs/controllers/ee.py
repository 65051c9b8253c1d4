"""The end-effector controllers: a grip-site position target, solved to joint targets
by mink differential IK each step, with the rig's held gripper orientation.

The action is ``(dx, dy, dz, gripper)``, or ``(dx, dy, dz)`` on a rig without a gripper; ``info`` gains ``ik_residual`` (the solution's
remaining position error, m) and ``ik_limit_active`` (a joint range bound it).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from unified_manip.envs.controllers.ik import MinkIK


class EEDeltaController:
    """Target ``p + a[:3] * step`` from the measured grip site ``p``."""

    #: What it carries between steps (:mod:`.memory`).
    memory: tuple[str, ...] = ()

    def __init__(self, config, rig) -> None:
        self.config, self.rig = config, rig
        self.action_dim = 3 + int(rig.has_gripper)
        rig.actuate("position")
        self.ik = MinkIK(rig.model, rig, orientation_cost=config.orientation_cost, iterations=config.iterations)
        self.ik_yield = None
        if config.yield_residual is not None:
            self.ik_yield = MinkIK(
                rig.model, rig, orientation_cost=config.yield_orientation_cost, iterations=config.iterations
            )

    def reset(self) -> None:
        self.rig.reset("position")

    def goal(self, action: np.ndarray) -> np.ndarray:
        """The grip-site target of this step."""
        return self.rig.site_position() + action[:3] * self.config.step

    def site_action_toward(self, site_target: np.ndarray) -> np.ndarray:
        """The (unclipped) ``a[:3]`` that makes ``site_target`` this step's target."""
        return (site_target - self.rig.site_position()) / self.config.step

    def __call__(self, action: np.ndarray) -> dict[str, Any]:
        rig = self.rig
        target = self.goal(action)
        rotation = rig.ee_rotation(target)
        q_arm, residual, limit_active = self.ik.solve(rig.data.qpos, target, rotation)
        if self.ik_yield is not None and residual > self.config.yield_residual:
            # Out of reach holding the orientation: let the gripper tilt.
            q_arm, residual, limit_active = self.ik_yield.solve(rig.data.qpos, target, rotation)
        rig.command(q_arm, action[3] if rig.has_gripper else None)
        return {"ik_residual": residual, "ik_limit_active": limit_active}


class EETargetDeltaController(EEDeltaController):
    """Target ``previous target + a[:3] * step``; the grip site's position at reset."""

    memory = ("target",)

    def __init__(self, config, rig) -> None:
        super().__init__(config, rig)
        self.target = np.zeros(3)

    def reset(self) -> None:
        super().reset()
        self.target = np.array(self.rig.site_position(), dtype=np.float64)

    def goal(self, action: np.ndarray) -> np.ndarray:
        self.target = self.target + action[:3] * self.config.step
        return self.target.copy()

    def site_action_toward(self, site_target: np.ndarray) -> np.ndarray:
        return (site_target - self.target) / self.config.step

    def lead(self) -> np.ndarray:
        """How far the carried target leads the measured grip site, in full action steps."""
        return (self.target - self.rig.site_position()) / self.config.step
