"""What a controller carries from one step to the next, read out and written back.

Most controllers compute each step's command from the action and the measured state
alone. The target modes also remember a target (``ee_target_delta``'s grip-site target,
``joint_target_delta``'s joint targets) and ``joint_position`` over a band its centre.
Each class names those attributes in ``memory``; :func:`remember` copies them out and
:func:`recall` writes them back, into the same controller or one of another env of the
same task and mode. With the simulator's data this is a
:class:`~unified_manip.envs.backend.Checkpoint`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: One dict per controller part (one per rig), attribute name to value.
Memory = tuple[dict[str, np.ndarray], ...]


def _parts(control: Any) -> tuple[Any, ...]:
    if control is None:
        return ()
    return tuple(getattr(control, "parts", (control,)))


def remember(control: Any) -> Memory:
    """Copies of what ``control`` (a controller, a :class:`~.composite.PerRig` of them,
    or ``None`` for a source's own controller) remembers between steps."""
    return tuple(
        {name: np.array(getattr(p, name), copy=True) for name in getattr(p, "memory", ())} for p in _parts(control)
    )


def recall(control: Any, memory: Memory) -> None:
    """Write ``memory`` (from :func:`remember` on a controller of the same mode) back."""
    parts = _parts(control)
    if len(parts) != len(memory):
        raise ValueError(f"a controller memory of {len(memory)} parts cannot be recalled by {len(parts)}")
    for part, values in zip(parts, memory):
        for name, value in values.items():
            setattr(part, name, value.copy())
