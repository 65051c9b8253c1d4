"""CrossQ (sb3-contrib) on goal-conditioned ``Dict`` observations, for ``crossq_her``.

sb3-contrib 2.9 ships CrossQ with an ``MlpPolicy`` only, and its update evaluates the
critic once on ``torch.cat([observations, next_observations])``, which fails for the
``Dict`` batches a HER replay buffer samples. Two small pieces
make it work without copying the algorithm:

* :class:`CrossQ` adds a ``MultiInputPolicy``: CrossQ's policy with SB3's
  ``CombinedExtractor``, as every other SB3 algorithm has.
* :class:`CatDictHerReplayBuffer` is a HER replay buffer whose sampled observations are a
  :class:`CatDict`: a dict that ``torch.cat`` concatenates key by key.
"""

from __future__ import annotations

from typing import Any

import torch
from sb3_contrib import CrossQ as _CrossQ
from sb3_contrib.crossq.policies import CrossQPolicy
from stable_baselines3.common.torch_layers import CombinedExtractor

from unified_manip.training.her import GoalRelHerReplayBuffer


class CatDict(dict):
    """A dict of tensors that ``torch.cat`` joins key by key (other torch calls refuse it)."""

    @classmethod
    def __torch_function__(cls, func, types, args=(), kwargs=None):
        if func is not torch.cat:
            return NotImplemented
        kwargs = dict(kwargs or {})
        tensors, rest = args[0], args[1:]
        return cls({key: torch.cat([t[key] for t in tensors], *rest, **kwargs) for key in tensors[0]})


class CatDictHerReplayBuffer(GoalRelHerReplayBuffer):
    """The HER algorithms' buffer (:mod:`unified_manip.training.her`), whose samples'
    observations and next observations are :class:`CatDict`."""

    def sample(self, batch_size: int, env=None):
        samples = super().sample(batch_size, env)
        return samples._replace(
            observations=CatDict(samples.observations), next_observations=CatDict(samples.next_observations)
        )


class MultiInputCrossQPolicy(CrossQPolicy):
    """CrossQ's policy over a ``Dict`` observation: each key flattened, then concatenated."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("features_extractor_class", CombinedExtractor)
        super().__init__(*args, **kwargs)


class CrossQ(_CrossQ):
    """sb3-contrib's CrossQ with a ``MultiInputPolicy`` alias for goal-conditioned envs."""

    policy_aliases = {**_CrossQ.policy_aliases, "MultiInputPolicy": MultiInputCrossQPolicy}
