"""The kitchen's action modes: ``{mode: controller config}``.

``native`` is upstream's joint-velocity control; the others run on the actuated copy of
the model (:mod:`.rig`). The joint modes' step and speed match upstream's reach per step
(its 80 ms step at up to 2 rad/s)."""

from __future__ import annotations

from unified_manip.envs import controllers as ctl

CONTROLLERS = {
    "joint_torque": ctl.JointTorque(),
    "joint_position": ctl.JointPosition(),
    "joint_delta": ctl.JointDelta(max_delta=0.1),
    "joint_target_delta": ctl.JointTargetDelta(max_delta=0.1),
    "joint_velocity": ctl.JointVelocity(max_velocity=1.0, kv=20.0),
    "ee_delta": ctl.EEDelta(step=0.05),
    "ee_target_delta": ctl.EETargetDelta(step=0.05),
    "native": ctl.Native(
        "upstream's joint-velocity control, 9 entries (7 arm joints, 2 fingers): the position "
        "target `q_obs + 2 a dt` from upstream's noisy observed `q_obs`, clipped to upstream's "
        "position bounds, on the servos"
    ),
}
