"""The kitchen's camera for image observations (``camera=``)."""

from __future__ import annotations

from unified_manip.envs.cameras import CameraConfig
from unified_manip.envs.rendering import SceneOptions

#: The free camera ``render()`` draws from: gymnasium-robotics' ``DEFAULT_CAMERA_CONFIG``
#: of ``franka_env`` (copied, so that registering the IDs imports no simulator; a test
#: compares the two).
FREE_CAMERA = {"distance": 2.2, "azimuth": 70.0, "elevation": -35.0, "lookat": (-0.2, 0.5, 2.0)}

SCENE = SceneOptions(free_camera=FREE_CAMERA)

#: ``front``: the view ``render()`` draws (upstream's free camera).
CAMERAS: dict[str, CameraConfig] = {"front": CameraConfig(SCENE)}
