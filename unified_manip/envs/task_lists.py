"""Named task lists: a benchmark's set of IDs under one name, ``<family>:<list>`` (e.g.
``metaworld:MT10``), which a bench grid's ``tasks:`` may name in place of its IDs.

A family package declares its lists as ``TASK_LISTS = {list name: (ID, ...)}``;
:mod:`unified_manip.envs.tasks` registers them here under the family's name. IDs never
hold a colon, so an entry with one is a list.
"""

from __future__ import annotations

from typing import Iterable

#: Every registered list, ``family:name`` -> its IDs, in the benchmark's order.
TASK_LISTS: dict[str, tuple[str, ...]] = {}


def register_task_lists(family: str, lists: dict[str, tuple[str, ...]]) -> None:
    """Add ``family``'s lists as ``family:name``."""
    for name, ids in lists.items():
        key = f"{family}:{name}"
        if key in TASK_LISTS:
            raise ValueError(f"task list {key} is already registered")
        TASK_LISTS[key] = tuple(ids)


def expand_task_lists(entries: Iterable[str]) -> list[str]:
    """``entries`` with each list name replaced by its IDs, in order, each ID once.

    Raises:
        ValueError: an entry holds a colon but names no registered list (one line naming
            the valid lists).
    """
    out: list[str] = []
    for entry in entries:
        if ":" not in entry:
            ids: Iterable[str] = (entry,)
        elif entry in TASK_LISTS:
            ids = TASK_LISTS[entry]
        else:
            raise ValueError(f"unknown task list {entry!r}; expected one of {', '.join(TASK_LISTS) or '(none)'}")
        out.extend(i for i in ids if i not in out)
    return out
