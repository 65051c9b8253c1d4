"""A grid's ``observations:`` axis: observation designs, each the ``gym.make`` keywords of
the observation (:data:`~unified_manip.envs.observations.DESIGN_KEYWORDS`), checked against
the env before any run starts."""

from __future__ import annotations

from typing import Any

import numpy as np

from unified_manip.envs.design_names import DESIGN_KEYWORDS, design_label
from unified_manip.envs.observations import PRESETS, build_stream
from unified_manip.envs.setup import env_setup


def parse_designs(value: Any) -> list[dict[str, Any]]:
    """A grid's ``observations``, one run each per design: presets, lists of group names, or
    mappings of :data:`DESIGN_KEYWORDS` (``{observation: default, observation_distractors: 32}``).
    Each design comes back as its ``gym.make`` keywords (none for the default design)."""

    def groups(v: Any) -> bool:
        return isinstance(v, str) or (isinstance(v, list) and bool(v) and all(isinstance(n, str) for n in v))

    shape = (
        f"a non-empty list of presets ({', '.join(PRESETS)}), lists of group names or mappings with keys "
        f"from {', '.join(DESIGN_KEYWORDS)}"
    )
    if not isinstance(value, list) or not value:
        raise ValueError(f"observations must be {shape}, got {value!r}")
    designs = []
    for v in value:
        if isinstance(v, dict):
            unknown = [k for k in v if k not in DESIGN_KEYWORDS]
            if unknown:
                raise ValueError(f"unknown key {unknown[0]!r} in observations; expected {', '.join(DESIGN_KEYWORDS)}")
            if not groups(v.get("observation", "default")):
                raise ValueError(f"observations must be {shape}, got {v!r}")
            design = dict(v)
        elif groups(v):
            design = {"observation": v}
        else:
            raise ValueError(f"observations must be {shape}, got {value!r}")
        designs.append({k: d for k, d in design.items() if not (k == "observation" and d == "default")})
    labels = [design_label(d) for d in designs]
    repeated = sorted({x for x in labels if labels.count(x) > 1})
    if repeated:
        raise ValueError(f"observation design {repeated[0]!r} is listed twice")
    return designs


def check_design(task: str, mode: str, design: dict[str, Any]) -> None:
    """The env's own check of an observation design (its gym.make keywords) on ``task``
    (builds one backend)."""
    setup = env_setup(task, action_mode=mode, **design)
    backend = setup.build_backend()
    try:
        backend.reset(np.random.default_rng(0))
        build_stream(setup.config, backend, setup.task.id)
    finally:
        backend.close()
