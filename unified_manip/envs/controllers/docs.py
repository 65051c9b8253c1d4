"""A task page's action modes, generated from its controller configs
(``unified-manip list --doc``); the table across tasks (the site's action-modes page) is
``docs/_gen/mode_table.py``'s."""

from __future__ import annotations

import textwrap
from typing import Mapping

from unified_manip.envs.controllers.configs import ControllerConfig


def modes_section(controllers: Mapping[str, ControllerConfig], width: int = 88) -> str:
    """A task page's list of its action modes, one config description each, then the
    parameters each mode's ``controller_options`` may set, with their values here."""
    pad = max(len(mode) for mode in controllers) + 6
    lines = []
    for mode, config in controllers.items():
        lines += textwrap.wrap(
            config.describe().replace("`", ""),
            width,
            initial_indent=f"    {mode:<{pad - 4}}",
            subsequent_indent=" " * pad,
        )
    params = "; ".join(
        f"{mode}: " + ", ".join(f"{name}={value!r}" for name, value in config.parameters().items())
        for mode, config in controllers.items()
        if config.parameters()
    )
    if params:
        lines += textwrap.wrap(
            f"gym.make(..., controller_options={{...}}) sets a mode's parameters ({params}).",
            width,
            initial_indent="    ",
            subsequent_indent="    ",
        )
    return "\n".join(lines)
