"""The baselines: each a Stable-Baselines3 class, with or without hindsight relabelling.

:data:`ALGOS` is the registry ``--algo`` and a grid's ``algos:`` choose from;
:func:`get_algo` looks one up by name.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Any


class HyperparameterError(ValueError):
    """A hyperparameter file or override is invalid (an unknown algorithm included)."""


@dataclass(frozen=True)
class Algo:
    """One baseline: an SB3 class, with or without hindsight relabelling."""

    name: str
    module: str
    cls_name: str
    her: bool = False
    off_policy: bool = True
    buffer: str = "unified_manip.training.her:GoalRelHerReplayBuffer"  # module:class of the HER buffer

    def cls(self):
        return getattr(importlib.import_module(self.module), self.cls_name)

    def buffer_cls(self):
        """The replay buffer class of a HER algorithm."""
        module, name = self.buffer.split(":")
        return getattr(importlib.import_module(module), name)

    def load(self, path, policy: Any = None, **kwargs: Any):
        """``cls().load(path, **kwargs)``, with this project's own classes handed over by
        name instead of unpickled from the file: a model saved before they moved (e.g.
        ``unified_manip.crossq`` to ``unified_manip.training.crossq``) still loads.

        Args:
            path: The model zip.
            policy: The run's ``policy`` hyperparameter (an alias such as
                ``"MultiInputPolicy"``, or a class); None: unpickled from the file.
            **kwargs: ``env``, ``device``, ... as for SB3's ``load``.

        A HER model saved without ``goal_rel`` in its ``replay_buffer_kwargs`` (every run
        trained before the harness stated it: with SB3's relabelling) keeps SB3's
        relabelling; the buffer would otherwise read the env's goal-dependent groups.
        """
        cls = self.cls()
        custom: dict[str, Any] = {}
        if self.module.startswith("unified_manip.") and policy is not None:
            custom["policy_class"] = cls.policy_aliases[policy] if isinstance(policy, str) else policy
        if self.her and self.buffer.startswith("unified_manip."):
            custom["replay_buffer_class"] = self.buffer_cls()
        model = cls.load(path, custom_objects=custom or None, **kwargs)
        if self.her and "goal_rel" not in model.replay_buffer_kwargs:
            model.replay_buffer_kwargs = {**model.replay_buffer_kwargs, "goal_rel": ()}
            if model.replay_buffer is not None:
                model.replay_buffer.goal_rel = ()
        return model


ALGOS: dict[str, Algo] = {
    a.name: a
    for a in (
        Algo("ppo", "stable_baselines3", "PPO", off_policy=False),
        Algo("sac", "stable_baselines3", "SAC"),
        Algo("td3", "stable_baselines3", "TD3"),
        Algo("sac_her", "stable_baselines3", "SAC", her=True),
        Algo("tqc_her", "sb3_contrib", "TQC", her=True),
        Algo(
            "crossq_her",
            "unified_manip.training.crossq",
            "CrossQ",
            her=True,
            buffer="unified_manip.training.crossq:CatDictHerReplayBuffer",
        ),
        # Behaviour cloning of a dataset (TD3's actor; --steps are gradient steps): unified_manip.training.bc.
        Algo("bc", "stable_baselines3", "TD3"),
    )
}


def get_algo(name: str) -> Algo:
    try:
        return ALGOS[name]
    except KeyError:
        raise HyperparameterError(f"unknown algorithm {name!r}; expected one of {', '.join(ALGOS)}") from None
