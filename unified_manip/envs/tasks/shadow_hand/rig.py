"""The Shadow Hand's rig: its 20 position actuators as the controllers' joints."""

from __future__ import annotations

import numpy as np

#: The finger actuators (J1) that also drive the distal joint J0.
COUPLED_FINGERS = ("FF", "MF", "RF", "LF")


class HandRig:
    """The hand's actuators, in upstream's order (WRJ1, WRJ0, FFJ3-1, MFJ3-1, RFJ3-1,
    LFJ4-1, THJ4-0). An actuator's "joint position" is its joint's angle, plus the
    coupled distal joint J0 for the FF/MF/RF/LF J1 actuators (upstream's relative
    control); its command range is the actuator's control range. No gripper entry.

    Args:
        model: The hand's model.
        data: Its data.
        dt: Seconds per env step.
    """

    has_gripper = False

    def __init__(self, model, data, dt: float) -> None:
        self.model, self.data, self.dt = model, data, dt
        self.n = model.nu
        self.lower = model.actuator_ctrlrange[:, 0].copy()
        self.upper = model.actuator_ctrlrange[:, 1].copy()
        # Upstream: an actuator's joint is its name with ":A_" replaced by ":".
        names = [model.actuator(i).name for i in range(model.nu)]
        self.act_qadr = np.array([model.jnt_qposadr[model.joint(n.replace(":A_", ":")).id] for n in names])
        self.coupled_act = np.array([names.index(f"robot0:A_{f}J1") for f in COUPLED_FINGERS])
        self.coupled_qadr = np.array([model.jnt_qposadr[model.joint(f"robot0:{f}J0").id] for f in COUPLED_FINGERS])

    def joint_positions(self) -> np.ndarray:
        q = self.data.qpos
        centre = q[self.act_qadr]
        centre[self.coupled_act] += q[self.coupled_qadr]
        return centre

    def actuate(self, kind: str, **_) -> None:
        if kind != "position":
            raise ValueError(f"the Shadow Hand's actuators are position servos; cannot command {kind!r}")

    def reset(self, kind: str) -> None:
        """Nothing: upstream's reset leaves the controls as they are."""

    def command(self, arm: np.ndarray, gripper: float | None) -> None:
        self.data.ctrl[:] = arm
