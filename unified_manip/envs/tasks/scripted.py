"""What the families' scripted policies share.

A scripted policy maps an observation dict to an ``ee_delta`` action (dx, dy, dz,
gripper). It is memoryless, so it works from any state. A family registers it through
:func:`ee_delta_policy`, which builds the ``TaskSpec.scripted_policy`` factory.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

Policy = Callable[[dict[str, np.ndarray]], np.ndarray]


def toward(delta: np.ndarray, gain: float = 10.0) -> np.ndarray:
    """A move along ``delta`` with ``gain`` action units per metre, clipped to [-1, 1]."""
    return np.clip(np.asarray(delta) * gain, -1.0, 1.0)


def pick_and_place(
    to_obj: np.ndarray, to_goal: np.ndarray, closed_on_cube: bool, align: float, hover: float, near: float
) -> np.ndarray:
    """The top-down grasp the arm and Fetch share: carry the object to the goal once the
    fingers are closed on it; otherwise line up ``hover`` m above it (open) until within
    ``align`` m in xy, descend (open) until within ``near`` m, and close.

    Args:
        to_obj: Object - grip site, m.
        to_goal: Goal - object, m.
        closed_on_cube: The fingers are closed on the object (the family's test).
    """
    if closed_on_cube and np.linalg.norm(to_obj) < 0.02:
        return np.append(toward(to_goal), -1.0).astype(np.float32)
    if np.linalg.norm(to_obj[:2]) > align:  # line up above the object, then come down
        return np.append(toward(to_obj + np.array([0.0, 0.0, hover])), 1.0).astype(np.float32)
    if np.linalg.norm(to_obj) > near:
        return np.append(toward(to_obj), 1.0).astype(np.float32)
    return np.array([0.0, 0.0, 0.0, -1.0], dtype=np.float32)


class EEDeltaPolicy:
    """``TaskSpec.scripted_policy`` factory of a policy that emits ``ee_delta`` actions.

    Calling it with an action mode returns the policy (its actions cast to float32),
    or raises ``ValueError`` for any mode but ``ee_delta``.

    Args:
        family: The family's name as the error message shows it, e.g. ``"Arm4"``.
        policy: ``obs -> action``.
    """

    def __init__(self, family: str, policy: Policy) -> None:
        self.family, self.policy = family, policy

    def __call__(self, action_mode: str) -> Policy:
        if action_mode != "ee_delta":
            raise ValueError(
                f"the {self.family} scripted policies emit ee_delta actions; got action_mode={action_mode!r}"
            )
        policy = self.policy
        return lambda obs: np.asarray(policy(obs), dtype=np.float32)
