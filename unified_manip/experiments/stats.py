"""Statistics over seeds for reports, from libraries rather than hand-rolled code.

* :func:`bootstrap_ci`: 95% percentile-bootstrap interval of the mean
  (``scipy.stats.bootstrap``);
* :func:`iqm_with_ci`: rliable's interquartile mean and its stratified-bootstrap interval;
* :func:`probability_of_improvement`: rliable's P(X > Y).
"""

from __future__ import annotations

import numpy as np

#: IQM needs enough runs to trim a quarter from each end.
MIN_RUNS_FOR_IQM = 4
CONFIDENCE = 0.95


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
    """rliable's IQM and its stratified-bootstrap 95% interval, or None with too few runs."""
    if len(values) < MIN_RUNS_FOR_IQM:
        return None
    from rliable import library as rly
    from rliable import metrics

    np.random.seed(seed)  # rliable draws from numpy's global generator
    scores = {"x": np.asarray(values, dtype=float).reshape(-1, 1)}
    point, interval = rly.get_interval_estimates(scores, lambda s: np.array([metrics.aggregate_iqm(s)]), reps=2000)
    return float(point["x"][0]), float(interval["x"][0, 0]), float(interval["x"][1, 0])


def probability_of_improvement(x: list[float], y: list[float]) -> float:
    """P(X > Y) from rliable (ties count half)."""
    from rliable import metrics

    return float(
        metrics.probability_of_improvement(np.asarray(x, float).reshape(-1, 1), np.asarray(y, float).reshape(-1, 1))
    )
