"""What ``unified-manip train`` is asked to do (:class:`TrainRequest`), validated, and
the error every training or evaluation request fails with (:class:`TrainError`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from unified_manip.envs.design_names import design_label, observation_label
from unified_manip.envs.randomization.presets import randomization_label
from unified_manip.envs.registry import get_task
from unified_manip.training.algorithms import ALGOS
from unified_manip.training.devices import DEVICES


def run_name(
    task: str,
    action_mode: str,
    reward_type: str,
    algo: str,
    seed: int,
    observation: Any,
    randomization: Any = "none",
) -> str:
    """A run's name: ``<task>__<mode>__<reward>__<algo>[__obs-<design>][__rand-<preset>]__s<seed>``;
    the default observation design and ``none`` randomisation add nothing, so runs from
    before designs and randomisation keep their names."""
    design = observation_label(observation)
    obs = "" if design == "default" else f"__obs-{design}"
    preset = randomization_label(randomization)
    rand = "" if preset == "none" else f"__rand-{preset}"
    return f"{task.split('/')[-1]}__{action_mode}__{reward_type}__{algo}{obs}{rand}__s{seed}"


class TrainError(ValueError):
    """Invalid training or evaluation request (reported as a one-line error, exit 2)."""


@dataclass(frozen=True)
class TrainRequest:
    """What ``unified-manip train`` was asked to do.

    Attributes:
        env: Registered task ID.
        action_mode: One of the task's action modes.
        reward_type: ``sparse``, ``dense`` or ``dense_penalized``.
        algo: ``ppo``, ``sac``, ``td3``, ``sac_her`` or ``tqc_her``.
        steps: Total environment steps (over all envs).
        seed: Seed of the model and of the envs (env k gets ``seed + k``).
        n_envs: Parallel envs, stepped as ``vec`` says; ``None`` takes the hyperparameter
            file's ``n_envs`` key, and 1 where that has none.
        run_dir: Where the run lives.
        overrides: ``key=value`` hyperparameter overrides.
        env_kwargs: Extra env keyword arguments (e.g. ``robot``, or ``randomization``: the
            training distribution, a preset other than ``none`` or a list of terms).
        device: ``auto``, ``cpu`` or ``cuda``; ``None`` takes the hyperparameter file's
            ``device`` key, and ``auto`` where that has none.
        vec: How the envs are stepped: ``native`` (the native vector env, through
            :class:`~unified_manip.training.sb3_vec_env.NativeSB3VecEnv`), ``dummy`` (SB3's
            ``DummyVecEnv``), ``subproc`` (``SubprocVecEnv``), or ``auto``: native where
            the ID has a native vector env and ``n_envs > 1``, else dummy for one env
            and subproc for more.
        restart: Start the run over from step 0, discarding its checkpoints, logs and
            models (same run: the settings must match its ``config.yaml``).
    """

    env: str
    action_mode: str
    reward_type: str
    algo: str
    steps: int
    seed: int = 0
    n_envs: int | None = None
    run_dir: Path | None = None
    overrides: tuple[str, ...] = ()
    env_kwargs: dict[str, Any] = field(default_factory=dict)
    device: str | None = None
    vec: str = "auto"
    restart: bool = False

    def __post_init__(self) -> None:
        try:  # the env's own checks and words (unknown ID, mode or reward type, unsupported mode)
            get_task(self.env).check_choices(self.action_mode, self.reward_type)
        except ValueError as err:
            raise TrainError(str(err)) from None
        if self.algo not in ALGOS:
            raise TrainError(f"unknown algorithm {self.algo!r}; expected one of {', '.join(ALGOS)}")
        if self.device is not None and self.device not in DEVICES:
            raise TrainError(f"unknown device {self.device!r}; expected one of {', '.join(DEVICES)}")
        for name in ("steps", "n_envs"):
            value = getattr(self, name)
            if value is not None and value <= 0:
                raise TrainError(f"--{name.replace('_', '-')} must be positive, got {value}")
        from unified_manip.envs.vector.factory import resolve_vec

        try:
            resolve_vec(self.vec, self.env, self.n_envs or 1)
        except ValueError as err:
            raise TrainError(str(err)) from None
        if self.run_dir is not None and ".." in Path(self.run_dir).parts:
            raise TrainError(
                f"--run-dir {str(self.run_dir)!r} climbs out of its directory with '..'; "
                "expected a path without '..' (relative, or absolute)"
            )

    @property
    def directory(self) -> Path:
        if self.run_dir is not None:
            return Path(self.run_dir)
        design = design_label(self.env_kwargs)
        preset = self.env_kwargs.get("randomization")
        return Path("runs") / run_name(
            self.env, self.action_mode, self.reward_type, self.algo, self.seed, design, preset
        )

    def env_config(self) -> dict[str, Any]:
        return {"action_mode": self.action_mode, "reward_type": self.reward_type, **self.env_kwargs}
