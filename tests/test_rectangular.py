"""N x M grids of square pixels: the BEM (periodic and not), the summit finder and the
spectral moments against analytic solutions and against the same problem on a square grid."""

from __future__ import annotations

import math

import numpy as np
import pytest

import asperity
import bem
from bem.reference import hertz, westergaard
from validation import surface_statistics, wm_surface


def paraboloid(rows, columns, spacing, radius=1.0, centre=(0.0, 0.0)):
    y = (np.arange(rows) - rows / 2 + 0.5) * spacing - centre[0]
    x = (np.arange(columns) - columns / 2 + 0.5) * spacing - centre[1]
    return -(x[None, :] ** 2 + y[:, None] ** 2) / (2 * radius), np.hypot(x[None, :], y[:, None])


@pytest.mark.parametrize("shape", [(48, 96), (96, 40)])
def test_rectangular_hertz_matches_the_analytic_solution(shape):
    load, radius, spacing = 0.2, 1.0, 4.0 / 64        # a = 0.531: 8.5 pixels, 3.5a from edges
    exact = hertz(load, radius)
    heights, r = paraboloid(*shape, spacing, radius)
    solution = bem.solve_contact(heights, spacing, load=load, stiffness=True)
    assert solution.converged and solution.pressure.shape == shape
    assert solution.load == pytest.approx(load, rel=1e-12)
    assert solution.nominal_area == pytest.approx(shape[0] * shape[1] * spacing**2)
    # as test_bem_solver.py's Hertz test at n = 64: approach to 2e-3, area to the edge ring,
    # pressure within 3 % of p0 inside 0.8 a (the peak of the pixel-wise constant pressures,
    # 2.5 % high at 8.5 pixels per radius, converges like h^2 there)
    assert -solution.separation == pytest.approx(exact.approach, rel=2e-3)
    assert abs(solution.pixel_area / exact.contact_area - 1) <= 2 * spacing / exact.contact_radius
    # perimeter-corrected: 2.5 % for this centring, as on the square grid (test_area.py
    # averages sub-pixel offsets to 0.5 %)
    assert solution.area == pytest.approx(exact.contact_area, rel=0.03)
    inner = r < 0.8 * exact.contact_radius
    assert np.max(np.abs(solution.pressure[inner] - exact.pressure(r[inner]))) \
        <= 0.03 * exact.peak_pressure
    assert solution.pressure.max() == pytest.approx(exact.peak_pressure, rel=0.03)
    # S = 2 E* a (T27), with the pixel edge of the contact radius
    assert solution.stiffness == pytest.approx(2 * exact.contact_radius, rel=0.03)


def test_rectangular_hertz_equals_the_square_grid_solution():
    """Non-periodic: a contact far from the edges does not see the grid's extent, so the
    rectangle and the square around it give the same pressures to the solver's tolerance."""
    spacing = 4.0 / 64
    square, _ = paraboloid(96, 96, spacing)
    rectangle = square[24:72, :]                           # 48 x 96, the same centre
    options = dict(load=0.2, tol=1e-12, stiffness=True)
    a, b = bem.solve_contact(square, spacing, **options), bem.solve_contact(rectangle, spacing,
                                                                             **options)
    np.testing.assert_array_equal(a.contact[24:72, :], b.contact)
    np.testing.assert_allclose(b.pressure, a.pressure[24:72, :], rtol=0, atol=1e-8 * a.pressure.max())
    assert b.separation == pytest.approx(a.separation, rel=1e-9)
    assert b.stiffness == pytest.approx(a.stiffness, rel=1e-8)


@pytest.mark.parametrize("psi", [0.1, 0.5, 0.9])
@pytest.mark.parametrize("axis", [0, 1])
def test_periodic_westergaard_sinusoid_on_a_rectangular_grid(psi, axis):
    """One period of a sinusoid along either side of a 96 x 40 periodic grid (T29)."""
    rows, columns, spacing, amplitude, e_star = 96, 40, 0.05, 0.01, 3.0
    wavelength = (rows, columns)[axis] * spacing
    coordinate = np.arange((rows, columns)[axis]) * spacing
    wave = amplitude * np.cos(2 * math.pi * coordinate / wavelength)
    heights = np.broadcast_to(wave[:, None] if axis == 0 else wave[None, :], (rows, columns))
    p_star = math.pi * e_star * amplitude / wavelength
    area = rows * columns * spacing**2
    solution = bem.solve_contact(heights, spacing, load=psi * p_star * area, e_star=e_star,
                                 periodic=True)
    exact = westergaard(psi * p_star, amplitude=amplitude, wavelength=wavelength, e_star=e_star)
    assert solution.converged
    # each of the two straight edges to one pixel of the wave's axis
    pixels = (rows, columns)[axis]
    assert abs(solution.pixel_area / area - exact.contact_fraction) <= 2.0 / pixels
    # mean gap to the edge discretisation (test_bem_solver.py: 5e-4 Delta at 128 pixels per
    # wavelength; 40 pixels: (128/40)^2 times that)
    assert solution.mean_gap == pytest.approx(exact.mean_gap, abs=5e-3 * amplitude)
    # the solution does not vary along the other axis
    pressure = np.asarray(solution.pressure)
    along = np.broadcast_to(pressure.mean(axis=1 - axis, keepdims=True), pressure.shape)
    np.testing.assert_allclose(pressure, along, rtol=0, atol=1e-9 * pressure.max())


def test_periodic_rectangle_of_two_periods_equals_the_square_period():
    """A periodic surface repeated twice along x on a 32 x 64 grid is the 32 x 32 problem."""
    cell = wm_surface(32, D=2.4, rms_slope=0.1, seed=3)
    cell = cell - cell.mean()
    spacing = 1.0 / 32
    options = dict(periodic=True, tol=1e-12, stiffness=True)
    one = bem.solve_contact(cell, spacing, load=2e-3, **options)
    two = bem.solve_contact(np.tile(cell, (1, 2)), spacing, load=4e-3, **options)
    np.testing.assert_allclose(two.pressure, np.tile(one.pressure, (1, 2)), rtol=0,
                               atol=1e-8 * one.pressure.max())
    assert two.separation == pytest.approx(one.separation, rel=1e-9)
    assert two.area == pytest.approx(2 * one.area, rel=1e-9)
    assert two.stiffness == pytest.approx(2 * one.stiffness, rel=1e-7)
    curve = bem.contact_curve(np.tile(cell, (1, 2)), spacing, loads=[4e-3], periodic=True,
                              quantities=("area", "contacts"))
    assert curve.contacts[0] == bem.count_contacts(np.tile(one.contact, (1, 2)), periodic=True)


@pytest.fixture(scope="module")
def wm_window():
    """A 96 x 96 WM map and its rectangular window of 96 rows x 48 columns."""
    square = wm_surface(96, D=2.3, rms_slope=0.1, seed=5)
    return square, square[:, 24:72]


def test_rectangular_wm_window_is_the_square_problem_padded_out_of_contact(wm_window):
    """The window solved on its own, and embedded in a square grid whose extra pixels lie far
    below (never in contact): the non-periodic half-space gives the same contact."""
    _, window = wm_window
    spacing = 1.0 / 96
    padded = np.full((96, 96), window.min() - 10.0)
    padded[:, 24:72] = window
    loads = [1e-4 * 0.5, 1e-3 * 0.5]
    quantities = ("area", "load", "separation", "contacts", "stiffness")
    own = bem.contact_curve(window, spacing, loads=loads, quantities=quantities, tol=1e-12,
                            error_estimate=True)
    embedded = bem.contact_curve(padded, spacing, loads=loads, quantities=quantities, tol=1e-12)
    assert own.extras["converged"].all() and np.all(own.extras["area_error"] > 0)
    assert own.nominal_area == pytest.approx(0.5)
    for name in ("separation", "contacts", "stiffness"):
        np.testing.assert_allclose(getattr(own, name), getattr(embedded, name), rtol=1e-7)
    # the same contact pixels (the perimeter-corrected area differs where a contact is cut by
    # the window's edge: that edge is no contact line of the window, but is one when padded)
    np.testing.assert_array_equal(own.extras["pixel_area"], embedded.extras["pixel_area"])


def test_rectangular_window_is_consistent_with_the_square_map(wm_window):
    """The same surface statistics make the same mean-pressure / area curve: the half window
    and the whole square agree within the scatter between the two halves."""
    square, window = wm_window
    spacing = 1.0 / 96
    pressures = np.array([1e-3, 1e-2])
    fraction = {}
    for name, heights in (("square", square), ("window", window),
                          ("other half", np.concatenate((square[:, :24], square[:, 72:]), 1))):
        curve = bem.contact_curve(heights, spacing, loads=pressures * heights.size * spacing**2)
        fraction[name] = curve.area_fraction
    scatter = np.abs(fraction["window"] - fraction["other half"])
    assert np.all(np.abs(fraction["window"] - fraction["square"]) <= scatter + 0.1 * fraction["square"])


def test_summits_of_a_rectangular_crop_are_the_square_maps_inside_it(wm_window):
    square, window = wm_window
    spacing = 1.0 / 96
    full, crop = asperity.find_summits(square, spacing), asperity.find_summits(window, spacing)
    inside = (full.column >= 25) & (full.column <= 70)    # all 8 neighbours within the crop
    assert crop.area == pytest.approx(96 * 48 * spacing**2)
    np.testing.assert_array_equal(crop.row, full.row[inside])
    np.testing.assert_array_equal(crop.column + 24, full.column[inside])
    np.testing.assert_array_equal(crop.radius, full.radius[inside])
    np.testing.assert_allclose(crop.x + 24 * spacing, full.x[inside], rtol=1e-12)
    periodic = asperity.find_summits(np.tile(window, (1, 2)), spacing, periodic=True)
    assert periodic.count == 2 * asperity.find_summits(window, spacing, periodic=True).count


def test_spectral_moments_of_a_rectangular_plane_wave():
    """z = cos(qx x + qy y) on a periodic 30 x 80 grid: the finite-difference moments are
    those of the sampled wave, m2 = (sin^2(qx h) + sin^2(qy h)) / (4 h^2) and
    m4 = ((2 sin(qx h/2)/h)^4 + (2 sin(qy h/2)/h)^4) / 4."""
    rows, columns, h = 30, 80, 0.1
    qx, qy = 2 * math.pi * 5 / (columns * h), 2 * math.pi * 3 / (rows * h)
    y, x = np.arange(rows)[:, None] * h, np.arange(columns)[None, :] * h
    z = np.cos(qx * x + qy * y)
    stats = surface_statistics(z, h, periodic=True)
    assert stats.m0 == pytest.approx(0.5, rel=1e-12)
    assert stats.m2 == pytest.approx((math.sin(qx * h) ** 2 + math.sin(qy * h) ** 2)
                                     / (4 * h**2), rel=1e-12)
    fx, fy = (2 * math.sin(qx * h / 2) / h) ** 2, (2 * math.sin(qy * h / 2) / h) ** 2
    assert stats.m4 == pytest.approx((fx**2 + fy**2) / 4, rel=1e-12)


@pytest.mark.parametrize("shape", [(64, 160), (160, 64)])
def test_radial_spectrum_of_a_rectangular_periodic_map(shape):
    """Ring averages over the N x M lattice of wavevectors (rings 2 pi / longer side wide)
    keep h_rms and h'_rms of a periodic map, as test_persson.py checks on square ones."""
    rows, columns = shape
    h = 1.0 / 128
    q_y = 2 * np.pi * np.fft.fftfreq(rows, h)[:, None]
    q_x = 2 * np.pi * np.fft.fftfreq(columns, h)[None, :]
    modulus = np.hypot(q_x, q_y)
    amplitude = np.where((modulus > 0) & (modulus < np.pi / h / 2),
                         np.maximum(modulus, 8 * np.pi) ** -1.8, 0.0)
    phases = np.exp(2j * np.pi * np.random.default_rng(1).random(shape))
    z = np.fft.ifft2(amplitude * phases).real
    transform = np.fft.fft2(z)
    slope = np.hypot(np.fft.ifft2(1j * q_x * transform).real,
                     np.fft.ifft2(1j * q_y * transform).real)
    spectrum = asperity.radial_power_spectrum(z, h, window="none")
    assert spectrum.rms_height == pytest.approx(z.std(), rel=0.05)
    assert spectrum.rms_gradient == pytest.approx(math.sqrt(np.mean(slope**2)), rel=0.03)
    persson = asperity.Persson.from_heights(z, h, window="none")
    assert persson.nominal_area == pytest.approx(rows * columns * h**2)


def test_nested_iteration_on_a_rectangular_grid_reaches_the_plain_solution():
    """128 x 192 has a coarse level (64 x 96): the preconditioned, nested solve and path
    converge to the plain iteration's state (as tests/test_bem_preconditioned.py on squares)."""
    heights = wm_surface(192, D=2.5, rms_slope=0.1, seed=2)[32:160, :]
    spacing = 1.0 / 192
    load = 5e-3 * heights.size * spacing**2
    nested = bem.solve_contact(heights, spacing, load=load, stiffness=True)
    plain = bem.solve_contact(heights, spacing, load=load, stiffness=True, preconditioned=False)
    assert nested.converged and plain.converged
    np.testing.assert_array_equal(nested.contact, plain.contact)
    assert nested.separation == pytest.approx(plain.separation, rel=1e-6)
    assert nested.stiffness == pytest.approx(plain.stiffness, rel=1e-6)
    curve = bem.contact_curve(heights, spacing, loads=[load / 4, load], error_estimate=True)
    assert curve.extras["converged"].all()
    assert curve.area[1] == pytest.approx(nested.area, rel=1e-6)


def test_discrete_model_on_a_rectangular_lattice_fft_equals_direct(wm_window):
    summits = asperity.find_summits(wm_window[1], 1.0 / 96)
    loads = [1e-4, 1e-3]
    fft = asperity.DiscreteAsperityModel(summits, method="fft").at_load(loads)
    direct = asperity.DiscreteAsperityModel(summits, method="direct").at_load(loads)
    np.testing.assert_allclose(fft.separation, direct.separation, rtol=1e-9)
    np.testing.assert_allclose(fft.area, direct.area, rtol=1e-9)
