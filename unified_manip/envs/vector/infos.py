"""Info dicts of arrays, laid out exactly as Gymnasium's ``SyncVectorEnv`` lays them out.

Gymnasium 1.x vector envs return one ``info`` dict whose entries are arrays over the
envs, each with a boolean mask ``_key`` saying which envs reported it; a nested dict
(``reward_terms``) is laid out the same way, one level down. :func:`merge` adds the
entries of a group of envs (one array per key, rows selected by a mask), so the native
vector env's infos compare equal, key for key and dtype for dtype, with
``SyncVectorEnv``'s over the single env.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

import numpy as np


def merge(out: dict[str, Any], values: Mapping[str, Any], mask: np.ndarray) -> dict[str, Any]:
    """Add ``values`` (``(N,)`` arrays, or dicts of them) at the envs where ``mask`` is True.

    Args:
        out: The info dict being built (modified and returned).
        values: One ``(N,)`` array per key; rows outside ``mask`` are ignored. Float
            entries should be float64 and flags bool, as Gymnasium makes them from
            Python floats and bools.
        mask: bool ``(N,)``.

    Returns:
        ``out``. Nothing is added when ``mask`` is all False.
    """
    every = bool(mask.all())
    if not every and not mask.any():
        return out
    shared = mask.copy()  # one mask array for the keys this call adds
    for key, value in values.items():
        array: Any
        if type(value) is dict:
            array = merge(out.get(key, {}), value, mask)
        else:
            array = out.get(key)
            if array is None and every:  # the common case: every env reports the key
                array = np.array(value)
            else:
                if array is None:
                    array = np.zeros(mask.shape + np.shape(value)[1:], dtype=np.asarray(value).dtype)
                array[mask] = np.asarray(value)[mask]
        seen = out.get(f"_{key}")
        out[key] = array
        out[f"_{key}"] = shared if seen is None else seen | mask
    return out


def objects(rows: Mapping[int, Any], num_envs: int) -> np.ndarray:
    """An object array of ``num_envs`` with ``rows[i]`` at ``i`` and None elsewhere
    (Gymnasium's layout of ``final_obs``)."""
    out = np.full(num_envs, None, dtype=object)
    for i, value in rows.items():
        out[i] = value
    return out


def reset_info(
    success: np.ndarray, quantities: Mapping[str, np.ndarray], at_rest: Sequence[str], extra: Mapping[str, Any]
) -> dict[str, Any]:
    """The info entries of envs that start an episode, as the single env's ``reset`` gives
    them: ``is_success`` (float64), the task's quantities, the reward inputs that are 0 at
    rest (``at_rest``: its events and ``action_sq``) and no instability."""
    n = len(success)
    return {
        "is_success": success,
        **quantities,
        **{k: np.zeros(n) for k in at_rest},
        "sim_unstable": np.zeros(n, dtype=bool),
        **extra,
    }


def gather(out: dict[str, np.ndarray], values: Mapping[str, Any], i: int, num_envs: int) -> dict[str, np.ndarray]:
    """Add env ``i``'s scalar info entries ``values`` to ``out``'s ``(num_envs,)`` arrays
    (made on first sight, with the value's Python type as dtype); return ``out``."""
    for key, value in values.items():
        if key not in out:
            out[key] = np.zeros(num_envs, dtype=type(value) if isinstance(value, (bool, int, float)) else object)
        out[key][i] = value
    return out


def merge_rows(out: dict[str, Any], key: str, rows: Mapping[int, Mapping[str, float]], num_envs: int) -> dict[str, Any]:
    """Add ``out[key]``, a nested group of floats, from the dicts ``rows[i]`` of some envs
    (all with the same keys), laid out as ``SyncVectorEnv`` lays out a nested info dict."""
    if not rows:
        return out
    mask = np.zeros(num_envs, dtype=bool)
    mask[list(rows)] = True
    keys = next(iter(rows.values()))
    values = {k: np.array([rows[i][k] if i in rows else 0.0 for i in range(num_envs)]) for k in keys}
    return merge(out, {key: values}, mask)
