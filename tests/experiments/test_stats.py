"""Per-cell intervals over seeds: a range below 5 seeds, a bootstrap CI from 5, labelled so."""

from __future__ import annotations

import math

import numpy as np

from unified_manip.experiments.figures import curve_band, interval_label
from unified_manip.experiments.stats import iqm_with_ci, seed_interval, seeded_global_numpy


def test_under_five_seeds_the_interval_is_the_range_and_says_so():
    iv = seed_interval([0.98, 0.88, 0.98])
    assert (iv.low, iv.high, iv.n) == (0.88, 0.98, 3)
    assert iv.text() == "[0.88, 0.98] (range of 3 seeds)"
    assert seed_interval([0.1, 0.4, 0.3, 0.2]).text() == "[0.10, 0.40] (range of 4 seeds)"


def test_one_seed_has_no_interval():
    iv = seed_interval([0.7])
    assert math.isnan(iv.low) and math.isnan(iv.high) and iv.text() == ""


def test_from_five_seeds_the_interval_is_the_bootstrap_ci_and_says_so():
    # The mean of 5 draws from [0, 0, 0, 0, 1] is k/5 with k ~ Binomial(5, 0.2):
    # P(k <= 2) = 0.942 and P(k <= 3) = 0.993, so the 97.5th percentile is 3/5 and the
    # 2.5th is 0 (P(k = 0) = 0.328): [0.00, 0.60], narrower than the range [0, 1].
    iv = seed_interval([0.0, 0.0, 0.0, 0.0, 1.0])
    assert iv.text() == "[0.00, 0.60] (95% CI)"
    # The same values, seeds 0-3 only: their range.
    assert seed_interval([0.0, 0.0, 0.0, 1.0]).text() == "[0.00, 1.00] (range of 4 seeds)"


def test_a_cell_iqm_needs_five_seeds_and_trims_a_quarter_from_each_end():
    assert iqm_with_ci([0.1, 0.2, 0.3, 0.4]) is None
    # Five values: scipy's trim_mean(0.25) drops int(1.25) = 1 from each end: (0.2+0.3+0.4)/3.
    point, low, high = iqm_with_ci([0.1, 0.2, 0.3, 0.4, 0.9])
    assert math.isclose(point, 0.3) and 0.1 <= low < point < high <= 0.9
    assert iqm_with_ci([0.1, 0.2, 0.3, 0.4, 0.9]) == (point, low, high)  # seeded: the same twice


def test_seeding_rliables_generator_leaves_numpys_global_state_as_it_was():
    np.random.seed(123)
    expected = np.random.rand()
    np.random.seed(123)
    with seeded_global_numpy(0):
        np.random.rand(10)
    assert np.random.rand() == expected


def test_figures_band_is_the_range_under_five_seeds_and_say_which_they_draw():
    three = [{"curve": [[10, v]]} for v in (0.0, 0.0, 1.0)]
    five = [{"curve": [[10, v]]} for v in (0.0, 0.0, 0.0, 0.0, 1.0)]
    assert [x.tolist() for x in curve_band(three)[2:]] == [[0.0], [1.0]]  # min and max
    assert [x.tolist() for x in curve_band(five)[2:]] == [[0.0], [0.6]]  # the bootstrap CI, as above
    assert interval_label([3, 3, 1]) == "range of the seeds"
    assert interval_label([5, 8]) == "95% bootstrap CI"
    assert interval_label([3, 5]) == "range of the seeds where n < 5, 95% bootstrap CI where n ≥ 5"
    assert interval_label([1, 1]) == "none, one seed each"
