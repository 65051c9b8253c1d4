"""Hindsight relabelling that keeps the goal-dependent observation groups on the new goal.

Stable-Baselines3's :class:`~stable_baselines3.HerReplayBuffer` relabels a sampled
transition by replacing its ``desired_goal`` with a goal achieved later in the episode, and
recomputes the reward. The ``observation`` vector stays as it was stored. An observation
with a group that depends on the goal (``goal_rel``, ``desired_goal - achieved_goal``: the
4-DOF arm's default, and the ``relative`` and ``full`` designs everywhere; see
:mod:`unified_manip.envs.observations`) then shows the episode's own goal beside the new
``desired_goal``: the relabelled transition contradicts itself.

:class:`GoalRelHerReplayBuffer` is a drop-in for SB3's buffer that moves those groups by
the goal's change, ``new_goal - stored_goal``, before the observation is normalised. The
stored value is shifted, not recomputed, so the sensor model stays as it was: noise on
``goal_rel`` is kept, and a delayed observation keeps its old achieved goal. It reads
which slices to move from the env (``env.unwrapped.goal_dependent_layout``)::

    from stable_baselines3 import SAC
    from unified_manip.training import GoalRelHerReplayBuffer

    model = SAC("MultiInputPolicy", env, replay_buffer_class=GoalRelHerReplayBuffer,
                replay_buffer_kwargs=dict(n_sampled_goal=4, goal_selection_strategy="future"))

The HER algorithms of ``unified-manip train`` use it, with the run setting
``relabel_goal_rel`` (:class:`~unified_manip.training.settings.RunConfig`, true by default)
deciding: the slices (none where it is false) go into ``replay_buffer_kwargs``, which the
saved model keeps, so a run resumes with the relabelling it was trained with.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from stable_baselines3 import HerReplayBuffer

#: The env attribute that names the goal-dependent groups of ``observation`` and their
#: slices (:attr:`unified_manip.envs.env.UnifiedManipEnv.goal_dependent_layout`).
GOAL_DEPENDENT_LAYOUT = "goal_dependent_layout"


def goal_dependent_slices(env: Any) -> tuple[tuple[int, int], ...]:
    """``(start, stop)`` of each goal-dependent group of a vector env's ``observation``
    (empty: none, or an env that does not say, i.e. not a unified_manip env)."""
    if env is None or not env.has_attr(GOAL_DEPENDENT_LAYOUT):
        return ()
    layout = env.get_attr(GOAL_DEPENDENT_LAYOUT, [0])[0]
    return tuple((int(part.start), int(part.stop)) for part in layout.values())


class GoalRelHerReplayBuffer(HerReplayBuffer):
    """SB3's HerReplayBuffer whose relabelled samples carry ``goal_rel`` for their new goal.

    Args:
        goal_rel: ``(start, stop)`` slices of the ``observation`` vector that hold
            ``desired_goal`` minus a state quantity; each is as wide as the goal. None
            (the default): the env's goal-dependent groups (:func:`goal_dependent_slices`).
            Empty: SB3's relabelling as it is.

    The other arguments are :class:`~stable_baselines3.HerReplayBuffer`'s.
    """

    #: Buffers saved by this class's base restore into it (the rows are the same):
    #: checkpoints written before the HER algorithms used it.
    restores_from: tuple[str, ...] = (f"{HerReplayBuffer.__module__}.{HerReplayBuffer.__qualname__}",)

    def __init__(self, *args: Any, goal_rel: Sequence[Sequence[int]] | None = None, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if goal_rel is None:
            goal_rel = goal_dependent_slices(self.env)
        self.goal_rel = tuple((int(start), int(stop)) for start, stop in goal_rel)
        if self.goal_rel:
            _check_slices(self.goal_rel, self.obs_shape)
        self._relabelled_from: np.ndarray | None = None

    def _get_virtual_samples(self, batch_indices: np.ndarray, env_indices: np.ndarray, env=None):
        # The stored goals, before SB3 replaces them; _normalize_obs shifts goal_rel by the
        # change. An episode's goal is fixed, so the observation and the next observation
        # of a transition were stored with the same goal.
        if self.goal_rel:
            self._relabelled_from = self.observations["desired_goal"][batch_indices, env_indices]
        try:
            return super()._get_virtual_samples(batch_indices, env_indices, env)
        finally:
            self._relabelled_from = None

    def _normalize_obs(self, obs: dict[str, np.ndarray], env=None) -> dict[str, np.ndarray]:
        if self._relabelled_from is not None:
            shift = obs["desired_goal"] - self._relabelled_from
            vector = obs["observation"].copy()  # a copy: the stored rows stay as they were
            for start, stop in self.goal_rel:
                vector[:, start:stop] += shift
            obs = {**obs, "observation": vector}
        return super()._normalize_obs(obs, env)


def _check_slices(slices: tuple[tuple[int, int], ...], obs_shape: Any) -> None:
    shapes = obs_shape if isinstance(obs_shape, dict) else {}
    if "observation" not in shapes or "desired_goal" not in shapes:
        raise ValueError("goal_rel needs a Dict observation with 'observation' and 'desired_goal' entries")
    size, goal = int(np.prod(shapes["observation"])), int(np.prod(shapes["desired_goal"]))
    for start, stop in slices:
        if not (0 <= start < stop <= size) or stop - start != goal:
            raise ValueError(
                f"goal_rel slice ({start}, {stop}) must lie in the observation's {size} entries "
                f"and be as wide as the goal ({goal})"
            )
