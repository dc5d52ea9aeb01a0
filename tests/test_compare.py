"""Errors at equal load and validity ranges, on synthetic curves with known errors."""

import numpy as np
import pytest

from bem.curve import ContactCurve
from validation.compare import curve_errors, summarise_errors, validity_range


def curve(load, area, separation, conductance=None):
    load = np.asarray(load, float)
    return ContactCurve(separation=separation, load=load, area=area, mean_pressure=load,
                        nominal_area=1.0, e_star=1.0, conductance=conductance)


def test_curve_errors_known_values():
    load = np.array([1.0, 2.0, 4.0])
    ref = curve(load, [0.1, 0.2, 0.4], [3.0, 2.0, 1.0], [1.0, 2.0, 3.0])
    model = curve(load, [0.11, 0.2, 0.2], [3.5, 2.0, 0.0], [1.0, 1.0, 6.0])
    errors = curve_errors(model, ref, sigma=0.5, quantities=("area", "separation", "conductance"))
    np.testing.assert_allclose(errors["area"], [0.1, 0.0, -0.5], atol=1e-15)
    np.testing.assert_allclose(errors["separation"], [1.0, 0.0, -2.0])
    np.testing.assert_allclose(errors["conductance"], [0.0, -0.5, 1.0])


def test_curve_errors_need_equal_loads():
    with pytest.raises(ValueError, match="same loads"):
        curve_errors(curve([1, 2], [1, 1], [1, 1]), curve([1, 3], [1, 1], [1, 1]), 1.0, ("area",))


def test_validity_range_picks_longest_contiguous_run():
    loads = np.logspace(-5, -2, 10)
    errors = np.array([0.5, 0.3, 0.04, -0.01, 0.02, 0.3, 0.01, 0.0, -0.03, 0.2])
    area = np.linspace(0.001, 0.3, 10)
    rng = validity_range(loads, errors, 0.05, area)
    assert (rng.first, rng.last, rng.points, rng.total) == (2, 4, 3, 10)
    assert rng.load_min == loads[2] and rng.load_max == loads[4]
    assert rng.area_fraction_min == area[2] and rng.area_fraction_max == area[4]
    wide = validity_range(loads, errors, 0.3)
    assert (wide.first, wide.last) == (1, 9)
    everywhere = validity_range(loads, errors, 1.0)
    assert everywhere.points == 10 and "whole range" in everywhere.describe()
    nowhere = validity_range(loads, np.abs(errors) + 0.06, 0.05)
    assert not nowhere.holds_anywhere and nowhere.describe() == "nowhere"


def test_validity_range_nan_does_not_hold():
    rng = validity_range(np.arange(1.0, 5.0), np.array([0.0, np.nan, 0.0, 0.0]), 0.1)
    assert (rng.first, rng.last) == (2, 3)


def test_summarise_errors_mean_and_sample_std():
    summary = summarise_errors("area", [np.array([0.1, 0.2]), np.array([0.3, np.nan])])
    np.testing.assert_allclose(summary.mean, [0.2, 0.2])
    np.testing.assert_allclose(summary.std, [np.std([0.1, 0.3], ddof=1), 0.0])
    assert summary.count == 2
