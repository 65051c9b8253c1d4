"""Kept for old imports: the action modes live in :mod:`unified_manip.controllers`.

``ArmRig`` is :class:`~unified_manip.controllers.rig.MujocoRig` (it no longer takes
``gains``: a mode's scales are in its controller config).
"""

from .controllers.ik import IKJoints, MinkIK, SitePoseTask  # noqa: F401
from .controllers.rig import MujocoRig
from .physics import bad_state_warnings  # noqa: F401

ArmRig = MujocoRig
