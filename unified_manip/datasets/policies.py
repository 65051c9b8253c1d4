"""The policies ``collect`` can record without a trained run: the task's scripted one and
uniform random actions. Each is built for one env (``env -> obs -> action``)."""

from __future__ import annotations

from typing import Any

from unified_manip.datasets.episodes import Policy
from unified_manip.datasets.errors import DatasetError


def scripted(env) -> Policy:
    """The task's scripted ``ee_delta`` policy, in ``env``'s action mode through
    :class:`~unified_manip.envs.controllers.translate.EEDeltaInMode` on the env's own rig;
    a policy that emits another mode (its factory's ``action_mode``: Meta-World's emit
    ``native``) is translated by its factory's ``translator(backend, ee_config)`` where it
    has one, else plays that mode only.

    It reads the env's state (``state_observation``: the default design, exact), not the
    observation it is handed, so it plays the same episodes whatever the env's observation
    design, noise or delay; what is recorded is the observation as the env gives it."""
    from unified_manip.envs.controllers.translate import EEDeltaInMode

    spec = env.unwrapped.task
    mode = env.unwrapped.config.action_mode
    if spec.scripted_policy is None:
        raise DatasetError(f"{spec.id} has no scripted policy; use --policy random or a trained run directory")
    emits = spec.scripted_mode
    translator = getattr(spec.scripted_policy, "translator", None) if emits != "ee_delta" else None
    if emits != "ee_delta" and mode != emits and translator is None:
        raise DatasetError(
            f"the scripted policy cannot play {spec.id} in action_mode {mode!r}: it emits {emits} actions; "
            f"expected {emits}"
        )
    scripted_policy = spec.scripted_policy(emits)
    state = env.unwrapped.state_observation

    def policy(obs: dict) -> Any:
        return scripted_policy(state())

    if mode == emits:
        return policy
    if mode not in shared_modes(spec):
        raise DatasetError(
            f"the scripted policy cannot play {spec.id} in action_mode {mode!r} (the source's own controller); "
            f"expected one of {', '.join(shared_modes(spec))}"
        )
    try:
        build = translator or EEDeltaInMode
        translate = build(env.unwrapped.backend, spec.controllers["ee_delta"])
    except ValueError as err:
        raise DatasetError(f"the scripted policy cannot play {spec.id} in action_mode {mode!r}: {err}") from None
    return lambda obs: translate(policy(obs))


def shared_modes(spec) -> list[str]:
    """The action modes of the task ``spec`` driven by the shared controllers: those an
    ``ee_delta`` action or a grip-site target can be translated into."""
    return [mode for mode, config in spec.controllers.items() if config.controller is not None]


class RandomPolicy:
    """Uniform random actions from the env's action space, seeded by :meth:`seed` (the
    recorder calls it with each episode's reset seed)."""

    def __init__(self, env) -> None:
        self.space = env.action_space

    def seed(self, seed: int) -> None:
        self.space.seed(seed)

    def __call__(self, obs):
        return self.space.sample()


#: ``--policy`` names that need no run directory, and their builders.
BUILT_IN = {"scripted": scripted, "random": RandomPolicy}
