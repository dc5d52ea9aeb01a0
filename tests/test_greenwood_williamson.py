"""GW and improved GW theory: independent integrals, exact relations of the paper, stress tests."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import integrate

from asperity import GreenwoodWilliamson, ImprovedGreenwoodWilliamson, gw_integral
from bem import ContactCurve

# A physically plausible set in SI units (so unit slips show): eta R sigma = 0.01, C = 31.6.
PARAMETERS = dict(density=1e9, radius=1e-5, sigma=1e-6, mean=0.5e-6, e_star=1e11, area=1e-4)
SIGMA = PARAMETERS["sigma"]


def gw(**changes):
    return GreenwoodWilliamson(**{**PARAMETERS, **changes})


def improved(**changes):
    return ImprovedGreenwoodWilliamson(**{**PARAMETERS, **changes})


def five_point_derivative(function, x, step):
    return (-function(x + 2 * step) + 8 * function(x + step) - 8 * function(x - step)
            + function(x - 2 * step)) / (12 * step)


# --------------------------------------------------------------------------------------------
# GW against the statistical sum written out independently

def test_gw_equals_the_integral_of_hertz_contacts_over_gaussian_summits():
    p = PARAMETERS
    n = p["density"] * p["area"]

    def summit_density(z):
        return math.exp(-0.5 * ((z - p["mean"]) / SIGMA) ** 2) / (SIGMA * math.sqrt(2 * math.pi))

    def expectation(d, per_summit):
        value, _ = integrate.quad(lambda z: per_summit(z - d) * summit_density(z), d,
                                  p["mean"] + 40 * SIGMA, epsabs=0, epsrel=1e-12, limit=200)
        return n * value

    for d in (-1e-6, 0.0, 1.3e-6, 4e-6):
        curve = gw().at_separation(d)
        hertz_force = lambda w: 4 / 3 * p["e_star"] * math.sqrt(p["radius"]) * w ** 1.5  # noqa
        # quad to 1e-12 on a smooth integrand; 1e-9 leaves room for its error estimate.
        assert curve.load == pytest.approx(expectation(d, hertz_force), rel=1e-9)
        assert curve.area == pytest.approx(expectation(d, lambda w: math.pi * p["radius"] * w),
                                           rel=1e-9)
        assert curve.contacts == pytest.approx(expectation(d, lambda w: 1.0), rel=1e-9)
        assert curve.stiffness == pytest.approx(
            expectation(d, lambda w: 2 * p["e_star"] * math.sqrt(p["radius"] * w)), rel=1e-9)
        assert curve.conductance == pytest.approx(2 * curve.stiffness / p["e_star"], rel=1e-15)
        assert curve.mean_pressure == pytest.approx(curve.load / p["area"], rel=1e-15)
        assert curve.nominal_area == p["area"] and curve.e_star == p["e_star"]


def test_curve_type_shapes_and_attributes():
    model = gw()
    assert isinstance(model.at_separation([0.0, 1e-6]), ContactCurve)
    assert model.at_separation(np.zeros((2, 3))).load.shape == (2, 3)
    assert model.at_load(np.ones((4, 1))).separation.shape == (4, 1)
    assert np.ndim(model.at_separation(0.0).load) == 0
    for name, value in PARAMETERS.items():
        assert getattr(model, name) == value
    assert model.distribution == "gaussian"
    assert model.interaction_parameter == pytest.approx(
        1e9 * math.sqrt(1e-4 * 1e-5 * 1e-6), rel=1e-15)
    assert model.summit_count == pytest.approx(1e5)
    assert model.reference_load == pytest.approx(1e5 * 1e11 * math.sqrt(1e-5) * 1e-9)


def test_stiffness_is_minus_the_derivative_of_load():
    d = PARAMETERS["mean"] + SIGMA * np.linspace(-4.0, 6.0, 41)
    step = 1e-4 * SIGMA
    for model in (gw(), improved(), improved(m=0.95), gw(distribution="exponential"),
                  improved(distribution="exponential")):
        numerical = -five_point_derivative(lambda x: model.at_separation(x).load, d, step)
        # Stencil truncation ~ (1e-4)^4, rounding ~ eps W / (1e-4 S sigma): 1e-8 is ample.
        np.testing.assert_allclose(model.at_separation(d).stiffness, numerical, rtol=1e-8)


# --------------------------------------------------------------------------------------------
# improved GW: the exact relations of Section 2

def test_improved_solves_equation_2():
    model = improved()
    d = PARAMETERS["mean"] + SIGMA * np.linspace(-5.0, 8.0, 27)
    curve = model.at_separation(d)
    p = PARAMETERS
    shift = model.m * curve.mean_pressure * math.sqrt(p["area"]) / p["e_star"]
    eta_term = 4 / 3 * p["density"] * p["e_star"] * math.sqrt(p["radius"]) * SIGMA ** 1.5
    right_side = eta_term * gw_integral(1.5, (d - p["mean"]) / SIGMA + shift / SIGMA)
    np.testing.assert_allclose(curve.mean_pressure, right_side, rtol=1e-12)
    # d1 - d cancels: absolute error a few eps |d1| where the shift is tiny.
    np.testing.assert_allclose(curve.extras["effective_separation"] - d, shift, rtol=1e-9,
                               atol=8 * np.finfo(float).eps * np.abs(d).max())
    assert np.all(curve.extras["converged"])


def test_identical_area_load_and_separation_shift():
    loads = gw().reference_load * np.logspace(-12, 3, 31)
    plain, inter = gw().at_load(loads), improved(m=0.9).at_load(loads)
    np.testing.assert_array_equal(plain.area, inter.area)
    np.testing.assert_array_equal(plain.contacts, inter.contacts)
    shift = 0.9 * plain.mean_pressure * math.sqrt(PARAMETERS["area"]) / PARAMETERS["e_star"]
    # d_GW - d_improved = m p_nom sqrt(A)/E*; cancellation in the difference: eps |d|.
    np.testing.assert_allclose(plain.separation - inter.separation, shift,
                               rtol=1e-12, atol=4e-16 * np.abs(plain.separation).max())
    # The same through the separation-controlled solve.
    d = PARAMETERS["mean"] + SIGMA * np.linspace(-3.0, 6.0, 19)
    solved = improved(m=0.9).at_separation(d)
    back = gw().at_load(solved.load)
    np.testing.assert_allclose(back.area, solved.area, rtol=1e-12)
    np.testing.assert_allclose(back.separation - d, 0.9 * solved.mean_pressure
                               * math.sqrt(PARAMETERS["area"]) / PARAMETERS["e_star"],
                               rtol=1e-9, atol=8 * np.finfo(float).eps * np.abs(d).max())


def test_improved_loads_are_lower_than_gw_at_the_same_separation():
    d = PARAMETERS["mean"] + SIGMA * np.linspace(-3.0, 6.0, 19)
    assert np.all(improved().at_separation(d).load < gw().at_separation(d).load)


def test_series_compliance_and_effective_stiffness():
    model = improved(m=0.95)
    d = PARAMETERS["mean"] + SIGMA * np.linspace(-4.0, 6.0, 21)
    curve = model.at_separation(d)
    np.testing.assert_allclose(curve.extras["gw_stiffness"],
                               gw().at_separation(curve.extras["effective_separation"]).stiffness,
                               rtol=1e-13)
    compliance = 1 / curve.extras["gw_stiffness"] + 0.95 / (PARAMETERS["e_star"] * math.sqrt(1e-4))
    np.testing.assert_allclose(1 / curve.stiffness, compliance, rtol=1e-13)
    np.testing.assert_allclose(curve.conductance, 2 * curve.stiffness / PARAMETERS["e_star"],
                               rtol=1e-15)


def test_small_interaction_recovers_gw():
    d = PARAMETERS["mean"] + SIGMA * np.linspace(-3.0, 6.0, 19)
    reference = gw().at_separation(d)
    exact = improved(m=0.0).at_separation(d)
    for name in ("load", "area", "contacts", "stiffness"):
        np.testing.assert_array_equal(getattr(exact, name), getattr(reference, name))
    # C -> 0 by shrinking the nominal area at fixed summit density: the relative change in
    # load is ~ C * 2 F_1/2 (first order), so it must shrink in proportion to C.
    errors = []
    for area in (1e-14, 1e-16, 1e-18):
        small = improved(area=area)
        plain = gw(area=area)
        errors.append(np.max(np.abs(small.at_separation(d).load / plain.at_separation(d).load - 1)))
        assert errors[-1] < 10 * small.interaction_parameter
    assert errors[1] < errors[0] / 5 and errors[2] < errors[1] / 5


def test_one_iteration_is_the_footnote_approximation():
    exact, approximate = improved(area=1e-8), improved(area=1e-8, one_iteration=True)  # C = 0.32
    p = PARAMETERS
    d = p["mean"] + SIGMA * np.linspace(-1.0, 5.0, 13)
    gw_load = gw(area=1e-8).at_separation(d).load
    k = 1.0 / (p["e_star"] * math.sqrt(1e-8))
    expected = gw(area=1e-8).at_separation(d + k * gw_load).load
    curve = approximate.at_separation(d)
    np.testing.assert_allclose(curve.load, expected, rtol=1e-14)
    np.testing.assert_allclose(curve.extras["effective_separation"], d + k * gw_load, rtol=1e-14)
    assert curve.extras["converged"].all()                # a closed form: all converged
    # A good approximation where 2 m C F_1/2 is small (the paper's footnote), within the
    # second-order term of the fixed-point iteration ~ (2 m C F_1/2)^2 relative to the shift.
    relative = np.abs(curve.load / exact.at_separation(d).load - 1)
    assert np.all(relative[d > p["mean"] + 2 * SIGMA] < 2e-3)
    # at_load is exact in both modes.
    loads = gw().reference_load * np.logspace(-8, 0, 5)
    np.testing.assert_array_equal(approximate.at_load(loads).separation,
                                  exact.at_load(loads).separation)


# --------------------------------------------------------------------------------------------
# exponential summit heights: eqs. (7)-(10), exact

@pytest.mark.parametrize("model_class", [GreenwoodWilliamson, ImprovedGreenwoodWilliamson])
def test_exponential_area_is_proportional_to_load(model_class):
    model = model_class(**{**PARAMETERS, "mean": 0.0}, distribution="exponential")
    d = SIGMA * np.linspace(-3.0, 10.0, 27)
    curve = model.at_separation(d)
    ratio = math.sqrt(math.pi) * math.sqrt(PARAMETERS["radius"] / SIGMA) / PARAMETERS["e_star"]
    np.testing.assert_allclose(curve.area, ratio * curve.load, rtol=1e-13)


def test_exponential_equations_8_to_10():
    p = {**PARAMETERS, "mean": 0.0}
    model = ImprovedGreenwoodWilliamson(**p, distribution="exponential", m=1.0)
    d = SIGMA * np.linspace(-3.0, 10.0, 27)
    curve = model.at_separation(d)
    pressure, area, e_star = curve.mean_pressure, p["area"], p["e_star"]
    # (8): p_nom = sqrt(pi) eta E* R^1/2 sigma^3/2 exp(-(d + p_nom sqrt(A)/E*)/sigma)
    eq8 = (math.sqrt(math.pi) * p["density"] * e_star * math.sqrt(p["radius"]) * SIGMA ** 1.5
           * np.exp(-(d + pressure * math.sqrt(area) / e_star) / SIGMA))
    np.testing.assert_allclose(pressure, eq8, rtol=1e-12)
    # (9): 1/S = sigma/(p_nom A) + 1/(E* sqrt A)
    np.testing.assert_allclose(1 / curve.stiffness,
                               SIGMA / (pressure * area) + 1 / (e_star * math.sqrt(area)),
                               rtol=1e-12)
    # (10): R/rho = E* sigma/(p_nom A) + 1/sqrt(A), with R/rho = 2/conductance (Barber, rho the
    # resistivity of each of two identical bodies; conductance = 2S/E*).
    np.testing.assert_allclose(2 / curve.conductance,
                               e_star * SIGMA / (pressure * area) + 1 / math.sqrt(area),
                               rtol=1e-12)


# --------------------------------------------------------------------------------------------
# inversion, extremes, bad input

@pytest.mark.parametrize("model", [gw(), improved(), gw(distribution="exponential"),
                                   improved(distribution="exponential")])
def test_round_trip(model):
    h = np.linspace(-5.0, 30.0, 71)
    d = PARAMETERS["mean"] + SIGMA * h
    curve = model.at_separation(d)
    back = model.at_load(curve.load)
    # Conditioning: dW/W = -(S sigma/W) dh, with S sigma/W >= ~1/|h| for the loads here, so a
    # 1e-15 relative load error moves d by < 1e-13 sigma (1 + |h| + |h1|); 1e-11 is ample.
    scale = SIGMA * (1 + np.abs(h) + np.abs((curve.extras["effective_separation"] - PARAMETERS["mean"])
                                            / SIGMA if "effective_separation" in curve.extras
                                            else 0))
    assert np.all(np.abs(back.separation - d) <= 1e-11 * scale)
    assert np.all(back.extras["converged"])
    np.testing.assert_array_equal(back.load, curve.load)


def test_zero_and_tiny_loads():
    for model in (gw(), improved()):
        zero = model.at_load([0.0, 0.0])
        assert np.all(zero.separation == np.inf)
        assert np.all(zero.area == 0) and np.all(zero.stiffness == 0)
        assert np.all(zero.contacts == 0)
        tiny = model.at_load([5e-324, 1e-300, 1e-200])
        assert np.all(np.isfinite(tiny.separation))
        assert np.all(np.diff(tiny.separation) < 0)
        out = model.at_separation([np.inf, 1.0])
        assert np.all(out.load == 0) and np.all(out.area == 0)


def test_huge_loads():
    model = improved()
    loads = model.reference_load * np.array([1e3, 1e10, 1e100])
    curve = model.at_load(loads)
    assert np.all(np.isfinite(curve.separation)) and np.all(np.diff(curve.separation) < 0)
    np.testing.assert_allclose(model.greenwood_williamson.at_separation(
        curve.extras["effective_separation"]).load, loads, rtol=1e-12)


@pytest.mark.parametrize("name", ["density", "radius", "sigma", "e_star", "area"])
@pytest.mark.parametrize("value", [0.0, -1.0, float("nan"), float("inf"), "abc"])
def test_bad_positive_parameters(name, value):
    for model_class in (GreenwoodWilliamson, ImprovedGreenwoodWilliamson):
        with pytest.raises(ValueError, match=name):
            model_class(**{**PARAMETERS, name: value})


def test_other_bad_input():
    with pytest.raises(ValueError, match="mean"):
        gw(mean=float("nan"))
    with pytest.raises(ValueError, match="distribution"):
        gw(distribution="uniform")
    with pytest.raises(ValueError, match="m must"):
        improved(m=-0.1)
    with pytest.raises(ValueError, match="m must"):
        improved(m=float("nan"))
    with pytest.raises(ValueError, match="one_iteration"):
        improved(one_iteration="yes")
    with pytest.raises(ValueError, match="separation"):
        gw().at_separation([0.0, float("nan")])
    with pytest.raises(ValueError, match="separation"):
        improved().at_separation(-np.inf)
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="load"):
            improved().at_load([1.0, bad])
    with pytest.raises(TypeError):
        GreenwoodWilliamson(1.0, 1.0, 1.0, 0.5)          # mean and the rest are keyword-only


# --------------------------------------------------------------------------------------------
# hypothesis: the numerical-stability stress tests

def model_from(log_c, eta_r_sigma, log_sigma, log_ratio, log_e_star, mean, m, exponential):
    sigma = 10.0 ** log_sigma
    radius = sigma * 10.0 ** log_ratio
    density = eta_r_sigma / (radius * sigma)
    c = 10.0 ** log_c
    area = c ** 2 / (density ** 2 * radius * sigma)          # C = eta sqrt(A R sigma)
    return ImprovedGreenwoodWilliamson(
        density, radius, sigma, mean=mean * sigma, e_star=10.0 ** log_e_star, area=area, m=m,
        distribution="exponential" if exponential else "gaussian")


models = st.builds(
    model_from, log_c=st.floats(-3, 4), eta_r_sigma=st.floats(0.005, 0.5),
    log_sigma=st.floats(-9, -2), log_ratio=st.floats(0, 4), log_e_star=st.floats(5, 12),
    mean=st.floats(-1, 2), m=st.floats(0, 2), exponential=st.booleans())


def non_increasing(values):
    # Allows rounding-level wiggles between nearly equal arguments.
    return np.all(values[1:] <= values[:-1] * (1 + 1e-13))


@given(model=models, h=st.lists(st.floats(-5, 30), min_size=2, max_size=20, unique=True))
def test_property_separations(model, h):
    h = np.sort(np.array(h))
    d = model.mean + model.sigma * h
    distinct = np.diff(h) > 1e-6
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for theory in (model, model.greenwood_williamson):
            curve = theory.at_separation(d)
            for name in ("load", "area", "contacts", "stiffness", "conductance"):
                values = getattr(curve, name)
                assert np.all(np.isfinite(values)) and np.all(values >= 0), name
                assert non_increasing(values), name
            positive = curve.load > 0
            assert np.all(np.diff(curve.load)[distinct & positive[1:]] < 0)
            back = theory.at_load(curve.load[positive])
            h1 = (curve.extras.get("effective_separation", d) - model.mean) / model.sigma
            # Round trip; conditioning as in test_round_trip, with a margin for C up to 1e4.
            scale = model.sigma * (1 + np.abs(h) + np.abs(h1))
            assert np.all(np.abs(back.separation - d[positive]) <= 1e-10 * scale[positive])


@given(model=models, exponents=st.lists(st.floats(-12, 3), min_size=2, max_size=20,
                                        unique=True))
def test_property_loads_over_15_decades(model, exponents):
    exponents = np.sort(np.array(exponents))
    loads = model.reference_load * 10.0 ** exponents
    distinct = np.diff(exponents) > 1e-9
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for theory in (model, model.greenwood_williamson):
            curve = theory.at_load(loads)
            assert np.all(np.isfinite(curve.separation))
            assert np.all(np.diff(curve.separation)[distinct] < 0)
            for name in ("area", "contacts", "stiffness", "conductance"):
                values = getattr(curve, name)
                assert np.all(np.isfinite(values)) and np.all(values >= 0), name
                assert non_increasing(values[::-1]), name
            # Back through the separation-controlled path (the exact solve for improved GW).
            again = theory.at_separation(curve.separation)
            np.testing.assert_allclose(again.load, loads, rtol=1e-9)


# --------------------------------------------------------------------------------------------
# the root finder and its convergence report

def test_monotone_root_solves_and_reports():
    from asperity.common.roots import monotone_root

    targets = np.array([1e-6, 0.5, 8.0, 1e6])

    def cube(x, index):
        return x ** 3 - targets[index], 3 * x ** 2

    root, converged, iterations = monotone_root(cube, np.zeros(4), np.full(4, 200.0),
                                                np.full(4, 200.0), increasing=True)
    np.testing.assert_allclose(root, np.cbrt(targets), rtol=1e-14)
    assert converged.all() and iterations < 60
    # Decreasing functions, started anywhere inside the bracket.
    root, converged, _ = monotone_root(lambda x, i: (targets[i] - x ** 3, -3 * x ** 2),
                                       np.zeros(4), np.full(4, 200.0), np.full(4, 1.0),
                                       increasing=False)
    np.testing.assert_allclose(root, np.cbrt(targets), rtol=1e-14)
    _, converged, iterations = monotone_root(cube, np.zeros(4), np.full(4, 200.0),
                                             np.full(4, 200.0), increasing=True,
                                             max_iterations=2)
    assert iterations == 2 and not converged.all()


def test_unconverged_solves_warn_and_say_so(monkeypatch):
    import functools

    import asperity.gw.greenwood_williamson as module
    from bem.common.warnings import ConvergenceWarning

    monkeypatch.setattr(module, "monotone_root",
                        functools.partial(module.monotone_root, max_iterations=1))
    with pytest.warns(ConvergenceWarning, match="did not converge"):
        curve = improved().at_separation(PARAMETERS["mean"] + SIGMA * np.array([-2.0, 0.0]))
    assert not curve.extras["converged"].all()


def test_one_iteration_stiffness_is_the_slope_of_its_own_curve():
    # Regression: the footnote approximation used to report the exact theory's series
    # stiffness at its own d1, which is not -dW/dd of the approximate curve (wrong sign where
    # the approximation's load falls).
    model = ImprovedGreenwoodWilliamson(density=50.0, radius=1.0, sigma=1.0, area=1.0,
                                        one_iteration=True)  # C = 50
    d = np.array([3.0, 2.5, 2.0, 1.0])
    step = 1e-6
    curve = model.at_separation(d)
    slope = -(model.at_separation(d + step).load - model.at_separation(d - step).load) / (2 * step)
    np.testing.assert_allclose(curve.stiffness, slope, rtol=1e-5)
    assert curve.stiffness[2] < 0  # d = 2: past the approximation's load maximum
