"""The robosuite tasks' documentation pages (``unified-manip list --doc``), in the
labelled paragraphs the site's task pages put under their headings (see the arm's docs)."""

from __future__ import annotations

from unified_manip.envs.controllers.docs import modes_section
from unified_manip.envs.tasks.robosuite_tasks.controllers import CONTROLLERS

_OPTIONS = """Options: ``robot`` (default "Panda"; also "Sawyer", "UR5e", "IIWA", "Kinova3",
"Jaco"). Unknown options raise TypeError, unknown robots ValueError. Camera images are
the ``rgb`` and ``depth`` observation groups of every family (``camera=``: agentview
(default), frontview, birdview, sideview, robot0_robotview, robot0_eye_in_hand, and each
as ``<name>_collision``, drawing the collision geoms instead of the visual meshes, about
20x faster on software rendering); the old ``camera_obs``, ``camera_width`` and ``camera_height`` options raise TypeError
naming them."""

_MODES = f"""Action modes (action in [-1, 1]; n = the robot's arm joints, 7 on Panda; in every
mode but native the last entry commands the gripper, -1 closed, +1 open, and the ee
modes take (dx, dy, dz, gripper)):
{modes_section(CONTROLLERS)}
Joint targets (+-pi on continuous joints) go as absolute targets to robosuite's
JOINT_POSITION controller (kp 150, critically damped, mass-matrix and gravity
compensated); torques (limits 87/12 N m on Panda) to its JOINT_TORQUE controller, plus
its gravity compensation. The ee modes hold the gripper orientation at reset (on Door
turned to point at the door, see the task doc) and put ``ik_residual`` (m) and
``ik_limit_active`` in ``info``. native, with the same seed and actions, gives
robosuite.make's observations and reward (``info["native_reward"]``)."""

_OBS = """Observation (float32): robosuite's ``robot0_proprio-state`` then ``object-state``.
Proprio (Panda: 50): joint pos (n, rad), cos, sin (n each), joint vel (n, rad/s), joint
acc (n, rad/s^2), eef position (3, m, world), eef quaternion xyzw (4), grip-site
quaternion (4), gripper finger qpos (2 on Panda, m) and qvel (2, m/s). Other robots:
Sawyer 50, UR5e 53, IIWA/Kinova3/Jaco 58 (grippers with more joints)."""

_INFO = """Info adds ``native_success`` (1.0/0.0, robosuite's ``_check_success()``) and
``native_reward`` (robosuite's own sparse reward for the step)."""

_HISTORY = """Version history: v0 initial (robosuite {env} 1.5.2, control_freq 20 Hz). Later,
without a version bump: rendered frames and camera images hide the collision geoms
(group 0), as robosuite's renderer does, with observations (low-dim), rewards and infos
unchanged; and the ``camera_obs=True`` option (an ``image`` key) became
``observation=['default', 'rgb']``, the image groups every family has."""

_ROBOT_START = """Starting state: the robot at robosuite's initial posture plus robosuite's default
joint noise (Gaussian, magnitude 0.02), at rest"""

_GRASP_REWARDS = """Rewards: grip_to_object is the distance from the grip site to the {what} (m);
grasped is robosuite's check that the gripper holds the {what}."""

LIFT_DOC = f"""Lift: pick up a cube (2 cm half-size) and hold it at a goal point above the table
(robosuite Lift).

The table top is at z = 0.8 m (world frame).

{_ROBOT_START}; the cube within 3 cm of the table centre (robosuite's placement); the
goal x, y ~ U(-0.1, 0.1) m around the table centre, z ~ U(0.10, 0.20) m above the table
top.

Success: the goal distance is the Euclidean distance between the cube's centre and the
goal point, in metres.

Native success (robosuite): cube centre > 4 cm above the table top. Every goal is at
least 10 cm up, so is_success implies native success; native success is looser (any
lift counts).

{_INFO}

{_OBS}
Object state (10): cube position (3, m), cube quaternion (4), grip site to cube (3, m).
Goal (3,): achieved = cube centre, desired = goal point, world frame, m.

{_MODES}

{_GRASP_REWARDS.format(what="cube")}

{_OPTIONS}

{_HISTORY.format(env="Lift")}
"""

STACK_DOC = f"""Stack: put cube A (2 cm half-size, red) on top of cube B (2.5 cm half-size, green)
(robosuite Stack).

The scripted ee_delta policy grasps A, raises it 4 cm over B's top and holds it there,
so it meets is_success and not native success.

{_ROBOT_START}; both cubes in a 16 x 16 cm square at the table centre (robosuite's
placement, from the env's seed); the goal cube B's centre at reset plus 4.5 cm (the two
half-sizes) in z: cube A resting on B. The goal is not sampled beyond the scene.

Success: the goal distance is the Euclidean distance between cube A's centre and the
goal point, in metres.

Native success (robosuite): A lifted, touching B and not grasped. Differences by
design: is_success does not require the gripper to let go, and is measured against
B's position at reset (if B is pushed away the goal stays); native success needs
contact with B wherever B is.

{_INFO}

{_OBS}
Object state (23): cube A position (3, m) and quaternion (4), cube B position (3) and
quaternion (4), A - B (3, m), grip to A (3, m), grip to B (3, m).
Goal (3,): achieved = cube A centre, desired = top of cube B at reset, m.

{_MODES}

{_GRASP_REWARDS.format(what="cube A")}

{_OPTIONS}

{_HISTORY.format(env="Stack")}
"""

CAN_DOC = f"""PickPlaceCan: pick up a can from the left bin and place it in its quadrant of the right
bin (robosuite PickPlaceCan).

Reach: the quadrant is the far one from the robot (Panda base at (-0.56, 0)); most of
it is out of reach with the gripper pointing straight down, so ee_delta tilts the
gripper there (see ee_delta below). Even tilted, the Panda cannot carry the can to the
goals of the far corner (x > ~0.22 and y > ~0.45 m, more than ~0.91 m from the base in
x-y): the scripted ee_delta policy fails there (about 6% of goals). The goal
distribution is left as is: those goals are in the bin, and other robots reach further.

{_ROBOT_START}; the can anywhere in bin 1 (robosuite's placement); the goal a point in
the can's quadrant of bin 2 (x in [0.10, 0.295], y in [0.28, 0.525] m) at least 5 cm
from the quadrant's walls, 5 cm above the bin floor (z = 0.85 m).

Success: the goal distance is the Euclidean distance between the can's centre and the
goal point, in metres.

Native success (robosuite): the can's centre inside its quadrant, between the bin
floor and 10 cm above it, and the eef more than about 4.2 cm from the can (robosuite's
r_reach < 0.6: the can has been let go). The goal keeps 5 cm from the walls and its z
ball stays in (0.80, 0.90), so once the can is released, is_success implies native
success; native success also counts any other point of the quadrant. Difference by
design: is_success does not require letting go (a can held within 5 cm of the goal
counts).

{_INFO}

{_OBS}
Object state (14): can position (3, m), quaternion (4), can relative to the eef in
the eef frame: position (3, m) and quaternion (4).
Goal (3,): achieved = can centre, desired = goal point, m.

{_MODES}

{_GRASP_REWARDS.format(what="can")}

{_OPTIONS}

{_HISTORY.format(env="PickPlaceCan")}
"""

NUT_DOC = f"""NutAssemblyRound: put the round nut on the round peg (robosuite NutAssemblyRound).

The round peg is fixed at (0.23, -0.10) m; the table top is at z = 0.82 m.

{_ROBOT_START}; the nut on the left of the table (robosuite's placement); the goal on
the peg's axis at a height U(0.005, 0.02) m above the table top, down the peg: the nut's
body origin (ring centre) around the peg.

Success: the goal distance is the Euclidean distance between the nut's body origin and
the goal point, in metres.

Native success (robosuite): the nut within 3 cm of the peg axis in x and y, below
5 cm above the table, and the gripper more than about 4 cm away. Differences by
design: is_success does not require the gripper to have let go.

{_INFO}

{_OBS}
Object state (14): nut position (3, m), quaternion (4), nut relative to the eef
(3, m, and 4).
Goal (3,): achieved = nut body position, desired = point on the peg, m.

{_MODES}

{_GRASP_REWARDS.format(what="nut")}

{_OPTIONS}

{_HISTORY.format(env="NutAssemblyRound")}
"""

DOOR_DOC = f"""Door: turn the latch handle and open the door to a target angle (robosuite Door,
latch on).

The door opens towards the robot (+y) only once the latch is turned down past ~1.2 rad
(the latch_joint's range is [-1.57, 1.57]) and must be held there until the latch
clears the frame. ee_delta holds the gripper pointing at the door (-y) with its
fingers one above the other, instead of pointing down: a downward hand hits the door
panel and the handle's base. The scripted ee_delta policy closes the fingers, comes
over the lever from the front, presses it down along its arc with the fingertips to
~1.4 rad, then swings the pressed point about the hinge to the goal angle (friction on
the lever drags the door).

{_ROBOT_START}; the door frame at robosuite's randomised position, closed and latched;
the goal a hinge angle ~ U(0.35, 0.40) rad (the hinge's range is [0, 0.4]).

Success: the goal distance is |hinge angle - goal angle|, in radians.

Native success (robosuite): hinge angle > 0.3 rad. Every goal is at least 0.35 rad,
so is_success implies native success.

{_INFO}

{_OBS}
Object state (14): door position (3, m), handle position (3, m), hinge angle (rad),
door - eef (3, m), handle - eef (3, m), handle (latch) angle (rad).
Goal (1,): achieved = hinge angle, desired = target angle, rad.

{_MODES}

Rewards: the template is "push" (no grasp gate): grip_to_object is the distance from
the grip site to the handle (m), and the place term reads the angle error (rad).

{_OPTIONS}

{_HISTORY.format(env="Door")}
"""

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
        obs=_OBS,
        modes=_MODES,
        options=_OPTIONS,
        info=_INFO,
        robot_start=_ROBOT_START,
        rewards=_GRASP_REWARDS.format(what=obj),
        history=_HISTORY.format(env=name),
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

{_ROBOT_START}; the nut on the right of the table, turned about z at random; the goal a
point on the peg's axis at a height U(0.005, 0.02) m above the table top (z = 0.82 m):
the nut's body origin (the hole's centre) around the peg.

Success: the goal distance is the Euclidean distance between the nut's body position and
the goal point, in metres.

{_OBS}
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

{_INFO}

{_MODES}

{_GRASP_REWARDS.format(what="nut's handle")}

{_OPTIONS}

{_HISTORY.format(env="NutAssemblySquare")}
"""

WIPE_DOC = f"""Wipe: wipe a line of 100 dirt markers off the table with a sponge tool (robosuite Wipe).

The Panda carries robosuite's WipingGripper, a sponge with no moving part, instead of
a gripper. A marker is wiped when the sponge's corners enclose it while the arm touches
nothing else and is off its joint limits.

{_ROBOT_START}; the 100 markers along a random path on the table (robosuite's placement).

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

{_INFO}

{_MODES}

Rewards: the template is "push": grip_to_object is the distance from the grip site to the
centroid of the markers left (0 once all are wiped), and the place term reads 1 minus the
fraction wiped. It has none of robosuite's own Wipe terms (contact, pressure, force and
collision penalties): ``native_reward`` gives those.

{_OPTIONS}

{_HISTORY.format(env="Wipe")}
"""

TOOL_HANG_DOC = f"""ToolHang: stand the frame in its stand, then hang the tool on it (robosuite ToolHang).

Three pieces lie on the table: a stand (fixed place), an L-shaped frame (hook) and a
tool with a hole at one end. The frame's free end goes into the stand's hole, then
the tool's hole onto the frame's arm. Both stages are robosuite's own checks: the frame
is assembled when the stand is upright and the frame's end stands between the stand's
walls within 5 cm of its base; the tool is on the frame when it hangs there without
touching the gripper.

{_ROBOT_START}; the stand, frame and tool at robosuite's placements.

Success: the goal is the two flags (frame assembled, tool on frame), 1.0 or 0.0 each,
desired (1, 1), and the goal distance their Euclidean distance: both set (below 0.5),
exactly robosuite's success.

{_OBS}
Object state (44): for the stand's base, the frame (its corner site) and the tool:
pose relative to the eef (3, m, and 4), position (3, m) and quaternion (4); then the
two flags (as robosuite observes them, at the first substep of the step).
Goal (2,): achieved = (frame assembled, tool on frame), desired = (1, 1).

Scripted policy: none. Both stages need the gripper turned (the frame is inserted
upright, the tool's hole aligned with the frame's arm), and the ee modes hold its turn.

{_INFO}

{_MODES}

Rewards: the template is "push": grip_to_object is the distance from the grip site to the
frame's corner until the frame is assembled, then to the tool (m), and the place term reads
the flags' distance (0, 1 or 1.41). A coarse shaping: it has no term for inserting the
frame or aligning the tool.

{_OPTIONS}

{_HISTORY.format(env="ToolHang")}
"""
