"""MuJoCo state checks the backends share."""

from __future__ import annotations

import mujoco

_W = mujoco.mjtWarning
#: The diverged-state warnings (bad qpos, qvel, qacc), consecutive in ``mjtWarning``.
_BAD_STATE = slice(int(_W.mjWARN_BADQPOS), int(_W.mjWARN_BADQACC) + 1)
assert _BAD_STATE.stop - _BAD_STATE.start == 3 and int(_W.mjWARN_BADQVEL) == _BAD_STATE.start + 1


def bad_state_warnings(data: mujoco.MjData) -> int:
    """How many times MuJoCo has found a diverged state (and reset it) so far."""
    return sum(data.warning.number[_BAD_STATE].tolist())  # a slice and a list: the fastest read
