"""MuJoCo state checks the backends share."""

from __future__ import annotations

import mujoco
import numpy as np

_BAD_STATE = np.array(
    [mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL, mujoco.mjtWarning.mjWARN_BADQACC], dtype=int
)


def bad_state_warnings(data: mujoco.MjData) -> int:
    """How many times MuJoCo has found a diverged state (and reset it) so far."""
    return int(data.warning.number[_BAD_STATE].sum())
