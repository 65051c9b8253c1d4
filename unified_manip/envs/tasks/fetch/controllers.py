"""Fetch's action modes: ``{mode: controller config}``. Every mode but ``native`` runs
on the actuated copy of the model (see the package docs)."""

from __future__ import annotations

from unified_manip.envs import controllers as ctl

CONTROLLERS = {
    "joint_torque": ctl.JointTorque(),
    "joint_position": ctl.JointPosition(),
    "joint_delta": ctl.JointDelta(max_delta=0.05),
    "joint_target_delta": ctl.JointTargetDelta(max_delta=0.05),
    "joint_velocity": ctl.JointVelocity(max_velocity=1.0, kv=(50.0, 50.0, 50.0, 50.0, 20.0, 20.0, 10.0)),
    "ee_delta": ctl.EEDelta(step=0.05),
    "ee_target_delta": ctl.EETargetDelta(step=0.05),
    "native": ctl.Native(
        "upstream's mocap control, unchanged: `(dx, dy, dz, gripper)`, the mocap target moves 5 cm "
        "per unit; the gripper entry is upstream's relative finger command (cast to float32 first)"
    ),
}
