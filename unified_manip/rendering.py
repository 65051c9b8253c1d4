"""A MuJoCo renderer that is built on first use and never pickled.

Every MuJoCo-based backend renders the same way: gymnasium's ``MujocoRenderer`` (which
does ``rgb_array`` headless and ``human`` in a window), created lazily because most envs
never render, and dropped when the env is pickled (a GL context cannot be).
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np


class LazyRenderer:
    """Renders ``(model, data)`` with gymnasium's ``MujocoRenderer``, built on first use.

    Args:
        mode: ``"rgb_array"`` or ``"human"``.
        width: Frame width in pixels.
        height: Frame height in pixels.
        camera_name: A named camera of the model, or ``None`` for the free camera.
        camera_config: gymnasium's ``default_cam_config`` for the free camera.
    """

    def __init__(self, mode: str | None, width: int, height: int, camera_name: str | None = None,
                 camera_config: dict[str, Any] | None = None) -> None:
        self.mode, self.width, self.height = mode, width, height
        self.camera_name, self.camera_config = camera_name, camera_config
        self._renderer = None

    def render(self, model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray | None:
        if self._renderer is None:
            from gymnasium.envs.mujoco.mujoco_rendering import MujocoRenderer

            # The offscreen buffer must be at least as large as the frame.
            model.vis.global_.offwidth = max(model.vis.global_.offwidth, self.width)
            model.vis.global_.offheight = max(model.vis.global_.offheight, self.height)
            self._renderer = MujocoRenderer(model, data, self.camera_config, width=self.width,
                                            height=self.height, camera_name=self.camera_name)
        return self._renderer.render(self.mode)

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_renderer": None}
