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


def test_compare_realizations_on_synthetic_results():
    # Two realizations with known errors: area +10 % and +30 % (mean +20 %, sample std 14.1 %),
    # separation exactly 0.5 sigma high; a non-converged reference point counts as not holding.
    from types import SimpleNamespace

    from validation.compare import compare_realizations

    load = np.array([1e-4, 1e-3, 1e-2])
    surface = SimpleNamespace(L=1.0)

    def realization(seed, area_factor, converged):
        reference = ContactCurve(separation=[3.0, 2.0, 1.0], load=load, area=[0.01, 0.05, 0.2],
                                 mean_pressure=load, nominal_area=1.0, e_star=1.0,
                                 extras={"converged": np.array(converged)})
        model = ContactCurve(separation=[3.5, 2.5, 1.5], load=load,
                             area=area_factor * np.array([0.01, 0.05, 0.2]), mean_pressure=load,
                             nominal_area=1.0, e_star=1.0)
        task = SimpleNamespace(seed=seed, surface=surface, quantities=("area", "separation"), D=2.3)
        return SimpleNamespace(task=task, curves={"bem": reference, "gw": model}, sigma=1.0)

    results = [realization(0, 1.1, [True, True, True]), realization(1, 1.3, [True, True, False])]
    comparison = compare_realizations(results, tolerances=(0.25, 0.6))
    area = comparison.models[("gw", "area")]
    np.testing.assert_allclose(area.summary.mean[:2], 0.2)
    np.testing.assert_allclose(area.summary.std[:2], np.std([0.1, 0.3], ddof=1))
    # the last point: only the converged realization counts
    np.testing.assert_allclose(area.summary.mean[2], 0.1)
    assert area.unconverged == 1
    assert (area.ranges[0].first, area.ranges[0].last) == (0, 2)
    separation = comparison.models[("gw", "separation")]
    np.testing.assert_allclose(separation.summary.mean, 0.5)
    assert not separation.ranges[0].holds_anywhere and separation.ranges[1].points == 3
    np.testing.assert_allclose(comparison.area_fraction, [0.01, 0.05, 0.2])
    np.testing.assert_allclose(comparison.load, load)
