"""The named randomisation presets, their extreme counterparts, and the test distributions.

``randomization=`` takes a preset name, several joined by ``+`` (``"dynamics+objects"``),
each optionally followed by ``:extreme`` (its ranges beyond training) or ``:in-range``
(its own ranges), or a list of terms. The presets' entities (``object``, ``table``,
``robot``, ``light``, ``camera``) are the names every family gives its entities; a preset
term whose entity a task lacks, or which its model cannot take (a mesh's shape), is left
out on that task, while a term given explicitly must apply. The ranges and why they were
chosen are documented on the randomisation page of the docs (``docs/randomization.md``).

The extreme counterparts follow Packer et al. (2018): each draws from a wider range with
the training range excluded, so that an extreme value is never one seen in training.
"""

from __future__ import annotations

import hashlib
import json
from typing import Any

from unified_manip.envs.randomization.terms import RandomizationTerm, choices, term_from

T = RandomizationTerm

#: The robot's joints and servos and the table's surface.
DYNAMICS: tuple[RandomizationTerm, ...] = (
    T("robot", "damping", (0.5, 2.0), "log_uniform", shared=False),
    T("robot", "armature", (0.5, 2.0), "log_uniform", shared=False),
    T("robot", "actuator_gain", (0.75, 1.5), "log_uniform", shared=False),
    T("table", "friction", (0.5, 1.5)),
)
DYNAMICS_EXTREME: tuple[RandomizationTerm, ...] = (
    T("robot", "damping", (0.25, 4.0), "log_uniform", exclude=(0.5, 2.0), shared=False),
    T("robot", "armature", (0.25, 4.0), "log_uniform", exclude=(0.5, 2.0), shared=False),
    T("robot", "actuator_gain", (0.5, 2.25), "log_uniform", exclude=(0.75, 1.5), shared=False),
    T("table", "friction", (0.25, 2.0), exclude=(0.5, 1.5)),
)

#: The object: its shape, size, mass and friction.
OBJECTS: tuple[RandomizationTerm, ...] = (
    T("object", "shape", operation="abs", shapes=("box", "cylinder", "sphere")),
    T("object", "size", (0.9, 1.1)),
    T("object", "mass", (0.5, 2.0), "log_uniform"),
    T("object", "friction", (0.5, 1.5)),
)
OBJECTS_EXTREME: tuple[RandomizationTerm, ...] = (
    T("object", "shape", operation="abs", shapes=("box", "cylinder", "sphere")),
    T("object", "size", (0.7, 1.3), exclude=(0.9, 1.1)),
    T("object", "mass", (0.25, 4.0), "log_uniform", exclude=(0.5, 2.0)),
    T("object", "friction", (0.25, 2.0), exclude=(0.5, 1.5)),
)

#: What a camera sees: colours, light and the camera's pose.
VISUAL: tuple[RandomizationTerm, ...] = (
    T("table", "rgba", (-0.2, 0.2), operation="add"),
    T("object", "rgba", (-0.3, 0.3), operation="add"),
    T("light", "light", (0.5, 1.5)),
    T("camera", "camera_pose", (-0.02, 0.02), operation="add"),
)
VISUAL_EXTREME: tuple[RandomizationTerm, ...] = (
    T("table", "rgba", (-0.5, 0.5), operation="add", exclude=(-0.2, 0.2)),
    T("object", "rgba", (-0.6, 0.6), operation="add", exclude=(-0.3, 0.3)),
    T("light", "light", (0.2, 2.0), exclude=(0.5, 1.5)),
    T("camera", "camera_pose", (-0.06, 0.06), operation="add", exclude=(-0.02, 0.02)),
)

#: Every preset, by name, as the terms it asks for (``none``: no term, the nominal task).
PRESETS: dict[str, tuple[RandomizationTerm, ...]] = {
    "none": (),
    "dynamics": DYNAMICS,
    "objects": OBJECTS,
    "visual": VISUAL,
    "all": DYNAMICS + OBJECTS + VISUAL,
}
#: Each preset's ranges beyond training (``<preset>:extreme``).
EXTREME: dict[str, tuple[RandomizationTerm, ...]] = {
    "none": (),
    "dynamics": DYNAMICS_EXTREME,
    "objects": OBJECTS_EXTREME,
    "visual": VISUAL_EXTREME,
    "all": DYNAMICS_EXTREME + OBJECTS_EXTREME + VISUAL_EXTREME,
}
#: The distributions a policy is tested on (Packer et al. 2018): ``default`` the nominal
#: task, ``in-range`` the training preset's ranges, ``extreme`` its ranges beyond them.
TEST_DISTRIBUTIONS: tuple[str, ...] = ("default", "in-range", "extreme")
_SUFFIXES = ("extreme", "in-range")


def preset_terms(name: str) -> tuple[RandomizationTerm, ...]:
    """The terms of a preset name (``"objects"``, ``"dynamics+objects:extreme"``).

    Raises:
        ValueError: An unknown preset or suffix, naming the valid ones.
    """
    if not isinstance(name, str):
        raise TypeError(f"a randomization preset must be a name, got {name!r}")
    terms: list[RandomizationTerm] = []
    for part in name.split("+"):
        preset, sep, suffix = part.strip().partition(":")
        if preset not in PRESETS:
            raise ValueError(
                f"unknown randomization preset {preset!r}; expected one of {choices(PRESETS)} "
                "(joined by '+', each optionally ':extreme' or ':in-range'), or a list of terms"
            )
        if sep and suffix not in _SUFFIXES:
            raise ValueError(f"unknown suffix {suffix!r} of preset {preset!r}; expected one of {choices(_SUFFIXES)}")
        terms.extend(EXTREME[preset] if suffix == "extreme" else PRESETS[preset])
    return tuple(terms)


def distribution_for(preset: str, distribution: str) -> str:
    """The ``randomization`` value that tests a policy trained under ``preset`` on
    ``distribution`` (:data:`TEST_DISTRIBUTIONS`): ``none``, the preset itself, or each
    of its presets' ``:extreme`` counterpart."""
    if distribution not in TEST_DISTRIBUTIONS:
        raise ValueError(f"unknown test distribution {distribution!r}; expected one of {choices(TEST_DISTRIBUTIONS)}")
    preset_terms(preset)  # a bad name fails here
    if distribution == "default":
        return "none"
    parts = [p.strip().partition(":")[0] for p in preset.split("+")]
    if distribution == "in-range":
        return "+".join(parts)
    return "+".join(f"{p}:extreme" for p in parts)


def randomization_label(value: Any) -> str:
    """How run names, result tables and reports spell a ``randomization`` value: a preset
    name as written (``"none"``, ``"dynamics+objects"``; spaces around ``+`` dropped), or
    ``terms-<8 hex digits>`` for a list of terms (a digest of the terms, so different
    lists have different names). A missing value (``None``, a run from before
    randomisation) is ``"none"``."""
    if value is None:
        return "none"
    if isinstance(value, str):
        return "+".join(part.strip() for part in value.split("+"))
    terms = [term_from(t).as_dict() for t in value]
    if not terms:
        return "none"
    return "terms-" + hashlib.sha1(json.dumps(terms, sort_keys=True).encode()).hexdigest()[:8]
