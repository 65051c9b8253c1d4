"""The one renderer every family draws with, configured by per-family scene options.

Every backend renders ``(model, data)`` the same way: gymnasium's ``MujocoRenderer``
(``rgb_array`` headless, ``human`` in a window), built on first use because most envs
never render, and dropped when the env is pickled (a GL context cannot be). What differs
between families is only the scene: which camera looks at it and which geom groups are
drawn. That is a :class:`SceneOptions`.
"""

from __future__ import annotations

import atexit
import weakref
from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

#: MuJoCo's geom groups (``mjNGROUP``).
N_GEOM_GROUPS = 6


@dataclass(frozen=True)
class SceneOptions:
    """How a family's scene is drawn.

    Attributes:
        camera: A named camera of the model, or ``None`` for the free camera.
        free_camera: gymnasium's ``default_cam_config`` for the free camera
            (``distance``, ``azimuth``, ``elevation``, ``lookat``, ...).
        hidden_geom_groups: Geom groups not drawn, e.g. ``(0,)`` for robosuite, whose
            collision geoms are group 0 (robosuite's own renderer hides them).
        max_geom: Capacity of the scene, geoms.
    """

    camera: str | None = None
    free_camera: Mapping[str, Any] | None = None
    hidden_geom_groups: tuple[int, ...] = ()
    max_geom: int = 1000

    def __post_init__(self) -> None:
        bad = [g for g in self.hidden_geom_groups if not 0 <= g < N_GEOM_GROUPS]
        if bad:
            raise ValueError(f"hidden_geom_groups must be in 0..{N_GEOM_GROUPS - 1}, got {bad}")
        if self.camera is not None and self.free_camera is not None:
            raise ValueError("give camera (a named camera) or free_camera (the free camera's config), not both")


#: Renderers holding a GL context. An env that rendered and was never closed would free
#: its context during interpreter teardown, after MuJoCo's own exit handler has
#: terminated the EGL display (two ``Exception ignored ... EGLError`` tracebacks); they
#: are closed at exit instead, by a handler registered after MuJoCo's, so run before it.
_OPEN: weakref.WeakSet[Any] = weakref.WeakSet()
_AT_EXIT: list[bool] = []


def _close_open_renderers() -> None:
    for renderer in list(_OPEN):
        renderer.close()


def track(renderer: Any, add: bool = True) -> None:
    """Close ``renderer`` (anything with ``close()`` holding a GL context) at exit, before
    MuJoCo's own exit handler; ``add=False`` forgets it (it was closed)."""
    if not add:
        _OPEN.discard(renderer)
        return
    if not _AT_EXIT:
        atexit.register(_close_open_renderers)  # exit handlers run last-registered first
        _AT_EXIT.append(True)
    _OPEN.add(renderer)


class Renderer:
    """Renders ``(model, data)`` with gymnasium's ``MujocoRenderer``, built on first use.

    Args:
        mode: ``"rgb_array"`` or ``"human"``.
        width: Frame width in pixels.
        height: Frame height in pixels.
        scene: The family's :class:`SceneOptions`.
    """

    def __init__(self, mode: str | None, width: int, height: int, scene: SceneOptions = SceneOptions()) -> None:
        self.mode, self.width, self.height, self.scene = mode, width, height, scene
        self._renderer: Any = None
        self._viewer: Any = None

    def render(self, model, data) -> np.ndarray | None:
        """An RGB frame of shape ``(height, width, 3)`` (``rgb_array``), or ``None``
        after drawing in the window (``human``)."""
        if self._renderer is None:
            self._renderer, self._viewer = self._build(model, data)
            track(self)
        # Another renderer in this process (another env, a camera observation) may have
        # made its own GL context current since the last frame.
        self._viewer.make_context_current()
        return self._renderer.render(self.mode)

    def _build(self, model, data):
        from gymnasium.envs.mujoco.mujoco_rendering import MujocoRenderer

        scene = self.scene
        # The offscreen buffer must be at least as large as the frame.
        model.vis.global_.offwidth = max(model.vis.global_.offwidth, self.width)
        model.vis.global_.offheight = max(model.vis.global_.offheight, self.height)
        free = dict(scene.free_camera) if scene.free_camera is not None else None
        renderer = MujocoRenderer(
            model, data, free, width=self.width, height=self.height, max_geom=scene.max_geom, camera_name=scene.camera
        )
        viewer = renderer._get_viewer(self.mode)  # creates the GL context and the scene options
        for group in scene.hidden_geom_groups:
            viewer.vopt.geomgroup[group] = 0
        return renderer, viewer

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = self._viewer = None
        _OPEN.discard(self)

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_renderer": None, "_viewer": None}
