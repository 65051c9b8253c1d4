"""The envs and model arguments of a training run: monitored vector envs (training and
evaluation), observation normalisation, and the algorithm's keyword arguments."""

from __future__ import annotations

import functools
import os
from pathlib import Path
from typing import Any

import numpy as np

from unified_manip.training.algorithms import get_algo
from unified_manip.training.request import TrainError, TrainRequest
from unified_manip.training.settings import RunConfig


def make_vec_env(
    env_id: str, env_kwargs: dict[str, Any], n_envs: int, seed: int, monitor_dir: Path | None, vec: str = "auto"
):
    """Monitored envs (``is_success`` logged), stepped as ``vec`` says: the native vector
    env (one ``VecMonitor``), or a ``DummyVecEnv`` / ``SubprocVecEnv`` of ``Monitor``-ed
    envs (see :func:`unified_manip.envs.vector.factory.resolve_vec` for ``auto``)."""
    from stable_baselines3.common.env_util import make_vec_env as sb3_make_vec_env
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

    from unified_manip.envs.vector.factory import resolve_vec

    kind = resolve_vec(vec, env_id, n_envs)
    if kind == "native":
        from unified_manip.training.sb3_vec_env import make_monitored

        return make_monitored(env_id, env_kwargs, n_envs, seed, monitor_dir, ("is_success", "sim_unstable"))

    return sb3_make_vec_env(
        # Worker processes import unified_manip, which registers the IDs.
        functools.partial(_worker_env, env_id) if kind == "subproc" else f"unified_manip:{env_id}",
        n_envs=n_envs,
        seed=seed,
        env_kwargs=env_kwargs,
        monitor_dir=str(monitor_dir) if monitor_dir else None,
        # sim_unstable: whether the episode ended because the physics diverged.
        monitor_kwargs={"info_keywords": ("is_success", "sim_unstable")},
        vec_env_cls=SubprocVecEnv if kind == "subproc" else DummyVecEnv,
    )


def _worker_env(env_id: str, **kwargs):
    """The env of a ``SubprocVecEnv`` worker. The worker ignores Ctrl-C: a terminal sends
    it to the whole process group, SB3's worker exits on it, and the trainer, which stops
    at the end of its rollout to checkpoint, would find its envs gone."""
    import signal

    import gymnasium as gym

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    return gym.make(env_id, **kwargs)


def eval_env(req: TrainRequest, n_envs: int):
    """The evaluation env of a run with ``n_envs`` training envs; a task that refuses the
    env keyword arguments is a TrainError.

    It has the training env's wrapper layers, because EvalCallback copies VecNormalize
    statistics layer by layer and refuses chains that differ: a ``VecMonitor`` over an
    unmonitored env when the training env is the native vector env, else ``Monitor``-ed."""
    from unified_manip.envs.vector.factory import resolve_vec

    native = resolve_vec(req.vec, req.env, n_envs) == "native"
    try:
        if native:
            import gymnasium as gym
            from stable_baselines3.common.vec_env import DummyVecEnv, VecMonitor

            env = VecMonitor(DummyVecEnv([lambda: gym.make(req.env, **req.env_config())]))
            env.seed(req.seed + 10_000)
        else:
            env = make_vec_env(req.env, req.env_config(), 1, req.seed + 10_000, None)
    except (TypeError, ValueError) as err:  # gymnasium appends where it was raised; keep the task's words
        reason = str(err).split(" was raised from the environment creator")[0]
        raise TrainError(f"cannot make {req.env} with {req.env_config()}: {reason}") from None
    return env


def model_kwargs(algo_name: str, algo_kwargs: dict[str, Any], run: RunConfig, env: Any) -> dict[str, Any]:
    """The algorithm's keyword arguments for a model on the vector ``env``: ``algo_kwargs``,
    plus the HER replay buffer, TD3's action noise (``run.action_noise_std``) and, for an
    observation with image keys, a CNN per image key
    (:class:`~unified_manip.training.images.ImageExtractor`).

    The HER buffer gets the slices of the goal-dependent groups of the env's observation
    (``goal_dependent_layout``) where ``run.relabel_goal_rel``, else none, always stated in
    ``replay_buffer_kwargs``: the saved model keeps them (:mod:`unified_manip.training.her`)."""
    algo = get_algo(algo_name)
    kwargs = dict(algo_kwargs)
    from unified_manip.training.images import has_images, with_image_extractor

    if has_images(env.observation_space):
        kwargs["policy_kwargs"] = with_image_extractor(kwargs.get("policy_kwargs"))
    if algo.her:
        from unified_manip.training.her import goal_dependent_slices

        kwargs["replay_buffer_class"] = algo.buffer_cls()
        slices = goal_dependent_slices(env) if run.relabel_goal_rel else ()
        kwargs["replay_buffer_kwargs"] = {**(kwargs.get("replay_buffer_kwargs") or {}), "goal_rel": slices}
    if run.action_noise_std is not None:
        from stable_baselines3.common.noise import NormalActionNoise

        std = float(run.action_noise_std)
        shape = env.action_space.shape
        kwargs["action_noise"] = NormalActionNoise(np.zeros(shape), std * np.ones(shape))
    return kwargs


def normalized(venv, run: RunConfig, stats: Path | None, training: bool, gamma: float = 0.99):
    """Wrap ``venv`` in VecNormalize when the run normalises observations (``run.normalize``).

    Rewards are left as the task defines them (HER recomputes them from goals); with
    ``stats`` the saved running statistics are loaded, otherwise they start fresh
    (``gamma``: the algorithm's discount, which VecNormalize keeps for its return statistics).
    """
    if not run.normalize:
        return venv
    from stable_baselines3.common.vec_env import VecNormalize, VecTransposeImage

    parts = getattr(venv.observation_space, "spaces", None)
    images = [k for k, s in parts.items() if len(s.shape) == 3] if parts is not None else []
    if images:
        # SB3 would put its channels-first transposition outside VecNormalize, whose
        # original observations (the ones the replay buffer stores) would stay channels-last.
        venv = VecTransposeImage(venv)
    if stats is not None:
        venv = VecNormalize.load(str(stats), venv)
    else:
        # Images are scaled by the policy (uint8 / 255), not by running statistics.
        keys = [k for k in parts if k not in images] if parts is not None else None
        venv = VecNormalize(venv, norm_obs=True, norm_reward=False, gamma=gamma, norm_obs_keys=keys)
    venv.training = training
    venv.norm_reward = False
    return venv


def save_stats(model, path: Path) -> None:
    """Save the VecNormalize statistics of ``model``'s env atomically."""
    tmp = path.with_name(path.stem + ".tmp.pkl")
    model.get_vec_normalize_env().save(str(tmp))
    os.replace(tmp, path)
