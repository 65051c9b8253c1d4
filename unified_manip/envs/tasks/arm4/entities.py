"""The 4-DOF arm's named entities, which randomisation terms address (``TaskSpec.entities``)."""

from __future__ import annotations

from unified_manip.envs.randomization.entities import Entity, RestHeight


def _rest_z(backend) -> float:
    return backend.object_rest_z


def _set_rest_z(backend, z: float) -> None:
    backend.object_rest_z = z


def _cube(shapes: tuple[str, ...]) -> Entity:
    return Entity(
        bodies="object",
        geoms="object_geom",
        solid=True,
        shapes=shapes,
        rest=RestHeight(_rest_z, _set_rest_z),
        doc=f"the cube (a primitive solid: {', '.join(shapes)})",
    )


_SHARED: dict[str, Entity] = {
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

#: Each scene's entities: the cube of a push task stays a box (a round object rolls off
#: the pusher's line), the one picked up may become a cylinder or a sphere.
ENTITIES: dict[str, dict[str, Entity]] = {
    "reach": _SHARED,
    "push": {"object": _cube(("box",)), **_SHARED},
    "pick_and_place": {"object": _cube(("box", "cylinder", "sphere")), **_SHARED},
}
