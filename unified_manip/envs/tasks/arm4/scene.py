"""The 4-DOF arm's scene: geometry, timing and the observation layout (no simulator)."""

from __future__ import annotations

from pathlib import Path

ASSET = Path(__file__).resolve().parents[1] / "assets" / "arm4.xml"

#: Physics substeps of 2 ms per env step (50 Hz control).
SUBSTEPS = 10
TABLE_Z = 0.42
CUBE_HALF = 0.025
CUBE_REST_Z = TABLE_Z + CUBE_HALF
#: Closed fingers sit at 0; a cube held between them keeps them near this opening.
FINGER_ON_CUBE = 0.01
#: Finger opening at reset, m (fully open).
FINGER_OPEN = 0.04
#: Where the grip site starts, pointing down, m (world): about 15 cm above the table.
HOME_SITE = (0.45, 0.0, 0.58)

#: ``qpos`` layout: the four arm joints, the two fingers, then the cube's free joint.
QPOS_ARM, QPOS_FINGERS, QPOS_CUBE_POS = slice(0, 4), slice(4, 6), slice(6, 9)
#: ``qpos``/``qvel`` of the arm and fingers: the whole state of the reach scene.
ROBOT_Q = slice(0, 6)
NQ_REACH, NQ_OBJECT = 6, 13

#: Slices of the push / pick-and-place observation (see the task docs).
OBS_FINGERS, OBS_CUBE, OBS_GRIP = slice(4, 6), slice(6, 9), slice(25, 28)
OBS_CUBE_REL, OBS_GOAL_REL = slice(28, 31), slice(31, 34)

#: Both fingers touch the cube and the grip site is within this distance of its centre.
GRASP_RADIUS = 0.04
