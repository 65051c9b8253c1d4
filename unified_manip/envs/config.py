"""The keyword arguments every ``UnifiedManip`` ID accepts, as one frozen dataclass.

``EnvConfig`` validates itself on construction, so a bad ``action_mode`` or
``reward_type`` fails with a message that lists the valid choices before any
simulator is built.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Mapping

from unified_manip.envs.cameras import (
    DEFAULT_IMAGE_SIZE,
    split_images,
    validate_camera_meshes,
    validate_image_size,
)
from unified_manip.envs.observations import validate_count, validate_noise
from unified_manip.envs.randomization.presets import preset_terms
from unified_manip.envs.randomization.terms import RandomizationTerm, term_from
from unified_manip.envs.rewards import RewardConfig, RewardSpec, validate_reward_type

if TYPE_CHECKING:
    from unified_manip.envs.termsets import TermSet

#: Every action mode the interface knows, in the order ``unified-manip list`` shows them.
#: A family declares which it supports, each with its controller config
#: (:mod:`unified_manip.envs.controllers`).
ACTION_MODES: tuple[str, ...] = (
    "joint_torque",
    "joint_position",
    "joint_delta",
    "joint_target_delta",
    "joint_velocity",
    "ee_delta",
    "ee_target_delta",
    "native",
)

RENDER_MODES: tuple[str, ...] = ("rgb_array", "human")


def _choices(values: tuple[str, ...]) -> str:
    return ", ".join(repr(v) for v in values)


def validate_action_mode(action_mode: str) -> None:
    """``ValueError`` naming the valid choices unless ``action_mode`` is one of :data:`ACTION_MODES`."""
    if action_mode not in ACTION_MODES:
        raise ValueError(f"unknown action_mode {action_mode!r}; expected one of {_choices(ACTION_MODES)}")


@dataclass(frozen=True)
class EnvConfig:
    """Options shared by every task family.

    Attributes:
        action_mode: How the ``Box(-1, 1)`` action becomes control; one of
            :data:`ACTION_MODES` that the task supports.
        reward_type: ``"sparse"`` (0 on success, -1 otherwise), ``"dense"`` (the task's
            shaped terms and a success bonus) or ``"dense_penalized"`` (dense plus the
            task's penalties).
        terminate_on_success: End the episode with ``terminated=True`` on success.
        terminate_on: The task's other termination conditions to switch on, by name
            (its term set's ``terminations``, e.g. ``("dropped",)`` on the gripper tasks
            with an object); none by default.
        render_mode: ``None``, ``"rgb_array"`` or ``"human"``.
        render_width: Width in pixels of ``rgb_array`` frames.
        render_height: Height in pixels of ``rgb_array`` frames.
        reward_config: The reward designs' numbers (:class:`~unified_manip.envs.rewards.RewardConfig`),
            or ``None`` for the defaults.
        reward_spec: A reward design of your own
            (:class:`~unified_manip.envs.rewards.RewardSpec`) used instead of ``reward_type``'s,
            e.g. a candidate checked by ``unified_manip.experiments.sanity``; ``None`` normally.
        options: Family-specific keyword arguments (e.g. ``robot`` for robosuite),
            validated by the family itself.
        controller_options: Parameters of the action mode's controller config that
            replace the family's (e.g. ``{"band": 0.75}`` for ``joint_position``); see
            :meth:`mode_config`.
        observation: The ``observation`` vector's design: a preset (``"default"``,
            ``"minimal"``, ``"relative"``, ``"full"``) or a list of group names, concatenated
            in order (:mod:`unified_manip.envs.observations`).
        observation_distractors: How many task-irrelevant features (a seeded random walk)
            to append to ``observation``.
        observation_noise: Std of the Gaussian noise added to ``observation``: one for
            every entry, or a mapping of group names to stds (in the groups' units).
        observation_delay: ``observation`` is the one of this many steps earlier; the
            first steps of an episode repeat the reset observation. Goals stay exact.
        camera: The camera of the ``rgb`` and ``depth`` image groups: one the task names
            (``TaskSpec.cameras``), or ``None`` for its first
            (:mod:`unified_manip.envs.cameras`).
        image_size: Side of the square ``rgb`` and ``depth`` images, pixels.
        camera_meshes: The visual meshes the ``rgb`` and ``depth`` camera draws:
            ``"full"`` (the default), or ``"decimated"``, about 5% of each mesh's faces
            (Lift at 84 px on software rendering: a frame about 3.5x cheaper, mean pixel
            change 1.8/255; needs the ``fast-camera`` extra;
            :mod:`unified_manip.envs.mesh_lod`). ``render()`` always draws the full meshes.
        randomization: Domain randomisation: a preset (``"none"``, the nominal task;
            ``"dynamics"``, ``"objects"``, ``"visual"``, ``"all"``, joined by ``+``, each
            optionally ``:extreme``) or a list of
            :class:`~unified_manip.envs.randomization.RandomizationTerm` s (or mappings of
            their fields) (:mod:`unified_manip.envs.randomization`).
    """

    action_mode: str = "native"
    reward_type: str = "sparse"
    terminate_on_success: bool = False
    terminate_on: tuple[str, ...] = ()
    render_mode: str | None = None
    render_width: int = 480
    render_height: int = 480
    reward_config: Any = None
    reward_spec: Any = None
    options: Mapping[str, Any] = field(default_factory=dict)
    controller_options: Mapping[str, Any] = field(default_factory=dict)
    observation: str | tuple[str, ...] = "default"
    observation_distractors: int = 0
    observation_noise: float | Mapping[str, float] = 0.0
    observation_delay: int = 0
    camera: str | None = None
    image_size: int = DEFAULT_IMAGE_SIZE
    camera_meshes: str = "full"
    randomization: str | tuple[RandomizationTerm, ...] = "none"

    def __post_init__(self) -> None:
        validate_action_mode(self.action_mode)
        validate_reward_type(self.reward_type)
        for name, cls in (("reward_config", RewardConfig), ("reward_spec", RewardSpec)):
            value = getattr(self, name)
            if value is not None and not isinstance(value, cls):
                raise TypeError(f"{name} must be a {cls.__name__} or None, got {type(value).__name__}")
        if self.render_mode is not None and self.render_mode not in RENDER_MODES:
            raise ValueError(
                f"unknown render_mode {self.render_mode!r}; expected None or one of {_choices(RENDER_MODES)}"
            )
        if not isinstance(self.terminate_on_success, bool):
            raise TypeError(f"terminate_on_success must be a bool, got {type(self.terminate_on_success).__name__}")
        if isinstance(self.terminate_on, str) or not all(isinstance(n, str) for n in self.terminate_on):
            raise TypeError(f"terminate_on must be a sequence of termination names, got {self.terminate_on!r}")
        object.__setattr__(self, "terminate_on", tuple(self.terminate_on))
        if self.controller_options is None:
            object.__setattr__(self, "controller_options", {})
        if not isinstance(self.controller_options, Mapping) or not all(
            isinstance(k, str) for k in self.controller_options
        ):
            raise TypeError(
                f"controller_options must be a mapping of parameter names to values, got {self.controller_options!r}"
            )
        object.__setattr__(self, "controller_options", dict(self.controller_options))  # the caller's stays theirs
        for name in ("render_width", "render_height"):
            value = getattr(self, name)
            if not isinstance(value, int) or value <= 0:
                raise ValueError(f"{name} must be a positive int, got {value!r}")
        if isinstance(self.observation, (list, tuple)):
            object.__setattr__(self, "observation", tuple(self.observation))
        elif not isinstance(self.observation, str):
            raise TypeError(f"observation must be a preset name or a list of group names, got {self.observation!r}")
        split_images(self.observation)
        validate_image_size(self.image_size)
        validate_camera_meshes(self.camera_meshes)
        if self.camera is not None and not isinstance(self.camera, str):
            raise TypeError(f"camera must be a camera's name or None, got {self.camera!r}")
        validate_count("observation_distractors", self.observation_distractors)
        validate_count("observation_delay", self.observation_delay)
        validate_noise(self.observation_noise)
        if isinstance(self.observation_noise, Mapping):
            object.__setattr__(self, "observation_noise", dict(self.observation_noise))
        if isinstance(self.randomization, str):
            preset_terms(self.randomization)
        elif isinstance(self.randomization, (list, tuple)):
            object.__setattr__(self, "randomization", tuple(term_from(t) for t in self.randomization))
        else:
            raise TypeError(f"randomization must be a preset name or a list of terms, got {self.randomization!r}")

    def reward_design(self, terms: TermSet) -> RewardSpec:
        """The reward design an env with this config uses: :attr:`reward_spec` if given,
        else :attr:`reward_type`'s from the task's term set with :attr:`reward_config`."""
        if self.reward_spec is not None:
            return self.reward_spec
        return terms.design(self.reward_type, self.reward_config)

    def require_supported(self, task_id: str, supported: tuple[str, ...]) -> None:
        """Raise ``ValueError`` if the task does not support the chosen action mode."""
        if self.action_mode not in supported:
            raise ValueError(
                f"action_mode {self.action_mode!r} is not supported by {task_id}; expected one of {_choices(supported)}"
            )

    def mode_config(self, controllers: Mapping[str, Any]):
        """The action mode's controller config from a family's ``{mode: config}``, with
        :attr:`controller_options` in place of its parameters; ``ValueError`` naming the
        mode's parameters for an unknown one, and the config's own check for a bad value."""
        config = controllers[self.action_mode]
        if not self.controller_options:
            return config
        names = tuple(config.parameters())
        if not names:
            raise ValueError(
                f"action_mode {self.action_mode!r} here ({type(config).__name__}) has no parameters; "
                f"expected no controller_options, got {dict(self.controller_options)!r}"
            )
        unknown = [k for k in self.controller_options if k not in names]
        if unknown:
            hint = (
                f" (YAML reads {unknown[0]!r} as one name: write a space after the colon)"
                if ":" in str(unknown[0])
                else ""
            )
            raise ValueError(
                f"unknown controller option {unknown[0]!r} for action_mode {self.action_mode!r} "
                f"({type(config).__name__}); expected one of {_choices(names)}{hint}"
            )
        value = dict(self.controller_options)
        for k, v in value.items():  # YAML and JSON give lists; the frozen configs hold tuples
            if isinstance(v, list):
                value[k] = tuple(v)
        return replace(config, **value)
