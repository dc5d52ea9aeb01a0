"""The BEM's ``leakage`` curve field: the exact Reynolds aperture of its solved gap."""

import numpy as np
import pytest

import bem
from bem.leakage.flow import hydraulic_aperture, leakage_aperture
from bem.contact.path_errors import ERROR_FACTOR
from validation import self_affine_surface

N = 64


@pytest.fixture(scope="module")
def heights():
    return self_affine_surface(N, hurst=0.8, rms_slope=0.1, rolloff=0.25, short_cutoff=4.0 / N,
                               seed=7)


@pytest.mark.parametrize("periodic", [False, True])
def test_out_of_contact_the_leakage_is_that_of_the_rigid_gap(heights, periodic):
    d = float(heights.max()) + 0.1 * float(heights.std())
    curve = bem.contact_curve(heights, 1.0 / N, separations=[d], periodic=periodic,
                              quantities=("leakage",))
    assert curve.load[0] == 0.0
    rigid = d - heights
    expected = np.cbrt(0.5 * sum(hydraulic_aperture(rigid, 1.0 / N, direction=direction,
                                                    periodic=periodic) ** 3
                                 for direction in ("x", "y")))
    assert curve.leakage[0] == pytest.approx(expected, rel=1e-12)
    # a uniform gap's aperture is the gap: a rough one leaks less than its mean gap suggests
    assert 0.0 < curve.leakage[0] < curve.extras["mean_gap"][0]


@pytest.mark.parametrize("periodic", [False, True])
def test_leakage_falls_with_load_and_is_exactly_zero_once_sealed(heights, periodic):
    loads = np.array([0.0, 0.002, 0.006, 0.02, 0.06, 0.2])
    kept = {}
    curve = bem.contact_curve(heights, 1.0 / N, loads=loads, periodic=periodic,
                              quantities=("area", "leakage"),
                              callback=lambda index, solution: kept.__setitem__(index, solution))
    assert np.all(np.diff(curve.leakage) <= 0.0)
    assert curve.leakage[1] > 0.0
    sealed = curve.area_fraction > 0.6
    assert sealed.any() and np.all(curve.leakage[sealed] == 0.0)
    # each point is the aperture of its own gap with the contact set closed, periodic as solved
    for index, solution in kept.items():
        gap = np.where(solution.contact, 0.0, np.maximum(solution.gap, 0.0))
        np.testing.assert_array_equal(solution.fluid_gap, gap)
        assert curve.leakage[index] == leakage_aperture(gap, 1.0 / N, periodic=periodic)
    # the fluid gap closes exactly the contact set, where the solved gap holds round-off
    loaded = kept[int(np.argmax(loads))]
    assert np.any(loaded.gap[loaded.contact] != 0.0)
    assert np.all(loaded.fluid_gap[loaded.contact] == 0.0)


def test_only_curves_that_ask_for_leakage_get_it(heights):
    curve = bem.contact_curve(heights, 1.0 / N, loads=[0.01], error_estimate=True)
    assert curve.leakage is None and "leakage_error" not in curve.extras
    with pytest.raises(ValueError, match="leakage"):
        curve.quantity("leakage")


def test_the_leakage_error_is_the_half_grid_difference(heights):
    loads = [0.002, 0.01]
    curve = bem.contact_curve(heights, 1.0 / N, loads=loads, periodic=True,
                              quantities=("leakage",), error_estimate=True)
    coarse = bem.contact_curve(heights[::2, ::2], 2.0 / N, loads=loads, periodic=True,
                               quantities=("leakage",))
    assert np.array_equal(curve.extras["leakage_error"],
                          ERROR_FACTOR * np.abs(curve.leakage - coarse.leakage))
    assert np.all(curve.extras["leakage_error"] > 0.0)


def test_the_model_contract_passes_leakage_through(heights):
    model = bem.BoundaryElementModel(heights, 1.0 / N, periodic=True)
    curve = model.at_load(np.array([[0.0, 0.01]]), quantities=("load", "leakage"))
    assert curve.leakage.shape == (1, 2) and curve.leakage[0, 0] > curve.leakage[0, 1] > 0.0
    assert model.at_load(np.empty(0), quantities=("leakage",)).leakage.shape == (0,)
    assert "leakage" in bem.CURVE_QUANTITIES
