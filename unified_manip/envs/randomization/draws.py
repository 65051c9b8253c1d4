"""Drawing a term's values from the env's generator, and combining them with the nominal ones.

Every draw comes from the ``np.random.Generator`` it is given (the env's ``np_random``),
so the same seed gives the same draws.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from unified_manip.envs.randomization.terms import FIELD_WIDTH, RandomizationTerm


class DrawPlan:
    """The draws of some terms, made together: one generator call for all of them (two
    when one is Gaussian), in the terms' order, so that drawing costs the same few numpy
    operations however many terms there are.

    Args:
        terms: ``(term, rows)`` pairs: each term draws ``rows`` rows of its field's width
            (``rows`` is 1 when the term is shared, else one per element).
    """

    def __init__(self, terms: Sequence[tuple[RandomizationTerm, int]]) -> None:
        lo: list[float] = []
        span: list[float] = []
        x0: list[float] = []
        gap: list[float] = []
        log: list[bool] = []
        k: list[float] = []
        gauss: list[bool] = []
        mean: list[float] = []
        std: list[float] = []
        self.splits: list[tuple[int, int, tuple[int, int]]] = []
        n = 0
        for term, rows in terms:
            width = FIELD_WIDTH[term.field]
            size = rows * width
            self.splits.append((n, n + size, (rows, width)))
            n += size
            low, high = term.range
            is_log = term.distribution == "log_uniform"
            if is_log:
                low, high = math.log(low), math.log(high)
            cut, jump = math.inf, 0.0
            if term.exclude is not None:
                e0, e1 = (math.log(v) for v in term.exclude) if is_log else term.exclude
                cut, jump = e0, e1 - e0
            for floats, value in (
                (lo, low),
                (span, high - low - jump),
                (x0, cut),
                (gap, jump),
                (k, float(len(term.shapes)) if term.field == "shape" else 0.0),
                (mean, term.range[0]),
                (std, term.range[1]),
            ):
                floats.extend([value] * size)
            log.extend([is_log] * size)
            gauss.extend([term.distribution == "gaussian"] * size)
        self.size = n
        self._lo, self._span, self._x0, self._gap = (np.array(v, dtype=np.float64) for v in (lo, span, x0, gap))
        self._log = np.array(log, dtype=np.bool_)
        self._k = np.array(k, dtype=np.float64)
        self._gauss = np.array(gauss, dtype=np.bool_)
        self._mean, self._std = np.array(mean, dtype=np.float64), np.array(std, dtype=np.float64)
        self._any = (bool(self._log.any()), bool(self._k.any()), bool(self._gauss.any()))
        self._excludes = bool(np.isfinite(self._x0).any())

    def draw(self, rng: np.random.Generator) -> tuple[np.ndarray, list[np.ndarray]]:
        """Every value, flat, and each term's ``(rows, width)`` block of them. A uniform
        draw avoids its ``exclude`` by skipping it; a ``shape`` draw is the index of a
        shape in the term's ``shapes``."""
        any_log, any_shape, any_gauss = self._any
        u = rng.random(self.size)
        v = self._lo + u * self._span
        if self._excludes:
            v = np.where(v > self._x0, v + self._gap, v)
        if any_log:
            v = np.where(self._log, np.exp(v), v)
        if any_shape:
            v = np.where(self._k > 0, np.floor(u * self._k), v)
        if any_gauss:
            v = np.where(self._gauss, self._mean + self._std * rng.standard_normal(self.size), v)
        return v, [v[a:b].reshape(shape) for a, b, shape in self.splits]


def combine(operation: str, nominal: np.ndarray, value: np.ndarray) -> np.ndarray:
    """The field's new values from its nominal ones: ``abs``, ``scale`` or ``add``."""
    if operation == "abs":
        out = np.empty(np.shape(nominal))
        out[...] = value
        return out
    if operation == "scale":
        return nominal * value
    return nominal + value


def value_bounds(term: RandomizationTerm) -> tuple[float, float]:
    """The lowest and highest value a draw of ``term`` can give (infinite for a gaussian)."""
    if term.distribution == "gaussian":
        return -np.inf, np.inf
    return term.range
