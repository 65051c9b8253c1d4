"""The Shadow Hand's camera for image observations (``camera=``)."""

from __future__ import annotations

from unified_manip.envs.cameras import CameraConfig
from unified_manip.envs.rendering import SceneOptions

#: The free camera ``render()`` draws from: gymnasium-robotics' ``DEFAULT_CAMERA_CONFIG``
#: of ``hand_env`` (copied, so that registering the IDs imports no simulator; a test
#: compares the two).
FREE_CAMERA = {"distance": 0.5, "azimuth": 55.0, "elevation": -25.0, "lookat": (1.0, 0.96, 0.14)}

#: ``front``: the view ``render()`` draws (the model has no camera of its own).
CAMERAS: dict[str, CameraConfig] = {"front": CameraConfig(SceneOptions(free_camera=FREE_CAMERA))}
