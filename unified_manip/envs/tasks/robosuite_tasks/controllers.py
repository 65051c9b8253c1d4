"""The robosuite tasks' action modes: ``{mode: controller config}``. Every mode but
``native`` sends its command through robosuite's own JOINT_POSITION (absolute targets,
kp 150, critically damped, mass-matrix and gravity compensated) or JOINT_TORQUE
(plus gravity compensation) controller; see :mod:`.rig`."""

from __future__ import annotations

from unified_manip.envs import controllers as ctl

#: ee modes: grip-site step as OSC_POSE's 5 cm; the held gripper orientation weighs 0.3
#: against position, and yields (0.01) where that leaves more than 5 mm of error, so
#: the arm can tilt the gripper to reach further (e.g. PickPlaceCan's far bin).
_EE = dict(step=0.05, orientation_cost=0.3, yield_residual=0.005, yield_orientation_cost=0.01)

CONTROLLERS = {
    "joint_torque": ctl.JointTorque(),
    "joint_position": ctl.JointPosition(),
    # robosuite's JOINT_POSITION delta input, which these tasks used first, does not clip.
    "joint_delta": ctl.JointDelta(max_delta=0.05, clip=False),
    "joint_target_delta": ctl.JointTargetDelta(max_delta=0.05),
    # robosuite 1.5.2's JOINT_VELOCITY controller raises AttributeError on
    # torque_compensation: the speed is integrated into a position target instead.
    "joint_velocity": ctl.IntegratedJointVelocity(max_velocity=1.0, max_lead=0.1),
    "ee_delta": ctl.EEDelta(**_EE),
    "ee_target_delta": ctl.EETargetDelta(**_EE),
    "native": ctl.Native(
        "robosuite's default BASIC composite controller, unchanged: OSC_POSE `(dx, dy, dz, droll, dpitch, "
        "dyaw)`, 5 cm and 0.5 rad per unit, + GRIP with robosuite's sign (-1 open, +1 closed)"
    ),
}
