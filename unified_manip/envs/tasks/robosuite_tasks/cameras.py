"""robosuite's cameras for image observations (``camera=``), the default first: the
cameras robosuite's arena and robot models define, without the collision geoms (group 0;
robosuite's own renderer hides them too), then each again drawing the collision geoms
alone (``agentview_collision``, ...), for speed."""

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
#: Each robot's own cameras: the two-arm tasks have ``robot1_robotview`` and
#: ``robot1_eye_in_hand`` too.
ROBOT_CAMERAS: tuple[str, ...] = ("robotview", "eye_in_hand")

#: Each camera also as ``<name>_collision``: the same view drawing the collision geoms
#: (group 0, in robosuite's debug colours) instead of the visual meshes. The Panda's and
#: the arena's visual meshes have about 168k faces against 15k, and software rendering
#: draws every one: Lift's agentview at 84 px took 53 ms a frame with the meshes and 2.2 ms
#: without (one core, beside two training runs), where a Lift step takes about 11 ms.
COLLISION_SUFFIX = "_collision"


def cameras_of(robots: int) -> dict[str, CameraConfig]:
    """The cameras of a scene of ``robots`` robots: :data:`CAMERA_NAMES`, the later robots'
    own, then each again as ``<name>_collision``."""
    names = CAMERA_NAMES + tuple(f"robot{i}_{c}" for i in range(1, robots) for c in ROBOT_CAMERAS)
    visual = {name: CameraConfig(SceneOptions(camera=name, hidden_geom_groups=(0,))) for name in names}
    collision = {
        name + COLLISION_SUFFIX: CameraConfig(SceneOptions(camera=name, hidden_geom_groups=(1,))) for name in names
    }
    return visual | collision


CAMERAS: dict[str, CameraConfig] = cameras_of(1)
