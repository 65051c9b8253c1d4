"""Meta-World's own scripted policies (``metaworld.policies``) as the tasks' scripted
policies: they emit ``native`` actions, which :mod:`.translate` plays in the other modes."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, ClassVar

import numpy as np


@dataclass(frozen=True)
class MetaWorldPolicy:
    """``TaskSpec.scripted_policy`` factory: Meta-World's expert policy of ``env_name``,
    which reads Meta-World's 39-number observation: the default observation vector
    followed by ``desired_goal``.

    Attributes:
        env_name: Meta-World's name of the task, e.g. ``"door-open-v3"``.
    """

    env_name: str

    #: The action mode its actions are in.
    action_mode: ClassVar[str] = "native"

    def __call__(self, action_mode: str) -> Callable[[dict[str, np.ndarray]], np.ndarray]:
        if action_mode != "native":
            raise ValueError(f"the Meta-World scripted policies emit native actions; got action_mode={action_mode!r}")
        from metaworld.policies import ENV_POLICY_MAP

        policy = ENV_POLICY_MAP[self.env_name]()

        def act(obs: dict[str, np.ndarray]) -> np.ndarray:
            upstream = np.concatenate([obs["observation"], obs["desired_goal"]]).astype(np.float64)
            return np.asarray(policy.get_action(upstream), dtype=np.float32)

        return act

    def translator(self, backend, ee) -> Callable[[np.ndarray], np.ndarray]:
        """Its actions in ``backend``'s mode, a mode of the shared controllers
        (:class:`~.translate.NativeInMode`); ``ee`` is the task's ``ee_delta`` config."""
        from unified_manip.envs.tasks.metaworld.translate import NativeInMode

        return NativeInMode(backend, ee)
