"""robosuite's named entities, per task, which randomisation terms address (``TaskSpec.entities``).

The object differs by task. Lift's cube and Stack's cube A (the one picked up) are
primitive solids that may become cylinders (not spheres: the scripted Panda grasp lost
every 2 cm-radius sphere on Lift); robosuite drops them from 1 cm above the table
(its placement sampler's ``z_offset``), so a resized cube needs no rest height. The can
is a mesh, the round nut a ring of boxes and the door a hinged panel: they keep their shape.
"""

from __future__ import annotations

from unified_manip.envs.randomization.entities import Entity


def _robots(index: str, doc: str) -> Entity:
    """The arms whose index matches the pattern ``index`` and their grippers."""
    prefix = f"(robot{index}|gripper{index})_.*"
    return Entity(
        bodies=prefix, geoms=prefix, joints=f"robot{index}_joint\\d|gripper{index}_.*", actuators=prefix, doc=doc
    )


_ROBOT = _robots("0", "the arm and its gripper: joints, actuators, links")
_TABLE = Entity(
    bodies="table|bin[12]",
    geoms=r"table_.*|bin[12]|bin[12]_.*",
    doc="the table (PickPlaceCan: its two bins; their unnamed geoms go by the bins' names)",
)
_SHARED: dict[str, Entity] = {
    "table": _TABLE,
    "robot": _ROBOT,
    "light": Entity(lights=".*", doc="the arena's light (unnamed)"),
    "camera": Entity(cameras=".*", doc="the arena's and the robot's cameras"),
}


def _cube(prefix: str) -> Entity:
    return Entity(
        bodies=f"{prefix}_main",
        geoms=f"{prefix}_g0(_vis)?",
        solid=True,
        shapes=("box", "cylinder"),
        doc=f"the cube {prefix!r} (box or cylinder)",
    )


#: Each task's entities: the shared ones and its object.
ENTITIES: dict[str, dict[str, Entity]] = {
    "Lift": {"object": _cube("cube"), **_SHARED},
    "Stack": {"object": _cube("cubeA"), **_SHARED},
    "PickPlaceCan": {"object": Entity(bodies="Can_main", geoms="Can_g0(_visual)?", doc="the can (a mesh)"), **_SHARED},
    "NutAssemblyRound": {
        "object": Entity(bodies="RoundNut_main", geoms=r"RoundNut_g\d+(_visual)?", doc="the round nut"),
        **_SHARED,
    },
    "Door": {
        "object": Entity(
            bodies="Door_door", geoms="Door_panel(_visual)?", joints="Door_hinge", doc="the door: panel and hinge"
        ),
        **_SHARED,
    },
}

#: The later one-arm tasks: the shared entities; their objects (meshes, a nut, markers,
#: a frame and a tool) are not named yet, so terms on ``object`` are refused there.
for _name in ("NutAssemblySquare", "PickPlaceMilk", "PickPlaceBread", "PickPlaceCereal", "Wipe", "ToolHang"):
    ENTITIES[_name] = dict(_SHARED)

#: The two-arm tasks: both robots (``robot0``, ``robot1``) and their grippers, and the object.
_TWO_ROBOTS = _robots(r"\d", "both arms and their grippers: joints, actuators, links")
ENTITIES["TwoArmLift"] = {
    "object": Entity(bodies="pot_root", geoms="pot_.*", doc="the pot and its two handles"),
    **_SHARED,
    "robot": _TWO_ROBOTS,
}
ENTITIES["TwoArmHandover"] = {
    "object": Entity(bodies="hammer_root", geoms="hammer_.*", doc="the hammer: handle, neck and head"),
    **_SHARED,
    "robot": _TWO_ROBOTS,
}
