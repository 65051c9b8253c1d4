"""A grid's ``randomizations:`` axis: the training distributions of its runs, each a
randomisation preset (:mod:`unified_manip.envs.randomization`), checked against every
task before any run starts.

``none`` (the nominal task) adds nothing to a run's name or env keyword arguments, so a
grid without the axis, or with ``[none]``, names and runs its runs as before; any other
preset is its runs' ``randomization`` keyword and their names' ``__rand-<preset>``.
"""

from __future__ import annotations

from typing import Any

from unified_manip.envs.randomization import PRESETS, preset_terms, randomization_label
from unified_manip.envs.randomization.randomizer import build_randomizer
from unified_manip.envs.setup import env_setup


def parse_randomizations(value: Any) -> list[str]:
    """A grid's ``randomizations``: a non-empty list of preset names (``none``, ``dynamics``,
    ``objects``, ``visual``, ``all``, joined by ``+``), each as run names spell it.

    Raises:
        ValueError: Not such a list, an unknown preset, or one listed twice.
    """
    shape = f"a non-empty list of randomization presets ({', '.join(PRESETS)}, joined by '+')"
    if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
        raise ValueError(f"randomizations must be {shape}, got {value!r}")
    for v in value:
        preset_terms(v)  # an unknown preset names the valid ones
    labels = [randomization_label(v) for v in value]
    repeated = sorted({x for x in labels if labels.count(x) > 1})
    if repeated:
        raise ValueError(f"randomization {repeated[0]!r} is listed twice")
    return labels


def grid_randomizations(doc: dict[str, Any], env_kwargs: dict[str, Any]) -> list[str]:
    """The training presets of a grid ``doc`` whose ``env_kwargs`` are given: its
    ``randomizations``, or without them the one its ``env_kwargs`` may set (``none`` where
    it sets none); both at once is an error."""
    if "randomizations" not in doc:
        return [randomization_label(env_kwargs.get("randomization"))]
    if "randomization" in env_kwargs:
        raise ValueError("randomization is set in both env_kwargs and randomizations; keep randomizations")
    return parse_randomizations(doc["randomizations"])


def check_randomization(task: str, mode: str, preset: Any) -> None:
    """Raise ``ValueError`` unless ``preset`` (a ``randomization`` value) applies to ``task``:
    a preset with a term the task can take, or terms that all apply (builds one backend)."""
    if randomization_label(preset) == "none":
        return
    setup = env_setup(task, action_mode=mode, randomization=preset)
    backend = setup.build_backend()
    try:
        build_randomizer(preset, setup.task.entities, backend, setup.task.id)
    finally:
        backend.close()
