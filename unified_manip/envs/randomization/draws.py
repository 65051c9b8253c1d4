"""Drawing a term's values from the env's generator, and combining them with the nominal ones.

Every draw comes from the ``np.random.Generator`` it is given (the env's ``np_random``),
so the same seed gives the same draws.
"""

from __future__ import annotations

import numpy as np

from unified_manip.envs.randomization.terms import FIELD_WIDTH, RandomizationTerm


def _interval(rng: np.random.Generator, low: float, high: float, exclude, size) -> np.ndarray:
    """Uniform on ``[low, high]``, or on ``[low, x0] U [x1, high]`` when ``exclude = (x0, x1)``."""
    if exclude is None:
        return rng.uniform(low, high, size)
    x0, x1 = exclude
    left = x0 - low
    u = rng.uniform(0.0, left + (high - x1), size)
    return np.where(u < left, low + u, x1 + (u - left))


def draw(term: RandomizationTerm, rng: np.random.Generator, count: int) -> np.ndarray:
    """``(count, width)`` values of ``term`` (``count``: 1 when shared, else one row per element).

    ``shape`` terms give the index of the drawn shape in ``term.shapes``.
    """
    size = (count, FIELD_WIDTH[term.field])
    if term.field == "shape":
        return rng.integers(len(term.shapes), size=size).astype(np.float64)
    low, high = term.range
    if term.distribution == "gaussian":
        return rng.normal(low, high, size)
    if term.distribution == "log_uniform":
        exclude = None if term.exclude is None else tuple(np.log(term.exclude))
        return np.exp(_interval(rng, float(np.log(low)), float(np.log(high)), exclude, size))
    return _interval(rng, low, high, term.exclude, size)


def combine(operation: str, nominal: np.ndarray, value: np.ndarray) -> np.ndarray:
    """The field's new values from its nominal ones: ``abs``, ``scale`` or ``add``."""
    if operation == "abs":
        return np.broadcast_to(value, np.shape(nominal)).astype(np.float64)
    if operation == "scale":
        return nominal * value
    return nominal + value


def value_bounds(term: RandomizationTerm) -> tuple[float, float]:
    """The lowest and highest value a draw of ``term`` can give (infinite for a gaussian)."""
    if term.distribution == "gaussian":
        return -np.inf, np.inf
    return term.range
