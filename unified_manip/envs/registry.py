"""The ID table: every task registers one :class:`TaskSpec` here.

A task module calls :func:`register_task` at import time. That adds the spec to
:data:`TASKS` and registers ``UnifiedManip/<name>-v<version>`` with Gymnasium, so
``gym.make`` and ``unified-manip list`` see it at once.
"""

from __future__ import annotations

import difflib
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, Mapping

import gymnasium as gym
import numpy as np

from unified_manip.envs.cameras import CameraConfig
from unified_manip.envs.config import ACTION_MODES, EnvConfig
from unified_manip.envs.controllers import ControllerConfig
from unified_manip.envs.mujoco_version import check_mujoco
from unified_manip.envs.randomization.entities import Entity
from unified_manip.envs.termsets import TermSet
from unified_manip.extras import EXTRAS, missing_modules, require

if TYPE_CHECKING:
    from unified_manip.envs.backend import Backend

NAMESPACE = "UnifiedManip"


def euclidean(achieved_goal: np.ndarray, desired_goal: np.ndarray) -> np.ndarray:
    """Goal distance along the last axis, in the goal's units."""
    diff = np.asarray(achieved_goal) - np.asarray(desired_goal)
    return np.sqrt((diff * diff).sum(axis=-1))


@dataclass(frozen=True)
class TaskSpec:
    """Everything the shared env and the CLI need to know about one task.

    Attributes:
        name: Short name, e.g. ``"Arm4Reach"``; the ID is ``UnifiedManip/<name>-v<version>``.
        family: The simulator family, e.g. ``"arm4"``.
        terms: The task's reward terms and the per-step quantities they read
            (:class:`~unified_manip.envs.termsets.TermSet`).
        make_backend: Builds the backend from a validated config and the action mode's
            resolved controller config (``EnvSetup.build_backend``).
        controllers: The action modes this task supports, each with its controller
            config, in the order ``unified-manip list`` shows them (``action_modes``).
        goal_dim: Length of ``achieved_goal`` and ``desired_goal``.
        max_episode_steps: The time limit ``gym.make`` applies.
        distance_threshold: Success when the goal distance is below this.
        doc: The task's documentation: what it is, what success means, the layout
            of observation and goal with units.
        goal_distance: Vectorised distance between goals, shape ``(..., g) -> (...)``.
        scripted_policy: Builds a scripted policy (a callable ``obs -> action``) for
            a given action mode, or ``None`` if the task has none.
        scripted_min_success: The ``ee_delta`` success rate the scripted policy must
            reach over ``scripted_episodes`` seeded episodes (asserted by the tests),
            or ``None`` if it is only reported.
        scripted_episodes: How many seeded episodes that success rate is measured
            over (lower it for slow simulators).
        version: The ``-vN`` suffix. Bump it on any behaviour change.
        render_fps: Frames per second of a rollout video.
        stability_steps: How many random-action steps the stability test plays in
            every action mode (CI time scales with it: lower it for slow simulators).
        upstream_id: A label of the env this task wraps (the Gymnasium ID, e.g.
            ``"FetchPush-v4"``, or ``"robosuite:Lift"``), so benchmarks can time the two
            side by side; ``None`` for tasks defined here.
        make_upstream: Builds that env for the benchmarks (anything with ``reset()``
            and ``step(action)``); ``None`` means ``gym.make(upstream_id)``.
        cameras: The cameras of image observations (``camera=``), by name, the default
            first (:mod:`unified_manip.envs.cameras`); the family declares them once.
        extra: The extra that installs the family's simulator (``"robosuite"``), or
            ``None`` when the base install has it. Without it, building the env raises
            :class:`unified_manip.extras.MissingExtra` naming the extra.
        entities: The named parts of the task's model that randomisation terms address
            (``object``, ``table``, ``robot``, ``light``, ``camera``), each an
            :class:`~unified_manip.envs.randomization.Entity`; the family declares them once.
    """

    name: str
    family: str
    terms: TermSet
    make_backend: Callable[[EnvConfig, ControllerConfig], "Backend"]
    controllers: Mapping[str, ControllerConfig]
    goal_dim: int
    max_episode_steps: int
    distance_threshold: float
    doc: str
    goal_distance: Callable[[np.ndarray, np.ndarray], np.ndarray] = euclidean
    scripted_policy: Callable[[str], Callable[[dict[str, np.ndarray]], np.ndarray]] | None = None
    scripted_min_success: float | None = None
    scripted_episodes: int = 100
    version: int = 0
    render_fps: int = 25
    stability_steps: int = 2_000
    upstream_id: str | None = None
    make_upstream: Callable[[], object] | None = None
    cameras: Mapping[str, CameraConfig] = field(default_factory=dict)
    entities: Mapping[str, Entity] = field(default_factory=dict)
    extra: str | None = None

    @property
    def scripted_mode(self) -> str | None:
        """The action mode the scripted policy emits: its ``action_mode`` where it declares
        one (Meta-World's: ``native``), else ``ee_delta``; ``None`` without a policy."""
        if self.scripted_policy is None:
            return None
        return getattr(self.scripted_policy, "action_mode", "ee_delta")

    @property
    def installed(self) -> bool:
        """Whether the family's simulator is installed (its extra, if it has one)."""
        return self.extra is None or not missing_modules(self.extra)

    def require_installed(self) -> None:
        """Raise :class:`unified_manip.extras.MissingExtra` (one line naming the extra and
        its install command) if the family's simulator is not installed, or
        :class:`~unified_manip.envs.mujoco_version.UnsupportedMuJoCo` (one line naming the
        supported range) if the installed MuJoCo is outside it."""
        if self.extra is not None:
            require(self.extra, what=self.id)
        check_mujoco()

    def build_upstream(self):
        """The wrapped upstream env, for side-by-side benchmarks."""
        self.require_installed()
        if self.make_upstream is not None:
            return self.make_upstream()
        if self.upstream_id is None:
            raise ValueError(f"{self.id} wraps no upstream env")
        return gym.make(self.upstream_id, disable_env_checker=True)

    def __post_init__(self) -> None:
        if not isinstance(self.terms, TermSet):
            raise TypeError(f"{self.name}: terms must be a TermSet, got {type(self.terms).__name__}")
        unknown = [m for m in self.controllers if m not in ACTION_MODES]
        if unknown:
            raise ValueError(f"{self.name}: unknown action modes {unknown}; expected from {ACTION_MODES}")
        bad = [m for m, c in self.controllers.items() if not isinstance(c, ControllerConfig)]
        if bad:
            raise TypeError(f"{self.name}: the controllers of {bad} are not ControllerConfig instances")
        bad = [name for name, c in self.cameras.items() if not isinstance(c, CameraConfig)]
        if bad:
            raise TypeError(f"{self.name}: the cameras {bad} are not CameraConfig instances")
        if self.extra is not None and self.extra not in EXTRAS:
            raise ValueError(f"{self.name}: unknown extra {self.extra!r}; expected one of {', '.join(EXTRAS)}")
        bad = [name for name, e in self.entities.items() if not isinstance(e, Entity)]
        if bad:
            raise TypeError(f"{self.name}: the entities {bad} are not Entity instances")
        if not isinstance(self.stability_steps, int) or self.stability_steps <= 0:
            raise ValueError(f"{self.name}: stability_steps must be a positive int, got {self.stability_steps!r}")

    @property
    def action_modes(self) -> tuple[str, ...]:
        """The supported action modes, in declaration order."""
        return tuple(self.controllers)

    @property
    def id(self) -> str:
        return f"{NAMESPACE}/{self.name}-v{self.version}"

    def check_choices(self, action_mode: str, reward_type: str) -> EnvConfig:
        """The :class:`EnvConfig` of ``action_mode`` and ``reward_type``, checked as
        ``gym.make`` checks them: ``ValueError`` with the env's own words for an unknown
        mode or reward type, or a mode this task does not support. ``train``, ``bench``
        and the CLI reuse these errors rather than checking again."""
        config = EnvConfig(action_mode=action_mode, reward_type=reward_type)
        config.require_supported(self.id, self.action_modes)
        return config


#: Every registered task, by ID, in registration order.
TASKS: dict[str, TaskSpec] = {}

#: One line per family plugin that failed to load (:mod:`unified_manip.envs.families`).
PLUGIN_FAILURES: list[str] = []


#: Gymnasium calls every version below an ID's highest "out of date". Here a higher version
#: is a variant beside the old one (Arm4Push-v1 beside v0), never
#: its replacement, so that notice is dropped for this namespace only.
_NOT_OUT_OF_DATE = rf".*The environment {NAMESPACE}/\S+ is out of date"


def register_task(spec: TaskSpec) -> TaskSpec:
    """Add ``spec`` to :data:`TASKS` and register its ID with Gymnasium."""
    if spec.id in TASKS:
        raise ValueError(f"{spec.id} is already registered")
    TASKS[spec.id] = spec
    gym.register(
        id=spec.id,
        entry_point="unified_manip.envs.env:UnifiedManipEnv",
        vector_entry_point="unified_manip.envs.vector:make_vector_env",
        kwargs={"task_id": spec.id},
        max_episode_steps=spec.max_episode_steps,
    )
    if spec.version > 0:
        warnings.filterwarnings("ignore", message=_NOT_OUT_OF_DATE, category=DeprecationWarning)
    return spec


def get_task(task_id: str) -> TaskSpec:
    """Look up a task by ID, with an error that names the closest IDs, or else lists the
    valid ones."""
    try:
        return TASKS[task_id]
    except KeyError:
        names = {tid.split("/", 1)[-1]: tid for tid in TASKS}  # the namespace would match everything
        close = [names[n] for n in difflib.get_close_matches(str(task_id).split("/", 1)[-1], names, n=3, cutoff=0.8)]
        if close:  # a misspelling: its matches, not every ID (hundreds)
            choices = f"; did you mean {' or '.join(close)}? (unified-manip list names all {len(TASKS)} IDs)"
        else:
            choices = f"; expected one of {', '.join(TASKS)}"
        failed = "".join(f"; {line}" for line in PLUGIN_FAILURES)
        raise ValueError(f"unknown task {task_id!r}{choices}{failed}") from None
