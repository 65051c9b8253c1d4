"""The Adroit tasks' action modes: ``{mode: controller config}``. The arm and hand are
driven by position servos only (no torque interface), and the hand's 24 finger
actuators have no one-number grasp for the end-effector modes' gripper entry."""

from __future__ import annotations

from unified_manip.envs import controllers as ctl

CONTROLLERS = {
    # Half of each joint's command range per step, as the Shadow Hand's relative control.
    "joint_delta": ctl.JointDelta(max_delta="half_range"),
    "joint_target_delta": ctl.JointTargetDelta(max_delta=0.02),
    "native": ctl.Native(
        "upstream's absolute controls: `ctrl = centre + a * half range` of each actuator's "
        "control range, as upstream's `step` (on the arm, gain 500 against stiffness 200: "
        "the joint settles at 2.5 ctrl)"
    ),
}
