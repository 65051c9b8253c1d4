"""``unified-manip eval``: a trained run's success rate (with a Wilson 95% CI), mean
return, and a video of its first episodes."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from unified_manip.envs.randomization.presets import randomization_label
from unified_manip.envs.randomization.terms import RandomizationTerm
from unified_manip.envs.registry import get_task
from unified_manip.envs.video import write_video
from unified_manip.training import rundir
from unified_manip.training.algorithms import get_algo
from unified_manip.training.devices import DeviceError, resolve_device
from unified_manip.training.request import TrainError
from unified_manip.training.rundir import RunDirectoryError


@dataclass(frozen=True)
class EvalResult:
    episodes: int
    successes: int
    success_rate: float
    ci_low: float
    ci_high: float
    mean_return: float
    std_return: float
    randomization: str = "none"
    """The randomisation the episodes ran under (``randomization_label``)."""
    test_distribution: str | None = None
    """The test distribution asked for (``default``, ``in-range``, ``extreme``), if any."""

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass
class Policy:
    """A trained run's policy and an env of the run's own settings to play it in.

    Attributes:
        env: The env (``gym.make`` of the run's ID and keyword arguments, with the
            overrides asked for); :meth:`close` closes it.
        config: The run's ``config.yaml``.
        model_path: The model played (best, final or newest checkpoint, or the one named).
    """

    env: Any
    config: dict[str, Any]
    model_path: Path
    _model: Any
    _normalizer: Any
    deterministic: bool = True

    def act(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """The policy's action for one observation of :attr:`env`."""
        if self._normalizer is not None:
            obs = self._normalizer.normalize_obs(obs)
        action, _ = self._model.predict(obs, deterministic=self.deterministic)
        return action

    def close(self) -> None:
        self.env.close()


def open_policy(
    target: Path,
    env_overrides: dict[str, Any] | None = None,
    deterministic: bool = True,
    device: str = "auto",
    action_mode: str | None = None,
) -> Policy:
    """Load the model of a run directory (its best model if any, else its final one, else
    its newest checkpoint) or a model zip inside one, with an env of the run's settings
    updated by ``env_overrides``. A model cannot be played in an action mode it was not
    trained in (``action_mode`` names the one asked for, to say so)."""
    import gymnasium as gym
    from stable_baselines3.common.vec_env import DummyVecEnv

    from unified_manip.training.run_envs import normalized

    try:
        device = resolve_device(device)
    except DeviceError as err:
        raise TrainError(str(err)) from None
    try:
        run_dir = rundir.containing(Path(target))
        config = rundir.read_config(run_dir)
        run, algo_kwargs = rundir.run_settings(run_dir, config)
    except RunDirectoryError as err:
        raise TrainError(str(err)) from None
    env_kwargs = dict(config["env_kwargs"])
    if action_mode is not None and action_mode != env_kwargs["action_mode"]:
        raise TrainError(
            f"the model was trained with action_mode {env_kwargs['action_mode']!r}; it cannot be evaluated "
            f"with action_mode {action_mode!r} (the actions mean different things)"
        )
    try:
        model_path = rundir.model_to_evaluate(Path(target), run_dir)
    except RunDirectoryError as err:
        raise TrainError(str(err)) from None
    try:  # the env's own checks of what is asked of it (a preset none of whose terms applies)
        env = gym.make(config["env"], **{**env_kwargs, **(env_overrides or {})})
    except ValueError as err:
        raise TrainError(str(err)) from None
    # HER models need an env to load; give them one over the same instance.
    venv = DummyVecEnv([lambda: env])
    model = get_algo(config["algo"]).load(model_path, algo_kwargs.get("policy"), env=venv, device=device)
    normalizer = normalized(venv, run, _stats_for(model_path, run_dir), training=False) if run.normalize else None
    return Policy(env, config, model_path, model, normalizer, deterministic)


def evaluate(
    target: Path,
    episodes: int,
    action_mode: str | None = None,
    reward_type: str | None = None,
    seed: int = 123,
    observation_noise: float | None = None,
    observation_delay: int | None = None,
    video: Path | None = None,
    video_episodes: int = 2,
    deterministic: bool = True,
    device: str = "auto",
    randomization: str | Sequence[RandomizationTerm] | None = None,
    test_distribution: str | None = None,
) -> EvalResult:
    """Evaluate a run directory (its best model if any, else its final one) or a model
    zip inside a run directory. The env defaults to the run's own settings; a model
    cannot be evaluated in an action mode it was not trained in. ``observation_noise`` and
    ``observation_delay`` replace the run's own, to measure a policy's robustness;
    ``randomization`` (a preset or a list of terms) and ``test_distribution`` choose the
    world it is tested in (:func:`evaluated_randomization`)."""
    from scipy.stats import binomtest

    from unified_manip.envs.observations import validate_count, validate_noise
    from unified_manip.envs.rewards import validate_reward_type

    if episodes <= 0:
        raise TrainError(f"--episodes must be positive, got {episodes}")
    if video is not None and Path(video).suffix.lower() not in (".mp4", ".gif"):
        raise TrainError(f"unsupported video format {Path(video).suffix!r}; expected .mp4 or .gif")
    overrides: dict[str, Any] = {}
    try:
        if reward_type is not None:
            validate_reward_type(reward_type)
            overrides["reward_type"] = reward_type
    except ValueError as err:
        raise TrainError(str(err)) from None
    try:
        if observation_noise is not None:
            validate_noise(observation_noise)
            overrides["observation_noise"] = observation_noise
        if observation_delay is not None:
            validate_count("observation_delay", observation_delay)
            overrides["observation_delay"] = observation_delay
    except ValueError as err:
        raise TrainError(f"--{str(err).replace('_', '-')}") from None
    if randomization is not None or test_distribution is not None:
        trained = rundir.read_config(_run_dir(target)).get("env_kwargs", {}).get("randomization")
        overrides["randomization"] = evaluated_randomization(trained, randomization, test_distribution)
    if video:
        overrides.update(render_mode="rgb_array", render_width=320, render_height=320)
    policy = open_policy(Path(target), overrides, deterministic, device, action_mode)
    env = policy.env
    returns, successes, frames = [], 0, []
    for ep in range(episodes):
        obs, info = env.reset(seed=seed + ep)
        done, total = False, 0.0
        if video and ep < video_episodes:
            frames.append(env.render())
        while not done:
            obs, reward, terminated, truncated, info = env.step(policy.act(obs))
            total += reward
            done = terminated or truncated
            if video and ep < video_episodes:
                frames.append(env.render())
        returns.append(total)
        successes += int(info.get("is_success", 0.0) > 0.5)
    policy.close()
    if video:
        write_video(Path(video), frames, fps=get_task(policy.config["env"]).render_fps)
    ci = binomtest(successes, episodes).proportion_ci(confidence_level=0.95, method="wilson")
    return EvalResult(
        episodes,
        successes,
        successes / episodes,
        float(ci.low),
        float(ci.high),
        float(np.mean(returns)),
        float(np.std(returns)),
        randomization_label(overrides.get("randomization", policy.config["env_kwargs"].get("randomization"))),
        test_distribution,
    )


def evaluated_randomization(
    trained: Any, preset: str | Sequence[RandomizationTerm] | None, distribution: str | None
) -> Any:
    """The ``randomization`` a policy trained under ``trained`` (its run's value; ``None``:
    ``none``) is evaluated under: ``preset`` (a name, or a list of terms) where given, else
    ``trained``; with a
    ``distribution`` (``default``, ``in-range``, ``extreme``: Packer et al. 2018), that
    preset's test distribution (``none``, the preset, its ``:extreme`` counterpart).

    Raises:
        TrainError: An unknown distribution or preset, or ``in-range``/``extreme`` with no
            preset to take the ranges from (a run trained under ``none`` or a list of terms
            needs ``preset``).
    """
    from unified_manip.envs.randomization import TEST_DISTRIBUTIONS, distribution_for, preset_terms

    if isinstance(preset, str):  # a list of terms is checked when the env is made
        try:
            preset_terms(preset)
        except (TypeError, ValueError) as err:
            raise TrainError(str(err)) from None
    base = preset if preset is not None else (trained if trained is not None else "none")
    if distribution is None:
        return base
    if distribution not in TEST_DISTRIBUTIONS:
        raise TrainError(f"unknown test distribution {distribution!r}; expected one of {', '.join(TEST_DISTRIBUTIONS)}")
    if distribution != "default" and (not isinstance(base, str) or randomization_label(base) == "none"):
        raise TrainError(
            f"--test-distribution {distribution} takes its ranges from a preset, and the run trained under "
            f"{randomization_label(base)}; add --randomization PRESET (dynamics, objects, visual or all, "
            "joined by '+')"
        )
    try:
        return distribution_for(base, distribution) if isinstance(base, str) else "none"
    except ValueError as err:
        raise TrainError(str(err)) from None


def _run_dir(target: Path) -> Path:
    try:
        return rundir.containing(Path(target))
    except RunDirectoryError as err:
        raise TrainError(str(err)) from None


def _stats_for(model_path: Path, run_dir: Path) -> Path:
    try:
        return rundir.stats_for(model_path, run_dir)
    except RunDirectoryError as err:
        raise TrainError(str(err)) from None
