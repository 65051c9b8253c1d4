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

from types import SimpleNamespace
from typing import Any

import numpy as np

from unified_manip.envs.controllers.configs import EEDelta
from unified_manip.envs.controllers.ik import MinkIK


def arms(backend: Any) -> list[Any]:
    """Each arm of ``backend`` as a one-arm view (``rig``, ``control``): its rig and the
    mode's controller on it (a two-arm task's :class:`~.composite.PerRig` part), in the
    action's order."""
    rigs = list(getattr(backend, "rigs", None) or [backend.rig])
    control = getattr(backend, "control", None)
    parts = list(getattr(control, "parts", [control] * len(rigs)))
    return [SimpleNamespace(rig=r, control=c) for r, c in zip(rigs, parts)]


class EEDeltaInMode:
    """Maps ``ee_delta`` actions to the actions of ``backend``'s mode, arm by arm (a
    two-arm task's ``ee_delta`` action is each arm's ``(dx, dy, dz, gripper)`` in turn).

    Args:
        backend: A backend with a ``rig`` (or ``rigs``) and a ``control`` of the shared
            controllers.
        ee: The task's ``ee_delta`` config (step and IK settings).

    Raises:
        ValueError: the backend's mode is not driven by a shared controller (``native``
            of Fetch and robosuite, the source's own controller).
    """

    def __init__(self, backend: Any, ee: EEDelta) -> None:
        self.trackers = [SiteTracker(arm, ee) for arm in arms(backend)]
        self.step = ee.step

    def __call__(self, ee_action: np.ndarray) -> np.ndarray:
        out, start = [], 0
        for tracker in self.trackers:
            gripper = tracker.rig.has_gripper
            a = np.asarray(ee_action[start : start + 3 + int(gripper)])
            start += 3 + int(gripper)
            out.append(tracker(tracker.rig.site_position() + a[:3] * self.step, a[3] if gripper else None))
        return np.concatenate(out)


class SiteTracker:
    """The action of ``backend``'s mode that moves the grip site toward a world target.

    An end-effector controller's ``site_action_toward`` the target; for a joint mode, the
    target solved to joint targets by the task's ``ee_delta`` IK, then the joint
    controller's ``action_toward`` them. ``unified-manip convert`` drives it with a recorded
    grip-site trajectory; :class:`EEDeltaInMode` with ``p + a[:3] * step``.

    Args:
        backend: A backend with a ``rig`` and a ``control`` of the shared controllers (one
            arm: a task of several arms passes each of :func:`arms`).
        ee: The task's ``ee_delta`` config (IK settings).

    Raises:
        ValueError: the backend has several arms, its mode is not driven by a shared
            controller, or its
            controller cannot follow a joint target on this robot (``joint_torque`` on
            robosuite, whose arms have no servo gains here).
    """

    def __init__(self, backend: Any, ee: EEDelta) -> None:
        control: Any = getattr(backend, "control", None)
        if len(getattr(backend, "rigs", ())) > 1:
            raise ValueError("a SiteTracker follows one arm; track each of a two-arm task's arms (translate.arms)")
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
