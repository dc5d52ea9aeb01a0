"""The headline (each model's error at fixed contact-area fractions), checked against independent
computations on constructed curves."""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest
from scipy import stats

from bem.curve import ContactCurve
from validation.judge.compare import compare_realizations
from validation.judge.headline import (HEADLINE_FRACTIONS, REGIMES, along_path, crossing,
                                       headline, reached_fractions, regime_of)
from validation.judge.tolerance import two_sided_factor
from validation.judge.verdicts import FAILS, HOLDS, UNDECIDED


# ------------------------------------------------------------------------------------------
# constructed curves: errors linear in log10(area fraction), so that the headline's
# interpolation in ln(area fraction) is exact and the numbers are known in closed form

LOADS = np.logspace(-6, -1, 11)
OFFSETS = np.array([0.02, -0.03, 0.05, 0.0, -0.01, 0.04])     # c_r of e_r(a) = c_r + s log10 a
SLOPE = 0.15
BAND = 0.02


def paths() -> np.ndarray:
    """Each realization's BEM area fraction a_r = k_r Load^0.8 (capped below 1)."""
    k = np.linspace(8.0, 14.0, OFFSETS.size)[:, None]
    return np.minimum(k * LOADS[None, :] ** 0.8, 0.9)


def constructed(offsets=OFFSETS):
    area = paths()[: len(offsets)]
    out = []
    for seed, (offset, a) in enumerate(zip(offsets, area)):
        error = offset + SLOPE * np.log10(a)
        reference = ContactCurve(separation=np.linspace(3, 0.5, LOADS.size), load=LOADS, area=a,
                                 mean_pressure=LOADS, nominal_area=1.0, e_star=1.0,
                                 extras={"area_error": BAND * a})
        model = ContactCurve(separation=np.linspace(3, 0.5, LOADS.size), load=LOADS,
                             area=a * (1 + error), mean_pressure=LOADS, nominal_area=1.0,
                             e_star=1.0)
        task = SimpleNamespace(seed=seed, surface=SimpleNamespace(L=1.0, sweep_name="D"),
                               quantities=("area",), sweep_value=2.3)
        out.append(SimpleNamespace(task=task, curves={"bem": reference, "gw": model}, sigma=1.0))
    return out


def test_crossing_interpolates_in_log_area_fraction():
    area = np.array([[0.0, 5e-4, 2e-3, 2e-2, 0.2], [8e-4, 1e-3, 1e-2, 0.1, 0.5]])
    before, after, weight, reached = crossing(area, 1e-3)
    assert reached.all() and list(before) == [1, 1] and list(after) == [2, 1]
    assert weight[0] == pytest.approx(np.log(2) / np.log(4)) and weight[1] == 0.0
    values = np.log(area + 1e-300)
    np.testing.assert_allclose(along_path(values, before, after, weight), np.log(1e-3))
    # 0.3 is beyond the first path; 5e-4 lies between a point without contact and one with
    assert list(crossing(area, 0.3)[3]) == [False, True]
    assert list(crossing(np.array([[0.0, 2e-3]]), 1e-3)[3]) == [False]
    with pytest.raises(ValueError, match="area fraction"):
        crossing(area, 0.0)
    assert [regime_of(f) for f in HEADLINE_FRACTIONS] == ["light", "light", "intermediate",
                                                          "heavy"]
    assert {f for _, held in REGIMES for f in held} == set(HEADLINE_FRACTIONS)


def test_headline_numbers_match_an_independent_computation():
    comparison = compare_realizations(constructed(), tolerances=(0.05, 0.2))
    area = paths()
    # every path spans 0.1 % to 30 % here
    assert reached_fractions(comparison) == HEADLINE_FRACTIONS
    cells = {c.fraction: c for c in headline(comparison)}
    assert set(cells) == set(HEADLINE_FRACTIONS)
    for fraction, cell in cells.items():
        errors = OFFSETS + SLOPE * np.log10(fraction)          # exact: linear in log a
        n = errors.size
        mean, sem, std = errors.mean(), stats.sem(errors), errors.std(ddof=1)
        low, high = stats.t.interval(0.95, n - 1, loc=mean, scale=sem)
        assert (cell.model, cell.quantity, cell.reference_field) == ("gw", "area", "area")
        assert cell.realizations == n and not cell.one_surface
        assert cell.mean == pytest.approx(mean, abs=1e-12)
        assert (cell.low, cell.high) == pytest.approx((low, high), abs=1e-12)
        assert cell.half_width == pytest.approx((high - low) / 2, abs=1e-12)
        k2 = two_sided_factor(n)
        assert (cell.surface_low, cell.surface_high) == pytest.approx(
            (mean - k2 * std, mean + k2 * std), abs=1e-12)
        assert cell.band == pytest.approx(BAND, rel=1e-12)
        # the Load at the fraction: a_r = k_r Load^0.8 inverted, realization by realization
        # (below the cap at 0.9 every pair of neighbours lies on the power law)
        k = area[:, 1] / LOADS[1] ** 0.8
        assert cell.load == pytest.approx(np.mean((fraction / k) ** (1 / 0.8)), rel=1e-9)
        # the verdicts by the rule, computed here from the interval and the band
        for tolerance, verdict, per_surface in zip(cell.tolerances, cell.verdicts,
                                                   cell.surface_verdicts):
            wide = (low - BAND, high + BAND)
            expected = (HOLDS if -tolerance <= wide[0] and wide[1] <= tolerance
                        and BAND <= tolerance / 4 else
                        FAILS if wide[0] > tolerance or wide[1] < -tolerance else UNDECIDED)
            assert verdict == expected, (fraction, tolerance)
            assert per_surface in (HOLDS, FAILS, UNDECIDED)
    # the constructed errors are chosen so that the headline says both
    assert {c.verdicts[1] for c in cells.values()} >= {HOLDS, FAILS}


def test_a_fraction_not_reached_by_every_realization_is_left_out():
    results = constructed()
    short = results[0].curves["bem"]
    cut = dataclasses.replace(short, area=np.minimum(short.area, 0.2))
    results[0] = SimpleNamespace(task=results[0].task, sigma=1.0,
                                 curves={"bem": cut, "gw": results[0].curves["gw"]})
    comparison = compare_realizations(results, tolerances=(0.2,))
    assert reached_fractions(comparison) == (0.001, 0.01, 0.1)
    assert {c.fraction for c in headline(comparison)} == {0.001, 0.01, 0.1}


def test_a_realization_without_an_error_at_the_fraction_prevents_holds():
    # one realization unconverged everywhere: left out of the mean, and nothing holds
    results = constructed(np.zeros(4))
    model = results[0].curves["gw"]
    results[0].curves["gw"] = dataclasses.replace(
        model, extras={"converged": np.zeros(LOADS.size, bool)})
    cells = headline(compare_realizations(results, tolerances=(10.0,)))
    assert all(c.realizations == 3 for c in cells)
    assert all(c.verdicts[0] != HOLDS for c in cells)
