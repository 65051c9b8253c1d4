"""Run settings: how a run trains, evaluates and checkpoints, beside the algorithm's own
hyperparameters (the keyword arguments handed to Stable-Baselines3).

A hyperparameter entry (``baselines/<algo>.yaml``) is one flat mapping. Its run settings
are the fields of :class:`RunConfig` and of its three nested configs, each under its own
name; every other key is the algorithm's. One name and one default per setting, from the
YAML file through ``config.yaml``, ``demonstrations.json`` and ``results.csv`` to the
report: a record holds the names written here, and :func:`demonstration_record` reads the
names older runs wrote.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping

from unified_manip.training.devices import DEVICES


class RunConfigError(ValueError):
    """A run setting of the wrong type or out of range (one line, naming the key)."""


# ---------------------------------------------------------------------- value rules
def _integer(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


#: Each rule: (what a value must be, as the error words it; whether a value is one).
_Rule = tuple[str, Callable[[Any], bool]]
POSITIVE: _Rule = ("an integer >= 1", lambda v: _integer(v) and v >= 1)
COUNT: _Rule = ("an integer >= 0", lambda v: _integer(v) and v >= 0)
WEIGHT: _Rule = ("a number >= 0", lambda v: _number(v) and math.isfinite(v) and v >= 0)
STD: _Rule = ("a number >= 0 or null", lambda v: v is None or WEIGHT[1](v))
FLAG: _Rule = ("true or false", lambda v: isinstance(v, bool))
DEVICE: _Rule = (f"one of {', '.join(DEVICES)}", lambda v: v in DEVICES)
DEMONSTRATIONS: _Rule = (
    "an integer >= 0 or a dataset path",
    lambda v: COUNT[1](v) or (isinstance(v, str) and bool(v.strip())),
)


def _setting(default: Any, rule: _Rule) -> Any:
    return field(default=default, metadata={"rule": rule})


def _check(config: Any) -> None:
    """Raise :class:`RunConfigError` for the first field of ``config`` that breaks its rule."""
    for f in dataclasses.fields(config):
        rule = f.metadata.get("rule")
        value = getattr(config, f.name)
        if rule is not None and not rule[1](value):
            raise RunConfigError(f"{f.name} must be {rule[0]}, got {value!r}")


# ---------------------------------------------------------------------- the nested configs
@dataclass(frozen=True)
class DemonstrationConfig:
    """Scripted demonstrations in the replay buffer, and behaviour cloning on them."""

    demonstrations: int | str = _setting(0, DEMONSTRATIONS)
    """Off-policy: episodes of the task's scripted policy put in the replay buffer before
    training (0: none; rounded up to whole episodes per env), or the path of a dataset
    (``unified-manip collect`` or ``convert``) whose episodes are put there instead."""
    bc_steps: int = _setting(0, COUNT)
    """With demonstrations: actor gradient steps of behaviour cloning on them before the
    first rollout (0: none)."""

    def __post_init__(self) -> None:
        _check(self)


@dataclass(frozen=True)
class CloningLossConfig:
    """A cloning loss on the demonstrations, added to every actor update while training."""

    bc_weight: float = _setting(0.0, WEIGHT)
    """Weight of the loss (0: no loss)."""
    bc_q_filter: bool = _setting(True, FLAG)
    """Keep the loss only where the critic rates the demonstrated action above the actor's."""
    bc_sampled: bool = _setting(False, FLAG)
    """Take the loss on a stochastic actor's sampled action rather than its mean."""

    def __post_init__(self) -> None:
        _check(self)


@dataclass(frozen=True)
class OfflineConfig:
    """Updates of the algorithm on the demonstrations alone, before the first rollout."""

    offline_steps: int = _setting(0, COUNT)
    """With demonstrations: gradient steps of the algorithm's own update on them (0: none)."""

    def __post_init__(self) -> None:
        _check(self)


#: The nested configs, by the RunConfig field that holds each.
GROUPS: dict[str, type] = {"demos": DemonstrationConfig, "cloning_loss": CloningLossConfig, "offline": OfflineConfig}


# ---------------------------------------------------------------------- the run config
@dataclass(frozen=True)
class RunConfig:
    """Every setting of a run that is not the algorithm's (see the module docstring)."""

    eval_freq: int = _setting(10_000, POSITIVE)
    """Env steps (over all envs) between evaluations."""
    n_eval_episodes: int = _setting(20, POSITIVE)
    """Episodes per evaluation."""
    checkpoint_freq: int = _setting(10_000, POSITIVE)
    """Env steps between resumable checkpoints."""
    action_noise_std: float | None = _setting(None, STD)
    """TD3: standard deviation of Gaussian exploration noise, in action units (null: SB3's default, none)."""
    normalize: bool = _setting(False, FLAG)
    """Running mean/std observation normalisation (VecNormalize), as the zoo's ``normalize``."""
    device: str = _setting("auto", DEVICE)
    """Where the run executes (``train --device`` overrides it); not compared on resume."""
    n_envs: int = _setting(1, POSITIVE)
    """Parallel training envs (``train --n-envs`` and a grid's ``n_envs`` override it)."""
    relabel_goal_rel: bool = _setting(True, FLAG)
    """HER: a relabelled transition's observation gets its goal-dependent groups
    (``goal_rel``, goal - achieved goal) for its new goal, shifted by the goal's change
    (:mod:`unified_manip.training.her`). False: SB3's relabelling, which leaves
    ``goal_rel`` at the episode's goal, as every committed run before this default was
    trained (their ``config.yaml`` says ``relabel_goal_rel: false``). Only designs with
    ``goal_rel`` differ (the arm's ``default``; ``relative`` and ``full`` everywhere)."""
    compile_loss: bool = _setting(False, FLAG)
    """TQC: ``torch.compile`` its quantile Huber loss (about 1.5x faster updates on one core; see
    :mod:`unified_manip.training.speedups`)."""
    demos: DemonstrationConfig = field(default_factory=DemonstrationConfig)
    """Demonstrations and behaviour cloning before training."""
    cloning_loss: CloningLossConfig = field(default_factory=CloningLossConfig)
    """The cloning loss during training."""
    offline: OfflineConfig = field(default_factory=OfflineConfig)
    """Offline steps before training."""

    def __post_init__(self) -> None:
        _check(self)
        for name, cls in GROUPS.items():
            if not isinstance(getattr(self, name), cls):
                raise RunConfigError(f"{name} must be a {cls.__name__}, got {getattr(self, name)!r}")

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> RunConfig:
        """The run settings among ``values`` (a flat hyperparameter mapping; other keys are ignored)."""
        nested = {name: group(**{k: values[k] for k in _names(group) if k in values}) for name, group in GROUPS.items()}
        return cls(**{k: values[k] for k in _names(cls) if k in values}, **nested)

    def to_mapping(self) -> dict[str, Any]:
        """Every setting under its key, flat, defaults included (what :meth:`from_mapping` reads)."""
        out = {k: getattr(self, k) for k in _names(RunConfig)}
        for name in GROUPS:
            out.update(dataclasses.asdict(getattr(self, name)))
        return out


def _names(cls: type) -> list[str]:
    return [f.name for f in dataclasses.fields(cls) if f.name not in GROUPS]


#: Every run setting's key (a hyperparameter entry's other keys are the algorithm's).
KEYS: tuple[str, ...] = tuple(_names(RunConfig)) + tuple(k for g in GROUPS.values() for k in _names(g))


def check_setting(key: str, value: Any) -> None:
    """Raise :class:`RunConfigError` unless ``value`` is a valid ``key`` (one of :data:`KEYS`)."""
    owner = next(c for c in (RunConfig, *GROUPS.values()) if key in _names(c))
    owner(**{key: value})


def split(values: Mapping[str, Any]) -> tuple[RunConfig, dict[str, Any]]:
    """``(run settings, the algorithm's keyword arguments)`` of a flat hyperparameter mapping."""
    return RunConfig.from_mapping(values), {k: v for k, v in values.items() if k not in KEYS}


# ---------------------------------------------------------------------- demonstrations.json
#: Where runs recorded before these names wrote a setting in ``demonstrations.json``.
_LEGACY = {
    "bc_weight": ("cloning_loss_weight",),
    "bc_q_filter": ("cloning_loss_q_filter",),
    "bc_sampled": ("cloning_loss_sampled",),
    "bc_steps": ("behaviour_cloning", "steps"),
    "offline_steps": ("offline", "steps"),
    "demonstrations": ("episodes",),  # the setting went unrecorded; what was stored is the nearest
}


def demonstration_settings(run: RunConfig) -> dict[str, Any]:
    """The settings a ``demonstrations.json`` records (its keys beside what was stored and learned)."""
    return {**dataclasses.asdict(run.demos), **dataclasses.asdict(run.cloning_loss), **dataclasses.asdict(run.offline)}


def demonstration_record(record: Mapping[str, Any]) -> dict[str, Any]:
    """A ``demonstrations.json`` record with every setting under its own name, its default
    where it was not recorded; a record written before the names were one (e.g.
    ``cloning_loss_weight`` for ``bc_weight``) reads the same."""
    out = dict(record)
    for key, path in _LEGACY.items():
        if key in out:
            continue
        value: Any = record
        for part in path:
            value = value.get(part) if isinstance(value, Mapping) else None
        if value is not None:
            out[key] = value
    defaults = demonstration_settings(RunConfig())
    return {**defaults, **out}
