"""Each converted step's action: the initial guesses, and ``convert``'s two methods over
them (``track`` plays the first guess; ``search`` searches from the best, :mod:`.search`,
and falls back to each guess played open loop)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from unified_manip.datasets.errors import DatasetError
from unified_manip.datasets.policies import shared_modes
from unified_manip.datasets.search import ActionSearch, SearchConfig, Target, leads, site_velocities, sites

#: One converted step: ``(recorded action, where the recording was after it) -> action``.
Stepper = Callable[[np.ndarray, Target], np.ndarray]


@dataclass(frozen=True)
class Way:
    """One way to re-execute an episode: its name (an episode's ``replayed_by``), what
    picks each step's action, and the extra steps it may spend catching up on one
    recorded step (:attr:`.search.SearchConfig.catch_up`)."""

    name: str
    step: Stepper
    catch_up: int = 0


def steppers(task, target, probe, source_mode: str, method: str, config: SearchConfig) -> list[Way]:
    """The ways an episode is tried, in turn, until one keeps it: ``track``'s first
    initial guess played as it is; or the search from the best guess catching up
    (``search``), then, for an episode it loses, the search one step per recorded step
    (``search, lockstep``: catching up can run out the time limit before the recorded
    path does), and with ``config.fallback``: in a mode that carries a target, the search
    catching up with the target's lead weighted in (``search, lead W`` for each of
    :attr:`~.search.SearchConfig.lead_weights`); then each initial guess played open loop."""
    backend = target.unwrapped.backend
    named = guessers(task, backend, source_mode, target.unwrapped.config.action_mode)
    if method == "track":
        return [Way(*named[0])]
    guess = _Guesses([guess for _, guess in named])
    search = _Search(ActionSearch(probe, config), backend, guess)
    ways = [Way("search", search, config.catch_up)]
    if not config.fallback:
        return ways
    if config.catch_up:
        ways.append(Way("search, lockstep", search))
    if leads(search.search.controls):
        for weight in config.lead_weights:
            held = _Search(ActionSearch(probe, config, lead_weight=weight), backend, guess)
            ways.append(Way(f"search, lead {weight:g}", held, config.catch_up))
    return ways + [Way(*n) for n in named]


def guessers(task, backend, source_mode: str, mode: str) -> list[tuple[str, Stepper]]:
    """Each step's initial guesses, named: ``recorded``, the recorded action itself, where
    the dataset was recorded in the mode converted into (so that ``track`` replays it
    exactly, seen through another observation design); ``translated``, the recorded action
    translated into the mode, where the dataset was recorded in ``ee_delta`` or in its
    scripted policy's own mode (as the ``demonstrations`` run setting plays a scripted
    policy: Meta-World's ``native`` through its policy's translator); and ``tracker``, where
    it was recorded in a mode of the shared controllers, the tracker's action toward the
    next recorded grip site with the recorded gripper command (one arm)."""
    from unified_manip.envs.controllers.translate import EEDeltaInMode, SiteTracker, arms

    ee = task.controllers["ee_delta"]
    named: list[tuple[str, Stepper]] = []
    if source_mode == mode:
        named.append(("recorded", _Open(lambda a, target: np.array(a))))
    translator = getattr(task.scripted_policy, "translator", None) if source_mode == task.scripted_mode else None
    try:
        if source_mode == "ee_delta" or translator is not None:
            translate = (translator or EEDeltaInMode)(backend, ee)
            named.append(("translated", _Open(lambda a, target: translate(np.asarray(a, dtype=np.float64)))))
        if source_mode in shared_modes(task) and len(arms(backend)) == 1:
            tracker = SiteTracker(backend, ee)
            gripper = bool(tracker.rig.has_gripper)
            named.append(("tracker", _Open(lambda a, target: tracker(target.site, float(a[-1]) if gripper else None))))
    except ValueError as err:
        raise DatasetError(f"{task.id}'s action_mode {mode!r} cannot follow a recorded trajectory: {err}") from None
    if not named:
        raise DatasetError(
            f"the dataset was recorded in {source_mode!r}, the source's own controller, which has no grip-site rig "
            "to read its trajectory from; convert a dataset of a shared-controller mode"
        )
    return named


class _Open:
    """Open loop: one initial guess, played as it is."""

    def __init__(self, guess: Callable[[np.ndarray, Target], np.ndarray]) -> None:
        self.guess = guess

    def start(self, seed: int) -> None:
        pass

    def __call__(self, action: np.ndarray, target: Target) -> np.ndarray:
        return self.guess(action, target)


class _Guesses:
    """Every initial guess of a step."""

    def __init__(self, guesses: list[_Open]) -> None:
        self.guesses = guesses

    def __call__(self, action: np.ndarray, target: Target) -> list[np.ndarray]:
        return [guess(action, target) for guess in self.guesses]


class _Search:
    """Each step's action searched from the converted env's checkpoint (:mod:`.search`)."""

    def __init__(self, search: ActionSearch, backend, guess: _Guesses) -> None:
        self.search, self.backend, self.guess = search, backend, guess

    def start(self, seed: int) -> None:
        self.search.start(seed)

    def __call__(self, action: np.ndarray, target: Target) -> np.ndarray:
        return self.search(self.backend.checkpoint(), self.guess(action, target), target).action


def recorded_targets(env, ep, task_id: str) -> list[Target]:
    """Where the recording was after each step: the grip sites' positions and velocities,
    read by restoring each recorded state in ``env`` (one with rigs), and the recorded
    achieved goal."""
    from unified_manip.envs.controllers.translate import arms

    backend = env.unwrapped.backend
    rigs = [arm.rig for arm in arms(backend)]
    states = ep.infos["state"]
    env.reset(seed=0)
    if backend.get_state().shape != states[0].shape:
        raise DatasetError(f"{task_id}'s recorded states do not fit the model of the mode converted into")
    goals = np.asarray(ep.observations["achieved_goal"], dtype=np.float64)
    targets = []
    for state, goal in zip(states, goals):
        backend.set_state(state)
        targets.append(Target(sites(rigs), site_velocities(rigs), goal))
    return targets
