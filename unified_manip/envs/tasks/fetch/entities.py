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


def _block(shapes: tuple[str, ...]) -> Entity:
    return Entity(
        bodies="object0",
        geoms="object0",
        solid=True,
        shapes=shapes,
        rest=RestHeight(_rest_z, _set_rest_z),
        doc=f"the block (a primitive solid: {', '.join(shapes)})",
    )


_SHARED: dict[str, Entity] = {
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

#: Each task's entities: a pushed or slid block stays a box (a round one rolls off the
#: pusher's line); the one picked up may become a cylinder or a sphere.
ENTITIES: dict[str, dict[str, Entity]] = {
    "Reach": _SHARED,
    "Push": {"object": _block(("box",)), **_SHARED},
    "Slide": {"object": _block(("box",)), **_SHARED},
    "PickAndPlace": {"object": _block(("box", "cylinder", "sphere")), **_SHARED},
}
