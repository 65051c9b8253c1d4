"""Does a dense reward's maximum coincide with success?

Rewards here are functions of ``(achieved_goal, desired_goal, info)``, so the check
needs no simulator states: desired goals come from seeded resets, achieved goals are
placed at distances from 0 to 20 success thresholds in random directions, and the goal-
independent inputs (the task's term set's ``info_keys``) take every combination of their
ends (``TermSet.input_range``; ``action_sq`` from 0 to the action's size). The reward is evaluated with the env's own
batched ``compute_reward``. A reward whose best value outside the success region reaches
its best value inside it is flagged: an agent maximising it need not succeed.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import gymnasium as gym
import numpy as np

from unified_manip.envs.registry import get_task
from unified_manip.envs.termsets import ACTION_SQ


@dataclass(frozen=True)
class DenseCheck:
    task_id: str
    reward_type: str
    max_inside: float
    max_outside: float
    samples: int

    @property
    def optimum_in_success(self) -> bool:
        return self.max_inside > self.max_outside

    @property
    def flagged(self) -> bool:
        return not self.optimum_in_success


def sample_goal_pairs(env, n_goals: int, per_goal: int, rng: np.random.Generator):
    """Desired goals from seeded resets; achieved goals around them at many distances."""
    spec = env.unwrapped.task
    thr = spec.distance_threshold
    desired = np.array(
        [env.reset(seed=int(s))[0]["desired_goal"] for s in rng.integers(0, 2**31, n_goals)], dtype=np.float64
    )
    radii = thr * np.concatenate(
        [np.linspace(0.0, 0.999, per_goal // 2), np.geomspace(1.001, 20.0, per_goal - per_goal // 2)]
    )
    ag, dg = [], []
    for g in desired:
        directions = rng.normal(size=(len(radii), g.shape[0]))
        directions /= np.linalg.norm(directions, axis=1, keepdims=True)
        candidates = g + directions * radii[:, None]
        # Scale each candidate so that the task's own distance is the intended radius.
        d = spec.goal_distance(candidates, np.broadcast_to(g, candidates.shape))
        scale = np.divide(radii, d, out=np.ones_like(radii), where=d > 0)
        ag.append(g + (candidates - g) * scale[:, None])
        dg.append(np.broadcast_to(g, candidates.shape))
    return np.concatenate(ag), np.concatenate(dg)


def dense_reward_check(
    task_id: str,
    reward_type: str = "dense",
    n_goals: int = 20,
    per_goal: int = 100,
    seed: int = 0,
    reward_spec=None,
) -> DenseCheck:
    """Check ``reward_type`` on ``task_id`` (or a candidate ``RewardSpec`` of your own,
    which the env is built with: ``gym.make(..., reward_spec=...)``)."""
    spec = get_task(task_id)
    env = gym.make(task_id, action_mode=spec.action_modes[-1], reward_type=reward_type, reward_spec=reward_spec)
    rng = np.random.default_rng(seed)
    ag, dg = sample_goal_pairs(env, n_goals, per_goal, rng)
    n = len(ag)
    distance = spec.goal_distance(ag, dg)
    inside = distance < spec.distance_threshold
    terms = spec.terms
    ends = {k: terms.input_range(k) for k in terms.info_keys if k != ACTION_SQ}
    ends[ACTION_SQ] = (0.0, float(env.action_space.shape[0]))
    rewards = np.full(n, -np.inf)
    for corner in itertools.product(*ends.values()):
        infos = np.array([dict(zip(ends, corner))] * n, dtype=object)
        rewards = np.maximum(rewards, env.unwrapped.compute_reward(ag, dg, infos))
    env.close()
    return DenseCheck(
        task_id,
        reward_type,
        float(rewards[inside].max()) if inside.any() else float("nan"),
        float(rewards[~inside].max()) if (~inside).any() else float("nan"),
        n,
    )
