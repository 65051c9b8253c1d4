"""The kitchen's named entities, which randomisation terms address (``TaskSpec.entities``).

The kettle is the one free object (a mesh: it keeps its shape); the counter it stands on is
the table. ``fixtures``, the kitchen's own entity, is its articulated parts (burner knobs,
light switch, cabinet and microwave doors): a term names it explicitly, e.g.
``{"entity": "fixtures", "field": "damping", "range": [0.5, 2.0]}``. The model's two
cameras are not offered: image observations use the free camera.
"""

from __future__ import annotations

from unified_manip.envs.randomization.entities import Entity

#: The joints of the articulated fixtures (every joint after the robot's but the kettle's).
FIXTURE_JOINTS = (
    r"knob_Joint_[1-4]|(bottom|top)_(left|right)_burner|light_switch|light_joint|slide_cabinet"
    r"|(left|right)_hinge_cabinet|microwave"
)

ENTITIES: dict[str, Entity] = {
    "object": Entity(bodies="kettle|kettleroot", geoms="kettleroot", doc="the kettle (a mesh: keeps its shape)"),
    "table": Entity(geoms="counters", doc="the counters the kettle stands on"),
    "robot": Entity(
        bodies="panda0_.*",
        geoms="panda0_.*",
        joints="robot:panda0_.*",
        actuators=".*",
        doc="the Franka: its joints, servos (all the model's actuators) and links",
    ),
    "light": Entity(lights=".*", doc="the scene's lights (three unnamed and the oven's)"),
    "fixtures": Entity(
        bodies="knob [1-4]|Burner [1-4]|lightswitchroot|lightblock_hinge|slide|slidelink|hingeleftdoor"
        "|hingerightdoor|microdoorroot",
        joints=FIXTURE_JOINTS,
        doc="the articulated fixtures: burner knobs, light switch, cabinet and microwave doors",
    ),
}
