"""Verdict logic on synthetic errors whose right verdict is known."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import stats

from validation.judge.verdicts import (
    FAILS,
    HOLDS,
    UNDECIDED,
    classify,
    confidence_interval,
    reference_band,
    validity_range,
    verdict_counts,
    verdict_range,
    verdict_strip,
)


def synthetic(means, spread, realizations=25, seed=0):
    """Errors with exactly the given per-point means and sample spread (columns: points)."""
    noise = np.random.default_rng(seed).standard_normal((realizations, len(means)))
    noise = (noise - noise.mean(axis=0)) / noise.std(axis=0, ddof=1)
    return np.asarray(means) + spread * noise


def test_interval_matches_the_t_distribution():
    errors = np.random.default_rng(1).normal(0.1, 0.05, size=(7, 3))
    interval = confidence_interval(errors)
    for k in range(3):
        low, high = stats.t.interval(0.95, 6, loc=errors[:, k].mean(), scale=stats.sem(errors[:, k]))
        assert interval.low[k] == pytest.approx(low, rel=1e-12)
        assert interval.high[k] == pytest.approx(high, rel=1e-12)
    assert np.all(interval.count == 7)


def test_interval_leaves_out_nan_and_needs_two_realizations():
    errors = np.array([[0.1, 0.2, np.nan], [0.3, np.nan, np.nan], [0.2, np.nan, np.nan]])
    interval = confidence_interval(errors)
    np.testing.assert_array_equal(interval.count, [3, 1, 0])
    assert interval.mean[0] == pytest.approx(0.2) and interval.mean[1] == pytest.approx(0.2)
    assert np.isfinite(interval.half_width[0])
    assert np.isinf(interval.half_width[1]) and np.isnan(interval.mean[2])


def test_interval_covers_the_true_mean_at_its_confidence():
    # 4000 experiments of 5 realizations: the 95 % interval covers the true mean in
    # 95 % +- 1 % (binomial standard deviation 0.34 %) of them.
    errors = np.random.default_rng(2).normal(0.3, 0.1, size=(5, 4000))
    interval = confidence_interval(errors)
    coverage = np.mean((interval.low <= 0.3) & (0.3 <= interval.high))
    assert 0.94 <= coverage <= 0.96


def test_known_verdicts():
    tolerance = 0.05
    # points: well inside, well outside above, well outside below, straddling the bound
    errors = synthetic([0.0, 0.3, -0.3, 0.05], spread=0.01)
    verdicts = classify(confidence_interval(errors), 0.0, tolerance)
    assert list(verdicts) == [HOLDS, FAILS, FAILS, UNDECIDED]
    assert verdict_counts(verdicts) == {HOLDS: 1, FAILS: 2, UNDECIDED: 1}
    assert verdict_strip(verdicts) == "✔✘✘?"


def test_scatter_makes_a_point_undecided():
    # mean 0.02 inside 0.05, but the realizations scatter by 0.2: 95 % interval +-0.08
    errors = synthetic([0.02], spread=0.2)
    assert classify(confidence_interval(errors), 0.0, 0.05)[0] == UNDECIDED
    # ... and 100 times more realizations decide it
    many = synthetic([0.02], spread=0.2, realizations=2500)
    assert classify(confidence_interval(many), 0.0, 0.05)[0] == HOLDS


def test_reference_band_widens_the_interval():
    errors = synthetic([0.03, 0.08], spread=0.001)
    interval = confidence_interval(errors)
    assert list(classify(interval, 0.0, 0.05)) == [HOLDS, FAILS]
    # at 0.1 a band of 0.025 pushes the second point (0.08 + 0.025) over the bound
    assert list(classify(interval, 0.025, 0.1)) == [HOLDS, UNDECIDED]
    # at 0.05 it makes the first undecided; the second, 0.08 - 0.025 > 0.05, still fails
    assert list(classify(interval, np.array([0.025, 0.025]), 0.05)) == [UNDECIDED, FAILS]


def test_reference_accuracy_rule():
    # the model agrees exactly, but the reference resolves only 0.02 > 0.05 / 4
    interval = confidence_interval(synthetic([0.0, 0.0], spread=0.001))
    assert list(classify(interval, np.array([0.012, 0.02]), 0.05)) == [HOLDS, UNDECIDED]
    # a band not estimated (NaN) is never zero: neither a hold nor even a clear failure
    interval = confidence_interval(synthetic([0.0, 1.0], spread=0.001))
    assert list(classify(interval, np.array([np.nan, np.nan]), 0.05)) == [UNDECIDED, UNDECIDED]
    assert list(classify(interval, np.array([np.nan, 0.0]), 0.05)) == [UNDECIDED, FAILS]


def test_unconverged_realizations_prevent_holds_not_fails():
    interval = confidence_interval(synthetic([0.0, 0.5], spread=0.001))
    verdicts = classify(interval, 0.0, 0.05, complete=np.array([False, False]))
    assert list(verdicts) == [UNDECIDED, FAILS]
    nothing = confidence_interval(np.full((3, 2), np.nan))
    assert list(classify(nothing, 0.0, 0.05)) == [UNDECIDED, UNDECIDED]


@given(st.lists(st.floats(-1, 1), min_size=2, max_size=12), st.floats(0.0, 0.1),
       st.floats(0.01, 0.5), st.floats(1.01, 5.0))
def test_verdicts_are_monotone_in_the_tolerance(values, band, tolerance, factor):
    interval = confidence_interval(np.array(values)[:, None])
    narrow = classify(interval, band, tolerance)[0]
    wide = classify(interval, band, factor * tolerance)[0]
    assert not (narrow == HOLDS and wide != HOLDS)
    assert not (wide == FAILS and narrow != FAILS)


def test_reference_band_is_the_mean_relative_error_over_realizations():
    absolute = np.array([[0.01, 0.02], [0.03, np.nan]])
    values = np.array([[1.0, 0.5], [1.0, 0.5]])
    np.testing.assert_allclose(reference_band(absolute, values), [0.02, 0.04])
    sigma = np.array([[0.5], [0.25]])
    np.testing.assert_allclose(reference_band(-absolute, sigma), [(0.02 + 0.12) / 2, 0.04])


def test_verdict_range_is_the_longest_run_of_holds():
    loads = np.logspace(-5, -2, 8)
    verdicts = np.array([HOLDS, UNDECIDED, HOLDS, HOLDS, HOLDS, FAILS, HOLDS, HOLDS])
    area = np.linspace(0.01, 0.2, 8)
    rng = verdict_range(loads, verdicts == HOLDS, 0.05, area)
    assert (rng.first, rng.last, rng.points, rng.total) == (2, 4, 3, 8)
    assert rng.area_fraction_min == area[2] and rng.area_fraction_max == area[4]
    tie = verdict_range(loads[:4], np.array([True, False, True, False]), 0.05)
    assert (tie.first, tie.last) == (0, 0) and tie.describe().startswith("only at")
    none = verdict_range(loads, np.zeros(8, bool), 0.05)
    assert not none.holds_anywhere and none.describe() == "nowhere"
    assert "whole range" in verdict_range(loads, np.ones(8, bool), 0.05).describe()


def test_point_estimate_range_and_bad_tolerance():
    rng = validity_range(np.arange(1.0, 5.0), np.array([0.0, np.nan, 0.0, 0.0]), 0.1)
    assert (rng.first, rng.last) == (2, 3)
    with pytest.raises(ValueError, match="tolerance"):
        classify(confidence_interval(np.zeros((2, 1))), 0.0, 0.0)
