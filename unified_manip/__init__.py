"""unified_manip: manipulation tasks from several simulators behind one goal-conditioned
Gymnasium interface.

``import unified_manip`` registers every task in the ``UnifiedManip`` namespace::

    import gymnasium as gym
    import unified_manip  # noqa: F401

    env = gym.make("UnifiedManip/Arm4PickAndPlace-v0", action_mode="ee_delta", reward_type="dense")
"""

import os as _os

# Headless machines (no display) render offscreen with EGL unless told otherwise. This
# must happen before mujoco is first imported, which reads MUJOCO_GL at import time.
if "MUJOCO_GL" not in _os.environ and not (_os.environ.get("DISPLAY") or _os.environ.get("WAYLAND_DISPLAY")):
    _os.environ["MUJOCO_GL"] = "egl"

from importlib.metadata import PackageNotFoundError, version  # noqa: E402

from unified_manip.envs._quiet import silence_import_notices  # noqa: E402

silence_import_notices()

from unified_manip.envs.config import ACTION_MODES, EnvConfig  # noqa: E402
from unified_manip.envs.registry import NAMESPACE, TASKS, TaskSpec, get_task, register_task  # noqa: E402
from unified_manip.envs.rewards import REWARD_TYPES  # noqa: E402

try:
    __version__ = version("unified_manip")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0+unknown"

from unified_manip.envs import tasks as _tasks  # noqa: E402,F401  (registers every task)

__all__ = [
    "ACTION_MODES",
    "REWARD_TYPES",
    "EnvConfig",
    "NAMESPACE",
    "TASKS",
    "TaskSpec",
    "get_task",
    "register_task",
    "__version__",
]
