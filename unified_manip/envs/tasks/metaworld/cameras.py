"""The Meta-World tasks' cameras for image observations (``camera=``), the default first:
every camera of Meta-World's Sawyer scene, by its own name (a test compares them with
the model's)."""

from __future__ import annotations

from unified_manip.envs.cameras import CameraConfig
from unified_manip.envs.rendering import SceneOptions

#: ``corner`` (what ``render()`` draws), the other three corner views, the view from
#: above, and the two gripper cameras.
NAMES = ("corner", "corner2", "corner3", "corner4", "topview", "behindGripper", "gripperPOV")

CAMERAS: dict[str, CameraConfig] = {name: CameraConfig(SceneOptions(camera=name)) for name in NAMES}
