"""Reset distributions of the 4-DOF arm's tasks (world frame, metres)."""

from __future__ import annotations

import numpy as np

from unified_manip.envs.tasks.arm4.scene import CUBE_REST_Z

OBJECT_XY_LOW, OBJECT_XY_HIGH = np.array([0.40, -0.10]), np.array([0.60, 0.10])
REACH_GOAL_LOW, REACH_GOAL_HIGH = np.array([0.30, -0.25, 0.46]), np.array([0.60, 0.25, 0.65])
PUSH_GOAL_XY_LOW, PUSH_GOAL_XY_HIGH = np.array([0.35, -0.15]), np.array([0.65, 0.15])
PLACE_GOAL_LOW, PLACE_GOAL_HIGH = np.array([0.30, 0.10, 0.50]), np.array([0.50, 0.30, 0.60])
#: Push goals are resampled until at least this far from the cube, m (not solved at reset).
PUSH_MIN_DISTANCE = 0.1


def sample_object_xy(rng: np.random.Generator) -> np.ndarray:
    """Where the cube rests at reset."""
    return rng.uniform(OBJECT_XY_LOW, OBJECT_XY_HIGH)


def sample_goal(
    scene: str,
    rng: np.random.Generator,
    object_xy: np.ndarray | None,
    min_distance: float = PUSH_MIN_DISTANCE,
    table_fraction: float = 0.0,
) -> np.ndarray:
    """The goal of the ``"reach"``, ``"push"`` or ``"pick_and_place"`` scene, drawn after the cube.

    Push goals are redrawn until farther than ``min_distance`` from the cube (0: any goal in
    the box, so some episodes start solved, as Fetch's). A pick-and-place goal is lowered
    onto the table top (the cube's resting height) with probability ``table_fraction`` (0:
    always in the air, as the design; Fetch's is 0.5); the draw is skipped at 0, so v0's
    random stream is unchanged."""
    if scene == "reach":
        return rng.uniform(REACH_GOAL_LOW, REACH_GOAL_HIGH)
    if scene == "push":
        while True:
            gxy = rng.uniform(PUSH_GOAL_XY_LOW, PUSH_GOAL_XY_HIGH)
            if min_distance <= 0.0 or np.linalg.norm(gxy - object_xy) > min_distance:
                return np.array([gxy[0], gxy[1], CUBE_REST_Z])
    goal = rng.uniform(PLACE_GOAL_LOW, PLACE_GOAL_HIGH)
    if table_fraction > 0.0 and rng.uniform() < table_fraction:
        goal[2] = CUBE_REST_Z
    return goal
