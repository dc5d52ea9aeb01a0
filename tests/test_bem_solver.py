"""The contact solver against analytic solutions, invariants and random surfaces."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bem import ContactSolution, ConvergenceWarning, HalfSpace, solve_contact
from bem.reference import (bisinusoid_area_high_load, bisinusoid_area_low_load,
                           flat_punch_stiffness, hertz, westergaard)


def random_surface(n, seed, *, hurst=0.8, rms_slope=0.1):
    """Self-affine Gaussian surface (zero mean) by filtering white noise in Fourier space."""
    rng = np.random.default_rng(seed)
    q = np.hypot(np.fft.fftfreq(n)[:, None], np.fft.fftfreq(n)[None, :])
    filter_ = np.divide(1.0, q ** (1.0 + hurst), out=np.zeros_like(q), where=q > 0)
    heights = np.fft.ifft2(np.fft.fft2(rng.normal(size=(n, n))) * filter_).real
    slope = np.sqrt(np.mean(np.gradient(heights, 1.0 / n, axis=0) ** 2
                            + np.gradient(heights, 1.0 / n, axis=1) ** 2))
    return heights * (rms_slope / slope)


def sphere(n, length, radius=1.0):
    spacing = length / n
    x = (np.arange(n) - n / 2 + 0.5) * spacing
    return -(x[None, :] ** 2 + x[:, None] ** 2) / (2 * radius), spacing, x


# -- analytic solutions ---------------------------------------------------------------------------

def test_hertz_converges_with_the_grid():
    load, radius = 0.2, 1.0
    exact = hertz(load, radius)  # a = 0.531 on a domain of side 4 (7.5a: no effect, non-periodic)
    peak_errors = []
    for n in (32, 64, 128):
        heights, spacing, x = sphere(n, 4.0, radius)
        solution = solve_contact(heights, spacing, load=load)
        assert solution.converged
        assert solution.load == pytest.approx(load, rel=1e-12)
        # Rigid approach: the apex is at z = 0, so delta = -d. Pixel-wise constant pressure on a
        # contact of 4 to 17 pixels in radius: observed error <= 6.4e-4, bound 2e-3.
        assert -solution.separation == pytest.approx(exact.approach, rel=2e-3)
        # Area from the pixel count: the edge runs through one ring of pixels, so
        # |A - pi a^2| <= perimeter x h = 2 pi a h, i.e. a relative bound 2 h / a.
        assert abs(solution.area / exact.contact_area - 1) <= 2 * spacing / exact.contact_radius
        peak_errors.append(abs(solution.pressure.max() / exact.peak_pressure - 1))
        # Pressure profile away from the edge (r < 0.8 a), against p0 sqrt(1 - r^2/a^2).
        r = np.hypot(x[None, :], x[:, None])
        inner = r < 0.8 * exact.contact_radius
        profile_error = np.max(np.abs(solution.pressure[inner] - exact.pressure(r[inner])))
        assert profile_error <= 0.03 * exact.peak_pressure
    # The peak pressure converges: error at least halves as N doubles (observed ~4x).
    assert peak_errors[1] < 0.5 * peak_errors[0] and peak_errors[2] < 0.5 * peak_errors[1]
    assert peak_errors[-1] < 2e-3


def test_hertz_separation_control_gives_hertz_load():
    exact = hertz(0.2, 1.0)
    heights, spacing, _ = sphere(64, 4.0)
    solution = solve_contact(heights, spacing, separation=-exact.approach)
    # Inverse of the approach check above: delta to 2e-4 relative at n = 64 -> W to 3/2 of it.
    assert solution.load == pytest.approx(0.2, rel=1e-3)


@pytest.mark.parametrize("psi", [0.01, 0.03, 0.1, 0.3, 0.5, 0.8, 0.95])
def test_westergaard_contact_fraction_and_mean_gap(psi):
    n, wavelength, amplitude, e_star = 128, 2.0, 0.01, 3.0
    spacing = wavelength / n
    x = np.arange(n) * spacing
    heights = np.tile(amplitude * np.cos(2 * math.pi * x / wavelength), (n, 1))
    p_star = math.pi * e_star * amplitude / wavelength
    solution = solve_contact(heights, spacing, load=psi * p_star * wavelength**2, e_star=e_star,
                             periodic=True)
    exact = westergaard(psi * p_star, amplitude=amplitude, wavelength=wavelength, e_star=e_star)
    assert solution.converged
    # Each of the two contact edges is resolved to one pixel: |fraction error| <= 2 h / lambda.
    assert abs(solution.area_fraction - exact.contact_fraction) <= 2.0 / n
    # Mean gap: the periodic separation is measured from the deformed mean plane, so
    # mean gap = d - mean(z) = d here. Edge discretisation: observed <= 1e-4 Delta at n = 128.
    assert solution.mean_gap == pytest.approx(exact.mean_gap, abs=5e-4 * amplitude)
    assert solution.separation == pytest.approx(solution.mean_gap, abs=1e-12 * amplitude)


def test_bisinusoid_follows_the_jgh_asymptotes():
    n, wavelength, amplitude = 128, 1.0, 0.01
    spacing = wavelength / n
    x = np.arange(n) * spacing
    heights = amplitude * np.cos(2 * math.pi * x)[None, :] * np.cos(2 * math.pi * x)[:, None]
    p_star = math.sqrt(2) * math.pi * amplitude / wavelength
    operator = HalfSpace((n, n), spacing, periodic=True)
    # Low load: two Hertz-like spots per period; pixel-count bound 2 h / a as for Hertz
    # (a ~ 11 pixels here), the asymptote itself being O(psi^(2/3)) relative, i.e. ~3 %.
    low = solve_contact(heights, spacing, load=0.005 * p_star, periodic=True, operator=operator)
    expected = float(bisinusoid_area_low_load(0.005))
    spot_radius = math.sqrt(expected / (2 * math.pi)) * wavelength
    assert abs(low.area_fraction / expected - 1) <= 2 * spacing / spot_radius
    # Near full contact: the non-contact islands are small; their pixel ring (perimeter x h,
    # about 0.8 h / lambda) bounds the discrete error, the asymptote's own is O((1 - psi)^2).
    for psi in (0.9, 0.95):
        high = solve_contact(heights, spacing, load=psi * p_star, periodic=True, operator=operator)
        assert high.converged
        assert high.area_fraction == pytest.approx(float(bisinusoid_area_high_load(psi)), abs=1e-2)


def test_flat_punch_stiffness():
    errors = []
    for n, pixels_per_radius in ((32, 6), (64, 12), (128, 24)):
        spacing = 1.0 / pixels_per_radius
        x = (np.arange(n) - n / 2 + 0.5) * spacing
        heights = np.where(np.hypot(x[None, :], x[:, None]) < 1.0, 0.0, -1.0)
        solution = solve_contact(heights, spacing, separation=-1e-3, e_star=2.0, stiffness=True)
        assert solution.converged
        # the punch is linear: W = S delta
        assert solution.load == pytest.approx(solution.stiffness * 1e-3, rel=1e-8)
        equivalent_radius = math.sqrt(solution.pixel_area / math.pi)
        error = abs(solution.stiffness / flat_punch_stiffness(equivalent_radius, 2.0) - 1)
        # pixelated boundary: observed 2 %, 1 %, 0.5 %, i.e. O(h / a); bound 0.2 h / a
        assert error <= 0.2 / pixels_per_radius
        errors.append(error)
    assert errors[2] < errors[1] < errors[0]


# -- invariants -------------------------------------------------------------------------------------

@pytest.mark.parametrize("periodic", [False, True])
def test_load_and_separation_control_give_the_same_state(periodic):
    heights = random_surface(64, 1)
    spacing = 1.0 / 64
    by_load = solve_contact(heights, spacing, load=3e-3, periodic=periodic)
    by_separation = solve_contact(heights, spacing, separation=by_load.separation, periodic=periodic)
    assert by_load.converged and by_separation.converged
    np.testing.assert_array_equal(by_load.contact, by_separation.contact)
    # Both stop at a relative pressure change of 1e-9; allow 100x for the conditioning.
    assert by_separation.load == pytest.approx(3e-3, rel=1e-7)
    assert np.max(np.abs(by_load.pressure - by_separation.pressure)) <= 1e-6 * by_load.pressure.max()
    assert by_separation.mean_gap == pytest.approx(by_load.mean_gap, rel=1e-7)


@pytest.mark.parametrize("periodic", [False, True])
def test_stiffness_equals_finite_difference_slope(periodic):
    heights = random_surface(64, 2)
    spacing = 1.0 / 64
    centre = solve_contact(heights, spacing, load=2e-3, periodic=periodic, stiffness=True)
    step = 1e-7 * float(np.ptp(heights))
    below = solve_contact(heights, spacing, separation=centre.separation - step, periodic=periodic)
    above = solve_contact(heights, spacing, separation=centre.separation + step, periodic=periodic)
    # the step is small enough that the contact set is the same on both sides ...
    np.testing.assert_array_equal(below.contact, above.contact)
    np.testing.assert_array_equal(below.contact, centre.contact)
    slope = (below.load - above.load) / (2 * step)
    # ... so W(d) is linear there and the central difference is exact up to the solver
    # tolerance: load error ~1e-9 W over a load change ~1e-7 d S / W, hence ~1e-4 at most.
    assert centre.stiffness == pytest.approx(slope, rel=1e-4)
    assert centre.conductance == pytest.approx(2 * centre.stiffness / centre.e_star, rel=1e-15)


@pytest.mark.parametrize("periodic", [False, True])
def test_scaling_heights_scales_pressure(periodic):
    heights = random_surface(32, 3)
    spacing = 1.0 / 32
    base = solve_contact(heights, spacing, load=1e-3, periodic=periodic)
    scaled = solve_contact(7.0 * heights, spacing, load=7e-3, periodic=periodic)
    np.testing.assert_array_equal(base.contact, scaled.contact)
    assert np.max(np.abs(scaled.pressure - 7.0 * base.pressure)) <= 1e-7 * scaled.pressure.max()
    assert scaled.separation == pytest.approx(7.0 * base.separation, rel=1e-7)


def test_shifting_a_periodic_surface_shifts_the_solution():
    heights = random_surface(32, 4)
    spacing = 1.0 / 32
    base = solve_contact(heights, spacing, load=2e-3, periodic=True)
    shifted = solve_contact(np.roll(heights, (5, -11), axis=(0, 1)), spacing, load=2e-3,
                            periodic=True)
    np.testing.assert_array_equal(np.roll(base.contact, (5, -11), axis=(0, 1)), shifted.contact)
    rolled = np.roll(base.pressure, (5, -11), axis=(0, 1))
    assert np.max(np.abs(shifted.pressure - rolled)) <= 1e-7 * base.pressure.max()
    assert shifted.separation == pytest.approx(base.separation, rel=1e-9)


def test_default_tolerance_gives_area_and_load_to_1e_6():
    heights = random_surface(64, 5, hurst=0.6)
    spacing = 1.0 / 64
    for separation in (0.6, 0.2, -0.3):
        d = separation * float(heights.std())
        default = solve_contact(heights, spacing, separation=d)
        tight = solve_contact(heights, spacing, separation=d, tol=1e-14, max_iter=20000)
        assert tight.converged
        assert default.area == pytest.approx(tight.area, rel=1e-6)
        assert default.load == pytest.approx(tight.load, rel=1e-6)


def test_warm_start_reaches_the_same_state():
    heights = random_surface(32, 6)
    cold = solve_contact(heights, 1 / 32, load=2e-3)
    warm = solve_contact(heights, 1 / 32, load=2e-3, initial=cold.pressure)
    assert warm.iterations <= 2
    np.testing.assert_allclose(warm.pressure, cold.pressure, rtol=0, atol=1e-8 * cold.pressure.max())


# -- robustness -------------------------------------------------------------------------------------

@pytest.mark.parametrize("periodic", [False, True])
def test_first_contact_is_one_pixel(periodic):
    heights = random_surface(64, 7)
    top = np.unravel_index(np.argmax(heights), heights.shape)
    second = np.sort(heights, axis=None)[-2]
    # a rigid approach of 1 % of the gap between the two highest points touches one pixel
    d = heights[top] - 0.01 * (heights[top] - second)
    solution = solve_contact(heights, 1 / 64, separation=d, periodic=periodic)
    assert solution.converged and np.count_nonzero(solution.contact) == 1 and solution.contact[top]
    by_load = solve_contact(heights, 1 / 64, load=solution.load, periodic=periodic)
    assert by_load.converged and np.count_nonzero(by_load.contact) == 1
    assert by_load.separation == pytest.approx(d, abs=1e-9 * float(np.ptp(heights)))


def test_near_full_contact_converges():
    heights = random_surface(64, 8)
    spacing = 1.0 / 64
    operator = HalfSpace((64, 64), spacing, periodic=True)
    for load in (0.05, 0.2, 0.5):
        solution = solve_contact(heights, spacing, load=load, periodic=True, operator=operator)
        assert solution.converged, solution.message
        assert solution.load == pytest.approx(load, rel=1e-12)
        assert np.all(solution.pressure >= 0)
    assert solution.area_fraction > 0.97
    # full contact: the separation approaches mean(z) from above and the mean gap vanishes (to
    # rounding: it is a mean of gaps that are zero on the contact set)
    assert -1e-12 * float(np.ptp(heights)) <= solution.mean_gap < 1e-3 * float(np.ptp(heights))


def test_separation_above_highest_point_gives_zero_load():
    heights = random_surface(16, 9)
    for periodic in (False, True):
        solution = solve_contact(heights, 0.1, separation=float(heights.max()) + 1e-3,
                                 periodic=periodic, stiffness=True)
        assert solution.converged and solution.load == 0 and solution.area == 0
        assert solution.stiffness == 0 and not solution.contact.any()
        np.testing.assert_allclose(solution.gap, float(heights.max()) + 1e-3 - heights)


def test_zero_load_gives_zero_pressure():
    heights = random_surface(16, 10)
    solution = solve_contact(heights, 0.1, load=0.0)
    assert solution.converged and not np.any(solution.pressure)
    assert solution.separation == pytest.approx(float(heights.max()))


def test_non_convergence_is_reported_and_warned():
    heights = random_surface(32, 11)
    with pytest.warns(ConvergenceWarning, match="not converged"):
        solution = solve_contact(heights, 1 / 32, load=1e-2, max_iter=2)
    assert not solution.converged and solution.iterations == 2
    assert "not converged" in solution.message and solution.residual > 1e-9


def test_solution_is_frozen_with_read_only_arrays():
    solution = solve_contact(random_surface(16, 12), 0.1, load=1e-3)
    assert isinstance(solution, ContactSolution)
    with pytest.raises(AttributeError):
        solution.load = 2.0
    with pytest.raises(ValueError):
        solution.pressure[0, 0] = 1.0
    assert solution.stiffness is None and solution.conductance is None
    assert solution.nominal_area == pytest.approx(2.56)
    assert solution.mean_pressure == pytest.approx(1e-3 / 2.56)


@pytest.mark.parametrize("kwargs, name", [
    (dict(heights=np.full((8, 8), np.nan), load=1.0), "heights"),
    (dict(heights=np.full((8, 8), np.inf), load=1.0), "heights"),
    (dict(heights=np.zeros((8, 3)), load=1.0), "heights"),    # N x M needs N, M >= 4
    (dict(heights=np.zeros(8), load=1.0), "heights"),
    (dict(heights=np.zeros((3, 3)), load=1.0), "heights"),
    (dict(heights=np.zeros((8, 8)), load=1.0, spacing=0.0), "spacing"),
    (dict(heights=np.zeros((8, 8)), load=1.0, spacing=-1.0), "spacing"),
    (dict(heights=np.zeros((8, 8)), load=-1.0), "load"),
    (dict(heights=np.zeros((8, 8)), load=float("nan")), "load"),
    (dict(heights=np.zeros((8, 8))), "exactly one"),
    (dict(heights=np.zeros((8, 8)), load=1.0, separation=0.0), "exactly one"),
    (dict(heights=np.zeros((8, 8)), separation=-1.0, periodic=True), "separation"),
    (dict(heights=np.zeros((8, 8)), load=1.0, e_star=0.0), "e_star"),
    (dict(heights=np.zeros((8, 8)), load=1.0, tol=0.0), "tol"),
    (dict(heights=np.zeros((8, 8)), load=1.0, max_iter=0), "max_iter"),
    (dict(heights=np.zeros((8, 8)), load=1.0, initial=np.zeros((4, 4))), "initial"),
    (dict(heights=np.zeros((8, 8)), load=1.0, operator=HalfSpace((8, 8), 1.0, periodic=True)),
     "operator"),
])
def test_bad_input_is_rejected(kwargs, name):
    kwargs.setdefault("spacing", 1.0)
    with pytest.raises(ValueError, match=name):
        solve_contact(**kwargs)


# -- random surfaces --------------------------------------------------------------------------------

@given(seed=st.integers(0, 2**32 - 1), n=st.sampled_from([16, 32]), periodic=st.booleans(),
       hurst=st.floats(0.3, 1.0), log_load=st.floats(-5.0, -0.5))
def test_random_surfaces_converge_to_a_contact_solution(seed, n, periodic, hurst, log_load):
    heights = random_surface(n, seed, hurst=hurst)
    spacing = 1.0 / n
    # Load over the nominal area in units of E* h'_rms (rms slope 0.1): 1e-5 .. 0.3, from a
    # few pixels to near-full contact.
    load = 10.0**log_load * 0.1
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        solution = solve_contact(heights, spacing, load=load, periodic=periodic)
    assert solution.converged
    assert solution.load == pytest.approx(load, rel=1e-12)
    assert np.all(solution.pressure >= 0)
    scale = float(np.ptp(heights))
    gap = solution.gap
    # gap >= 0 outside the contact set and ~0 on it; the gap error is that of the displacement,
    # tol x (displacement scale) with tol = 1e-9: 1e-7 of the height range is generous.
    assert np.min(gap) >= -1e-7 * scale
    assert np.max(np.abs(gap[solution.contact])) <= 1e-7 * scale
    # complementarity: sum p gap relative to W x height range
    assert abs(float(np.sum(solution.pressure * gap))) <= 1e-7 * scale * solution.pressure.sum()


def test_separation_control_recovers_from_a_poor_initial_pressure():
    # Regression: a start far too high made the first step clip every pixel, and the solver
    # reported "no contact" (zero load, converged) although the plane overlapped the surface.
    n, h = 64, 1.0 / 64
    x = (np.arange(n) - n / 2) * h
    z = -(x[None, :] ** 2 + x[:, None] ** 2) / 2.0
    d = z.max() - 1e-3
    good = solve_contact(z, h, separation=d)
    poor = solve_contact(z, h, separation=d, initial=np.full(z.shape, 10.0))
    assert good.converged and poor.converged and good.load > 0
    assert poor.load == pytest.approx(good.load, rel=1e-6)
    assert poor.gap.min() >= -1e-9 * np.ptp(z)


@pytest.mark.parametrize("periodic", [False, True])
def test_the_nested_start_interpolates_the_coarse_pressure_linearly(periodic):
    """The fine start keeps every coarse value at its sample (z[::2, ::2]) and interpolates
    linearly between samples, across the period when periodic, else holding the last one."""
    from types import SimpleNamespace

    from bem.contact.nested_grid import _prolonged

    rng = np.random.default_rng(3)
    coarse = rng.random((6, 8))
    fine = _prolonged(coarse, SimpleNamespace(periodic=periodic, mirror=False))
    assert fine.shape == (12, 16)
    np.testing.assert_array_equal(fine[::2, ::2], coarse)
    below = np.roll(coarse, -1, axis=0)
    if not periodic:
        below[-1] = coarse[-1]
    np.testing.assert_allclose(fine[1::2, ::2], 0.5 * (coarse + below))
    right = np.roll(coarse, -1, axis=1)
    if not periodic:
        right[:, -1] = coarse[:, -1]
    np.testing.assert_allclose(fine[::2, 1::2], 0.5 * (coarse + right))
    # the centre of four samples is their mean
    np.testing.assert_allclose(fine[1, 1], coarse[:2, :2].mean())
