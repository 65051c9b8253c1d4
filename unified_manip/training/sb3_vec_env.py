"""Stable-Baselines3's ``VecEnv`` interface over the native vector env.

SB3 resets an env on the step its episode ends, and wants one info dict per env, the
terminal observation in it (``terminal_observation``) and ``TimeLimit.truncated``: what
``DummyVecEnv`` gives over ``gym.make``'s env. :class:`NativeSB3VecEnv` gives exactly
that (same observations, float32 rewards, dones and info dicts, bit for bit) from a
:class:`~.env.NativeVectorEnv` in Gymnasium's ``SAME_STEP`` autoreset mode, so
``HerReplayBuffer`` (through ``env_method("compute_reward", ...)``), ``VecNormalize``
and ``VecMonitor`` work on it unchanged.

The N envs share one object, so ``get_attr`` and ``env_method`` answer from the vector
env itself, once per requested index: ``env_method("compute_reward", ag, dg, infos,
indices=[0])`` is the batched ``compute_reward``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping, Sequence

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode
from stable_baselines3.common.vec_env.base_vec_env import VecEnv, VecEnvIndices, VecEnvObs, VecEnvStepReturn

from unified_manip.envs.vector.env import NativeVectorEnv
from unified_manip.envs.vector.factory import make_vector_env

_SKIP = ("final_obs", "final_info")


def _as_lists(info: Mapping[str, Any]) -> dict[str, Any]:
    """``{key: (values, mask)}`` as Python lists (nested dicts alike), skipping masks."""
    out = {}
    for key, value in info.items():
        if key.startswith("_") or key in _SKIP:
            continue
        mask = info[f"_{key}"].tolist()
        out[key] = (_as_lists(value) if isinstance(value, Mapping) else value.tolist(), mask)
    return out


def _env_dict(lists: Mapping[str, Any], i: int) -> dict[str, Any]:
    """Env ``i``'s own info dict from :func:`_as_lists`' output."""
    return {
        key: _env_dict(values, i) if isinstance(values, dict) else values[i]
        for key, (values, mask) in lists.items()
        if mask[i]
    }


class NativeSB3VecEnv(VecEnv):
    """A :class:`~.env.NativeVectorEnv` as a Stable-Baselines3 ``VecEnv``.

    Args:
        venv: The native vector env, built with ``autoreset_mode=AutoresetMode.SAME_STEP``.

    Raises:
        ValueError: ``venv`` is not a native vector env in ``SAME_STEP`` mode.
    """

    def __init__(self, venv: NativeVectorEnv) -> None:
        if not isinstance(venv, NativeVectorEnv):
            raise ValueError(f"NativeSB3VecEnv wraps a NativeVectorEnv, got {type(venv).__name__}")
        if venv.autoreset_mode != AutoresetMode.SAME_STEP:
            raise ValueError(
                f"NativeSB3VecEnv needs autoreset_mode=SAME_STEP (SB3 resets on the last step), got {venv.autoreset_mode}"
            )
        self.venv = venv
        super().__init__(venv.num_envs, venv.single_observation_space, venv.single_action_space)
        self._actions: np.ndarray | None = None

    def reset(self) -> VecEnvObs:
        # Reset options are not passed on: the tasks take none (the single env ignores them).
        obs, info = self.venv.reset(seed=list(self._seeds))
        lists = _as_lists(info)
        self.reset_infos = [_env_dict(lists, i) for i in range(self.num_envs)]
        self._reset_seeds()
        self._reset_options()
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions

    def step_wait(self) -> VecEnvStepReturn:
        obs, reward, terminated, truncated, info = self.venv.step(self._actions)
        dones = terminated | truncated
        now = _as_lists(info)
        final = _as_lists(info["final_info"]) if dones.any() else {}
        time_limit = (truncated & ~terminated).tolist()
        infos = []
        for i, done in enumerate(dones.tolist()):
            if done:
                env_info = _env_dict(final, i)
                env_info["TimeLimit.truncated"] = time_limit[i]
                env_info["terminal_observation"] = info["final_obs"][i]
                self.reset_infos[i] = _env_dict(now, i)
            else:
                env_info = _env_dict(now, i)
                env_info["TimeLimit.truncated"] = time_limit[i]
            infos.append(env_info)
        return obs, reward.astype(np.float32), dones, infos

    def close(self) -> None:
        self.venv.close()

    def get_images(self) -> Sequence[np.ndarray | None]:
        frames = self.venv.render()
        return [None] * self.num_envs if frames is None else list(frames)

    # ------------------------------------------------------------------ attributes
    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        """The vector env's attribute, once per index (the envs share it)."""
        return [getattr(self.venv, attr_name)] * len(self._indices(indices))

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        """Set an attribute shared by every env; a subset of envs is refused."""
        if len(self._indices(indices)) != self.num_envs:
            raise ValueError(f"the native vector env's envs share their attributes; set {attr_name!r} on all of them")
        setattr(self.venv, attr_name, value)

    def env_method(self, method_name: str, *method_args, indices: VecEnvIndices = None, **method_kwargs) -> list[Any]:
        """Call the vector env's method, once per index (``compute_reward`` is batched)."""
        method = getattr(self.venv, method_name)
        return [method(*method_args, **method_kwargs) for _ in self._indices(indices)]

    def env_is_wrapped(self, wrapper_class: type, indices: VecEnvIndices = None) -> list[bool]:
        """No Gymnasium wrappers: use ``VecMonitor`` rather than ``Monitor``."""
        return [False] * len(self._indices(indices))

    def _indices(self, indices: VecEnvIndices) -> list[int]:
        return list(self._get_indices(indices))


def make_monitored(
    task_id: str,
    env_kwargs: dict[str, Any],
    n_envs: int,
    seed: int,
    monitor_dir: Path | None,
    info_keywords: tuple[str, ...] = ("is_success",),
):
    """What ``unified-manip train --vec native`` trains on: the adapter over ``n_envs``
    native envs (env ``k`` seeded ``seed + k`` at the first reset, as SB3's
    ``make_vec_env``), in a ``VecMonitor`` writing ``<monitor_dir>/native.monitor.csv``."""
    from stable_baselines3.common.vec_env import VecMonitor

    spec = gym.spec(task_id)
    venv = NativeSB3VecEnv(
        make_vector_env(n_envs, task_id, spec.max_episode_steps, AutoresetMode.SAME_STEP, **env_kwargs)
    )
    venv.seed(seed)
    filename = None
    if monitor_dir is not None:
        Path(monitor_dir).mkdir(parents=True, exist_ok=True)
        filename = str(Path(monitor_dir) / "native")
    return VecMonitor(venv, filename=filename, info_keywords=info_keywords)
