"""The 4-DOF arm tasks' documentation pages (``unified-manip list --doc``).

Each doc is paragraphs: a summary, then labelled ones (``Starting state:``, ``Success:``,
``Observation``, ``Action modes``, ``Rewards:``, ``Version history:``) that the site's task
pages put under their headings. The reset distributions are printed from the constants
the backend samples them with.
"""

from __future__ import annotations

import textwrap

from unified_manip.envs.controllers.docs import modes_section
from unified_manip.envs.tasks.arm4 import goals
from unified_manip.envs.tasks.arm4.controllers import CONTROLLERS, CONTROLLERS_25HZ
from unified_manip.envs.tasks.arm4.scene import CUBE_HALF, CUBE_REST_Z, FINGER_OPEN, HOME_SITE, TABLE_Z

_MODES_HEAD = """Action modes (action in [-1, 1]; the last entry commands the gripper, -1 closed,
+1 open; native is joint_delta, the scheme the arm was first specified with):"""
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


def _box(low, high, axes: str = "xyz") -> str:
    """``x [0.30, 0.60], y [-0.25, 0.25] m``: a uniform box, one interval per axis."""
    return ", ".join(f"{a} [{lo:.2f}, {hi:.2f}]" for a, lo, hi in zip(axes, low, high)) + " m"


def _wrap(text: str) -> str:
    """A paragraph filled to 88 columns, as the rest of the doc."""
    return textwrap.fill(" ".join(text.split()), 88)


_ARM_START = f"""the arm at its home posture, the grip site at ({", ".join(f"{v:g}" for v in HOME_SITE)}) m
pointing down, fingers open ({FINGER_OPEN * 100:g} cm), at rest"""
_CUBE_START = f"""the cube ({CUBE_HALF * 200:g} cm) at rest, upright, its centre
uniform in {_box(goals.OBJECT_XY_LOW, goals.OBJECT_XY_HIGH, "xy")}, z = {CUBE_REST_Z:g} m"""
_SUCCESS_CUBE = """Success: the goal distance is the Euclidean distance between the cube's centre and
the goal point, in metres."""

_REACH_START = _wrap(
    f"""Starting state: {_ARM_START}; the goal uniform in {_box(goals.REACH_GOAL_LOW, goals.REACH_GOAL_HIGH)}."""
)

REACH_DOC = f"""Arm4Reach: bring the 4-DOF arm's grip site to a goal point.

There is no object. The table top is at z = {TABLE_Z:g} m (world frame).

{_REACH_START}

Success: the goal distance is the Euclidean distance between the grip site and the goal
point, in metres.

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

Rewards: with no object, the reach term reads the goal distance d_goal.

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

_OBJECT_OBS = f"""Observation (34,):
{_OBJECT_TABLE}
Goal (3,): achieved = cube centre, desired = goal point, m.

{_OBJECT_HER}"""

_PUSH_REWARDS = """Rewards: grip_to_object is the distance from the grip site to the cube's centre (m);
the place term has no grasp gate."""

_GRASP_REWARDS = """Rewards: grip_to_object is the distance from the grip site to the cube's centre (m);
grasped is 1 while both fingers touch the cube."""

_PUSH_GOAL = f"""on the table top (z = {CUBE_REST_Z:g} m, the cube's resting
height), uniform in {_box(goals.PUSH_GOAL_XY_LOW, goals.PUSH_GOAL_XY_HIGH, "xy")}"""

_PUSH_START = _wrap(
    f"""Starting state: {_ARM_START}; {_CUBE_START}; the goal {_PUSH_GOAL}, drawn again until
more than {goals.PUSH_MIN_DISTANCE * 100:g} cm from the cube, so no episode starts solved."""
)

PUSH_DOC = f"""Arm4Push: push the cube across the table to a goal on the table.

{_PUSH_START}

{_SUCCESS_CUBE}

{_OBJECT_OBS}

{_MODES}

{_PUSH_REWARDS}

Version history: v0 initial.
"""

_AIR = f"uniform in {_box(goals.PLACE_GOAL_LOW, goals.PLACE_GOAL_HIGH)}"

_PLACE_START = _wrap(
    f"""Starting state: {_ARM_START}; {_CUBE_START}; the goal {_AIR}, i.e.
{(goals.PLACE_GOAL_LOW[2] - CUBE_REST_Z) * 100:g}-{(goals.PLACE_GOAL_HIGH[2] - CUBE_REST_Z) * 100:g} cm above the cube's resting height."""
)

PICK_AND_PLACE_DOC = f"""Arm4PickAndPlace: grasp the cube and carry it to a goal in the air.

The arm's first task: every goal is above the cube's resting height, so a success needs a
lift.

{_PLACE_START}

{_SUCCESS_CUBE}

{_OBJECT_OBS}

{_MODES}

{_GRASP_REWARDS}

Version history: v0 initial.
"""

_PUSH_V1_START = _wrap(f"""Starting state: {_ARM_START}; {_CUBE_START}; the goal {_PUSH_GOAL}.""")

PUSH_V1_DOC = f"""Arm4Push-v1: Arm4Push with Fetch's timing and goal distribution.

The same arm, cube and table as v0. Two things change, both to match FetchPush, to find
out why the arm learned more slowly than Fetch:
- Goals: no minimum distance from the cube (v0: more than {goals.PUSH_MIN_DISTANCE * 100:g} cm), so some episodes
  start solved, as in Fetch (about 8% here, 6.8% in FetchPush).
- Timing: 40 ms steps (25 Hz control, 20 substeps of 2 ms) and half as many of them, as
  Fetch; v0 has 20 ms steps. Each mode's step doubles (ee_delta 5 cm, joint_delta
  0.1 rad), so the speed per second is v0's. A discount of 0.95 then spans 0.8 s
  instead of 0.4 s.

{_PUSH_V1_START}

{_SUCCESS_CUBE}

{_OBJECT_OBS}

{_MODES_25HZ}

{_PUSH_REWARDS}

Version history: v0 initial; v1 Fetch's timing (25 Hz, 50 steps) and goals (no minimum
distance from the cube).
"""

_PLACE_V1_START = _wrap(
    f"""Starting state: {_ARM_START}; {_CUBE_START}; the goal {_AIR}, then with probability 0.5
lowered onto the table top (z = {CUBE_REST_Z:g} m, the cube's resting height)."""
)

PICK_AND_PLACE_V1_DOC = f"""Arm4PickAndPlace-v1: Arm4PickAndPlace with Fetch's goal distribution.

The same arm, cube, table and timing as v0. One thing changes, to match
FetchPickAndPlace, to find out why the arm learned more slowly than Fetch: half of the
goals lie on the table top, the other half in v0's band in the air. A goal on the table
can be met by pushing or carrying the cube there, so a sparse reward meets successes
without a lift, as in Fetch (where the air half reaches 45 cm above the table).

{_PLACE_V1_START}

{_SUCCESS_CUBE}

{_OBJECT_OBS}

{_MODES}

{_GRASP_REWARDS}

Version history: v0 initial; v1 half of the goals on the table (Fetch's distribution).
"""
