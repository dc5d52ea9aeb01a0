"""Leakage predictions of the theories (asperity.common.leakage, asperity.spectral.persson_gaps; docs/theory.md,
section "Gas-tightness and leakage"): the effective medium against closed forms and adaptive
quadrature, its percolation threshold, and each model's hook."""

import dataclasses
import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate, optimize, stats

import asperity
from asperity.common.leakage import (effective_medium_aperture, effective_medium_density,
                              log_aperture_error, rigid_gaussian_aperture, two_phase_aperture)
from asperity.spectral.persson_gaps import _unresolved_mean_gap, gap_distribution, persson_leakage


def two_gap_root(f, g1, g2, a_c=0.5):
    """The root of the quadratic k c^2 - B c - s1 s2 = 0 of (L2) for fractions f, 1 - f of two
    open gaps (docs/theory.md, section 10.2), written out independently of the solver."""
    k = a_c / (1.0 - a_c)
    s1, s2 = g1**3, g2**3
    b = s1 * (f * k - 1.0 + f) + s2 * ((1.0 - f) * k - f)
    return ((b + math.sqrt(b * b + 4.0 * k * s1 * s2)) / (2.0 * k)) ** (1.0 / 3.0)


def gaussian_reference(t, a_c=0.5):
    """h_eff / s of the rigid Gaussian gap (L5) by adaptive quadrature and Brent's method."""
    k = a_c / (1.0 - a_c)
    sealed = stats.norm.sf(t)

    def condition(c):
        def integrand(z):
            return stats.norm.pdf(z) * ((t - z) ** 3 - c) / ((t - z) ** 3 + k * c)
        splits = [t - 1e-3, t - 1e-2, t - 0.1, t - 1.0]
        with warnings.catch_warnings():      # rounding caps the requested 1e-13
            warnings.simplefilter("ignore", integrate.IntegrationWarning)
            value = integrate.quad(integrand, -40.0, t, points=splits, limit=800,
                                   epsabs=1e-15, epsrel=1e-13)[0]
        return value - sealed / k

    return optimize.brentq(condition, 1e-30, (t + 10.0) ** 3, xtol=1e-16, rtol=1e-15) ** (1 / 3)


# -- the effective medium (L2) -------------------------------------------------------------------

@pytest.mark.parametrize("gap", [3.7e-9, 1.0, 2.5e4])
def test_a_single_gap_is_its_own_aperture(gap):
    np.testing.assert_allclose(effective_medium_aperture([gap]), gap, rtol=1e-13)
    np.testing.assert_allclose(effective_medium_aperture(np.full(7, gap), np.arange(1.0, 8.0)),
                               gap, rtol=1e-13)


@pytest.mark.parametrize("a_c", [0.5, 0.415, 0.7])
def test_two_open_gaps_match_the_quadratic(a_c):
    fractions = np.array([0.05, 0.3, 0.5, 0.77, 0.99])
    gaps = np.broadcast_to([0.4, 1.7], (fractions.size, 2))
    weights = np.column_stack((fractions, 1.0 - fractions))
    got = effective_medium_aperture(gaps, weights, critical_area=a_c)
    want = [two_gap_root(f, 0.4, 1.7, a_c) for f in fractions]
    np.testing.assert_allclose(got, want, rtol=1e-12)


@pytest.mark.parametrize("a_c", [0.5, 0.415])
def test_contact_and_one_gap_match_the_two_phase_closed_form(a_c):
    contact = np.array([0.0, 0.1, 0.3, 0.99 * a_c])
    got = effective_medium_aperture([2.0], contact_fraction=contact, critical_area=a_c)
    mean_gap = 2.0 * (1.0 - contact)
    np.testing.assert_allclose(got, two_phase_aperture(mean_gap, contact, critical_area=a_c),
                               rtol=1e-12)
    np.testing.assert_allclose(got, 2.0 * np.cbrt(1.0 - contact / a_c), rtol=1e-12)


def test_two_phase_closed_form_by_hand():
    # mean gap 2 over the nominal area, 20 % contact: open gap 2/0.8 = 2.5, and
    # h^3 = 2.5^3 (1 - 0.2/0.5) = 15.625 * 0.6 = 9.375
    np.testing.assert_allclose(two_phase_aperture(2.0, 0.2), 9.375 ** (1 / 3), rtol=1e-14)
    assert two_phase_aperture(2.0, 0.5) == 0 and two_phase_aperture(2.0, 0.8) == 0


@pytest.mark.parametrize("a_c", [0.5, 0.415])
def test_the_medium_stops_conducting_at_its_threshold(a_c):
    gaps = np.geomspace(0.1, 3.0, 50)
    below = effective_medium_aperture(gaps, contact_fraction=[a_c - 1e-3, a_c - 1e-6],
                                      critical_area=a_c)
    assert np.all(below > 0) and below[1] < below[0] < 0.2 * gaps.mean()
    at_and_after = effective_medium_aperture(gaps, contact_fraction=[a_c, a_c + 0.01, 1.0],
                                             critical_area=a_c)
    assert np.all(at_and_after == 0)
    # zero gaps count as contact: half the samples closed is the plain threshold
    half_closed = np.concatenate((np.zeros(50), gaps))
    assert effective_medium_aperture(half_closed) == 0
    assert effective_medium_aperture(half_closed[1:]) > 0


def test_aperture_falls_as_the_contact_grows():
    contact = np.linspace(0.0, 0.5, 26)
    h = effective_medium_aperture(np.geomspace(0.01, 1.0, 40), contact_fraction=contact)
    assert np.all(np.diff(h) < 0) and h[-1] == 0


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(1e-3, 1e3), min_size=1, max_size=30),
       st.floats(1e-6, 1e6), st.floats(0.0, 0.45))
def test_aperture_is_scale_free_and_inside_its_bounds(gaps, scale, contact):
    gaps = np.array(gaps)
    h = effective_medium_aperture(gaps, contact_fraction=contact)
    np.testing.assert_allclose(effective_medium_aperture(scale * gaps, contact_fraction=contact),
                               scale * h, rtol=1e-9)
    # the order of the samples changes the sums' rounding only (2e-12 found for 4 gaps)
    np.testing.assert_allclose(effective_medium_aperture(gaps[::-1], contact_fraction=contact),
                               h, rtol=1e-10)
    weights = np.full(gaps.size, (1.0 - contact) / gaps.size)
    lower = (1.0 - 2.0 * contact) / (2.0 * np.sum(weights / gaps**3))      # (L3), k = 1
    upper = np.sum(weights * gaps**3) / (1.0 - contact)
    assert lower * (1 - 1e-9) <= h**3 <= upper * (1 + 1e-9)


def test_a_density_on_a_grid_matches_its_samples():
    grid = np.linspace(1.0, 2.0, 4001)
    by_grid = effective_medium_density(lambda g: np.ones_like(g), grid, contact_fraction=0.2)
    nodes, weights = np.polynomial.legendre.leggauss(40)
    by_rule = effective_medium_aperture(1.5 + 0.5 * nodes, weights, contact_fraction=0.2)
    np.testing.assert_allclose(by_grid, by_rule, rtol=1e-6)


@pytest.mark.parametrize("call, name", [
    (lambda: effective_medium_aperture([1.0, -0.1]), "gaps"),
    (lambda: effective_medium_aperture([1.0, np.nan]), "gaps"),
    (lambda: effective_medium_aperture([1.0, 2.0], [1.0, -1.0]), "weights"),
    (lambda: effective_medium_aperture([1.0, 2.0], [1.0, 2.0, 3.0]), "weights"),
    (lambda: effective_medium_aperture([1.0], contact_fraction=1.5), "contact_fraction"),
    (lambda: effective_medium_aperture([1.0], critical_area=1.0), "critical_area"),
    (lambda: effective_medium_aperture([]), "gaps"),
    (lambda: rigid_gaussian_aperture(1.0, -1e-3), "height_rms"),
    (lambda: rigid_gaussian_aperture(np.nan, 1.0), "separation"),
    (lambda: two_phase_aperture(1.0, 1.2), "area_fraction"),
])
def test_bad_input_names_the_parameter(call, name):
    with pytest.raises(ValueError, match=name):
        call()


# -- the rigid Gaussian gap (L5) -----------------------------------------------------------------

@pytest.mark.parametrize("t", [0.001, 0.3, 1.0, 2.5, 8.0])
def test_rigid_gaussian_gap_matches_adaptive_quadrature(t):
    np.testing.assert_allclose(rigid_gaussian_aperture(3e-6 * t, 3e-6), 3e-6 * gaussian_reference(t),
                               rtol=1e-9)


def test_rigid_gaussian_gap_with_a_moved_threshold():
    np.testing.assert_allclose(rigid_gaussian_aperture(0.4, 1.0, critical_area=0.415),
                               gaussian_reference(0.4, a_c=0.415), rtol=1e-9)
    threshold = stats.norm.isf(0.415)           # bearing fraction 0.415 at d = 0.215 s
    assert rigid_gaussian_aperture(threshold - 1e-9, 1.0, critical_area=0.415) == 0


def test_rigid_gaussian_gap_grows_with_the_separation_and_tends_to_it():
    d = np.linspace(-2.0, 6.0, 161)
    h = rigid_gaussian_aperture(d, 1.0)
    assert np.all(h[d <= 0] == 0) and np.all(np.diff(h[d > 0]) > 0)
    t = np.array([30.0, 100.0])
    # second-order effective medium: h_eff^3 = <g^3> - var(g^3) / (2 <g^3>) = d^3 - 3 d s^2 / 2
    deviation = rigid_gaussian_aperture(t, 1.0) / t - (1.0 - 0.5 / t**2)
    assert np.all(np.abs(deviation) < 10.0 / t**4)
    assert rigid_gaussian_aperture(np.inf, 1.0) == np.inf
    np.testing.assert_array_equal(rigid_gaussian_aperture([-1.0, 0.0, 2.0], 0.0), [0, 0, 2.0])
    assert rigid_gaussian_aperture(2.0, 1.0).shape == ()


# -- GW, improved GW, discrete model -----------------------------------------------------------

GW_ARGS = dict(density=500.0, radius=1e-4, sigma=1e-3)
GW_KWARGS = dict(mean=5e-4, e_star=1.0, area=1.0)


def test_gw_leakage_is_the_rigid_gap_at_d():
    gw = asperity.GreenwoodWilliamson(**GW_ARGS, **GW_KWARGS)
    d = np.array([3e-3, 2e-3, 1e-3, 5e-4, 0.0])
    np.testing.assert_array_equal(gw.at_separation(d, quantities=("leakage",)).leakage,
                                  rigid_gaussian_aperture(d, 1e-3))
    surface = dataclasses.replace(gw, height_rms=2e-3)
    np.testing.assert_array_equal(surface.at_separation(d, quantities=("leakage",)).leakage,
                                  rigid_gaussian_aperture(d, 2e-3))
    assert gw.at_separation(d, quantities=("area",)).leakage is None


def test_improved_gw_differs_from_gw_exactly_by_d1():
    gw = asperity.GreenwoodWilliamson(**GW_ARGS, **GW_KWARGS)
    improved = asperity.ImprovedGreenwoodWilliamson(**GW_ARGS, **GW_KWARGS, m=1.0)
    d = np.array([3e-3, 2e-3, 1.5e-3, 1e-3])
    curve = improved.at_separation(d, quantities=("leakage",))
    d1 = curve.extras["effective_separation"]
    assert np.all(d1 > d)
    np.testing.assert_array_equal(curve.leakage,
                                  gw.at_separation(d1, quantities=("leakage",)).leakage)
    assert np.all(curve.leakage > gw.at_separation(d, quantities=("leakage",)).leakage)
    # at equal load GW's d is improved GW's d1: the same leakage
    loads = np.geomspace(1e-8, 1e-4, 6)
    np.testing.assert_allclose(improved.at_load(loads, quantities=("leakage",)).leakage,
                               gw.at_load(loads, quantities=("leakage",)).leakage, rtol=1e-12)


@pytest.fixture(scope="module")
def surface():
    from validation.surfaces.wm import wm_surface

    heights = wm_surface(64, D=2.3, rms_slope=0.1, seed=3)
    return heights, 1.0 / 64


def test_discrete_leakage_is_the_rigid_gap_at_its_own_separation(surface):
    heights, spacing = surface
    summits = asperity.find_summits(heights, spacing)
    model = asperity.DiscreteAsperityModel(summits, e_star=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        curve = model.at_load([1e-5, 1e-4, 1e-3], quantities=("leakage",))
    np.testing.assert_array_equal(
        curve.leakage, rigid_gaussian_aperture(curve.separation, float(np.std(summits.height))))
    assert curve.stiffness is None and np.all(np.diff(curve.leakage) < 0)
    given = asperity.DiscreteAsperityModel(summits, e_star=1.0, interaction=False,
                                           height_rms=float(np.std(heights)))
    lone = given.at_separation(curve.separation[0], quantities=("leakage",))
    np.testing.assert_array_equal(
        lone.leakage, rigid_gaussian_aperture(curve.separation[0], float(np.std(heights))))
    with pytest.raises(ValueError, match="height_rms"):
        asperity.DiscreteAsperityModel(summits, height_rms=-1.0)


# -- Persson (L6) ---------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def persson():
    return asperity.Persson.from_spectrum([1.0, 100.0], [1e-6, 1e-14], 1.0, e_star=1.0)


def test_persson_leakage_is_positive_at_light_load_and_falls_with_load(persson):
    loads = np.geomspace(1e-6, 5e-3, 14)
    curve = persson.at_load(loads, quantities=("leakage",))
    leaking = curve.leakage > 0
    assert leaking[0] and np.all(np.diff(curve.leakage[leaking]) < 0)
    assert np.all(curve.area[~leaking] >= 0.5) and np.all(curve.area[leaking] < 0.5)
    assert curve.leakage[0] < curve.separation[0]          # below the mean gap at light load
    back = persson.at_separation(curve.separation[:6], quantities=("leakage",))
    np.testing.assert_allclose(back.leakage, curve.leakage[:6], rtol=1e-6)
    assert persson.at_load(0.0, quantities=("leakage",)).leakage == np.inf
    assert persson.at_load(loads, quantities=("area",)).leakage is None
    assert curve.extras["leakage_two_phase"].shape == loads.shape


def test_persson_gap_distribution_is_normalised_and_starts_at_the_mean_gap(persson):
    pressure = np.array([1e-5, 3e-4, 1e-3])
    distribution = gap_distribution(persson, pressure)
    np.testing.assert_allclose(distribution.weights.sum(axis=1)
                               + distribution.contact_fraction, 1.0, rtol=1e-12)
    np.testing.assert_allclose(distribution.contact_fraction,
                               persson.at_load(pressure).area / persson.nominal_area, rtol=1e-12)
    # u_q at q = q_L, under p0, is Persson's mean gap (P5) itself
    np.testing.assert_allclose(
        _unresolved_mean_gap(persson, np.zeros(3), pressure / (math.sqrt(math.pi) * 1.0)),
        persson.mean_gap(pressure), rtol=1e-6)


def test_persson_leakage_quadrature_is_converged(persson):
    pressure = np.array([1e-5, 3e-4, 1e-3])              # areas 0.3 %, 10 %, 34 %
    base = gap_distribution(persson, pressure).aperture()
    for options in (dict(magnifications=64), dict(fine=20)):
        finer = gap_distribution(persson, pressure, **options).aperture()
        np.testing.assert_allclose(finer, base, rtol=1e-3)


def test_persson_leakage_by_function_and_bad_input(persson):
    out = persson_leakage(persson, np.array([[1e-5, 0.0], [1e3, 3e-4]]))
    assert out["leakage"].shape == (2, 2) and out["leakage"][0, 1] == np.inf
    assert out["leakage"][1, 0] == 0 and out["leakage_two_phase"][1, 0] == 0
    with pytest.raises(ValueError, match="pressure"):
        gap_distribution(persson, [0.0])
    with pytest.raises(TypeError, match="Persson"):
        gap_distribution(object(), [1e-4])


# -- the error measure (L7) ------------------------------------------------------------------------

def test_log_aperture_error():
    model = np.array([2.0, 0.5, 1.0, 0.0, 0.0, 1.0])
    reference = np.array([1.0, 1.0, 1.0, 0.0, 1.0, 0.0])
    error = log_aperture_error(model, reference)
    np.testing.assert_allclose(error[:4], [math.log(2.0), -math.log(2.0), 0.0, 0.0])
    assert np.isnan(error[4]) and np.isnan(error[5])
    # one third of the log error of the leak rate Q ~ h^3
    np.testing.assert_allclose(log_aperture_error(1.3, 1.0), math.log(1.3**3) / 3)
