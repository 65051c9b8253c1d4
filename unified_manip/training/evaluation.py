"""``unified-manip eval``: a trained run's success rate (with a Wilson 95% CI), mean
return, and a video of its first episodes."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.envs.registry import get_task
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

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


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
) -> EvalResult:
    """Evaluate a run directory (its best model if any, else its final one) or a model
    zip inside a run directory. The env defaults to the run's own settings; a model
    cannot be evaluated in an action mode it was not trained in. ``observation_noise`` and
    ``observation_delay`` replace the run's own, to measure a policy's robustness."""
    import gymnasium as gym
    from scipy.stats import binomtest

    from unified_manip.envs.rewards import validate_reward_type

    if episodes <= 0:
        raise TrainError(f"--episodes must be positive, got {episodes}")
    try:
        device = resolve_device(device)
    except DeviceError as err:
        raise TrainError(str(err)) from None
    if video is not None and Path(video).suffix.lower() not in (".mp4", ".gif"):
        raise TrainError(f"unsupported video format {Path(video).suffix!r}; expected .mp4 or .gif")
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
    if reward_type is not None:
        try:
            validate_reward_type(reward_type)
        except ValueError as err:
            raise TrainError(str(err)) from None
        env_kwargs["reward_type"] = reward_type
    from unified_manip.envs.observations import validate_count, validate_noise

    try:
        if observation_noise is not None:
            validate_noise(observation_noise)
            env_kwargs["observation_noise"] = observation_noise
        if observation_delay is not None:
            validate_count("observation_delay", observation_delay)
            env_kwargs["observation_delay"] = observation_delay
    except ValueError as err:
        raise TrainError(f"--{str(err).replace('_', '-')}") from None
    try:
        model_path = rundir.model_to_evaluate(Path(target), run_dir)
    except RunDirectoryError as err:
        raise TrainError(str(err)) from None
    algo = get_algo(config["algo"])
    render = {"render_mode": "rgb_array", "render_width": 320, "render_height": 320} if video else {}
    from stable_baselines3.common.vec_env import DummyVecEnv

    from unified_manip.training.run_envs import normalized

    env = gym.make(config["env"], **env_kwargs, **render)
    # HER models need an env to load; give them one over the same instance.
    venv = DummyVecEnv([lambda: env])
    model = algo.load(model_path, algo_kwargs.get("policy"), env=venv, device=device)
    normalizer = None
    if run.normalize:
        normalizer = normalized(venv, run, _stats_for(model_path, run_dir), training=False)
    returns, successes, frames = [], 0, []
    for ep in range(episodes):
        obs, info = env.reset(seed=seed + ep)
        done, total = False, 0.0
        if video and ep < video_episodes:
            frames.append(env.render())
        while not done:
            action, _ = model.predict(normalizer.normalize_obs(obs) if normalizer else obs, deterministic=deterministic)
            obs, reward, terminated, truncated, info = env.step(action)
            total += reward
            done = terminated or truncated
            if video and ep < video_episodes:
                frames.append(env.render())
        returns.append(total)
        successes += int(info.get("is_success", 0.0) > 0.5)
    env.close()
    if video:
        write_video(Path(video), frames, fps=get_task(config["env"]).render_fps)
    ci = binomtest(successes, episodes).proportion_ci(confidence_level=0.95, method="wilson")
    return EvalResult(
        episodes,
        successes,
        successes / episodes,
        float(ci.low),
        float(ci.high),
        float(np.mean(returns)),
        float(np.std(returns)),
    )


def _stats_for(model_path: Path, run_dir: Path) -> Path:
    try:
        return rundir.stats_for(model_path, run_dir)
    except RunDirectoryError as err:
        raise TrainError(str(err)) from None


def write_video(path: Path, frames: list[np.ndarray], fps: int) -> None:
    """MP4 (via imageio-ffmpeg) or GIF, chosen by the file suffix."""
    import imageio.v3 as iio

    path.parent.mkdir(parents=True, exist_ok=True)
    suffix = path.suffix.lower()
    if suffix == ".gif":
        iio.imwrite(path, np.stack(frames), duration=1000 / fps, loop=0)
    elif suffix == ".mp4":
        iio.imwrite(path, np.stack(frames), fps=fps, codec="libx264", macro_block_size=1)
    else:
        raise TrainError(f"unsupported video format {path.suffix!r}; expected .mp4 or .gif")
