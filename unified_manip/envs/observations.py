"""Observation designs: which named groups the ``observation`` vector concatenates, and the
sensor model on top of it (distractors, Gaussian noise, delay).

A family declares its groups in one place, one :class:`ObservationGroup` per name
(``Backend.observation_groups``), and which of them, in which order, make its
``"default"`` observation (``Backend.default_observation``), today's vector exactly. The
shared names of :data:`SHARED_GROUPS` mean the same quantity on every family; a family
may add groups of its own. The presets of :data:`PRESETS` are derived from the groups'
kinds, so shared code never asks which family it is.

Goals are never part of a design: ``achieved_goal`` and ``desired_goal`` stay exact state.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from unified_manip.envs.cameras import split_images

#: Group names that mean the same quantity on every family that has it.
SHARED_GROUPS: tuple[str, ...] = (
    "joint_pos",
    "joint_vel",
    "gripper",
    "ee_pos",
    "ee_vel",
    "object_pos",
    "object_rot",
    "object_vel",
    "object_rel",
    "goal_rel",
)

#: What a group is: plain state, a velocity, or a difference of two positions.
KINDS: tuple[str, ...] = ("state", "velocity", "relative")

#: ``"default"``: the family's own vector; ``"minimal"``: its state groups (no velocity,
#: no relative vector); ``"relative"``: minimal plus ``object_rel`` and ``goal_rel``;
#: ``"full"``: every group, in declaration order.
PRESETS: tuple[str, ...] = ("default", "minimal", "relative", "full")

#: The relative vectors the ``"relative"`` preset adds.
RELATIVE_PRESET_GROUPS: tuple[str, ...] = ("object_rel", "goal_rel")

#: Distractor features: uniform in +-``DISTRACTOR_START`` at reset, then a Gaussian random
#: walk of ``DISTRACTOR_STEP`` per env step (metre-like scale).
DISTRACTOR_START, DISTRACTOR_STEP = 0.1, 0.01


def _choices(values: Sequence[str]) -> str:
    return ", ".join(repr(v) for v in values)


@dataclass(frozen=True)
class ObservationGroup:
    """One named quantity a family can put in the ``observation`` vector.

    Attributes:
        units: Units of its entries, as the docs list them (e.g. ``"rad"``, ``"m"``).
        read: ``backend -> values``: the group's entries from the backend's current state.
        kind: One of :data:`KINDS`; decides which presets include it.
    """

    units: str
    read: Callable[[Any], np.ndarray]
    kind: str = "state"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"unknown observation group kind {self.kind!r}; expected one of {_choices(KINDS)}")

    @property
    def goal_dependent(self) -> bool:
        """Whether its entries are ``desired_goal - achieved_goal`` (it reads :func:`goal_rel`):
        another goal moves them by the goal's change, so hindsight relabelling, which swaps
        the goal of a stored transition, must move them too
        (``unified_manip.training.GoalRelHerReplayBuffer`` does). Every other group is
        independent of the goal (tested on every ID, by measurement)."""
        return self.read is goal_rel


def goal_rel(backend: Any) -> np.ndarray:
    """``desired_goal - achieved_goal`` (the shared ``goal_rel`` group)."""
    return np.asarray(backend.desired_goal(), dtype=np.float64) - np.asarray(backend.achieved_goal(), dtype=np.float64)


def goal_rel_group(units: str) -> ObservationGroup:
    """The shared ``goal_rel`` group (``desired_goal - achieved_goal``, in ``units``): a
    relative vector that depends on the goal."""
    return ObservationGroup(units, goal_rel, "relative")


def validate_noise(noise: Any) -> None:
    """``ValueError`` unless ``noise`` is a std >= 0 or a mapping of group names to such stds."""
    values = noise.items() if isinstance(noise, Mapping) else [(None, noise)]
    for name, std in values:
        where = "observation_noise" if name is None else f"observation_noise[{name!r}]"
        if isinstance(std, bool) or not isinstance(std, (int, float)) or not np.isfinite(std) or std < 0:
            raise ValueError(f"{where} must be a standard deviation >= 0, got {std!r}")


def validate_count(name: str, value: Any) -> None:
    """``ValueError`` unless ``value`` is an int >= 0 (``observation_delay``, ``observation_distractors``)."""
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise ValueError(f"{name} must be an int >= 0, got {value!r}")


def resolve_groups(
    observation: str | Sequence[str], groups: Mapping[str, ObservationGroup], default: Sequence[str], task_id: str
) -> tuple[str, ...]:
    """The group names of a preset or a list of groups, checked against the task's groups.

    Raises:
        ValueError: An unknown preset or group, a group the task does not have, a repeated
            group, or an empty list (each naming the valid choices).
    """
    available = _choices(tuple(groups))
    if isinstance(observation, str):
        if observation not in PRESETS:
            raise ValueError(
                f"unknown observation preset {observation!r}; expected one of {_choices(PRESETS)} "
                f"or a list of groups of {task_id} ({available})"
            )
        kinds = {name: g.kind for name, g in groups.items()}
        if observation == "default":
            return tuple(default)
        if observation == "full":
            return tuple(groups)
        minimal = [name for name, kind in kinds.items() if kind == "state"]
        if observation == "minimal":
            return tuple(minimal)
        return (*minimal, *(name for name in RELATIVE_PRESET_GROUPS if name in groups))
    if not observation or not all(isinstance(n, str) for n in observation):
        raise ValueError(f"observation must be a preset or a non-empty list of group names, got {observation!r}")
    # In a list, a preset stands for its groups (``["default", "rgb"]``).
    names = tuple(
        g for n in observation for g in (resolve_groups(n, groups, default, task_id) if n in PRESETS else (n,))
    )
    for name in names:
        if name not in groups:
            if name in SHARED_GROUPS:
                raise ValueError(
                    f"observation group {name!r} is not available on {task_id}; expected some of {available}"
                )
            raise ValueError(f"unknown observation group {name!r} for {task_id}; expected some of {available}")
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise ValueError(f"observation group {repeated[0]!r} is listed twice")
    return names


class ObservationStream:
    """One env's ``observation`` vector under a design: reads the groups from the backend,
    appends distractors, adds noise and delays it. All randomness comes from the env's
    generator, in a fixed order (distractors, then noise), so a seed fixes the stream.

    Args:
        names: The design's groups, in order.
        groups: The task's groups (``Backend.observation_groups``).
        exact: The names are the family's default: read ``Backend.observation`` itself.
        sizes: Each group's length.
        distractors: How many distractor features to append.
        noise: One std for every entry, or a mapping of group names to stds.
        delay: Return the vector of this many steps earlier.
    """

    def __init__(
        self,
        names: tuple[str, ...],
        groups: Mapping[str, ObservationGroup],
        exact: bool,
        sizes: Mapping[str, int],
        distractors: int,
        noise: float | Mapping[str, float],
        delay: int,
    ) -> None:
        self.names = names
        self.exact = exact
        self._readers = [] if exact else [groups[n].read for n in names]
        self.layout: dict[str, slice] = {}
        start = 0
        for name in names:
            self.layout[name] = slice(start, start + sizes[name])
            start += sizes[name]
        #: The groups of ``layout`` that depend on the goal (``ObservationGroup.goal_dependent``).
        self.goal_layout = {n: self.layout[n] for n in names if groups[n].goal_dependent}
        self._distractors = distractors
        if distractors:
            self.layout["distractors"] = slice(start, start + distractors)
        self.size = start + distractors
        if isinstance(noise, Mapping):
            unknown = [n for n in noise if n not in names]
            if unknown:
                raise ValueError(
                    f"observation_noise names group {unknown[0]!r}, which the observation does not have; "
                    f"expected some of {_choices(names)}"
                )
            std = np.zeros(self.size)
            for name, value in noise.items():
                std[self.layout[name]] = value
        else:
            std = np.full(self.size, float(noise))
        self._std = std if std.any() else None
        self._delay = delay
        self.passthrough = not distractors and self._std is None and not delay
        self._walk = np.zeros(distractors)
        self._past: deque[np.ndarray] = deque(maxlen=delay + 1)

    def raw(self, backend: Any) -> np.ndarray:
        """The groups' values now, as float32 (the env's finiteness check reads these)."""
        if self.exact:
            return np.asarray(backend.observation(), dtype=np.float32)
        return np.concatenate([np.asarray(r(backend), dtype=np.float64).ravel() for r in self._readers]).astype(
            np.float32
        )

    def start(self, raw: np.ndarray, np_random: np.random.Generator) -> np.ndarray:
        """The first vector of an episode from ``raw``; the delay repeats it."""
        if self.passthrough:
            return raw
        if self._distractors:
            self._walk = np_random.uniform(-DISTRACTOR_START, DISTRACTOR_START, self._distractors)
        out = self._sense(raw, np_random)
        self._past.clear()
        self._past.extend([out] * (self._delay + 1))
        return out.copy()

    def advance(self, raw: np.ndarray, np_random: np.random.Generator) -> np.ndarray:
        """The vector after a step: this step's, or the one ``delay`` steps earlier."""
        if self.passthrough:
            return raw
        if self._distractors:
            self._walk = self._walk + DISTRACTOR_STEP * np_random.standard_normal(self._distractors)
        self._past.append(self._sense(raw, np_random))
        return self._past[0].copy()

    def _sense(self, raw: np.ndarray, np_random: np.random.Generator) -> np.ndarray:
        x = raw.astype(np.float64)
        if self._distractors:
            x = np.concatenate((x, self._walk))
        if self._std is not None:
            x = x + self._std * np_random.standard_normal(self.size)
        return x.astype(np.float32)

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_readers": []}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)


def build_stream(config: Any, backend: Any, task_id: str) -> ObservationStream:
    """The :class:`ObservationStream` of ``config``'s observation options on ``backend``
    (reset once, so that the groups can be sized)."""
    groups = backend.observation_groups()
    default = tuple(backend.default_observation())
    names = resolve_groups(split_images(config.observation)[0], groups, default, task_id)
    sizes = {n: int(np.asarray(groups[n].read(backend)).size) for n in names}
    return ObservationStream(
        names,
        groups,
        names == default,
        sizes,
        config.observation_distractors,
        config.observation_noise,
        config.observation_delay,
    )


def reattach(stream: ObservationStream, backend: Any) -> None:
    """Give an unpickled stream its readers back (they are the family's functions)."""
    if not stream.exact:
        groups = backend.observation_groups()
        stream._readers = [groups[n].read for n in stream.names]


def describe_groups(backend: Any) -> list[tuple[str, int, str, str, bool]]:
    """``(name, size, units, kind, in default)`` of every group of a reset backend."""
    default = set(backend.default_observation())
    return [
        (name, int(np.asarray(g.read(backend)).size), g.units, g.kind, name in default)
        for name, g in backend.observation_groups().items()
    ]
