"""Kept for old imports: the action modes live in :mod:`unified_manip.controllers`.

``ArmRig`` is :class:`~unified_manip.controllers.rig.MujocoRig` (it no longer takes
``gains``: a mode's scales are in its controller config).
"""

from .controllers.ik import IKJoints, MinkIK, SitePoseTask
from .controllers.rig import MujocoRig
from .physics import bad_state_warnings

ArmRig = MujocoRig

__all__ = ["ArmRig", "IKJoints", "MinkIK", "SitePoseTask", "bad_state_warnings"]
