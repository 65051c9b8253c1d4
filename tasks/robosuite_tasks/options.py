"""Options the robosuite tasks accept (``gym.make(..., robot="Sawyer")``), validated."""

from __future__ import annotations

from typing import Any

#: Robots accepted by the ``robot`` option (single-arm robots tested on every task's Lift).
ROBOTS: tuple[str, ...] = ("Panda", "Sawyer", "UR5e", "IIWA", "Kinova3", "Jaco")

#: Options the family accepts, with their defaults.
DEFAULT_OPTIONS: dict[str, Any] = {"robot": "Panda", "camera_obs": False, "camera_width": 84, "camera_height": 84}


def validate_options(options: dict[str, Any]) -> dict[str, Any]:
    unknown = sorted(set(options) - set(DEFAULT_OPTIONS))
    if unknown:
        raise TypeError(f"robosuite tasks got unknown options {unknown}; expected some of {sorted(DEFAULT_OPTIONS)}")
    opts = {**DEFAULT_OPTIONS, **options}
    if opts["robot"] not in ROBOTS:
        raise ValueError(f"unknown robot {opts['robot']!r}; expected one of {', '.join(repr(r) for r in ROBOTS)}")
    if not isinstance(opts["camera_obs"], bool):
        raise TypeError(f"camera_obs must be a bool, got {type(opts['camera_obs']).__name__}")
    for key in ("camera_width", "camera_height"):
        if not isinstance(opts[key], int) or opts[key] <= 0:
            raise ValueError(f"{key} must be a positive int, got {opts[key]!r}")
    return opts
