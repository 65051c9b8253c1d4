"""Meta-World's native actions played in the other action modes, live.

A native action moves Meta-World's mocap target by ``a[:3]`` times 1 cm (its
``action_scale``), clipped to the task's mocap box, and the hand, welded to the mocap,
follows it. :class:`NativeInMode` keeps that target itself, from the mocap's position at
the episode's start, and asks the env's own mode for the grip site at the target plus the
site's offset from the mocap at the start (:class:`~unified_manip.envs.controllers.translate.SiteTracker`:
the end-effector modes' action toward it, or the mink IK's joint targets for a joint
mode). The gripper entry changes sign (Meta-World's +1 closes, this interface's -1).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from unified_manip.envs.controllers.configs import EEDelta
from unified_manip.envs.controllers.translate import SiteTracker


class NativeInMode:
    """Maps Meta-World's native actions to the actions of ``backend``'s mode.

    Args:
        backend: A :class:`~.backend.MetaWorldBackend` in a mode of the shared controllers.
        ee: The task's ``ee_delta`` config (the IK settings of a joint mode).

    Raises:
        ValueError: the backend's mode is ``native`` (play the actions as they are).
    """

    def __init__(self, backend: Any, ee: EEDelta) -> None:
        self.backend = backend
        self.tracker = SiteTracker(backend, ee)
        up = backend.upstream
        self.scale, self.low, self.high = float(up.action_scale), up.mocap_low, up.mocap_high
        self.target = np.zeros(3)
        self.offset = np.zeros(3)

    def __call__(self, action: np.ndarray) -> np.ndarray:
        b = self.backend
        if b.upstream.curr_path_length == 0:  # the episode's first step: the mocap's start
            self.target = b.data.mocap_pos[0].copy()
            self.offset = b.rig.site_position() - self.target
        step = np.clip(np.asarray(action[:3], dtype=np.float64), -1.0, 1.0) * self.scale
        self.target = np.clip(self.target + step, self.low, self.high)
        return self.tracker(self.target + self.offset, -float(action[3]))
