"""Training on image observations: a CNN per image key, and the replay buffer's memory.

SB3's ``MultiInputPolicy`` builds its ``CombinedExtractor``: a ``NatureCNN`` for every key
that ``is_image_space`` accepts (uint8, values 0..255, 3 dimensions), a flattening for the
rest. That takes ``rgb`` (SB3 transposes it to channels-first with ``VecTransposeImage``
and scales it by 1/255), but not ``depth``: float32 metres fail the dtype check, so 84 x 84
depth would be flattened into 7,056 MLP inputs. :class:`ImageExtractor` gives every
3-dimensional key a ``NatureCNN``: uint8 images as SB3 does, float images
(``normalized_image=True``: no dtype check, no scaling) made channels-first here.

An image replay buffer is large (1e6 transitions of 84 x 84 RGB: ~42 GB, observation and
next observation), so ``train`` estimates it (:func:`buffer_bytes`) and refuses, before it
starts, one larger than the memory available (:func:`check_buffer_fits`).
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np
import torch as th
from gymnasium import spaces
from stable_baselines3.common.preprocessing import get_flattened_obs_dim, is_image_space_channels_first
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor, NatureCNN
from torch import nn

#: SB3's ``buffer_size`` default for the off-policy algorithms.
SB3_BUFFER_SIZE = 1_000_000
#: Of the available memory, the share a suggested buffer may fill (the rest: the
#: networks, the envs, the process itself).
BUFFER_SHARE = 0.8


def has_images(space: Any) -> bool:
    """Whether a Dict observation space has an image key (a 3-dimensional Box)."""
    parts = getattr(space, "spaces", None)
    return isinstance(parts, dict) and any(len(s.shape) == 3 for s in parts.values())


class ImageExtractor(BaseFeaturesExtractor):
    """A ``NatureCNN`` per image key (uint8 or float, channels first or last), a
    flattening per vector key, concatenated (SB3's ``CombinedExtractor`` otherwise).

    Args:
        observation_space: The policy's Dict observation space.
        cnn_output_dim: Features of each image key's CNN.
    """

    def __init__(self, observation_space: spaces.Dict, cnn_output_dim: int = 256) -> None:
        super().__init__(observation_space, features_dim=1)
        extractors: dict[str, nn.Module] = {}
        self._permute: list[str] = []
        total = 0
        for key, sub in observation_space.spaces.items():
            if len(sub.shape) != 3:
                extractors[key] = nn.Flatten()
                total += get_flattened_obs_dim(sub)
                continue
            uint8 = sub.dtype == np.uint8
            if not is_image_space_channels_first(sub):  # SB3 transposes only uint8 images
                self._permute.append(key)
                sub = spaces.Box(np.moveaxis(sub.low, -1, 0), np.moveaxis(sub.high, -1, 0), dtype=sub.dtype)
            extractors[key] = NatureCNN(sub, features_dim=cnn_output_dim, normalized_image=not uint8)
            total += cnn_output_dim
        self.extractors = nn.ModuleDict(extractors)
        self._features_dim = total

    def forward(self, observations: dict[str, th.Tensor]) -> th.Tensor:
        encoded = []
        for key, extractor in self.extractors.items():
            x = observations[key]
            if key in self._permute:
                x = x.permute(0, 3, 1, 2)
            encoded.append(extractor(x))
        return th.cat(encoded, dim=1)


def with_image_extractor(policy_kwargs: dict[str, Any] | None) -> dict[str, Any]:
    """``policy_kwargs`` with :class:`ImageExtractor`, unless it names an extractor."""
    kwargs = dict(policy_kwargs or {})
    kwargs.setdefault("features_extractor_class", ImageExtractor)
    return kwargs


def buffer_bytes(observation_space: Any, action_dim: int, buffer_size: int, her: bool) -> int:
    """The memory SB3's (HER / dict) replay buffer of ``buffer_size`` transitions holds:
    observation and next observation in their dtypes, the float32 action, reward, done
    and timeout, and HER's two int64 episode indices per transition."""
    parts = getattr(observation_space, "spaces", {"obs": observation_space})
    obs = sum(int(np.prod(s.shape)) * np.dtype(s.dtype).itemsize for s in parts.values())
    per_transition = 2 * obs + 4 * action_dim + 3 * 4 + (2 * 8 if her else 0)
    return int(buffer_size) * per_transition


def available_bytes() -> int | None:
    """The memory available to a new process (Linux ``MemAvailable``), or None if unknown."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def _gb(n: float) -> str:
    return f"{n / 1e9:.1f} GB"


def check_buffer_fits(observation_space: Any, action_dim: int, buffer_size: int, her: bool) -> None:
    """``ValueError`` in one line when the replay buffer needs more memory than is
    available: the size it needs, what is available, and a ``buffer_size`` that fits."""
    available = available_bytes()
    if available is None:
        return
    need = buffer_bytes(observation_space, action_dim, buffer_size, her)
    if need <= available:
        return
    per = need / buffer_size
    fits = max(int(BUFFER_SHARE * available / per), 1)
    scale = 10 ** (len(str(fits)) - 1)
    suggestion = fits // scale * scale  # one significant digit, rounded down: 123_456 -> 100_000
    raise ValueError(
        f"the replay buffer of {buffer_size:,} transitions needs {_gb(need)} of memory "
        f"({per / 1e3:.1f} kB per transition) and {_gb(available)} is available; "
        f"set buffer_size={suggestion} or less (--set buffer_size={suggestion})"
    )
