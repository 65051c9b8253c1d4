"""The documentation pages of the robosuite tasks added after the first five (:mod:`.docs`):
PickPlaceMilk, PickPlaceBread, PickPlaceCereal, NutAssemblySquare, Wipe and ToolHang."""

from __future__ import annotations

from unified_manip.envs.tasks.robosuite_tasks.doc_parts import (
    GRASP_REWARDS,
    HISTORY,
    INFO,
    MODES,
    OBS,
    OPTIONS,
    ROBOT_START,
)

_PICK_PLACE = """{name}: pick up the {obj} from the left bin and place it in its quadrant of the right
bin (robosuite {name}).

{robot_start}; the {obj} anywhere in bin 1, turned about z at random; the goal a
point in the {obj}'s quadrant of bin 2 ({quadrant}) at least 5 cm from the quadrant's
walls, {z} cm above the bin's origin (its centre's height standing on the bin floor).

Success: the goal distance is the Euclidean distance between the {obj}'s centre and the
goal point, in metres.

{obs}
Object state (14): {obj} position (3, m), quaternion (4), {obj} relative to the eef in
the eef frame: position (3, m) and quaternion (4).
Goal (3,): achieved = {obj} centre, desired = goal point, m.

Native success (robosuite): the {obj}'s centre inside its quadrant, between the bin
origin and 10 cm above it, and the eef more than about 4.2 cm from it (let go).
Difference by design: is_success does not require letting go.

{extra}

{info}

{modes}

{rewards}

{options}

{history}
"""


def _pick_place(name: str, obj: str, quadrant: str, z: str, extra: str) -> str:
    return _PICK_PLACE.format(
        name=name,
        obj=obj,
        quadrant=quadrant,
        z=z,
        extra=extra,
        obs=OBS,
        modes=MODES,
        options=OPTIONS,
        info=INFO,
        robot_start=ROBOT_START,
        rewards=GRASP_REWARDS.format(what=obj),
        history=HISTORY.format(env=name),
    )


MILK_DOC = _pick_place(
    "PickPlaceMilk",
    "milk carton",
    "x in [-0.095, 0.10], y in [0.035, 0.28] m",
    "8",
    "The carton is 4 x 4 cm across and 14.4 cm tall: it fits the Panda's 8 cm opening at any turn. "
    "The scripted ee_delta policy grasps it 4.5 cm above its centre (the hand clears its top), "
    "lifts it 14 cm over the goal, carries it across, lowers it and lets go: 26 of 30 seeded "
    "episodes (seeds 0-29).",
)
BREAD_DOC = _pick_place(
    "PickPlaceBread",
    "bread",
    "x in [0.10, 0.295], y in [0.035, 0.28] m",
    "4.5",
    "The loaf is 4 x 4.8 cm across and 4.8 cm tall: it fits the Panda's 8 cm opening at any turn. "
    "The scripted ee_delta policy grasps it at its centre: 23 of 30 seeded episodes (seeds "
    "0-29). It fails where the loaf lies within about 10 cm of a bin wall along the hand's "
    "width: the hand, 20 cm wide, meets the wall's top before the fingers reach the loaf.",
)
CEREAL_DOC = _pick_place(
    "PickPlaceCereal",
    "cereal box",
    "x in [-0.095, 0.10], y in [0.28, 0.525] m",
    "9.5",
    "The box is 3 x 10 cm across and 15 cm tall. The ee modes hold the gripper's turn, and "
    "its fingers close across the box only when the box's narrow side faces them: the "
    "scripted ee_delta policy (grasp 4 cm above the centre, as for the milk) succeeds in 14 "
    "of 30 seeded episodes (seeds 0-29).",
)

SQUARE_NUT_DOC = f"""NutAssemblySquare: put the square nut on the square peg (robosuite NutAssemblySquare).

The square peg (3.2 cm across) is fixed at (0.23, 0.10) m. The nut's hole is 4.55 cm
across, so the peg passes it at any turn, with no clearance left at 45 degrees.

{ROBOT_START}; the nut on the right of the table, turned about z at random; the goal a
point on the peg's axis at a height U(0.005, 0.02) m above the table top (z = 0.82 m):
the nut's body origin (the hole's centre) around the peg.

Success: the goal distance is the Euclidean distance between the nut's body position and
the goal point, in metres.

{OBS}
Object state (14): nut position (3, m), quaternion (4), nut relative to the eef
(3, m, and 4).
Goal (3,): achieved = nut body position, desired = point on the peg, m.

Native success (robosuite): the nut within 3 cm of the peg axis in x and y, below
5 cm above the table, and the gripper more than about 4 cm away. Difference by design:
is_success does not require the gripper to have let go.

The scripted ee_delta policy grasps the handle from above (where the nut's turn puts
it), raises the nut over the peg, centres the hole on the peg's axis and lets go at
the peg's top: held by its handle the nut tilts and catches there, let go it levels
and drops down the peg. It succeeds in 12 of 30 seeded episodes (seeds 0-29); among the failures seen, grasps
that never close on the handle, the nut turned across the fingers.

{INFO}

{MODES}

{GRASP_REWARDS.format(what="nut's handle")}

{OPTIONS}

{HISTORY.format(env="NutAssemblySquare")}
"""

WIPE_DOC = f"""Wipe: wipe a line of 100 dirt markers off the table with a sponge tool (robosuite Wipe).

The Panda carries robosuite's WipingGripper, a sponge with no moving part, instead of
a gripper. A marker is wiped when the sponge's corners enclose it while the arm touches
nothing else and is off its joint limits.

{ROBOT_START}; the 100 markers along a random path on the table (robosuite's placement).

Success: the goal is the fraction of the markers wiped, desired 1, and the goal distance
1 minus the fraction: all 100 wiped (within 0.005 of 1), exactly robosuite's success.

Observation (float32): robosuite's ``robot0_proprio-state`` then ``object-state``.
Proprio (Panda: 47): joint pos (7, rad), cos, sin (7 each), joint vel (7, rad/s), joint
acc (7, rad/s^2), eef position (3, m, world), eef quaternion xyzw (4), grip-site
quaternion (4), contact (1: 1 while the sponge pushes with more than 1 N).
Object state (8): fraction wiped (1), radius of the markers left around their centroid
(1, m), their centroid (3, m), centroid - eef (3, m).
Goal (1,): achieved = fraction wiped, desired = 1.

No gripper: the joint modes take the n arm entries alone and the ee modes (dx, dy, dz);
native takes robosuite's 6 OSC_POSE entries.

Scripted policy: none. The observation gives the markers' centroid and spread, not the
path they lie along, so a policy that follows the line needs more than it sees.

{INFO}

{MODES}

Rewards: the template is "push": grip_to_object is the distance from the grip site to the
centroid of the markers left (0 once all are wiped), and the place term reads 1 minus the
fraction wiped. It has none of robosuite's own Wipe terms (contact, pressure, force and
collision penalties): ``native_reward`` gives those.

{OPTIONS}

{HISTORY.format(env="Wipe")}
"""

TOOL_HANG_DOC = f"""ToolHang: stand the frame in its stand, then hang the tool on it (robosuite ToolHang).

Three pieces lie on the table: a stand (fixed place), an L-shaped frame (hook) and a
tool with a hole at one end. The frame's free end goes into the stand's hole, then
the tool's hole onto the frame's arm. Both stages are robosuite's own checks: the frame
is assembled when the stand is upright and the frame's end stands between the stand's
walls within 5 cm of its base; the tool is on the frame when it hangs there without
touching the gripper.

{ROBOT_START}; the stand, frame and tool at robosuite's placements.

Success: the goal is the two flags (frame assembled, tool on frame), 1.0 or 0.0 each,
desired (1, 1), and the goal distance their Euclidean distance: both set (below 0.5),
exactly robosuite's success.

{OBS}
Object state (44): for the stand's base, the frame (its corner site) and the tool:
pose relative to the eef (3, m, and 4), position (3, m) and quaternion (4); then the
two flags (as robosuite observes them, at the first substep of the step).
Goal (2,): achieved = (frame assembled, tool on frame), desired = (1, 1).

Scripted policy: none. Both stages need the gripper turned (the frame is inserted
upright, the tool's hole aligned with the frame's arm), and the ee modes hold its turn.

{INFO}

{MODES}

Rewards: the template is "push": grip_to_object is the distance from the grip site to the
frame's corner until the frame is assembled, then to the tool (m), and the place term reads
the flags' distance (0, 1 or 1.41). A coarse shaping: it has no term for inserting the
frame or aligning the tool.

{OPTIONS}

{HISTORY.format(env="ToolHang")}
"""
