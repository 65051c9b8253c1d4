"""Families from other packages: the ``unified_manip.families`` entry-point group.

A separately installed package adds IDs, with no edit here, by naming a module that
defines ``SPECS`` (a sequence of :class:`~unified_manip.envs.registry.TaskSpec`) in its
``pyproject.toml``::

    [project.entry-points."unified_manip.families"]
    valve = "unified_manip_valve.specs"

``import unified_manip`` registers them after the built-in families, in the order of the
installed distributions' names. As Gymnasium does with its own plugins, a family that
fails to load does not stop the others: it is skipped with one warning line
(:class:`FamilyPluginWarning`) naming the package and its error, and the same line ends
the error of :func:`~unified_manip.envs.registry.get_task` for an ID nobody registered,
which is what the CLI prints. ``examples/valve_family/`` is such a package.
"""

from __future__ import annotations

import warnings
from importlib.metadata import EntryPoint, entry_points
from typing import Callable

from unified_manip.envs.registry import PLUGIN_FAILURES, TASKS, TaskSpec

#: The entry-point group a family package registers under.
GROUP = "unified_manip.families"


class FamilyPluginWarning(UserWarning):
    """A family plugin failed to load; its IDs are not registered."""


def _package(ep: EntryPoint) -> str:
    return ep.dist.name if ep.dist is not None else ep.module


def _specs(ep: EntryPoint) -> tuple[TaskSpec, ...]:
    """The plugin's specs, checked before any of them is registered."""
    family = ep.load()
    specs = getattr(family, "SPECS", None)
    if specs is None:
        raise TypeError(f"{ep.value} has no SPECS (a sequence of TaskSpec)")
    specs = tuple(specs)
    bad = [type(s).__name__ for s in specs if not isinstance(s, TaskSpec)]
    if bad or not specs:
        raise TypeError(f"{ep.value}.SPECS must be a non-empty sequence of TaskSpec, got {bad or 'none'}")
    taken = [s.id for s in specs if s.id in TASKS]
    if taken or len({s.id for s in specs}) != len(specs):
        raise ValueError(f"{ep.value}.SPECS registers IDs twice or already registered: {taken or 'a repeat'}")
    return specs


def load_plugin_families(register: Callable[[TaskSpec], TaskSpec]) -> tuple[str, ...]:
    """Register every installed family plugin's specs with ``register``; return the IDs added.

    A plugin that fails to load registers nothing; its failure is warned about once and
    kept in :data:`~unified_manip.envs.registry.PLUGIN_FAILURES`."""
    added: list[str] = []
    for ep in sorted(entry_points(group=GROUP), key=lambda e: (_package(e), e.name)):
        try:
            specs = _specs(ep)
        except Exception as err:  # any error of a third-party import: report it, load the rest
            line = (
                f"the family plugin {ep.name!r} of package {_package(ep)!r} failed to load: {type(err).__name__}: {err}"
            )
            PLUGIN_FAILURES.append(line)
            warnings.warn(line, FamilyPluginWarning, stacklevel=2)
            continue
        added += [register(spec).id for spec in specs]
    return tuple(added)
