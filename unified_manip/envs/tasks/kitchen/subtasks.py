"""The kitchen's subtasks and the goal distance that judges them (numpy only).

gymnasium-robotics' ``KitchenEnv`` reads each subtask's joints from ``qpos`` and calls a
subtask complete when the Euclidean norm of its joints' error to the subtask's target is
below ``BONUS_THRESH`` (0.3, in the joints' own units: rad, m, and the kettle's
quaternion). Here a task's goal is its subtasks' joints one after another, in the order
of the task's subtask tuple: ``achieved_goal`` their values now, ``desired_goal`` their
targets. :class:`SubtaskDistance` is the largest of the subtasks' errors, so that with the
threshold 0.3 the goal distance is below the threshold exactly when every subtask is
within upstream's threshold of its target at once (the last bit of rounding at the
threshold aside).

The tables are copied from gymnasium-robotics 1.4.2 (``kitchen_env.OBS_ELEMENT_INDICES``,
``OBS_ELEMENT_GOALS``, ``BONUS_THRESH``), so that registering the IDs imports no
simulator; a test compares them with upstream's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Upstream's completion threshold of every subtask (the norm of its joints' error).
BONUS_THRESH = 0.3

#: Each subtask's joints, as ``qpos`` addresses (upstream's ``OBS_ELEMENT_INDICES``).
QPOS_INDICES: dict[str, tuple[int, ...]] = {
    "bottom burner": (11, 12),
    "top burner": (15, 16),
    "light switch": (17, 18),
    "slide cabinet": (19,),
    "hinge cabinet": (20, 21),
    "microwave": (22,),
    "kettle": (23, 24, 25, 26, 27, 28, 29),
}

#: Each subtask's target (upstream's ``OBS_ELEMENT_GOALS``): rad and m of its joints; the
#: kettle's free joint as position (m) and quaternion (w, x, y, z).
TARGETS: dict[str, tuple[float, ...]] = {
    "bottom burner": (-0.88, -0.01),
    "top burner": (-0.92, -0.01),
    "light switch": (-0.69, -0.05),
    "slide cabinet": (0.37,),
    "hinge cabinet": (0.0, 1.45),
    "microwave": (-0.75,),
    "kettle": (-0.23, 0.75, 1.62, 0.99, 0.0, 0.0, -0.06),
}

#: What each subtask asks, and its joints' units (for the task pages).
DESCRIPTIONS: dict[str, tuple[str, str]] = {
    "bottom burner": ("turn the bottom burner's knob: knob angle, burner slide", "rad, m"),
    "top burner": ("turn the top burner's knob: knob angle, burner slide", "rad, m"),
    "light switch": ("turn the light on: switch angle, light slide", "rad, m"),
    "slide cabinet": ("slide the cabinet's door open: slide", "m"),
    "hinge cabinet": ("swing the left hinge cabinet open: both doors' hinges", "rad"),
    "microwave": ("swing the microwave's door open: hinge", "rad"),
    "kettle": ("move the kettle to the top left burner: position, quaternion (w, x, y, z)", "m, -"),
}

#: D4RL's kitchen tasks (and Minari's kitchen datasets): the microwave, the kettle, the
#: light and the slide cabinet. gymnasium-robotics' own default is all seven.
D4RL_SUBTASKS: tuple[str, ...] = ("microwave", "kettle", "light switch", "slide cabinet")


def check_subtasks(subtasks: tuple[str, ...]) -> None:
    """``ValueError`` naming the valid choices unless ``subtasks`` is a non-empty tuple of
    distinct subtask names."""
    unknown = [s for s in subtasks if s not in QPOS_INDICES]
    if not subtasks or unknown or len(set(subtasks)) != len(subtasks):
        raise ValueError(
            f"kitchen subtasks must be distinct names from {', '.join(map(repr, QPOS_INDICES))}; got {subtasks!r}"
        )


@dataclass(frozen=True)
class SubtaskDistance:
    """The goal distance of a kitchen task: the largest of its subtasks' errors.

    ``d = max_i |achieved_i - desired_i|`` over the task's subtasks ``i``, each the
    Euclidean norm over that subtask's joints (upstream's per-subtask distance), for goals
    of shape ``(..., goal_dim)``.

    Attributes:
        subtasks: The subtasks, in the goal's order.
    """

    subtasks: tuple[str, ...] = D4RL_SUBTASKS

    def __post_init__(self) -> None:
        check_subtasks(self.subtasks)

    @property
    def slices(self) -> tuple[slice, ...]:
        """Each subtask's slice of the goal vector."""
        out, start = [], 0
        for name in self.subtasks:
            n = len(QPOS_INDICES[name])
            out.append(slice(start, start + n))
            start += n
        return tuple(out)

    @property
    def goal_dim(self) -> int:
        return sum(len(QPOS_INDICES[name]) for name in self.subtasks)

    @property
    def qpos_indices(self) -> np.ndarray:
        """The ``qpos`` addresses ``achieved_goal`` reads, in order."""
        return np.array([i for name in self.subtasks for i in QPOS_INDICES[name]])

    @property
    def target(self) -> np.ndarray:
        """``desired_goal``: the subtasks' targets, in order."""
        return np.array([v for name in self.subtasks for v in TARGETS[name]])

    def errors(self, achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
        """Each subtask's error, shape ``(..., n_subtasks)``."""
        diff = np.asarray(achieved_goal) - np.asarray(desired_goal)
        return np.stack([np.sqrt((diff[..., s] * diff[..., s]).sum(axis=-1)) for s in self.slices], axis=-1)

    def __call__(self, achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
        return self.errors(achieved_goal, desired_goal).max(axis=-1)
