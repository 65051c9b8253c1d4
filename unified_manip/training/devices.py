"""Which torch device a run trains on (``auto``, ``cpu`` or ``cuda``), and with how many CPU threads."""

from __future__ import annotations

import os

DEVICES = ("auto", "cpu", "cuda")


class DeviceError(ValueError):
    """An unknown device, or ``cuda`` where torch sees no GPU (one-line error, exit 2)."""


def resolve_device(name: str) -> str:
    """``auto`` becomes ``cuda`` when torch sees a GPU and ``cpu`` otherwise.

    Raises :class:`DeviceError` for a name outside :data:`DEVICES`, or for ``cuda`` on a
    machine without one, naming the valid choices.
    """
    if name not in DEVICES:
        raise DeviceError(f"unknown device {name!r}; expected one of {', '.join(DEVICES)}")
    import torch

    available = torch.cuda.is_available()
    if name == "cuda" and not available:
        raise DeviceError("device 'cuda' requested but torch sees no GPU here; use --device cpu or auto")
    if name == "auto":
        return "cuda" if available else "cpu"
    return name


def default_threads() -> int:
    """OMP_NUM_THREADS where the user set it (torch.set_num_threads would override it),
    else up to 2."""
    try:
        return max(1, int(os.environ["OMP_NUM_THREADS"]))
    except (KeyError, ValueError):
        return max(1, min(2, os.cpu_count() or 1))
