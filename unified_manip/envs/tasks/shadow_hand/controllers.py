"""The Shadow Hand's action modes: ``{mode: controller config}``. The hand has no end
effector and no torque interface: its 20 actuators are position servos."""

from __future__ import annotations

from unified_manip.envs import controllers as ctl

CONTROLLERS = {
    # Upstream's relative_control: a step of up to half of each actuator's range, where
    # the other families step 0.05 rad. Kept: it is the hand's own relative scheme.
    "joint_delta": ctl.JointDelta(max_delta="half_range"),
    "joint_target_delta": ctl.JointTargetDelta(max_delta=0.05),
    "native": ctl.Native(
        "upstream's absolute targets: `ctrl = centre + a * half range` of each actuator's "
        "control range (rad), by upstream's `_set_action`"
    ),
}
