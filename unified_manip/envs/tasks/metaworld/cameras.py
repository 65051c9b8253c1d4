"""The Meta-World tasks' cameras for image observations (``camera=``), the default first:
a free camera over the table, then every camera of Meta-World's Sawyer scene by its own
name (a test compares them with the model's)."""

from __future__ import annotations

from unified_manip.envs.cameras import CameraConfig
from unified_manip.envs.rendering import SceneOptions

#: The free camera ``render()`` draws from: the arm, the table and the targets from the
#: front left, upright (Meta-World's own corner cameras render its scene upside down or
#: turned, as Meta-World returns their images).
FREE_CAMERA = {"distance": 1.7, "azimuth": 140.0, "elevation": -28.0, "lookat": (0.0, 0.7, 0.15)}

SCENE = SceneOptions(free_camera=FREE_CAMERA)

#: The model's cameras: four corner views, the view from above, and two at the gripper.
NAMES = ("corner", "corner2", "corner3", "corner4", "topview", "behindGripper", "gripperPOV")

#: ``front`` (what ``render()`` draws), then the model's cameras.
CAMERAS: dict[str, CameraConfig] = {
    "front": CameraConfig(SCENE),
    **{name: CameraConfig(SceneOptions(camera=name)) for name in NAMES},
}
