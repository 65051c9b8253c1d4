"""Camera observations: the ``rgb`` and ``depth`` image groups of an observation design.

A family declares its cameras once, as a mapping of names to :class:`CameraConfig`
(``TaskSpec.cameras``, the first being the default). ``observation=[..., "rgb"]`` then
adds an ``rgb`` key (uint8, H x W x 3) to the observation dict, and ``"depth"`` a
``depth`` key (float32 metres, H x W x 1), drawn from ``camera=`` at ``image_size=``.

Each camera names its :class:`RenderSettings`. Observation cameras default to
:data:`FAST`: on software rendering (EGL on llvmpipe) shadows, reflections, the skybox
and multisampling take most of a small frame (the arm at 84 px: 28 frames/s with
MuJoCo's defaults, 174 without shadows, reflections and skybox, 528 with multisampling
off too). ``env.render()`` for people keeps the full look (:mod:`.rendering`).
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np

from unified_manip.envs.rendering import SceneOptions, track
from unified_manip.extras import MissingExtra

#: The image groups an observation design may add beside its vector groups.
IMAGE_GROUPS: tuple[str, ...] = ("rgb", "depth")

#: ``camera_meshes``: the visual meshes observation cameras draw, ``"full"`` or
#: ``"decimated"`` (about 5% of the faces, :mod:`unified_manip.envs.mesh_lod`).
CAMERA_MESHES: tuple[str, ...] = ("full", "decimated")

#: ``image_size`` when none is given, pixels (square frames).
DEFAULT_IMAGE_SIZE = 84


def _choices(values: Sequence[str]) -> str:
    return ", ".join(repr(v) for v in values)


@dataclass(frozen=True)
class RenderSettings:
    """How much of MuJoCo's look a camera draws.

    Attributes:
        shadows: Draw shadows (``mjRND_SHADOW``).
        reflections: Draw reflective surfaces (``mjRND_REFLECTION``).
        skybox: Draw the skybox (``mjRND_SKYBOX``).
        multisamples: Multisampling of the offscreen buffer (MSAA samples, 0 for none),
            or ``None`` for the model's own (``visual/quality/offsamples``, 4 by default).
        shadow_size: Side of the shadow map in pixels, or ``None`` for the model's own
            (``visual/quality/shadowsize``, 4096 by default); read only with shadows on.
    """

    shadows: bool = False
    reflections: bool = False
    skybox: bool = False
    multisamples: int | None = 0
    shadow_size: int | None = 1024

    def __post_init__(self) -> None:
        for name in ("multisamples", "shadow_size"):
            value = getattr(self, name)
            if value is not None and (isinstance(value, bool) or not isinstance(value, int) or value < 0):
                raise ValueError(f"{name} must be an int >= 0 or None, got {value!r}")


#: Observation cameras' default: no shadows, reflections, skybox or multisampling.
FAST = RenderSettings()
#: MuJoCo's own look, as ``env.render()`` draws it.
FULL = RenderSettings(shadows=True, reflections=True, skybox=True, multisamples=None, shadow_size=None)


@dataclass(frozen=True)
class CameraConfig:
    """One camera a family offers for image observations.

    Attributes:
        scene: Which camera of the model (or the free camera's pose) and which geom groups.
        settings: Its render settings; :data:`FAST` by default.
    """

    scene: SceneOptions
    settings: RenderSettings = FAST


def validate_image_size(value: Any) -> None:
    """``ValueError`` unless ``value`` is a positive int (the side of square frames)."""
    if isinstance(value, bool) or not isinstance(value, int) or value <= 0:
        raise ValueError(f"image_size must be a positive int (pixels), got {value!r}")


def validate_camera_meshes(value: Any) -> None:
    """``ValueError`` unless ``value`` is one of :data:`CAMERA_MESHES`."""
    if value not in CAMERA_MESHES:
        raise ValueError(f"unknown camera_meshes {value!r}; expected one of {_choices(CAMERA_MESHES)}")


def split_images(observation: str | Sequence[str]) -> tuple[str | tuple[str, ...], tuple[str, ...]]:
    """An observation design's vector part (a preset or groups) and its image groups.

    Raises:
        ValueError: A list of image groups alone (the ``observation`` vector needs a group
            or a preset beside them).
    """
    if isinstance(observation, str):
        return observation, ()
    names = tuple(observation)
    images = tuple(n for n in names if n in IMAGE_GROUPS)
    rest = tuple(n for n in names if n not in IMAGE_GROUPS)
    if images and not rest:
        raise ValueError(
            f"observation {list(names)!r} has only image groups; add a preset (e.g. 'default') "
            "or vector groups (e.g. 'joint_pos') for the observation vector"
        )
    return rest, images


def resolve_camera(camera: str | None, cameras: Mapping[str, CameraConfig], task_id: str) -> str:
    """The camera's name: ``camera``, or the task's first when None.

    Raises:
        ValueError: An unknown camera, or a task without cameras (naming the valid ones).
    """
    if not cameras:
        raise ValueError(f"{task_id} has no cameras for image observations")
    if camera is None:
        return next(iter(cameras))
    if camera not in cameras:
        raise ValueError(f"unknown camera {camera!r} for {task_id}; expected one of {_choices(tuple(cameras))}")
    return camera


class RendererUnavailable(RuntimeError):
    """No OpenGL renderer could start for an image observation."""


class ImageSensor:
    """One env's camera: draws its ``rgb`` and ``depth`` images of ``(model, data)``.

    Built with MuJoCo's own ``mujoco.Renderer`` on first use (its GL context is made with
    the camera's multisampling and shadow map size; the model's values are restored
    after), dropped when pickled. With ``meshes="decimated"`` the GL context holds
    simplified meshes (:func:`~unified_manip.envs.mesh_lod.decimated_meshes`; the
    model's own are restored once it is made).

    Args:
        groups: The image groups to draw, a subset of :data:`IMAGE_GROUPS`.
        camera: The camera's config.
        size: Side of the square frames, pixels.
        meshes: One of :data:`CAMERA_MESHES`.
    """

    def __init__(self, groups: tuple[str, ...], camera: CameraConfig, size: int, meshes: str = "full") -> None:
        validate_camera_meshes(meshes)
        self.groups, self.camera, self.size, self.meshes = groups, camera, size, meshes
        self._renderer: Any = None
        self._option: Any = None
        self._view: Any = None

    def read(self, model, data) -> dict[str, np.ndarray]:
        """The images of the current state, by group name."""
        if self._renderer is None:
            self._build(model)
        import mujoco

        r = self._renderer
        mujoco.mjv_updateScene(model, data, self._option, None, self._view, mujoco.mjtCatBit.mjCAT_ALL, r.scene)
        self._apply_flags()
        out: dict[str, np.ndarray] = {}
        if "rgb" in self.groups:
            out["rgb"] = r.render()
        if "depth" in self.groups:
            r.enable_depth_rendering()
            out["depth"] = r.render()[:, :, None].astype(np.float32, copy=False)
            r.disable_depth_rendering()
        return out

    def _apply_flags(self) -> None:
        import mujoco

        s, flags = self.camera.settings, self._renderer.scene.flags
        flags[mujoco.mjtRndFlag.mjRND_SHADOW] = s.shadows
        flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = s.reflections
        flags[mujoco.mjtRndFlag.mjRND_SKYBOX] = s.skybox

    def _build(self, model) -> None:
        import mujoco

        s, scene = self.camera.settings, self.camera.scene
        vis = model.vis
        vis.global_.offwidth = max(vis.global_.offwidth, self.size)
        vis.global_.offheight = max(vis.global_.offheight, self.size)
        saved = (vis.quality.offsamples, vis.quality.shadowsize)
        if s.multisamples is not None:
            vis.quality.offsamples = s.multisamples
        if s.shadow_size is not None:
            vis.quality.shadowsize = s.shadow_size
        try:
            with self._meshes(model):  # the GL context uploads the meshes as it is made
                self._renderer = mujoco.Renderer(model, self.size, self.size, max_geom=scene.max_geom)
        except MissingExtra:
            raise
        except Exception as err:  # EGL / OSMesa / GLFW each fail in their own way
            raise RendererUnavailable(
                f"image observations need an OpenGL renderer, and none could start "
                f"({type(err).__name__}: {str(err).strip().splitlines()[0] if str(err).strip() else 'no detail'}); "
                "set MUJOCO_GL=egl (or osmesa) on a machine that has it"
            ) from None
        finally:
            vis.quality.offsamples, vis.quality.shadowsize = saved
        track(self)
        option = mujoco.MjvOption()
        for group in scene.hidden_geom_groups:
            option.geomgroup[group] = 0
        self._option = option
        view = mujoco.MjvCamera()
        if scene.camera is not None:
            view.type = mujoco.mjtCamera.mjCAMERA_FIXED
            view.fixedcamid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_CAMERA, scene.camera)
            if view.fixedcamid < 0:
                raise ValueError(f"the model has no camera {scene.camera!r}")
        else:
            mujoco.mjv_defaultFreeCamera(model, view)
            for key, value in (scene.free_camera or {}).items():
                if key == "lookat":
                    view.lookat[:] = value
                else:
                    setattr(view, key, value)
        self._view = view

    def _meshes(self, model) -> Any:
        if self.meshes == "decimated":
            from unified_manip.envs.mesh_lod import decimated_meshes

            return decimated_meshes(model)
        return contextlib.nullcontext(model)

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
        track(self, False)

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_renderer": None, "_option": None, "_view": None}


def image_sensor(config: Any, cameras: Mapping[str, CameraConfig], task_id: str) -> ImageSensor | None:
    """The :class:`ImageSensor` of an :class:`~unified_manip.envs.config.EnvConfig`'s
    observation design, or None when it has no image group."""
    _, images = split_images(config.observation)
    if not images:
        return None
    name = resolve_camera(config.camera, cameras, task_id)
    if config.camera_meshes == "decimated":
        from unified_manip.envs.mesh_lod import require_simplifier

        require_simplifier()  # at gym.make, not at the first frame
    return ImageSensor(images, cameras[name], config.image_size, config.camera_meshes)


def observation_box(key: str, value: np.ndarray) -> Any:
    """The ``Box`` of one observation-dict entry: uint8 images in 0..255, depth in metres
    (>= 0), every other entry float32 without bounds."""
    from gymnasium import spaces

    if value.dtype == np.uint8:
        return spaces.Box(0, 255, shape=value.shape, dtype=np.uint8)
    low = 0.0 if key == "depth" else -np.inf
    return spaces.Box(low, np.inf, shape=value.shape, dtype=np.float32)
