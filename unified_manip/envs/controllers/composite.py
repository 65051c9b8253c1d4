"""Several rigs under one action: the mode's controller once per rig, their actions
side by side. A two-arm task's ``ee_delta`` action is ``2 × (3 + 1)``: each arm's
``(dx, dy, dz, gripper)`` in turn; its joint modes are each arm's joints and gripper.

:func:`build_controller` builds the mode's controller on every rig of a backend; with
one rig it is that rig's controller itself, so one-arm tasks are driven as before.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np


def part_layout(dims: Sequence[int], grippers: Sequence[bool]) -> str:
    """The layout of an action made of parts, e.g. ``"2 × (3 + 1)"`` (two arms, three arm
    entries and a gripper each), or ``"(7 + 1) + (6 + 1)"`` when the parts differ."""
    parts = [f"({d - int(g)} + 1)" if g else f"({d})" for d, g in zip(dims, grippers)]
    if len(set(parts)) == 1:
        return f"{len(parts)} × {parts[0]}"
    return " + ".join(parts)


def merge_diagnostics(parts: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """One step's diagnostics of several controllers as one arm's keys: the worst arm's
    value (a bool: whether any arm's is true; a number: the largest, e.g. ``ik_residual``)."""
    merged: dict[str, Any] = {}
    for key in parts[0]:
        values = [p[key] for p in parts]
        merged[key] = any(values) if isinstance(values[0], bool) else max(values)
    return merged


class PerRig:
    """The controllers of one mode on several rigs, under one action.

    Attributes:
        parts: One controller per rig, in the action's order.
        action_dim: The sum of theirs.
        layout: The action's layout in words (:func:`part_layout`).
    """

    def __init__(self, parts: Sequence[Any], rigs: Sequence[Any]) -> None:
        self.parts = tuple(parts)
        dims = [p.action_dim for p in self.parts]
        ends = np.cumsum(dims)
        self._slices = [slice(int(e - d), int(e)) for d, e in zip(dims, ends)]
        self.action_dim = int(ends[-1])
        self.layout = part_layout(dims, [r.has_gripper for r in rigs])

    def reset(self) -> None:
        for part in self.parts:
            part.reset()

    def __call__(self, action: np.ndarray) -> dict[str, Any]:
        return merge_diagnostics([p(action[s]) for p, s in zip(self.parts, self._slices)])


def build_controller(config, rigs: Sequence[Any]):
    """``config``'s controller on each of ``rigs``: the one controller of a single rig, or
    a :class:`PerRig` of them."""
    parts = [config.build(rig) for rig in rigs]
    return parts[0] if len(parts) == 1 else PerRig(parts, rigs)
