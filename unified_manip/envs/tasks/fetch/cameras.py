"""Fetch's cameras for image observations (``camera=``), the default first."""

from __future__ import annotations

from unified_manip.envs.cameras import CameraConfig
from unified_manip.envs.rendering import SceneOptions

#: The free camera ``render()`` draws from: gymnasium-robotics' ``DEFAULT_CAMERA_CONFIG``
#: of ``fetch_env`` (copied, so that registering the IDs imports no simulator; a test
#: compares the two).
FREE_CAMERA = {"distance": 2.5, "azimuth": 132.0, "elevation": -14.0, "lookat": (1.3, 0.75, 0.55)}

#: ``front``: the view ``render()`` draws; then the model's own cameras: the robot's head
#: and gripper cameras and the external camera.
CAMERAS: dict[str, CameraConfig] = {
    "front": CameraConfig(SceneOptions(free_camera=FREE_CAMERA)),
    "head_camera_rgb": CameraConfig(SceneOptions(camera="head_camera_rgb")),
    "gripper_camera_rgb": CameraConfig(SceneOptions(camera="gripper_camera_rgb")),
    "external_camera_0": CameraConfig(SceneOptions(camera="external_camera_0")),
}
