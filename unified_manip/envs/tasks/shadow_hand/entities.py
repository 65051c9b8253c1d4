"""The Shadow Hand's named entities, which randomisation terms address (``TaskSpec.entities``).

The block is not marked a solid: its orientation is part of the goal, so it keeps its
shape. The model has no table and no camera of its own.
"""

from __future__ import annotations

from unified_manip.envs.randomization.entities import Entity

ENTITIES: dict[str, Entity] = {
    "object": Entity(bodies="object", geoms="object|object_hidden", doc="the block"),
    "robot": Entity(
        bodies="robot0:.*",
        geoms="robot0:.*",
        joints="robot0:.*",
        actuators="robot0:.*",
        doc="the hand: joints, actuators, links",
    ),
    "light": Entity(lights="light0", doc="the scene's light"),
}
