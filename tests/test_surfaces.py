"""Weierstrass-Mandelbrot surfaces (docs/theory.md eqs. 11-12) and surface statistics."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from validation import surface_statistics, wm_amplitude, wm_surface


def direct_wm(n, D, G, L, gamma, M, phases):
    """Eq. (11)-(12) evaluated point by point in polar form, independently of the library."""
    n_max = phases.shape[1] - 1
    B = L * (G / L) ** (D - 2) * (math.log(gamma) / M) ** 0.5
    x = np.arange(n) * L / n
    X, Y = np.meshgrid(x, x)  # X varies along columns, Y along rows: heights[j, i]
    r = np.hypot(X, Y)
    theta = np.arctan2(Y, X)
    z = np.zeros((n, n))
    for m in range(1, M + 1):
        for k in range(n_max + 1):
            phi = phases[m - 1, k]
            z += gamma ** ((D - 3) * k) * (
                math.cos(phi) - np.cos(2 * np.pi * gamma**k * r / L * np.cos(theta - np.pi * m / M) + phi)
            )
    return B * z


@pytest.mark.parametrize("D", [2.05, 2.5, 2.95])
@pytest.mark.parametrize("L", [1.0, 3.7])
def test_matches_direct_evaluation_of_eq_11(D, L):
    M, n_max, n, G, gamma = 7, 5, 40, 1e-3, 1.7
    phases = np.random.default_rng(1).uniform(0, 2 * np.pi, size=(M, n_max + 1))
    expected = direct_wm(n, D, G, L, gamma, M, phases)
    expected_mean = expected.mean()
    got = wm_surface(n, D=D, G=G, L=L, gamma=gamma, M=M, n_max=n_max, phases=phases)
    # The library removes the mean; the direct form keeps it (cos(phi) offset included).
    scale = np.abs(expected).max()
    np.testing.assert_allclose(got, expected - expected_mean, rtol=0, atol=1e-12 * scale)
    # The cos(phi) offset makes z(0, 0) = 0 before the mean is removed.
    assert abs(expected[0, 0]) < 1e-12 * scale
    assert got[0, 0] == pytest.approx(-expected_mean, rel=1e-12, abs=1e-14 * scale)


def test_amplitude_B_of_eq_12():
    D, G, L, gamma, M = 2.3, 0.02, 2.0, 1.5, 10
    assert wm_amplitude(G, D=D, L=L, gamma=gamma, M=M) == pytest.approx(
        L * (G / L) ** (D - 2) * math.sqrt(math.log(gamma) / M), rel=1e-15)


def test_row_index_is_y_and_column_index_is_x():
    # One ridge (M = 1: direction pi m / M = pi, along -x) varies only along x: rows are equal.
    z = wm_surface(16, D=2.5, G=1.0, M=1, n_max=2, seed=3)
    np.testing.assert_allclose(z, np.broadcast_to(z[0], z.shape), atol=1e-14)
    assert np.ptp(z[0]) > 0
    # M = 2 adds the direction pi/2 (along y); removing the x ridge leaves a pure y-wave.
    phases = np.zeros((2, 1))
    z2 = wm_surface(16, D=2.5, G=1.0, M=2, n_max=0, phases=phases)
    z1 = wm_surface(16, D=2.5, G=1.0, M=1, n_max=0, phases=phases[:1])
    # both surfaces share B up to the sqrt(1/M) factor of eq. (12)
    only_y = z2 / math.sqrt(1 / 2) - z1 / math.sqrt(1.0)
    np.testing.assert_allclose(only_y, np.broadcast_to(only_y[:, :1], only_y.shape), atol=1e-12)


@pytest.mark.parametrize("D", [2.05, 2.5, 2.95])
def test_heights_scale_as_G_to_the_D_minus_2(D):
    a = wm_surface(32, D=D, G=1e-4, seed=5)
    b = wm_surface(32, D=D, G=1e-2, seed=5)
    np.testing.assert_allclose(b, a * 100.0 ** (D - 2), rtol=1e-12, atol=1e-15 * np.abs(b).max())


@pytest.mark.parametrize("slope", [1e-3, 0.1, 2.0])
def test_rms_slope_mode_hits_the_slope(slope):
    z = wm_surface(128, D=2.3, rms_slope=slope, L=2.0, seed=0)
    assert surface_statistics(z, 2.0 / 128).rms_gradient == pytest.approx(slope, rel=1e-12)


def test_seed_reproducible_and_mean_removed():
    a = wm_surface(64, D=2.4, G=1e-3, seed=11)
    b = wm_surface(64, D=2.4, G=1e-3, seed=11)
    c = wm_surface(64, D=2.4, G=1e-3, seed=12)
    np.testing.assert_array_equal(a, b)
    assert np.abs(a - c).max() > 0.1 * a.std()
    assert abs(a.mean()) < 1e-15 * np.abs(a).max() * a.size ** 0.5


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(D=2.0, G=1.0), "D"),
        (dict(D=3.0, G=1.0), "D"),
        (dict(D=float("nan"), G=1.0), "D"),
        (dict(D=2.5, G=1.0, gamma=1.0), "gamma"),
        (dict(D=2.5, G=1.0, M=0), "M"),
        (dict(D=2.5, G=1.0, n_max=-1), "n_max"),
        (dict(D=2.5, G=1.0, rms_slope=0.1), "G"),
        (dict(D=2.5), "G"),
        (dict(D=2.5, G=float("inf")), "G"),
        (dict(D=2.5, G=-1.0), "G"),
        (dict(D=2.5, rms_slope=0.0), "rms_slope"),
        (dict(D=2.5, G=1.0, L=0.0), "L"),
        (dict(D=2.5, G=1.0, phases=np.zeros((10, 8))), "phases"),
        (dict(D=2.5, G=1.0, phases=np.full((10, 9), np.nan)), "phases"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, name):
    with pytest.raises(ValueError, match=name):
        wm_surface(16, **kwargs)


@pytest.mark.parametrize("n", [1, 0, 2.5])
def test_bad_grid_size(n):
    with pytest.raises(ValueError, match="n"):
        wm_surface(n, D=2.5, G=1.0)


def test_statistics_of_a_sinusoid():
    # z = a cos(k x): m0 = a^2/2, and on the x-profile <z_x^2> = a^2 k^2/2 (exact for the
    # central-difference derivative with the discrete wavenumber sin(k h)/h).
    n, L, a = 256, 1.0, 0.01
    h = L / n
    k = 2 * np.pi * 4 / L
    x = np.arange(n) * h
    z = np.broadcast_to(a * np.cos(k * x), (n, n)).copy()
    s = surface_statistics(z, h, periodic=True)
    k1 = math.sin(k * h) / h
    k2 = (2 - 2 * math.cos(k * h)) / h**2
    assert s.m0 == pytest.approx(a**2 / 2, rel=1e-12)
    assert s.rms_gradient == pytest.approx(a * k1 / math.sqrt(2), rel=1e-12)
    assert s.m2 == pytest.approx(a**2 * k1**2 / 4, rel=1e-12)  # averaged over x and y
    assert s.m4 == pytest.approx(a**2 * k2**2 / 4, rel=1e-12)
    assert s.rms_curvature == pytest.approx(a * k2 / 2 / math.sqrt(2), rel=1e-12)
    assert s.nayak == pytest.approx(s.m0 * s.m4 / s.m2**2, rel=1e-12)


def test_statistics_bad_input():
    with pytest.raises(ValueError, match="spacing"):
        surface_statistics(np.zeros((8, 8)), 0.0)
    with pytest.raises(ValueError, match="finite"):
        surface_statistics(np.full((8, 8), np.nan), 1.0)
    with pytest.raises(ValueError, match="2-D"):
        surface_statistics(np.zeros(8), 1.0)


@given(
    D=st.floats(2.001, 2.999),
    slope=st.floats(1e-6, 1e2),
    gamma=st.floats(1.05, 3.0),
    M=st.integers(1, 12),
    n_max=st.integers(0, 10),
    n=st.integers(8, 64),
    seed=st.integers(0, 2**32 - 1),
)
def test_property_finite_and_slope_consistent(D, slope, gamma, M, n_max, n, seed):
    z = wm_surface(n, D=D, rms_slope=slope, gamma=gamma, M=M, n_max=n_max, seed=seed)
    assert z.shape == (n, n)
    assert np.all(np.isfinite(z))
    stats = surface_statistics(z, 1.0 / n)
    assert stats.rms_gradient == pytest.approx(slope, rel=1e-10)
    assert abs(z.mean()) <= 1e-12 * max(np.abs(z).max(), 1e-300)


def test_slope_grid_samples_one_continuous_surface_on_several_grids():
    # The same phases and amplitude on grids n and 2n: every point of the coarse grid is a point
    # of the fine one (x_i = i L/n = 2i L/(2n)), up to the mean each grid removes.
    coarse = wm_surface(32, D=2.6, rms_slope=0.1, seed=4)
    fine = wm_surface(64, D=2.6, rms_slope=0.1, seed=4, slope_grid=32)
    difference = fine[::2, ::2] - coarse
    np.testing.assert_allclose(difference, difference.mean(), atol=1e-14 * np.abs(coarse).max())
    # while each grid measuring its own slope gives a differently scaled surface
    own = wm_surface(64, D=2.6, rms_slope=0.1, seed=4)
    assert np.abs(own[::2, ::2] - own.mean() - coarse).max() > 1e-3 * np.abs(coarse).max()
    with pytest.raises(ValueError, match="slope_grid"):
        wm_surface(16, D=2.5, rms_slope=0.1, slope_grid=2)
