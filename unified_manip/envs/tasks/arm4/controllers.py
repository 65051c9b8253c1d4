"""The 4-DOF arm's action modes: ``{mode: controller config}``."""

from __future__ import annotations

from unified_manip.envs import controllers as ctl

#: Grip-site step of the end-effector modes, m. Half of Fetch's and robosuite's 5 cm
#: because the arm is controlled twice as often (50 Hz): both move at most 1.25 m/s.
EE_STEP = 0.025

CONTROLLERS = {
    "joint_torque": ctl.JointTorque(),
    "joint_position": ctl.JointPosition(),
    "joint_delta": ctl.JointDelta(max_delta=0.05),
    "joint_target_delta": ctl.JointTargetDelta(max_delta=0.05),
    "joint_velocity": ctl.JointVelocity(max_velocity=2.0, kv=(20.0, 20.0, 12.0, 6.0)),
    "ee_delta": ctl.EEDelta(step=EE_STEP),
    "ee_target_delta": ctl.EETargetDelta(step=EE_STEP),
    # The arm's first proposed scheme: native is joint_delta.
    "native": ctl.JointDelta(max_delta=0.05),
}

#: The v1 tasks' action modes (Fetch's timing: 25 Hz, twice the 20 ms step): every step,
#: position delta and target step is doubled, so each mode keeps v0's speed per second.
CONTROLLERS_25HZ = {
    **CONTROLLERS,
    "joint_delta": ctl.JointDelta(max_delta=0.10),
    "joint_target_delta": ctl.JointTargetDelta(max_delta=0.10),
    "ee_delta": ctl.EEDelta(step=2 * EE_STEP),
    "ee_target_delta": ctl.EETargetDelta(step=2 * EE_STEP),
    "native": ctl.JointDelta(max_delta=0.10),
}
