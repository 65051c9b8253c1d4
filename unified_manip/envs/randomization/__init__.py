"""Domain randomisation: terms that write MuJoCo model fields of named entities.

``gym.make(ID, randomization=...)`` takes a preset name (``none``, the default, and
``dynamics``, ``objects``, ``visual``, ``all``, with ``:extreme`` counterparts) or a list
of :class:`RandomizationTerm` s. Each family names its entities once (``TaskSpec.entities``);
the env draws every value from its own ``np_random``, shows the values in force in
``info["randomization"]`` and on ``env.unwrapped.randomization_state()``.

Modules, one concept each: :mod:`.terms` (the term config), :mod:`.draws` (distributions
and operations), :mod:`.entities` (named parts of a model), :mod:`.fields` (how each field
is written), :mod:`.geometry` (what a mass, size or shape change leaves to derive),
:mod:`.presets` (the presets and test distributions), :mod:`.randomizer` (one env's terms).
"""

from unified_manip.envs.randomization.entities import Entity, RestHeight
from unified_manip.envs.randomization.presets import (
    EXTREME,
    PRESETS,
    TEST_DISTRIBUTIONS,
    distribution_for,
    preset_terms,
    randomization_label,
)
from unified_manip.envs.randomization.terms import (
    DISTRIBUTIONS,
    FIELDS,
    MODES,
    OPERATIONS,
    SHAPES,
    RandomizationTerm,
    term_from,
)

__all__ = [
    "DISTRIBUTIONS",
    "EXTREME",
    "FIELDS",
    "MODES",
    "OPERATIONS",
    "PRESETS",
    "SHAPES",
    "TEST_DISTRIBUTIONS",
    "Entity",
    "RandomizationTerm",
    "RestHeight",
    "preset_terms",
    "term_from",
    "distribution_for",
    "randomization_label",
]
