"""A trained run's policy as a plain ``obs -> action`` callable, for tools that play it
outside SB3 (``unified-manip collect --policy RUN_DIR``)."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

import numpy as np

from unified_manip.training import rundir
from unified_manip.training.request import TrainError
from unified_manip.training.rundir import RunDirectoryError


def run_settings(target: Path) -> tuple[Path, dict[str, Any]]:
    """The run directory ``target`` belongs to and its settings (``config.yaml``), or a
    one-line :class:`~unified_manip.training.request.TrainError`."""
    try:
        run_dir = rundir.containing(Path(target))
        return run_dir, rundir.read_config(run_dir)
    except RunDirectoryError as err:
        raise TrainError(str(err)) from None


def run_policy(target: Path, deterministic: bool = True, device: str = "cpu") -> Callable[[Any], Callable]:
    """``env -> (obs -> action)``: the model of the run ``target`` (its best, final or
    newest checkpoint model, as ``eval`` picks it) acting in ``env``, with the run's
    observation normalisation; ``deterministic`` plays the policy's mean action."""
    from stable_baselines3.common.vec_env import DummyVecEnv

    from unified_manip.training.algorithms import get_algo
    from unified_manip.training.run_envs import normalized

    run_dir, config = run_settings(target)
    try:
        run, algo_kwargs = rundir.run_settings(run_dir, config)
        model_path = rundir.model_to_evaluate(Path(target), run_dir)
    except RunDirectoryError as err:
        raise TrainError(str(err)) from None
    algo = get_algo(config["algo"])

    def build(env) -> Callable[[dict[str, np.ndarray]], np.ndarray]:
        venv = DummyVecEnv([lambda: env])  # HER models need an env to load
        model = algo.load(model_path, algo_kwargs.get("policy"), env=venv, device=device)
        normalizer = None
        if run.normalize:
            normalizer = normalized(venv, run, rundir.stats_for(model_path, run_dir), training=False)

        def act(obs):
            action, _ = model.predict(normalizer.normalize_obs(obs) if normalizer else obs, deterministic=deterministic)
            return action

        return act

    return build
