"""The Box(-1, 1) action contract every mode shares: shape, finiteness, clipping.

One check for the single env and the native vector env (one row per env), so both
reject the same actions with the same words.
"""

from __future__ import annotations

import numpy as np


def checked_actions(actions, shape: tuple[int, ...], expected: str) -> np.ndarray:
    """``actions`` as float64 clipped to [-1, 1].

    ``expected`` is the sentence a wrong shape reports (``"action must have shape
    (4,) for ..."``); a non-finite action names its env when ``shape`` is batched.
    """
    a = np.asarray(actions, dtype=np.float64)
    if a.shape != shape:
        raise ValueError(f"{expected}, got shape {a.shape}")
    if not np.isfinite(a).all():
        rows = np.atleast_2d(a)
        i = int(np.flatnonzero(~np.isfinite(rows).all(axis=1))[0])
        which = "action" if a.ndim == 1 else f"action of env {i}"
        raise ValueError(f"{which} must be finite, got {rows[i].tolist()} (NaN or inf)")
    return np.minimum(np.maximum(a, -1.0), 1.0)  # faster than np.clip on tiny arrays


def squared_norm(action: np.ndarray) -> float:
    """``action @ action`` (the reward's ``action_sq``) for one checked action.

    OpenBLAS's dot sums in an order that depends on whether the array starts on a 16-byte
    boundary (measured on SSE3 and AVX-512 kernels: a vector of 5 moved by 8 bytes changed
    the last bit in 41 of 2,000 draws). So an action that does not start on one (a row of
    a batch with an odd number of columns) is summed from a fresh copy, which numpy
    allocates aligned; a checked action already is one, and is not copied again.
    """
    a = np.asarray(action, dtype=np.float64)
    if a.ctypes.data % 16 or not a.flags.c_contiguous:
        a = a.copy()
    return float(a @ a)


def squared_norms(actions: np.ndarray) -> np.ndarray:
    """:func:`squared_norm` of each row of a batch, bit for bit."""
    return np.array([squared_norm(row) for row in actions])
