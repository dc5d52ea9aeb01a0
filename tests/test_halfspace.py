"""The half-space operator against direct sums, analytic responses and invariants."""

import math

import numpy as np
import pytest

from bem import HalfSpace
from bem.reference import (UNIFORM_SQUARE_CENTRE_DEFLECTION, UNIFORM_SQUARE_MEAN_DEFLECTION,
                           love_pixel_displacement)


def dense_love_matrix(shape, spacing, e_star):
    """Influence matrix of Love's pixel formula by a direct double loop over pixel pairs."""
    ny, nx = shape
    j, i = np.mgrid[0:ny, 0:nx]
    dx = (i.ravel()[:, None] - i.ravel()[None, :]) * spacing
    dy = (j.ravel()[:, None] - j.ravel()[None, :]) * spacing
    return love_pixel_displacement(dx, dy, half_width_x=spacing / 2, e_star=e_star)


def test_love_pixel_reference_values():
    # docs/theory.md, eq. T23: unit square, p = E* = 1: centre 4 ln(1 + sqrt 2)/pi, corner half of it.
    assert love_pixel_displacement(0.0, 0.0, half_width_x=0.5) == pytest.approx(1.1221997, abs=1e-7)
    assert love_pixel_displacement(0.5, 0.5, half_width_x=0.5) == pytest.approx(0.5610999, abs=1e-7)
    assert love_pixel_displacement(0.5, -0.5, half_width_x=0.5) == pytest.approx(0.5610999, abs=1e-7)


def test_love_pixel_matches_log_form_and_far_field():
    # The asinh form equals the textbook log form where the latter is defined.
    def log_f(X, Y):
        r = math.hypot(X, Y)
        return X * math.log(Y + r) + Y * math.log(X + r)

    x, y, a, b = 1.7, 0.9, 0.5, 0.3
    expected = (log_f(x + a, y + b) - log_f(x + a, y - b) - log_f(x - a, y + b)
                + log_f(x - a, y - b)) / math.pi
    value = love_pixel_displacement(x, y, half_width_x=a, half_width_y=b)
    assert value == pytest.approx(expected, rel=1e-12)
    # Far away the pixel acts as a point force P = 4ab p: u -> P / (pi E* r), relative
    # correction O((a/r)^2).
    r = 200.0
    far = love_pixel_displacement(r, 0.0, half_width_x=a, half_width_y=b, e_star=2.0)
    assert far == pytest.approx(4 * a * b / (math.pi * 2.0 * r), rel=1e-5)


def test_love_pixel_far_field_accuracy_against_mpmath():
    mpmath = pytest.importorskip("mpmath")

    def f(X, Y):
        X, Y = mpmath.mpf(X), mpmath.mpf(Y)
        return ((X * mpmath.asinh(Y / abs(X)) if X else 0)
                + (Y * mpmath.asinh(X / abs(Y)) if Y else 0))

    eps = np.finfo(float).eps
    for x, y in [(0, 0), (3, 4), (50, 0), (500, 700), (1500, 3), (2047, 2047)]:
        with mpmath.workdps(40):
            exact = (f(x + 0.5, y + 0.5) - f(x + 0.5, y - 0.5) - f(x - 0.5, y + 0.5)
                     + f(x - 0.5, y - 0.5)) / mpmath.pi
        value = love_pixel_displacement(x, y, half_width_x=0.5)
        # Four terms of size ~ r log r cancel to a result ~ 1/r (r in pixels): the rounding
        # error is ~ eps r^2 log r relative (observed 6e-10 at the 2048-pixel diagonal, i.e.
        # 7e-14 of the self-influence; far below any discretisation error).
        r = max(math.hypot(x, y), 2.0)
        assert abs(value / float(exact) - 1) <= 4 * eps * r * r * math.log(r)


def test_love_pixel_is_finite_on_grid_points():
    offsets = np.arange(-4, 5) * 0.5
    values = love_pixel_displacement(offsets[None, :], offsets[:, None], half_width_x=0.5)
    assert np.all(np.isfinite(values)) and np.all(values > 0)


@pytest.mark.parametrize("shape", [(9, 9), (7, 12)])
def test_nonperiodic_operator_matches_dense_love_sum(shape):
    rng = np.random.default_rng(3)
    spacing, e_star = 0.37, 2.5
    pressure = rng.normal(size=shape)
    operator = HalfSpace(shape, spacing, e_star=e_star)
    expected = (dense_love_matrix(shape, spacing, e_star) @ pressure.ravel()).reshape(shape)
    result = operator.displacement(pressure)
    # Same formula, summed two ways: rounding only (FFT error ~ 1e-16 of the largest term).
    assert np.max(np.abs(result - expected)) <= 1e-12 * np.max(np.abs(expected))


@pytest.mark.parametrize("periodic", [False, True])
def test_operator_is_symmetric_maxwell_betti(periodic):
    rng = np.random.default_rng(4)
    operator = HalfSpace((24, 24), 0.1, e_star=3.0, periodic=periodic)
    a, b = rng.normal(size=(2, 24, 24))
    left = float(np.sum(a * operator.displacement(b)))
    right = float(np.sum(b * operator.displacement(a)))
    assert left == pytest.approx(right, rel=1e-12)


@pytest.mark.parametrize("wave", [(3, 0), (0, 5), (2, 7), (16, 16)])
def test_periodic_operator_single_cosine(wave):
    n, length, e_star = 32, 2.0, 1.7
    spacing = length / n
    x = np.arange(n) * spacing
    kx, ky = (2 * math.pi * w / length for w in wave)
    pressure = np.cos(kx * x[None, :] + ky * x[:, None] + 0.3)
    operator = HalfSpace((n, n), spacing, e_star=e_star, periodic=True)
    # u = 2 p / (E* |q|) for a cosine of wavevector q (docs/theory.md, eq. T24).
    expected = 2.0 * pressure / (e_star * math.hypot(kx, ky))
    assert np.max(np.abs(operator.displacement(pressure) - expected)) <= 1e-13 * np.max(np.abs(expected))


def test_periodic_uniform_pressure_gives_zero_displacement():
    # q = 0 convention: u_hat(0) = 0, the mean plane of the surface does not move.
    operator = HalfSpace((16, 16), 0.5, periodic=True)
    assert np.max(np.abs(operator.displacement(np.full((16, 16), 3.0)))) < 1e-14


@pytest.mark.parametrize("periodic", [False, True])
def test_elastic_energy_is_positive(periodic):
    rng = np.random.default_rng(5)
    operator = HalfSpace((20, 20), 0.2, periodic=periodic)
    for _ in range(20):
        pressure = rng.normal(size=(20, 20)) * rng.uniform(0, 1, size=(20, 20)) ** 4
        if periodic:
            pressure -= pressure.mean()  # the uniform mode carries no energy in the periodic case
        assert float(np.sum(pressure * operator.displacement(pressure))) > 0.0


def test_uniform_square_mean_deflection_converges():
    # Uniform p on the whole grid: the pixel-centre values are the exact Love integral over the
    # square, so their mean differs from the exact mean 0.9464 p L / E* only by the midpoint
    # rule, whose error falls by ~3.5 per doubling (edge singularity of the slope).
    errors = []
    for n in (8, 16, 32, 64):
        operator = HalfSpace((n, n), 2.0 / n, e_star=4.0)
        mean = operator.displacement(np.full((n, n), 3.0)).mean()
        errors.append(abs(mean / (UNIFORM_SQUARE_MEAN_DEFLECTION * 3.0 * 2.0 / 4.0) - 1.0))
    assert errors[-1] < 3e-4
    assert all(later < 0.4 * earlier for earlier, later in zip(errors, errors[1:]))


def test_uniform_square_centre_deflection_is_exact():
    # Odd n: the centre pixel's centre is the square's centre, where the superposition of pixel
    # kernels is exactly Love's formula for the whole square: 4 ln(1 + sqrt 2)/pi p L / E*.
    n = 15
    operator = HalfSpace((n, n), 1.0 / n)
    centre = operator.displacement(np.ones((n, n)))[n // 2, n // 2]
    assert centre == pytest.approx(UNIFORM_SQUARE_CENTRE_DEFLECTION, rel=1e-12)


def test_centred_kernel_matches_products():
    operator = HalfSpace((6, 8), 0.25)
    unit = np.zeros((6, 8))
    unit[2, 3] = 1.0
    response = operator.displacement(unit)
    kernel = operator.centred_kernel
    np.testing.assert_allclose(response, kernel[5 - 2: 11 - 2, 7 - 3: 15 - 3], rtol=1e-12)
    assert operator.self_influence == pytest.approx(
        float(love_pixel_displacement(0.0, 0.0, half_width_x=0.125)), rel=1e-12)


@pytest.mark.parametrize("shape", [(8, 8), (6, 10), (7, 9)])
def test_mirror_self_influence_is_the_pulse_response_without_the_influence_array(shape):
    # the mirror operator's self influence is the response at the loaded pixel (its images
    # included), the influence array's first coefficient; read alone it keeps no grid array
    alone = HalfSpace(shape, 0.5, periodic=True, mirror=True)
    full = HalfSpace(shape, 0.5, periodic=True, mirror=True)
    value = alone.self_influence
    assert alone._influence is None
    assert value == full.influence[0, 0]
    assert full.self_influence == value
    pulse = np.zeros(shape)
    pulse[0, 0] = 1.0
    assert value == pytest.approx(float(alone.displacement(pulse)[0, 0]), rel=1e-15)


def test_displacement_returns_fresh_arrays_and_leaves_input_alone():
    operator = HalfSpace((8, 8), 1.0)
    pressure = np.ones((8, 8))
    first = operator.displacement(pressure)
    second = operator.displacement(pressure)
    assert first is not second and not np.shares_memory(first, second)
    first[...] = 0.0
    np.testing.assert_array_equal(pressure, 1.0)
    assert np.all(second > 0)


@pytest.mark.parametrize("kwargs, name", [
    (dict(shape=(8, 8), spacing=0.0), "spacing"),
    (dict(shape=(8, 8), spacing=-1.0), "spacing"),
    (dict(shape=(8, 8), spacing=float("nan")), "spacing"),
    (dict(shape=(8, 8), spacing=1.0, e_star=0.0), "e_star"),
    (dict(shape=(8,), spacing=1.0), "shape"),
    (dict(shape=(0, 8), spacing=1.0), "shape"),
])
def test_bad_construction_is_rejected(kwargs, name):
    with pytest.raises(ValueError, match=name):
        HalfSpace(**kwargs)


def test_bad_pressure_is_rejected():
    operator = HalfSpace((8, 8), 1.0)
    with pytest.raises(ValueError, match="pressure"):
        operator.displacement(np.ones((8, 9)))
    bad = np.ones((8, 8))
    bad[1, 1] = np.nan
    with pytest.raises(ValueError, match="pressure"):
        operator.displacement(bad)
