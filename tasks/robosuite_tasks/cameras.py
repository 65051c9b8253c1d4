"""robosuite's cameras for image observations (``camera=``), the default first: the
cameras robosuite's arena and robot models define, without the collision geoms (group 0;
robosuite's own renderer hides them too)."""

from __future__ import annotations

from unified_manip.envs.cameras import CameraConfig
from unified_manip.envs.rendering import SceneOptions

#: ``agentview`` (robosuite's default camera observation) first.
CAMERA_NAMES: tuple[str, ...] = (
    "agentview",
    "frontview",
    "birdview",
    "sideview",
    "robot0_robotview",
    "robot0_eye_in_hand",
)

CAMERAS: dict[str, CameraConfig] = {
    name: CameraConfig(SceneOptions(camera=name, hidden_geom_groups=(0,))) for name in CAMERA_NAMES
}
