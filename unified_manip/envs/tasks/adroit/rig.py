"""The Adroit rig: the arm's and hand's position actuators as the controllers' joints."""

from __future__ import annotations

import numpy as np


class AdroitRig:
    """Every actuator of an Adroit model (arm, then wrist and fingers, upstream's order)
    as one controller joint: its joint's position, and a position target it holds.

    Upstream's actuators are ``general`` servos with force ``gain ctrl - k q``; on the
    arm ``gain`` (500) and ``k`` (200) differ, so ``ctrl`` is not the position the joint
    settles at. The rig commands the settling position: ``ctrl = target k / gain``
    (the fingers' ``gain = k``: ``ctrl = target``). A joint's command range is the
    positions its actuator can hold, within the joint's own range. No gripper entry.

    Args:
        model: The model.
        data: Its data.
        dt: Seconds per env step.
    """

    has_gripper = False

    def __init__(self, model, data, dt: float) -> None:
        self.model, self.data, self.dt = model, data, dt
        self.n = model.nu
        joints = model.actuator_trnid[:, 0]
        self.qpos_adr = model.jnt_qposadr[joints].copy()
        gain = model.actuator_gainprm[:, 0]
        stiffness = -model.actuator_biasprm[:, 1]
        self.ctrl_per_position = stiffness / gain
        held = model.actuator_ctrlrange / self.ctrl_per_position[:, None]
        limited = model.jnt_limited[joints].astype(bool)
        self.lower = np.where(limited, np.maximum(held[:, 0], model.jnt_range[joints, 0]), held[:, 0])
        self.upper = np.where(limited, np.minimum(held[:, 1], model.jnt_range[joints, 1]), held[:, 1])

    def joint_positions(self) -> np.ndarray:
        return self.data.qpos[self.qpos_adr]

    def actuate(self, kind: str, **_) -> None:
        if kind != "position":
            raise ValueError(f"the Adroit actuators are position servos; cannot command {kind!r}")

    def reset(self, kind: str) -> None:
        """Nothing: upstream's reset leaves the controls as they are."""

    def command(self, arm: np.ndarray, gripper: float | None) -> None:
        self.data.ctrl[:] = arm * self.ctrl_per_position
