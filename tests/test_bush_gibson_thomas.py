"""Bush-Gibson-Thomas theory (asperity.spectral.bush_gibson_thomas) and the elliptic Hertz contact.

Checked against: the displacement of Hertz's elliptic pressure (quadrature of the Boussinesq
integral), direct numerical integration of the model's own definition (scipy), Nayak's summit
density, the small-load limit A/A0 = sqrt(2 pi) p/(E* h'_rms) and its own derivatives.
"""

import math
import pickle

import numpy as np
import pytest
from scipy import integrate, special

from asperity import BushGibsonThomas, hertz_elliptic_factors, spectral_summits
from asperity.spectral.bush_gibson_thomas import _curvature_integrals
from asperity.spectral.hertz_elliptic import eccentricity_parameter
from bem import ConvergenceWarning

ROOT_TWO_PI = math.sqrt(2 * math.pi)


def _displacement(x0, y0, a, b, p0, e_star=1.0):
    """Surface displacement at (x0, y0) under p0 sqrt(1 - x^2/a^2 - y^2/b^2): the point-force
    integral (T2) in polar coordinates about (x0, y0), where the 1/rho kernel cancels."""
    def ray(phi):
        c, s = math.cos(phi), math.sin(phi)
        qa = (c / a) ** 2 + (s / b) ** 2
        qb = 2 * (x0 * c / a**2 + y0 * s / b**2)
        qc = (x0 / a) ** 2 + (y0 / b) ** 2 - 1
        end = (-qb + math.sqrt(qb * qb - 4 * qa * qc)) / (2 * qa)
        return integrate.quad(lambda rho: p0 * math.sqrt(max(
            0.0, 1 - ((x0 + rho * c) / a) ** 2 - ((y0 + rho * s) / b) ** 2)), 0, end,
            epsabs=1e-13, epsrel=1e-12)[0]
    return integrate.quad(ray, 0, 2 * math.pi, epsabs=1e-12, epsrel=1e-11,
                          limit=200)[0] / (math.pi * e_star)


@pytest.mark.parametrize("ratio", [0.5, 0.05])
def test_elliptic_hertz_pressure_fits_the_paraboloid(ratio):
    # Build the contact of curvatures (1, ratio) at approach 1 from the factors, then check that
    # its elliptic Hertz pressure displaces the surface exactly by the paraboloid's gap.
    f_area, f_load = hertz_elliptic_factors(ratio)
    m = float(eccentricity_parameter(ratio))
    radius = 1 / math.sqrt(ratio)                        # geometric mean radius, kappa = (1, ratio)
    area = math.pi * radius * f_area                     # A = pi R_e w f_A at w = 1
    load = 4 / 3 * math.sqrt(radius) * f_load            # P = (4/3) E* R_e^1/2 w^3/2 f_P
    a = math.sqrt(area / (math.pi * math.sqrt(1 - m)))   # semi-axes, b/a = sqrt(1 - m)
    b = a * math.sqrt(1 - m)
    p0 = 3 * load / (2 * math.pi * a * b)
    for x0, y0 in ((0, 0), (0.5 * a, 0), (0, 0.5 * b), (0.3 * a, 0.4 * b)):
        gap = 1 - (ratio * x0**2 + y0**2) / 2           # a lies along the smaller curvature
        assert _displacement(x0, y0, a, b, p0) == pytest.approx(gap, rel=1e-9)


def test_hertz_factors_limits():
    f_area, f_load = hertz_elliptic_factors([1.0, 1 - 1e-9, 0.9])
    np.testing.assert_allclose(f_area[:2], 1.0, rtol=1e-8)
    np.testing.assert_allclose(f_load[:2], 1.0, rtol=1e-8)
    # m -> 0: lambda = 1 - 3m/4 + O(m^2), from K - E = (pi/4) m (1 + 3m/8), E/(1-m) - K = ...
    m = eccentricity_parameter(1 - 3e-6 / 4)
    assert float(m) == pytest.approx(1e-6, rel=1e-5)
    with pytest.raises(ValueError, match="ratio"):
        hertz_elliptic_factors(1.5)


@pytest.mark.parametrize("alpha", [2.0, 40.0])
def test_every_summit_counts_far_below_the_mean_plane(alpha):
    model = BushGibsonThomas(1e-12, 1e-4, alpha * 1e-8 / 1e-12, area=3.0)
    curve = model.at_separation(-30e-6, quantities=("contacts",))
    expected = spectral_summits(model.m0, model.m2, model.m4).density * 3.0
    assert float(curve.contacts) == pytest.approx(expected, rel=1e-10)


def test_curvature_integrals_against_their_definition():
    # T_Q(x) = integral_0^1 t (1 - t^2)^beta g_Q(t) exp(-x^2 t^2 / 2) dt, g the Hertz factor
    x = np.array([0.3, 3.0, 30.0])
    computed = _curvature_integrals(x, elliptic=True)
    betas = np.array([1.0, 0.5, 0.75])[:, None]

    def integrand(t):
        f_area, f_load = hertz_elliptic_factors(max((1 - t) / (1 + t), 1e-300))
        g = np.array([1.0, float(f_area), float(f_load)])[:, None]
        return t * (1 - t * t) ** betas * g * np.exp(-0.5 * (x[None, :] * t) ** 2)

    exact = integrate.quad_vec(integrand, 0, 1, epsabs=0, epsrel=1e-11)[0]
    for row, name in enumerate(("contacts", "area", "load")):
        np.testing.assert_allclose(computed[name], exact[row], rtol=1e-8, err_msg=name)


def _nayak_load(m0, m2, m4, d, factor=None, tol=1e-6):
    """Load per unit area, integral of Nayak's summit density n(z, a, r) times the Hertz load
    (4/3) (z - d)^3/2 f_P / (a^2 - r^2)^1/4 (E* = 1), by scipy's tplquad."""
    s = m4 / 3
    cov = np.array([[m0, m2], [m2, 2 * s]])
    inverse, det = np.linalg.inv(cov), np.linalg.det(cov)

    def integrand(r, a, z):
        quadratic = inverse[0, 0] * z * z + 2 * inverse[0, 1] * z * a + inverse[1, 1] * a * a
        density = ((a * a - r * r) / (2 * math.pi * m2) * math.exp(-quadratic / 2)
                   / (2 * math.pi * math.sqrt(det)) * r / s * math.exp(-r * r / (2 * s)))
        g = 1.0 if factor is None else factor((a - r) / (a + r))
        return density * 4 / 3 * (z - d) ** 1.5 * g / (a * a - r * r) ** 0.25

    top = 14 * math.sqrt(2 * s)
    return integrate.tplquad(integrand, d, d + 14 * math.sqrt(m0), 0, top, 0, lambda z, a: a,
                             epsabs=0, epsrel=tol)[0]


def test_load_equals_the_integral_of_its_definition_spherical_summits():
    model = BushGibsonThomas(1.0, 1.0, 3.0, elliptic=False)
    d = 1.0
    assert float(model.at_separation(d).load) == pytest.approx(
        _nayak_load(1.0, 1.0, 3.0, d), rel=1e-6)


@pytest.mark.slow
def test_load_equals_the_integral_of_its_definition_elliptic_summits():
    # f_P from a dense table (its interpolation error, ~2e-7, sets the tolerance)
    ratios = np.geomspace(1e-12, 1.0, 4001)
    table = hertz_elliptic_factors(ratios)[1]
    factor = lambda lam: np.interp(math.log(lam), np.log(ratios), table)  # noqa: E731
    model = BushGibsonThomas(1.0, 1.0, 3.0)
    assert float(model.at_separation(1.5).load) == pytest.approx(
        _nayak_load(1.0, 1.0, 3.0, 1.5, factor), rel=1e-6)


@pytest.mark.parametrize("alpha", [2.0, 10.0, 100.0])
def test_small_load_limit_is_linear_with_kappa_root_two_pi(alpha):
    # A/A0 = kappa p/(E* h'_rms) with kappa -> sqrt(2 pi) as the load vanishes: the summits
    # that touch are then high, and their curvature is tied to their height (mean m2 z/m0,
    # spread sqrt(2 alpha/3 - 1) relative to it at z = sqrt(m0)). kappa approaches from below,
    # with a relative error O((2 alpha/3 - 1) m0 / d^2).
    m0, m2 = 4e-12, 2.5e-5
    model = BushGibsonThomas(m0, m2, alpha * m2**2 / m0, e_star=7.0, area=2.0)
    reduced = np.array([2.0, 4.0, 8.0, 16.0, 32.0, 38.0])
    curve = model.at_separation(reduced * math.sqrt(m0))
    kappa = curve.area_fraction / (curve.mean_pressure / (7.0 * math.sqrt(2 * m2)))
    assert np.all(np.diff(kappa) > 0) and np.all(kappa < ROOT_TWO_PI)
    gap = 1 - kappa / ROOT_TWO_PI
    assert np.all(gap[3:] < (2 * alpha / 3) / reduced[3:] ** 2)


def test_stiffness_contacts_and_the_load_inversion():
    model = BushGibsonThomas(1.0, 1.0, 5.0, e_star=2.0, area=0.5)
    d = np.linspace(-1.0, 5.0, 7)
    curve = model.at_separation(d)
    step = 1e-6
    slope = (model.at_separation(d - step).load - model.at_separation(d + step).load) / (2 * step)
    np.testing.assert_allclose(curve.stiffness, slope, rtol=1e-7)
    np.testing.assert_allclose(curve.conductance, 2 * curve.stiffness / 2.0, rtol=1e-15)
    assert np.all(np.diff(curve.contacts) < 0) and np.all(np.diff(curve.area) < 0)
    back = model.at_load(curve.load)
    assert back.extras["converged"].all()
    np.testing.assert_allclose(back.separation, d, rtol=0, atol=1e-12)
    tiny = model.at_load([0.0, 1e-300])
    assert tiny.separation[0] == np.inf and tiny.area[0] == 0
    assert 30 < tiny.separation[1] < 40 and tiny.extras["converged"].all()


def test_greenwoods_simplification_is_close_to_the_elliptic_theory():
    # Greenwood (2006): summits as spheres of the geometric-mean radius change little. At
    # equal load an elliptic summit has the area of the sphere times f_A f_P^(-2/3) < 1
    # (0.99 at lambda = 1/2, 0.95 at 1/4, 0.90 at 1/10); few summits are more elongated.
    elliptic = BushGibsonThomas(1.0, 1.0, 10.0)
    round_ = BushGibsonThomas(1.0, 1.0, 10.0, elliptic=False)
    loads = elliptic.at_separation([0.0, 1.0, 2.0]).load
    ratio = elliptic.at_load(loads).area / round_.at_load(loads).area
    f_area, f_load = hertz_elliptic_factors(0.1)
    assert np.all(ratio < 1) and np.all(ratio > f_area / f_load ** (2 / 3))


def test_shapes_pickle_and_bad_input():
    model = BushGibsonThomas(1.0, 1.0, 4.0)
    assert model.at_separation(1.0).load.shape == ()
    assert model.at_separation(np.ones((2, 3))).area.shape == (2, 3)
    assert model.at_load(np.zeros(0)).load.shape == (0,)
    clone = pickle.loads(pickle.dumps(model))
    assert clone.at_separation(1.0).load == model.at_separation(1.0).load
    assert model.summits.density == pytest.approx(4.0 / (6 * math.pi * math.sqrt(3)))
    with pytest.raises(ValueError, match="alpha"):
        BushGibsonThomas(1.0, 1.0, 1.5)
    with pytest.raises(ValueError, match="e_star"):
        BushGibsonThomas(1.0, 1.0, 4.0, e_star=-1.0)
    with pytest.raises(ValueError, match="separation"):
        model.at_separation([1.0, -np.inf])
    with pytest.raises(ValueError, match="load"):
        model.at_load(-1.0)
    with pytest.warns(ConvergenceWarning):
        assert not model.at_load(1e305).extras["converged"]


def test_elliptic_integrals_used_by_the_factors():
    # the eccentricity solves lambda = (K - E)/(E/(1 - m) - K) (Johnson 1985, eq. 4.39)
    for ratio in (0.9, 0.3, 1e-3):
        m = float(eccentricity_parameter(ratio))
        k, e = special.ellipk(m), special.ellipe(m)
        assert (k - e) / (e / (1 - m) - k) == pytest.approx(ratio, rel=1e-9)
