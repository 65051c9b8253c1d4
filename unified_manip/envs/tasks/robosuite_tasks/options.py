"""Options the robosuite tasks accept (``gym.make(..., robot="Sawyer")``), validated."""

from __future__ import annotations

from typing import Any

#: Robots accepted by the ``robot`` option (single-arm robots tested on every task's Lift).
ROBOTS: tuple[str, ...] = ("Panda", "Sawyer", "UR5e", "IIWA", "Kinova3", "Jaco")

#: Options the family accepts, with their defaults.
DEFAULT_OPTIONS: dict[str, Any] = {"robot": "Panda"}

#: The camera options of old, now the image groups every family has (``unified_manip.envs.cameras``).
REPLACED_OPTIONS: tuple[str, ...] = ("camera_obs", "camera_width", "camera_height")
REPLACEMENT = "observation=['default', 'rgb'] with camera='agentview' and image_size=84"


def validate_options(options: dict[str, Any]) -> dict[str, Any]:
    replaced = [k for k in REPLACED_OPTIONS if k in options]
    if replaced:
        raise TypeError(f"{replaced[0]} was replaced by the image groups of every family: {REPLACEMENT}")
    unknown = sorted(set(options) - set(DEFAULT_OPTIONS))
    if unknown:
        raise TypeError(f"robosuite tasks got unknown options {unknown}; expected some of {sorted(DEFAULT_OPTIONS)}")
    opts = {**DEFAULT_OPTIONS, **options}
    if opts["robot"] not in ROBOTS:
        raise ValueError(f"unknown robot {opts['robot']!r}; expected one of {', '.join(repr(r) for r in ROBOTS)}")
    return opts
