"""The robosuite tasks' documentation pages (``unified-manip list --doc``), in the
labelled paragraphs the site's task pages put under their headings (see the arm's docs):
Lift, Stack, PickPlaceCan, NutAssemblyRound and Door; :mod:`.more_docs` has the rest."""

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

LIFT_DOC = f"""Lift: pick up a cube (2 cm half-size) and hold it at a goal point above the table
(robosuite Lift).

The table top is at z = 0.8 m (world frame).

{ROBOT_START}; the cube within 3 cm of the table centre (robosuite's placement); the
goal x, y ~ U(-0.1, 0.1) m around the table centre, z ~ U(0.10, 0.20) m above the table
top.

Success: the goal distance is the Euclidean distance between the cube's centre and the
goal point, in metres.

Native success (robosuite): cube centre > 4 cm above the table top. Every goal is at
least 10 cm up, so is_success implies native success; native success is looser (any
lift counts).

{INFO}

{OBS}
Object state (10): cube position (3, m), cube quaternion (4), grip site to cube (3, m).
Goal (3,): achieved = cube centre, desired = goal point, world frame, m.

{MODES}

{GRASP_REWARDS.format(what="cube")}

{OPTIONS}

{HISTORY.format(env="Lift")}
"""

STACK_DOC = f"""Stack: put cube A (2 cm half-size, red) on top of cube B (2.5 cm half-size, green)
(robosuite Stack).

The scripted ee_delta policy grasps A, raises it 4 cm over B's top and holds it there,
so it meets is_success and not native success.

{ROBOT_START}; both cubes in a 16 x 16 cm square at the table centre (robosuite's
placement, from the env's seed); the goal cube B's centre at reset plus 4.5 cm (the two
half-sizes) in z: cube A resting on B. The goal is not sampled beyond the scene.

Success: the goal distance is the Euclidean distance between cube A's centre and the
goal point, in metres.

Native success (robosuite): A lifted, touching B and not grasped. Differences by
design: is_success does not require the gripper to let go, and is measured against
B's position at reset (if B is pushed away the goal stays); native success needs
contact with B wherever B is.

{INFO}

{OBS}
Object state (23): cube A position (3, m) and quaternion (4), cube B position (3) and
quaternion (4), A - B (3, m), grip to A (3, m), grip to B (3, m).
Goal (3,): achieved = cube A centre, desired = top of cube B at reset, m.

{MODES}

{GRASP_REWARDS.format(what="cube A")}

{OPTIONS}

{HISTORY.format(env="Stack")}
"""

CAN_DOC = f"""PickPlaceCan: pick up a can from the left bin and place it in its quadrant of the right
bin (robosuite PickPlaceCan).

Reach: the quadrant is the far one from the robot (Panda base at (-0.56, 0)); most of
it is out of reach with the gripper pointing straight down, so ee_delta tilts the
gripper there (see ee_delta below). Even tilted, the Panda cannot carry the can to the
goals of the far corner (x > ~0.22 and y > ~0.45 m, more than ~0.91 m from the base in
x-y): the scripted ee_delta policy fails there (about 6% of goals). The goal
distribution is left as is: those goals are in the bin, and other robots reach further.

{ROBOT_START}; the can anywhere in bin 1 (robosuite's placement); the goal a point in
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

{INFO}

{OBS}
Object state (14): can position (3, m), quaternion (4), can relative to the eef in
the eef frame: position (3, m) and quaternion (4).
Goal (3,): achieved = can centre, desired = goal point, m.

{MODES}

{GRASP_REWARDS.format(what="can")}

{OPTIONS}

{HISTORY.format(env="PickPlaceCan")}
"""

NUT_DOC = f"""NutAssemblyRound: put the round nut on the round peg (robosuite NutAssemblyRound).

The round peg is fixed at (0.23, -0.10) m; the table top is at z = 0.82 m.

{ROBOT_START}; the nut on the left of the table (robosuite's placement); the goal on
the peg's axis at a height U(0.005, 0.02) m above the table top, down the peg: the nut's
body origin (ring centre) around the peg.

Success: the goal distance is the Euclidean distance between the nut's body origin and
the goal point, in metres.

Native success (robosuite): the nut within 3 cm of the peg axis in x and y, below
5 cm above the table, and the gripper more than about 4 cm away. Differences by
design: is_success does not require the gripper to have let go.

{INFO}

{OBS}
Object state (14): nut position (3, m), quaternion (4), nut relative to the eef
(3, m, and 4).
Goal (3,): achieved = nut body position, desired = point on the peg, m.

{MODES}

{GRASP_REWARDS.format(what="nut")}

{OPTIONS}

{HISTORY.format(env="NutAssemblyRound")}
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

{ROBOT_START}; the door frame at robosuite's randomised position, closed and latched;
the goal a hinge angle ~ U(0.35, 0.40) rad (the hinge's range is [0, 0.4]).

Success: the goal distance is |hinge angle - goal angle|, in radians.

Native success (robosuite): hinge angle > 0.3 rad. Every goal is at least 0.35 rad,
so is_success implies native success.

{INFO}

{OBS}
Object state (14): door position (3, m), handle position (3, m), hinge angle (rad),
door - eef (3, m), handle - eef (3, m), handle (latch) angle (rad).
Goal (1,): achieved = hinge angle, desired = target angle, rad.

{MODES}

Rewards: the template is "push" (no grasp gate): grip_to_object is the distance from
the grip site to the handle (m), and the place term reads the angle error (rad).

{OPTIONS}

{HISTORY.format(env="Door")}
"""
