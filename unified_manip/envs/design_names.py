"""Names of observation designs: how run names, result tables and the CLI spell a design
(:mod:`unified_manip.envs.observations` builds it)."""

from __future__ import annotations

from typing import Any, Mapping, Sequence

from unified_manip.envs.observations import PRESETS


def observation_label(observation: str | Sequence[str]) -> str:
    """A design's name in run names and result tables: the preset, or the groups joined by ``+``."""
    return observation if isinstance(observation, str) else "+".join(observation)


#: The gym.make keywords (and EnvConfig fields) that make up an observation design.
DESIGN_KEYWORDS = ("observation", "observation_distractors", "observation_noise", "observation_delay")


def design_label(env_kwargs: Mapping[str, Any]) -> str:
    """A run's observation design as run names and result tables show it: the
    :func:`observation_label`, then each training-time perturbation not at its default
    (``default+distractors32``, ``relative+noise0.01``, ``minimal+delay1``; a per-group noise
    reads ``+noise_joint_pos0.01_object_pos0.02``)."""
    label = observation_label(env_kwargs.get("observation", "default"))
    distractors = env_kwargs.get("observation_distractors", 0)
    noise = env_kwargs.get("observation_noise", 0.0)
    delay = env_kwargs.get("observation_delay", 0)
    if distractors:
        label += f"+distractors{distractors}"
    if isinstance(noise, Mapping):
        if any(noise.values()):
            label += "+noise_" + "_".join(f"{g}{s:g}" for g, s in noise.items() if s)
    elif noise:
        label += f"+noise{noise:g}"
    if delay:
        label += f"+delay{delay}"
    return label


def parse_observation(text: str) -> str | list[str]:
    """``--observation``'s value: a preset name, or group names separated by commas (a
    list, as YAML writes it in ``config.yaml``; one name that is not a preset is a list of one)."""
    return text if text in PRESETS else [n.strip() for n in text.split(",")]
