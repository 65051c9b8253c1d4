"""The 4-DOF arm's named entities, which randomisation terms address (``TaskSpec.entities``)."""

from __future__ import annotations

from unified_manip.envs.randomization.entities import Entity, RestHeight


def _rest_z(backend) -> float:
    return backend.object_rest_z


def _set_rest_z(backend, z: float) -> None:
    backend.object_rest_z = z


ENTITIES: dict[str, Entity] = {
    "object": Entity(
        bodies="object",
        geoms="object_geom",
        solid=True,
        rest=RestHeight(_rest_z, _set_rest_z),
        doc="the cube (a primitive solid: its shape may change)",
    ),
    "table": Entity(bodies="table", geoms="table_top|table_leg", doc="the table"),
    "robot": Entity(
        bodies="base|link[123]|gripper|finger_(left|right)",
        geoms="base_geom|link[123]_geom|palm|finger_[lr]_geom",
        joints="j[0-3]|finger_[lr]",
        actuators="a_j[0-3]|a_f[lr]",
        doc="the arm and its gripper: joints, servos, links",
    ),
    "light": Entity(lights="key|fill", doc="the key and fill lights"),
    "camera": Entity(cameras="front|wrist", doc="the front and wrist cameras"),
}
