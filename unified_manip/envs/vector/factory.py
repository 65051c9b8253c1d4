"""``make_vector_env``: the ``vector_entry_point`` of every ``UnifiedManip`` ID.

``gym.make_vec(ID, num_envs=N, ...)`` lands here. Where the task's family has a batched
backend (:data:`BATCHED`), the result is a :class:`~.env.NativeVectorEnv`; otherwise it
is Gymnasium's ``SyncVectorEnv`` over ``gym.make(ID)``, with a one-line
:class:`VectorFallbackWarning` saying so.
"""

from __future__ import annotations

import importlib
import warnings
from typing import Any

from gymnasium.vector import AutoresetMode, SyncVectorEnv, VectorEnv

from unified_manip.envs.registry import get_task
from unified_manip.envs.setup import env_setup
from unified_manip.envs.vector.pool import default_num_threads

#: Family -> ``"module:Class"`` of its batched backend, built as
#: ``Class(backends, action_mode, num_threads)`` from N of the family's own backends.
BATCHED: dict[str, str] = {
    "arm4": "unified_manip.envs.vector.arm4:VectorizedArm4",
    "fetch": "unified_manip.envs.vector.threaded:ThreadedBatch",
}

#: Options the native vector env cannot honour; an ID given one falls back too.
_UNSUPPORTED_RENDER_MODES = ("human",)


#: How ``unified-manip train --vec`` steps its envs (``auto``: see :func:`resolve_vec`).
VEC_KINDS: tuple[str, ...] = ("auto", "native", "dummy", "subproc")


class VectorFallbackWarning(UserWarning):
    """An ID was vectorised with Gymnasium's ``SyncVectorEnv`` instead of natively."""


def native_support(task_id: str, render_mode: str | None = None) -> str | None:
    """Why ``task_id`` cannot run natively, or None if it can."""
    family = get_task(task_id).family
    if family not in BATCHED:
        return f"the {family} family has no batched backend (native: {', '.join(sorted(BATCHED))})"
    if render_mode in _UNSUPPORTED_RENDER_MODES:
        return f"render_mode={render_mode!r} needs a window per env"
    return None


def resolve_vec(vec: str, task_id: str, n_envs: int) -> str:
    """The vectorisation ``train`` uses: ``native``, ``dummy`` or ``subproc``.

    ``auto`` is ``native`` where the ID has a native vector env and ``n_envs > 1``;
    otherwise SB3's ``DummyVecEnv`` for one env and ``SubprocVecEnv`` for more.

    Raises:
        ValueError: ``vec`` is unknown, or ``native`` for an ID without a native vector env.
    """
    if vec not in VEC_KINDS:
        raise ValueError(f"unknown vec {vec!r}; expected one of {', '.join(VEC_KINDS)}")
    reason = native_support(task_id)
    if vec == "native" and reason is not None:
        raise ValueError(
            f"--vec native: {task_id} has no native vector env ({reason}); expected --vec auto, dummy or subproc"
        )
    if vec == "auto":
        return "native" if reason is None and n_envs > 1 else ("subproc" if n_envs > 1 else "dummy")
    return vec


def make_vector_env(
    num_envs: int,
    task_id: str,
    max_episode_steps: int | None = None,
    autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
    num_threads: int | None = None,
    **env_kwargs: Any,
) -> VectorEnv:
    """N envs of ``task_id`` with the single env's keyword arguments.

    Args:
        num_envs: N, at least 1.
        task_id: The registered ID (``gym.make_vec`` passes it from the registration).
        max_episode_steps: The time limit (``gym.make_vec`` passes the ID's).
        autoreset_mode: Gymnasium's autoreset mode; ``NEXT_STEP`` by default.
        num_threads: Threads stepping the physics; default: the cores this process may use.
        **env_kwargs: ``action_mode``, ``reward_type``, ... as for ``gym.make``.

    Raises:
        ValueError: ``num_envs`` or ``num_threads`` is not a positive int, or an env
            option is invalid (the single env's messages).
    """
    if not isinstance(num_envs, int) or isinstance(num_envs, bool) or num_envs < 1:
        raise ValueError(f"num_envs must be a positive int, got {num_envs!r}")
    if num_threads is None:
        num_threads = min(default_num_threads(), num_envs)
    elif not isinstance(num_threads, int) or isinstance(num_threads, bool) or num_threads < 1:
        raise ValueError(f"num_threads must be a positive int, got {num_threads!r}")
    autoreset_mode = AutoresetMode(autoreset_mode)
    spec = get_task(task_id)
    reason = native_support(task_id, env_kwargs.get("render_mode"))
    if reason is not None:
        warnings.warn(
            f"{task_id}: no native vector env ({reason}); using gymnasium's SyncVectorEnv",
            VectorFallbackWarning,
            stacklevel=3,
        )
        import gymnasium as gym

        def make_one():
            return gym.make(task_id, max_episode_steps=max_episode_steps, **env_kwargs)

        return SyncVectorEnv([make_one] * num_envs, autoreset_mode=autoreset_mode)
    from unified_manip.envs.vector.env import NativeVectorEnv

    setup = env_setup(task_id, **env_kwargs)
    module, name = BATCHED[spec.family].split(":")
    batched_cls = getattr(importlib.import_module(module), name)
    backends = [setup.build_backend() for _ in range(num_envs)]
    batched = batched_cls(backends, setup.config.action_mode, num_threads)
    return NativeVectorEnv(task_id, batched, setup.config, max_episode_steps, autoreset_mode)
