"""``--only KEY=VALUE``: the runs of a bench a command acts on (``bench`` trains them,
``robustness`` evaluates them), by the keys run names are made of."""

from __future__ import annotations

from typing import Any, Mapping

#: The keys ``--only`` selects on, as run names and results rows show them.
SELECT_KEYS = ("task", "action_mode", "reward_type", "algo", "seed", "observation", "randomization")


def parse_only(select: tuple[str, ...]) -> dict[str, set[str]]:
    """``key -> the values asked for`` (values of one key are alternatives; keys must all
    match).

    Raises:
        ValueError: An item that is not ``KEY=VALUE`` with a key of :data:`SELECT_KEYS`.
    """
    wanted: dict[str, set[str]] = {}
    for item in select:
        key, sep, value = item.partition("=")
        if not sep or key not in SELECT_KEYS or not value:
            raise ValueError(f"malformed --only {item!r}; expected KEY=VALUE with KEY one of {', '.join(SELECT_KEYS)}")
        wanted.setdefault(key, set()).add(value)
    return wanted


def matches(values: Mapping[str, Any], wanted: Mapping[str, set[str]]) -> bool:
    """Whether a run's ``values`` (its grid entry's or results row's keys) match every key of
    ``wanted``."""
    return all(str(values[k]) in v for k, v in wanted.items())
