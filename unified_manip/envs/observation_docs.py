"""The observation groups of a task as text: ``unified-manip list --doc`` and the task pages."""

from __future__ import annotations

import numpy as np

from unified_manip.envs.observations import PRESETS, describe_groups, resolve_groups
from unified_manip.envs.registry import get_task
from unified_manip.envs.setup import env_setup


def observation_groups_doc(task_id: str, action_mode: str | None = None) -> str:
    """A table of the task's observation groups (size, kind, units, in the default
    vector) and the groups of each preset, under ``action_mode`` (``native``, or the
    task's first mode, by default: Fetch's joint modes add the arm's joints to the default)."""
    if action_mode is None:
        action_mode = "native" if "native" in get_task(task_id).action_modes else get_task(task_id).action_modes[0]
    setup = env_setup(task_id, action_mode=action_mode)
    backend = setup.build_backend()
    try:
        backend.reset(np.random.default_rng(0))
        rows = describe_groups(backend)
        groups, default = backend.observation_groups(), backend.default_observation()
        presets = {p: resolve_groups(p, groups, default, setup.task.id) for p in PRESETS}
    finally:
        backend.close()
    width = max(len(r[0]) for r in rows)
    lines = [
        f"Observation groups (gym.make(..., observation=<preset or list of groups>); "
        f"sizes under action_mode={setup.config.action_mode!r}):",
        f"  {'group':<{width}}  size  kind      default  units",
    ]
    for name, size, units, kind, in_default in rows:
        lines.append(f"  {name:<{width}}  {size:>4}  {kind:<8}  {'yes' if in_default else '':<7}  {units}")
    lines.append("Presets:")
    for preset, names in presets.items():
        size = sum(next(r[1] for r in rows if r[0] == n) for n in names)
        lines.append(f"  {preset} ({size}): {', '.join(names)}")
    moving = [name for name, g in groups.items() if g.goal_dependent]
    lines.append(
        f"Goal-dependent (desired goal minus state; a HER buffer must relabel them too): {', '.join(moving) or 'none'}"
    )
    cameras = ", ".join(setup.task.cameras)
    lines.append(
        "Image groups: rgb (uint8, H x W x 3), depth (float32 m, H x W x 1), e.g. observation=['default', 'rgb'], "
        f"image_size=84; camera= one of {cameras} (default {next(iter(setup.task.cameras), None)})"
    )
    return "\n".join(lines)
