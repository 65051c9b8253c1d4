"""The Meta-World tasks' action modes: ``{mode: controller config}``.

``native`` is Meta-World's own: its Sawyer's hand follows a mocap body welded to it. The
joint modes run on the actuated copy of the model (:mod:`.rig`: the weld removed, the
arm's 7 joints on servos); the end-effector modes through mink are not offered yet."""

from __future__ import annotations

from unified_manip.envs import controllers as ctl

CONTROLLERS = {
    "joint_torque": ctl.JointTorque(),
    "joint_position": ctl.JointPosition(),
    "joint_delta": ctl.JointDelta(max_delta=0.05),
    "joint_target_delta": ctl.JointTargetDelta(max_delta=0.05),
    "native": ctl.Native(
        "Meta-World's own: (dx, dy, dz) moves the mocap body the hand is welded to by "
        "1 cm per unit (clipped to the hand's box), and the gripper entry drives the two "
        "fingers' position actuators (+1 closes, -1 opens)"
    ),
}
