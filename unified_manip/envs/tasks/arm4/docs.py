"""The 4-DOF arm tasks' documentation pages (``unified-manip list --doc``)."""

from __future__ import annotations

from unified_manip.envs.controllers.docs import modes_section
from unified_manip.envs.tasks.arm4.controllers import CONTROLLERS, CONTROLLERS_25HZ

_MODES_HEAD = """Action modes (action in [-1, 1]; the last entry commands the gripper, -1 closed,
+1 open; native is joint_delta, the design document's scheme):"""
_MODES = f"""{_MODES_HEAD}
{modes_section(CONTROLLERS)}"""
_MODES_25HZ = f"""{_MODES_HEAD}
{modes_section(CONTROLLERS_25HZ)}"""


def _her(entries: str, group: str) -> str:
    """The HER paragraph: the default observation's last group depends on the goal."""
    return f"""HER: entries {entries} ({group}, the ``goal_rel`` group) depend on the goal. SB3's
HerReplayBuffer relabels ``desired_goal`` but not ``observation``, so it leaves them at the
episode's goal in every relabelled transition. Use
``unified_manip.training.GoalRelHerReplayBuffer``, a drop-in that moves them to the new goal;
``unified-manip train`` does so by default."""


_TABLE_HEAD = """\
    =====  ==========================================  ==========
    index  content                                     units
    =====  ==========================================  ==========
"""
_TABLE_END = "    =====  ==========================================  ==========\n"

REACH_DOC = f"""Arm4Reach: bring the 4-DOF arm's grip site to a goal point.

The goal is sampled uniformly in x [0.30, 0.60], y [-0.25, 0.25], z [0.46, 0.65] m
(world frame; the table top is z = 0.42). There is no object. Success: the grip site
is within 5 cm of the goal. 50 steps of 20 ms.

Observation (18,):
{_TABLE_HEAD}    0-3    joint angles j0..j3                         rad
    4-5    finger openings (left, right), 0 = closed   m
    6-9    joint velocities j0..j3                     rad/s
    10-11  finger velocities                           m/s
    12-14  grip-site position (world)                  m
    15-17  goal - grip site                            m
{_TABLE_END}
Goal (3,): achieved = grip-site position, desired = goal point, m.

{_her("15-17", "goal - grip site")}
{_MODES}
Dense reward: reach = 1 - tanh(5 d), success bonus 10.
Version history: v0 initial.
"""

_OBJECT_TABLE = f"""{_TABLE_HEAD}    0-3    joint angles j0..j3                         rad
    4-5    finger openings (left, right), 0 = closed   m
    6-8    cube position (world)                       m
    9-12   cube orientation quaternion (w, x, y, z)
    13-16  joint velocities j0..j3                     rad/s
    17-18  finger velocities                           m/s
    19-21  cube linear velocity                        m/s
    22-24  cube angular velocity                       rad/s
    25-27  grip-site position (world)                  m
    28-30  cube - grip site                            m
    31-33  goal - cube                                 m
{_TABLE_END}"""

_OBJECT_HER = _her("31-33", "goal - cube")

PUSH_DOC = f"""Arm4Push: push the cube across the table to a goal on the table.

The cube starts at rest at x [0.40, 0.60], y [-0.10, 0.10] m; the goal lies on the
table top (z = 0.445, the cube's resting height) at x [0.35, 0.65], y [-0.15, 0.15] m,
at least 10 cm from the cube. Success: the cube's centre is within 5 cm of the goal.
100 steps of 20 ms.

Observation (34,):
{_OBJECT_TABLE}
Goal (3,): achieved = cube centre, desired = goal point, m.

{_OBJECT_HER}
{_MODES}
Dense reward: reach = 1 - tanh(5 |grip - cube|), place = 5 (1 - tanh(5 d)) without a
grasp gate, success bonus 10.
Version history: v0 initial.
"""

PICK_AND_PLACE_DOC = f"""Arm4PickAndPlace: grasp the cube and carry it to a goal in the air.

The design document's task. The cube starts at rest at x [0.40, 0.60],
y [-0.10, 0.10] m; the goal is sampled in x [0.30, 0.50], y [0.10, 0.30],
z [0.50, 0.60] m, i.e. 5.5-15.5 cm above the cube's resting height, as in the design.
Success: the cube's centre is within 5 cm of the goal. 100 steps of 20 ms.

Observation (34,):
{_OBJECT_TABLE}
Goal (3,): achieved = cube centre, desired = goal point, m.

{_OBJECT_HER}
{_MODES}
Dense reward: reach = 1 - tanh(5 |grip - cube|), place = 5 grasped (1 - tanh(5 d)),
success bonus 10; ``grasped`` means both fingers touch the cube.
Version history: v0 initial.
"""

PUSH_V1_DOC = f"""Arm4Push-v1: Arm4Push with Fetch's timing and goal distribution.

The same arm, cube and table as v0. Two things change, both to match FetchPush (issue 10,
part 3b: why the arm learns more slowly than Fetch):
- Goals: anywhere in x [0.35, 0.65], y [-0.15, 0.15] m on the table top, with no minimum
  distance from the cube (v0: at least 10 cm), so some episodes start solved, as in Fetch
  (about 8% here, 6.8% in FetchPush).
- Timing: 50 steps of 40 ms (25 Hz control, 20 substeps), as Fetch; v0 has 100 steps of
  20 ms. Each mode's step doubles (ee_delta 5 cm, joint_delta 0.1 rad), so the speed per
  second is v0's. A discount of 0.95 then spans 0.8 s instead of 0.4 s.
The cube starts at rest at x [0.40, 0.60], y [-0.10, 0.10] m. Success: the cube's centre
is within 5 cm of the goal.

Observation (34,):
{_OBJECT_TABLE}
Goal (3,): achieved = cube centre, desired = goal point, m.

{_OBJECT_HER}
{_MODES_25HZ}
Dense reward: as v0.
Version history: v0 initial; v1 Fetch's timing (25 Hz, 50 steps) and goals (no minimum
distance from the cube).
"""

PICK_AND_PLACE_V1_DOC = f"""Arm4PickAndPlace-v1: Arm4PickAndPlace with Fetch's goal distribution.

The same arm, cube, table and timing as v0 (100 steps of 20 ms). One thing changes, to match
FetchPickAndPlace (issue 10, part 3b: why the arm learns more slowly than Fetch): half of
the goals lie on the table top (z at the cube's resting height), the other half in v0's
band in the air. Goals are sampled in x [0.30, 0.50], y [0.10, 0.30] m; with probability
0.5 z is the resting height, otherwise z [0.50, 0.60] m. A goal on the table can be met by
pushing or carrying the cube there, so a sparse reward meets successes without a lift, as
in Fetch (where the air half reaches 45 cm above the table).
The cube starts at rest at x [0.40, 0.60], y [-0.10, 0.10] m. Success: the cube's centre is
within 5 cm of the goal.

Observation (34,):
{_OBJECT_TABLE}
Goal (3,): achieved = cube centre, desired = goal point, m.

{_OBJECT_HER}
{_MODES}
Dense reward: as v0.
Version history: v0 initial; v1 half of the goals on the table (Fetch's distribution).
"""
