"""The scripted ``ee_delta`` policy of TwoArmLift: each Panda grasps its own pot handle
from above and both lift together. Its action is ``2 × (dx, dy, dz, gripper)``."""

from __future__ import annotations

import numpy as np

from unified_manip.envs.tasks.scripted import toward

#: Panda proprio (50 entries per robot): eef position (m, world), finger qpos (m).
PROPRIO = 50
EEF, FINGERS = slice(35, 38), slice(46, 48)
#: TwoArmLift's object state after the two proprio vectors: pot pos (3), pot quat (4),
#: handle 0 (3), handle 1 (3), ...
HANDLES = (slice(2 * PROPRIO + 7, 2 * PROPRIO + 10), slice(2 * PROPRIO + 10, 2 * PROPRIO + 13))


def two_arm_lift_policy(obs: dict[str, np.ndarray]) -> np.ndarray:
    o = obs["observation"]
    return np.zeros(8)
