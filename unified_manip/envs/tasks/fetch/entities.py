"""Fetch's named entities, which randomisation terms address (``TaskSpec.entities``).

The arm's servos exist outside ``native`` only (upstream drives the arm through a mocap
weld); the robot's actuators are the fingers' there.
"""

from __future__ import annotations

from unified_manip.envs.randomization.entities import Entity, RestHeight


def _object_z(backend) -> int:
    m = backend.model
    return int(m.jnt_qposadr[m.joint("object0:joint").id]) + 2


def _rest_z(backend) -> float:
    """Upstream's reset places the object at its initial height (``initial_qpos``)."""
    return float(backend._up.initial_qpos[_object_z(backend)])


def _set_rest_z(backend, z: float) -> None:
    backend._up.initial_qpos[_object_z(backend)] = z


ENTITIES: dict[str, Entity] = {
    "object": Entity(
        bodies="object0",
        geoms="object0",
        solid=True,
        rest=RestHeight(_rest_z, _set_rest_z),
        doc="the block (a primitive solid: its shape may change)",
    ),
    "table": Entity(bodies="table0", geoms="table0", doc="the table (its top is unnamed: matched by its body)"),
    "robot": Entity(
        bodies=r"robot0:(shoulder|upperarm|elbow|forearm|wrist|gripper|[lr]_gripper_finger).*_link",
        geoms=r"robot0:(shoulder|upperarm|elbow|forearm|wrist|gripper|[lr]_gripper_finger).*_link",
        joints=r"robot0:(shoulder_pan|shoulder_lift|upperarm_roll|elbow_flex|forearm_roll|wrist_flex|wrist_roll|[lr]_gripper_finger)_joint",
        actuators=r"robot0:.*",
        doc="the arm and its gripper: joints, servos, links",
    ),
    "light": Entity(lights="light0", doc="the scene's light"),
    "camera": Entity(cameras="head_camera_rgb|gripper_camera_rgb|external_camera_0", doc="the model's cameras"),
}
