"""Gymnasium wrappers for ``UnifiedManip`` envs."""

from __future__ import annotations

from typing import Any

import gymnasium as gym


class RawRewardTerms(gym.Wrapper):
    """Adds ``info["reward_terms_raw"]``: the step's reward terms before their scales,
    beside ``info["reward_terms"]`` (scaled), so that what an agent optimises is visible
    term by term (MuJoCo Playground logs its raw terms the same way).

    The raw terms are computed from the step's goals and info exactly as the reward is
    (``env.unwrapped.compute_reward_terms(..., raw=True)``); ``raw * scale`` is the
    scaled term.
    """

    def step(self, action: Any):
        obs, reward, terminated, truncated, info = self.env.step(action)
        env: Any = self.env.unwrapped
        raw = env.compute_reward_terms(obs["achieved_goal"], obs["desired_goal"], info, raw=True)
        info["reward_terms_raw"] = {name: float(value) for name, value in raw.items()}
        return obs, reward, terminated, truncated, info
