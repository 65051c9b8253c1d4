"""Goal distances of the Meta-World tasks (numpy only).

Meta-World's ``evaluate_state`` calls a step a success when a distance between a point of
the scene (an object, a handle, the gripper) and the task's target ``_target_pos`` is
within a radius. The distance is not always the Euclidean one: some tasks compare one
axis (a button pressed along y), some weigh the axes (the ball's height counts twice), a
few compare a height from one side (a peg lifted above its target). Each metric here
reproduces one of those, batched over goals ``(..., 3)``, so that ``distance <
threshold`` is Meta-World's success (up to a distance exactly at the radius, which
Meta-World counts as success and the shared env does not).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Weighted:
    """``|(achieved - desired) * scale|``: Euclidean with per-axis weights; a weight of 0
    leaves the axis out (``(0, 1, 0)`` is Meta-World's ``|dy|``).

    Attributes:
        scale: The weight of x, y and z.
    """

    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)

    def __call__(self, achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
        diff = (np.asarray(achieved_goal) - np.asarray(desired_goal)) * np.asarray(self.scale)
        return np.sqrt((diff * diff).sum(axis=-1))

    def describe(self) -> str:
        terms = [f"{w:g} d{axis}" if w != 1.0 else f"d{axis}" for axis, w in zip("xyz", self.scale) if w != 0.0]
        return f"|{terms[0]}|" if len(terms) == 1 else "|(" + ", ".join(terms) + ")|"


#: The plain Euclidean distance and the one-axis ones.
EUCLIDEAN = Weighted()
ALONG_X, ALONG_Y, ALONG_Z = Weighted((1.0, 0.0, 0.0)), Weighted((0.0, 1.0, 0.0)), Weighted((0.0, 0.0, 1.0))
HORIZONTAL = Weighted((1.0, 1.0, 0.0))


@dataclass(frozen=True)
class Short:
    """``max(desired[axis] - achieved[axis], 0)``: how far the point falls short of the
    target along one axis (0 once it is past it).

    Attributes:
        axis: 0, 1 or 2 (x, y, z).
    """

    axis: int

    def __call__(self, achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
        a, b = np.asarray(achieved_goal), np.asarray(desired_goal)
        return np.maximum(b[..., self.axis] - a[..., self.axis], 0.0)

    def describe(self) -> str:
        axis = "xyz"[self.axis]
        return f"max({axis}_target - {axis}, 0)"


@dataclass(frozen=True)
class Hooked:
    """Meta-World's nut assembly: the nut's centre within ``radius`` of the peg's axis in
    xy and below the target's height. The distance is the horizontal one while the nut is
    below the target height, and at least ``radius`` plus the height above it otherwise,
    so ``distance < radius`` is exactly "aligned and hooked".

    Attributes:
        radius: The horizontal radius, m.
    """

    radius: float

    def __call__(self, achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
        a, b = np.asarray(achieved_goal), np.asarray(desired_goal)
        diff = a[..., :2] - b[..., :2]
        horizontal = np.sqrt((diff * diff).sum(axis=-1))
        above = a[..., 2] - b[..., 2]
        return np.where(above < 0.0, horizontal, np.maximum(horizontal, self.radius) + above)

    def describe(self) -> str:
        return f"|dxy| while below the target, else max(|dxy|, {self.radius:g}) + dz"
