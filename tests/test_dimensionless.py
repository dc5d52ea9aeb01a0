"""The paper's dimensionless forms and the curves of its Figs. 1-3."""

import math

import numpy as np
import pytest

from asperity import (GreenwoodWilliamson, ImprovedGreenwoodWilliamson, dimensionless,
                      dimensionless_pressure, gw_integral, interaction_curves,
                      interaction_parameter)

PARAMETERS = dict(density=1e9, radius=1e-5, sigma=1e-6, e_star=1e11, area=1e-4)


def test_section_4_variables_of_a_curve():
    length = 1e-2                                   # L^2 = the nominal area 1e-4
    model = GreenwoodWilliamson(**PARAMETERS, mean=3e-7)
    d = 3e-7 + 1e-6 * np.linspace(-2.0, 4.0, 61)
    curve = model.at_separation(d)
    result = dimensionless(curve, 1e-6, length)
    np.testing.assert_allclose(result.separation, d / 1e-6, rtol=1e-15)
    np.testing.assert_allclose(result.load, curve.load / (1e11 * length ** 2), rtol=1e-15)
    np.testing.assert_allclose(result.area, curve.area / length ** 2, rtol=1e-15)
    # Conductance = -2 dLoad/dSeparation, by five-point differences of the dimensionless curve.
    step = 1e-4

    def load_of(separation):
        return dimensionless(model.at_separation(separation * 1e-6), 1e-6, length).load

    s = result.separation
    derivative = (-load_of(s + 2 * step) + 8 * load_of(s + step) - 8 * load_of(s - step)
                  + load_of(s - 2 * step)) / (12 * step)
    np.testing.assert_allclose(result.conductance, -2 * derivative, rtol=1e-8)
    with pytest.raises(ValueError):
        result.load[0] = 1.0                        # read-only arrays


def test_conductance_is_none_without_stiffness():
    from bem import ContactCurve
    curve = ContactCurve(separation=[1.0], load=[2.0], area=[3.0], mean_pressure=[2.0],
                         nominal_area=1.0, e_star=1.0)
    assert dimensionless(curve, 1.0, 1.0).conductance is None


def test_equations_3_and_4():
    p = PARAMETERS
    c = interaction_parameter(p["density"], p["radius"], p["sigma"], p["area"])
    n = p["density"] * p["area"]
    assert c == pytest.approx(math.sqrt(n * p["density"] * p["radius"] * p["sigma"]), rel=1e-15)
    # eta R sigma = 0.05: C = sqrt(N/20), so 500 summits give C = 5 (the paper's Fig. 1).
    assert interaction_parameter(500.0, 0.05 / 500 / 1e-3, 1e-3, 1.0) == pytest.approx(5.0)
    model = GreenwoodWilliamson(**p)
    curve = model.at_separation(np.array([0.0, 1e-6]))
    p_bar = dimensionless_pressure(curve.mean_pressure, p["density"], p["radius"], p["sigma"],
                                   p["e_star"])
    np.testing.assert_allclose(p_bar, 4 / 3 * gw_integral(1.5, [0.0, 1.0]), rtol=1e-14)


@pytest.mark.parametrize("c", [5.0, 50.0])
def test_figure_curves_solve_the_reduced_equation(c):
    curves = interaction_curves(c)
    h = curves.separation
    assert h[0] == -1.0 and h[-1] == 4.0 and h.size == 201
    np.testing.assert_allclose(curves.gw_pressure, 4 / 3 * gw_integral(1.5, h), rtol=1e-14)
    # p_bar = (4/3) F_3/2(h + m C p_bar) (eq. 2 in the paper's reduced form).
    p_bar = curves.improved_pressure
    np.testing.assert_allclose(p_bar, 4 / 3 * gw_integral(1.5, h + c * p_bar), rtol=1e-12)
    np.testing.assert_allclose(curves.effective_separation, h + c * p_bar, rtol=1e-12)
    np.testing.assert_allclose(curves.effective_stiffness,
                               2 * gw_integral(0.5, curves.effective_separation), rtol=1e-14)
    np.testing.assert_allclose(curves.gw_stiffness, 2 * gw_integral(0.5, h), rtol=1e-14)
    np.testing.assert_allclose(
        curves.improved_stiffness,
        curves.effective_stiffness / (1 + c * curves.effective_stiffness), rtol=1e-14)
    assert np.all(p_bar < curves.gw_pressure)
    assert np.all(curves.improved_stiffness < curves.effective_stiffness)


def test_figure_stiffness_is_the_derivative_of_the_pressure():
    h = np.linspace(-1.0, 4.0, 26)
    step = 1e-4
    pressure = lambda x: interaction_curves(50.0, separation=x).improved_pressure  # noqa: E731
    derivative = (-pressure(h + 2 * step) + 8 * pressure(h + step) - 8 * pressure(h - step)
                  + pressure(h - 2 * step)) / (12 * step)
    np.testing.assert_allclose(interaction_curves(50.0, separation=h).improved_stiffness,
                               -derivative, rtol=1e-8)


def test_figure_curves_match_a_physical_model():
    # C = 5 from 500 summits with eta R sigma = 0.05, in SI-like units.
    sigma, density = 1e-3, 500.0
    radius = 0.05 / (density * sigma)
    model = ImprovedGreenwoodWilliamson(density, radius, sigma, e_star=2e9, area=1.0, m=0.9)
    h = np.linspace(-1.0, 4.0, 11)
    curve = model.at_separation(h * sigma)
    p_bar = dimensionless_pressure(curve.mean_pressure, density, radius, sigma, 2e9)
    curves = interaction_curves(model.interaction_parameter, m=0.9, separation=h)
    np.testing.assert_allclose(p_bar, curves.improved_pressure, rtol=1e-12)


def test_depends_on_m_times_c_only_and_recovers_gw():
    h = np.linspace(-1.0, 4.0, 11)
    a = interaction_curves(10.0, m=0.5, separation=h)
    b = interaction_curves(5.0, m=1.0, separation=h)
    np.testing.assert_allclose(a.improved_pressure, b.improved_pressure, rtol=1e-13)
    zero = interaction_curves(0.0, separation=h)
    np.testing.assert_array_equal(zero.improved_pressure, zero.gw_pressure)
    np.testing.assert_array_equal(zero.improved_stiffness, zero.gw_stiffness)


def test_bad_input():
    with pytest.raises(ValueError, match="interaction_parameter"):
        interaction_curves(-1.0)
    with pytest.raises(ValueError, match="m must"):
        interaction_curves(5.0, m=float("nan"))
    curve = GreenwoodWilliamson(**PARAMETERS).at_separation([0.0])
    with pytest.raises(ValueError, match="sigma"):
        dimensionless(curve, 0.0, 1.0)
    with pytest.raises(ValueError, match="length"):
        dimensionless(curve, 1.0, -2.0)
    with pytest.raises(ValueError, match="density"):
        interaction_parameter(0.0, 1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="e_star"):
        dimensionless_pressure(1.0, 1.0, 1.0, 1.0, float("inf"))
