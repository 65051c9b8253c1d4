"""The 4-DOF arm's cameras for image observations (``camera=``), the default first."""

from __future__ import annotations

from unified_manip.envs.cameras import CameraConfig
from unified_manip.envs.rendering import SceneOptions

#: ``front``: the model's ``front`` camera, the view ``render()`` draws; ``wrist``: on the
#: gripper, behind the palm, looking along the fingers (a camera adds no physics: the
#: golden hashes are unchanged).
CAMERAS: dict[str, CameraConfig] = {
    "front": CameraConfig(SceneOptions(camera="front")),
    "wrist": CameraConfig(SceneOptions(camera="wrist")),
}
