"""What a task's rewards are made of: its term set.

The shared env knows no task vocabulary. A task declares, in one
:class:`TermSet`:

* ``inputs``: the names of the per-step quantities its reward terms read, which its
  backend's :meth:`~unified_manip.envs.backend.Backend.quantities` provides (a distance
  from the gripper to an object, a cleaned fraction, a hinge angle). They do not depend
  on the goal, so they travel in ``info`` and hindsight relabelling (which changes only
  the goals) recomputes the reward exactly;
* ``events``: quantities derived from the last step's inputs and this step's (an object
  let go), each an :class:`Event`;
* ``dense`` and ``penalties``: the terms of the ``dense`` design and the ones
  ``dense_penalized`` adds, built from the :class:`~unified_manip.envs.rewards.RewardConfig`;
* ``terminations``: the conditions besides success that may end an episode
  (:class:`Termination`), each switched on by name with ``gym.make(..., terminate_on=...)``.
  Success ends one with ``terminate_on_success``; a diverged simulator always truncates it.

Every design also reads ``action_sq``, the squared norm of the clipped action, which the
env computes itself. A term is a function of ``(distance, success, ctx)``, where ``ctx``
maps every name of :attr:`TermSet.info_keys` to an array shaped like ``distance``, plus
its scale (:class:`~unified_manip.envs.rewards.Term`): batched, so ``compute_reward`` and
``step`` give the same values.

The term sets of the families with a gripper live beside those families
(:mod:`unified_manip.envs.tasks.gripper_terms`); a family of your own declares its own.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Mapping

import numpy as np

from unified_manip.envs.rewards import RewardConfig, RewardSpec, Term, sparse_terms, validate_reward_type

#: The reward input every env computes itself, from the action.
ACTION_SQ = "action_sq"

EventFn = Callable[[Mapping[str, np.ndarray], Mapping[str, np.ndarray]], np.ndarray]


@dataclass(frozen=True)
class Event:
    """A reward input derived from two successive steps' quantities.

    Attributes:
        name: Its ``info`` key.
        fn: ``(before, now) -> value``: ``before`` and ``now`` map the term set's inputs to
            arrays (or floats) of one shape; the value has that shape. Picklable (a
            module-level function or a frozen dataclass instance, not a closure).
    """

    name: str
    fn: EventFn


@dataclass(frozen=True)
class Termination:
    """A condition that ends the episode (``terminated=True``) when switched on.

    Attributes:
        name: What ``terminate_on`` calls it.
        fn: ``ctx -> bool array``: reads the reward inputs (``TermSet.info_keys``) of one
            step, as arrays of one shape, and says where the episode ends. Picklable.
        doc: One line for the task pages.
    """

    name: str
    fn: Callable[[Mapping[str, np.ndarray]], np.ndarray]
    doc: str = field(default="", compare=False)


def _no_terms(config: RewardConfig) -> tuple[Term, ...]:
    return ()


@dataclass(frozen=True)
class TermSet:
    """A task's reward terms and the quantities they read.

    Attributes:
        name: A label for documentation (``"grasp"``).
        inputs: The quantities of :meth:`Backend.quantities` the terms read, in the order
            ``info`` shows them.
        dense: The terms of the ``dense`` design, from the reward config.
        events: Inputs derived from the last step's and this step's inputs (0 at reset).
        penalties: The terms ``dense_penalized`` adds to ``dense``.
        ranges: Each input's and event's ``(low, high)``, where not ``(0, 1)``: what the
            dense-reward sanity check (``unified-manip report``) sweeps.
        terminations: The conditions ``terminate_on`` may switch on.
        doc: One line on what the terms reward, for the task pages.
    """

    name: str
    inputs: tuple[str, ...]
    dense: Callable[[RewardConfig], tuple[Term, ...]]
    events: tuple[Event, ...] = ()
    penalties: Callable[[RewardConfig], tuple[Term, ...]] = _no_terms
    ranges: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    terminations: tuple[Termination, ...] = ()
    doc: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        names = (*self.inputs, *(e.name for e in self.events), ACTION_SQ)
        if len(set(names)) != len(names):
            raise ValueError(f"term set {self.name!r}: the reward inputs {names} repeat a name")
        bad = [e for e in self.events if not isinstance(e, Event)]
        if bad:
            raise TypeError(f"term set {self.name!r}: events must be Event instances, got {bad!r}")
        unknown = sorted(set(self.ranges) - set(names[:-1]))
        if unknown:
            raise ValueError(f"term set {self.name!r}: ranges of unknown inputs {unknown}; expected from {names[:-1]}")
        inverted = sorted(k for k, (low, high) in self.ranges.items() if not low <= high)
        if inverted:
            raise ValueError(f"term set {self.name!r}: ranges {inverted} have low > high")
        if any(not isinstance(t, Termination) for t in self.terminations):
            raise TypeError(f"term set {self.name!r}: terminations must be Termination instances")

    def check_terminations(self, names: tuple[str, ...], task_id: str) -> tuple[Termination, ...]:
        """The terminations ``names`` (``terminate_on``), or ``ValueError`` naming the valid ones."""
        known = {t.name: t for t in self.terminations}
        unknown = [n for n in names if n not in known]
        if unknown:
            choices = ", ".join(repr(n) for n in known) or "none"
            raise ValueError(f"{task_id} has no termination {unknown[0]!r}; terminate_on takes {choices}")
        return tuple(known[n] for n in names)

    @property
    def info_keys(self) -> tuple[str, ...]:
        """Every reward input, in ``info``'s order: the inputs, the events, ``action_sq``."""
        return (*self.inputs, *(e.name for e in self.events), ACTION_SQ)

    def design(self, reward_type: str, config: RewardConfig | None = None) -> RewardSpec:
        """The reward design ``reward_type`` of this term set, with ``config``'s numbers."""
        validate_reward_type(reward_type)
        config = config or RewardConfig()
        if reward_type == "sparse":
            return RewardSpec("sparse", sparse_terms(config))
        dense = self.dense(config)
        return RewardSpec(reward_type, dense + self.penalties(config) if reward_type == "dense_penalized" else dense)

    def input_range(self, name: str) -> tuple[float, float]:
        """``(low, high)`` of an input or event (``(0, 1)`` unless :attr:`ranges` says otherwise)."""
        return self.ranges.get(name, (0.0, 1.0))

    def events_at_rest(self) -> dict[str, float]:
        """The events' values at reset: 0."""
        return {e.name: 0.0 for e in self.events}

    def events_between(self, before: Mapping[str, np.ndarray], now: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
        """Every event's value for the step from ``before`` to ``now``."""
        return {e.name: e.fn(before, now) for e in self.events}
