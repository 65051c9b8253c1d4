"""``ee_delta`` actions played in another action mode of the same rig.

The families' scripted policies emit ``ee_delta`` actions. :class:`EEDeltaInMode` turns
each into the action of the env's own mode that commands the same motion, from the
grip-site target ``p + a[:3] * step`` of the task's ``ee_delta`` config: an end-effector
controller's ``site_action_toward`` that target; for a joint mode, the target solved to
joint targets by the same mink IK, then the joint controller's ``action_toward`` them
(:mod:`.joint`). The result is clipped to ``[-1, 1]``; the gripper entry passes through. In ``joint_position`` that is
the ``ee_delta`` controller's own command; the relative modes clip it to their step, and
the velocity and torque modes follow it through their own dynamics, so a policy's
success can differ by mode (demonstrations record it).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from unified_manip.envs.controllers.configs import EEDelta
from unified_manip.envs.controllers.ik import MinkIK


class EEDeltaInMode:
    """Maps ``ee_delta`` actions to the actions of ``backend``'s mode.

    Args:
        backend: A backend with a ``rig`` and a ``control`` of the shared controllers.
        ee: The task's ``ee_delta`` config (step and IK settings).

    Raises:
        ValueError: the backend's mode is not driven by a shared controller (``native``
            of Fetch and robosuite, the source's own controller).
    """

    def __init__(self, backend: Any, ee: EEDelta) -> None:
        self.tracker = SiteTracker(backend, ee)
        self.step = ee.step

    def __call__(self, ee_action: np.ndarray) -> np.ndarray:
        target = self.tracker.rig.site_position() + np.asarray(ee_action[:3]) * self.step
        return self.tracker(target, ee_action[3] if self.tracker.rig.has_gripper else None)


class SiteTracker:
    """The action of ``backend``'s mode that moves the grip site toward a world target.

    An end-effector controller's ``site_action_toward`` the target; for a joint mode, the
    target solved to joint targets by the task's ``ee_delta`` IK, then the joint
    controller's ``action_toward`` them. ``unified-manip convert`` drives it with a recorded
    grip-site trajectory; :class:`EEDeltaInMode` with ``p + a[:3] * step``.

    Args:
        backend: A backend with a ``rig`` and a ``control`` of the shared controllers.
        ee: The task's ``ee_delta`` config (IK settings).

    Raises:
        ValueError: the backend's mode is not driven by a shared controller, or its
            controller cannot follow a joint target on this robot (``joint_torque`` on
            robosuite, whose arms have no servo gains here).
    """

    def __init__(self, backend: Any, ee: EEDelta) -> None:
        control: Any = getattr(backend, "control", None)
        if len(getattr(backend, "rigs", ())) > 1:
            raise ValueError(
                "ee_delta actions are played in other modes on one arm only; a task of several arms "
                "(TwoArmLift) records its scripted policy in ee_delta"
            )
        self.site_mode = hasattr(control, "site_action_toward")
        if not (self.site_mode or hasattr(control, "action_toward")):
            raise ValueError(
                "only the modes of the shared controllers can play ee_delta actions (not a source's own controller)"
            )
        self.rig, self.control = backend.rig, control
        if not self.site_mode:
            control.action_toward(self.rig.joint_positions())  # a mode that cannot follow a target fails here
            self.ik = MinkIK(self.rig.model, self.rig, orientation_cost=ee.orientation_cost, iterations=ee.iterations)

    def __call__(self, target: np.ndarray, gripper: float | None) -> np.ndarray:
        """The action toward ``target`` (world frame, m), with ``gripper`` (-1 closed, 1
        open; ``None`` for a rig without one) passed through, clipped to [-1, 1]."""
        rig = self.rig
        if self.site_mode:
            arm = self.control.site_action_toward(target)
        else:
            q_target, _, _ = self.ik.solve(rig.data.qpos, target, rig.ee_rotation(target))
            arm = self.control.action_toward(q_target)
        action = arm if gripper is None else np.append(arm, gripper)
        return np.clip(action, -1.0, 1.0).astype(np.float32)
