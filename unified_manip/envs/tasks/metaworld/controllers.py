"""The Meta-World tasks' action modes: ``{mode: controller config}``.

``native`` is Meta-World's own: its Sawyer's hand follows a mocap body welded to it. The
joint and end-effector modes run on the actuated copy of the model (:mod:`.rig`: the
weld removed, the arm's 7 joints on servos); the end-effector modes solve their grip-site
target to joint targets with mink, as on Fetch."""

from __future__ import annotations

from unified_manip.envs import controllers as ctl

#: ``ee_target_delta``'s step at ``|a| = 1``, m: Meta-World's own 1 cm per unit, so that
#: its target moves as native's mocap does.
TARGET_STEP = 0.01
#: ``ee_delta``'s step, m. Its target is re-anchored on the measured grip site every step
#: and the servos close only part of the gap in a 12.5 ms step, so the hand's speed scales
#: with the lead: at native's 1 cm a full action moves the hand a fraction of native's top
#: speed, and Meta-World's translated policies, which push with their mocap's lead, fail.
#: benchmarks/out/metaworld_scripted_ee_delta*.json measure MT10 at 5, 10 and 20 cm.
EE_STEP = 0.1

CONTROLLERS = {
    "joint_torque": ctl.JointTorque(),
    "joint_position": ctl.JointPosition(),
    "joint_delta": ctl.JointDelta(max_delta=0.05),
    "joint_target_delta": ctl.JointTargetDelta(max_delta=0.05),
    "ee_delta": ctl.EEDelta(step=EE_STEP),
    "ee_target_delta": ctl.EETargetDelta(step=TARGET_STEP),
    "native": ctl.Native(
        "Meta-World's own: (dx, dy, dz) moves the mocap body the hand is welded to by "
        "1 cm per unit (clipped to the hand's box), and the gripper entry drives the two "
        "fingers' position actuators (+1 closes, -1 opens)"
    ),
}
