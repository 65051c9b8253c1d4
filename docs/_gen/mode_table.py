"""The action-mode table across tasks, generated from the controller configs: the site's
action-modes page shows it (the ``gen:mode-table`` marker, :mod:`hooks`), and
``python docs/_gen/mode_table.py`` prints it."""

from __future__ import annotations

from typing import Mapping

from unified_manip import ACTION_MODES, TASKS
from unified_manip.envs.controllers import ControllerConfig


def _labelled_controllers(tasks) -> list[tuple[str, Mapping[str, ControllerConfig], Mapping | None]]:
    """``(label, controllers, family's)``: each family's first task's controllers under
    the family's name (``family's`` None), then every task whose controllers differ from
    those under ``"family (Name-vN)"`` (e.g. Arm4Push-v1's doubled steps)."""
    first: dict[str, Mapping[str, ControllerConfig]] = {}
    labelled: list[tuple[str, Mapping[str, ControllerConfig], Mapping | None]] = []
    for spec in tasks.values():
        if spec.family not in first:
            first[spec.family] = spec.controllers
            labelled.append((spec.family, spec.controllers, None))
        elif spec.controllers != first[spec.family]:
            labelled.append((f"{spec.family} ({spec.id.split('/', 1)[1]})", spec.controllers, first[spec.family]))
    return labelled


def mode_table(tasks=None) -> str:
    """Markdown: one row per mode and distinct config, naming the families (and the
    tasks whose config of that mode differs from their family's) that use it."""
    if tasks is None:
        tasks = TASKS
    labelled = _labelled_controllers(tasks)
    rows = ["| mode | families | the action (`a` in [-1, 1] per joint or axis) |", "|---|---|---|"]
    for mode in ACTION_MODES:
        by_config: dict[ControllerConfig, list[str]] = {}
        for label, controllers, family in labelled:
            if mode in controllers and (family is None or family.get(mode) != controllers[mode]):
                by_config.setdefault(controllers[mode], []).append(label)
        for config, names in by_config.items():
            rows.append(f"| `{mode}` | {', '.join(names)} | {config.describe()} |")
    return "\n".join(rows)


if __name__ == "__main__":
    print(mode_table())
