"""Statistics over seeds for reports, from libraries rather than hand-rolled code.

* :func:`seed_interval`: the interval a per-cell result is shown with, labelled as what it
  is: the range (min–max) of fewer than :data:`MIN_SEEDS_FOR_CI` seeds, otherwise the 95%
  percentile bootstrap of the mean (:func:`bootstrap_ci`, ``scipy.stats.bootstrap``). A
  percentile bootstrap over 3 values returns about their minimum and maximum, so calling
  it a 95% CI would overstate what 3 seeds say;
* :func:`iqm_with_ci`: rliable's interquartile mean and its stratified-bootstrap interval;
* :func:`probability_of_improvement`: rliable's P(X > Y);
* :func:`iqm` and :func:`score_distributions`: rliable's statistics in plain numpy, to
  the bit, for the bootstraps that call them thousands of times.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import NamedTuple

import numpy as np

#: Fewest seeds a per-cell interval is computed and labelled as a 95% bootstrap CI from;
#: with fewer it is the seeds' range.
MIN_SEEDS_FOR_CI = 5
CONFIDENCE = 0.95


class SeedInterval(NamedTuple):
    """A per-cell interval over ``n`` seeds: their range below :data:`MIN_SEEDS_FOR_CI`,
    else the 95% bootstrap CI of the mean; NaNs with fewer than two seeds."""

    low: float
    high: float
    n: int

    @property
    def label(self) -> str:
        return "95% CI" if self.n >= MIN_SEEDS_FOR_CI else f"range of {self.n} seeds"

    def text(self) -> str:
        """``[low, high] (label)``, or an empty string with fewer than two seeds."""
        return "" if self.n < 2 else f"[{self.low:.2f}, {self.high:.2f}] ({self.label})"


def seed_interval(values: list[float], seed: int = 0) -> SeedInterval:
    """The interval a per-cell result over seeds is shown with (see :class:`SeedInterval`)."""
    data = np.asarray(values, dtype=float)
    if len(data) < 2:
        return SeedInterval(float("nan"), float("nan"), len(data))
    if len(data) < MIN_SEEDS_FOR_CI:
        return SeedInterval(float(data.min()), float(data.max()), len(data))
    return SeedInterval(*bootstrap_ci(values, seed=seed), len(data))


def bootstrap_ci(values: list[float], seed: int = 0) -> tuple[float, float]:
    """95% percentile-bootstrap interval of the mean; NaNs with fewer than two values."""
    from scipy.stats import bootstrap

    data = np.asarray(values, dtype=float)
    if len(data) < 2:
        return float("nan"), float("nan")
    if np.all(data == data[0]):  # no spread: the interval is the point
        return float(data[0]), float(data[0])
    res = bootstrap(
        (data,),
        np.mean,
        confidence_level=CONFIDENCE,
        method="percentile",
        n_resamples=10_000,
        random_state=np.random.default_rng(seed),
    )
    return float(res.confidence_interval.low), float(res.confidence_interval.high)


def iqm_with_ci(values: list[float], seed: int = 0) -> tuple[float, float, float] | None:
    """rliable's IQM of one cell's seeds and its stratified-bootstrap 95% interval, or None
    with fewer than :data:`MIN_SEEDS_FOR_CI` seeds (too few for a bootstrap to mean much)."""
    if len(values) < MIN_SEEDS_FOR_CI:
        return None
    from rliable import library as rly

    with seeded_global_numpy(seed):  # rliable draws from numpy's global generator
        scores = {"x": np.asarray(values, dtype=float).reshape(-1, 1)}
        point, interval = rly.get_interval_estimates(scores, lambda s: np.array([iqm(s)]), reps=2000)
    return float(point["x"][0]), float(interval["x"][0, 0]), float(interval["x"][1, 0])


def iqm(scores: np.ndarray) -> float:
    """rliable's ``metrics.aggregate_iqm``, the 25% trimmed mean of all scores, by the same
    numpy calls as scipy's ``trim_mean`` (so the same bits) without scipy's per-call
    dispatch, which cost 1 ms of each bootstrap resample."""
    flat = np.ravel(scores)
    low = int(0.25 * flat.size)
    high = flat.size - low
    return float(np.mean(np.partition(flat, (low, high - 1))[low:high]))


def score_distributions(scores: np.ndarray, taus: np.ndarray) -> np.ndarray:
    """rliable's ``score_distributions``: the fraction of all scores above each tau, in one
    comparison instead of rliable's ``np.vectorize`` loop over the taus (about 50x faster)."""
    return np.mean(np.ravel(scores)[None, :] > np.asarray(taus)[:, None], axis=1)


@contextmanager
def seeded_global_numpy(seed: int) -> Iterator[None]:
    """Seed numpy's global generator inside the block and restore its state after:
    rliable's bootstraps draw from it and ignore their ``random_state`` argument."""
    state = np.random.get_state()
    np.random.seed(seed)
    try:
        yield
    finally:
        np.random.set_state(state)


def probability_of_improvement(x: list[float], y: list[float]) -> float:
    """P(X > Y) from rliable (ties count half)."""
    from rliable import metrics

    return float(
        metrics.probability_of_improvement(np.asarray(x, float).reshape(-1, 1), np.asarray(y, float).reshape(-1, 1))
    )
