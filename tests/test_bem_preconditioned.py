"""The preconditioned, nested solver against the plain Polonsky-Keer iteration on WM surfaces.

The contract: the same contact set, and area, load, separation and stiffness to 1e-6 relative,
at several grids and area fractions, periodic and not, in load and in separation control.
"""

import numpy as np
import pytest

from bem import HalfSpace, contact_curve, solve_contact
from bem.contact.preconditioner import InverseKernel
from validation import wm_surface

#: Loads of the WM surface below giving about 4 %, 18 % and 44 % contact area.
LOADS = (2e-3, 1e-2, 3e-2)


def surface(n: int) -> np.ndarray:
    return wm_surface(n, D=2.5, rms_slope=0.1, seed=9173, slope_grid=1024)


def assert_same_state(new, plain):
    assert new.converged and plain.converged
    assert np.array_equal(new.contact, plain.contact)
    assert new.area == plain.area
    assert new.load == pytest.approx(plain.load, rel=1e-6)
    assert new.separation == pytest.approx(plain.separation, rel=1e-6)
    assert new.mean_gap == pytest.approx(plain.mean_gap, rel=1e-6)


def compare_load_control(n: int, periodic: bool) -> None:
    heights = surface(n)
    operator = HalfSpace((n, n), 1.0 / n, periodic=periodic)
    for load in LOADS:
        new = solve_contact(heights, 1.0 / n, load=load, periodic=periodic, operator=operator,
                            stiffness=True)
        plain = solve_contact(heights, 1.0 / n, load=load, periodic=periodic, operator=operator,
                              stiffness=True, preconditioned=False)
        assert_same_state(new, plain)
        assert new.stiffness == pytest.approx(plain.stiffness, rel=1e-6)
        # separation control at the separation found gives the same state
        at_separation = solve_contact(heights, 1.0 / n, separation=plain.separation,
                                      periodic=periodic, operator=operator)
        plain_at_separation = solve_contact(heights, 1.0 / n, separation=plain.separation,
                                            periodic=periodic, operator=operator,
                                            preconditioned=False)
        assert_same_state(at_separation, plain_at_separation)


@pytest.mark.parametrize("periodic", [False, True])
def test_same_state_as_polonsky_keer(periodic):
    compare_load_control(64, periodic)


@pytest.mark.slow
@pytest.mark.parametrize("periodic", [False, True])
@pytest.mark.parametrize("n", [128, 256])
def test_same_state_as_polonsky_keer_on_finer_grids(n, periodic):
    compare_load_control(n, periodic)


def test_load_path_matches_single_solves():
    n = 64
    heights = surface(n)
    curve = contact_curve(heights, 1.0 / n, loads=LOADS, quantities=("area", "stiffness"))
    for index, load in enumerate(LOADS):
        plain = solve_contact(heights, 1.0 / n, load=load, stiffness=True, preconditioned=False)
        assert curve.area[index] == plain.area
        assert curve.separation[index] == pytest.approx(plain.separation, rel=1e-6)
        assert curve.stiffness[index] == pytest.approx(plain.stiffness, rel=1e-6)


@pytest.mark.parametrize("precision, accuracy", [("double", 1e-12), ("single", 1e-6)])
def test_inverse_kernel_inverts_the_periodic_half_space(precision, accuracy):
    n, spacing, e_star = 32, 0.01, 2.5
    operator = HalfSpace((n, n), spacing, e_star=e_star, periodic=True)
    inverse = InverseKernel((n, n), spacing, e_star=e_star, precision=precision)
    pressure = np.random.default_rng(3).normal(size=(n, n))
    pressure -= pressure.mean()  # the periodic operator drops the mean
    inverse.input_block[...] = operator.displacement(pressure)
    inverse.execute()
    out = inverse.read(np.arange(n * n)).reshape(n, n)
    assert out.dtype == np.float64
    error = np.abs(out - pressure).max() / np.abs(pressure).max()
    assert error < accuracy
    # single precision is not double's in disguise
    assert (error > 1e-10) == (precision == "single")


def test_inverse_kernel_rejects_an_unknown_precision():
    with pytest.raises(ValueError, match="precision"):
        InverseKernel((8, 8), 1.0, precision="half")


def test_odd_grid_solves_without_nested_start():
    heights = surface(66)[:63, :63]
    new = solve_contact(heights, 1.0 / 63, load=1e-2)
    plain = solve_contact(heights, 1.0 / 63, load=1e-2, preconditioned=False)
    assert_same_state(new, plain)


def test_periodic_separation_near_full_contact():
    # a separation between the mean height and the (higher) mean of every other point: the
    # coarse problem would be in full contact, so the solve starts without it
    n = 128
    heights = -surface(n)
    coarse_mean, mean = float(heights[::2, ::2].mean()), float(heights.mean())
    assert coarse_mean > mean
    separation = 0.5 * (mean + coarse_mean)
    new = solve_contact(heights, 1.0 / n, separation=separation, periodic=True)
    plain = solve_contact(heights, 1.0 / n, separation=separation, periodic=True,
                          preconditioned=False)
    assert new.area_fraction > 0.5
    assert_same_state(new, plain)


@pytest.mark.parametrize("periodic", [False, True])
def test_nested_load_path_matches_cold_single_solves(periodic):
    # 128 x 128 has a coarse level: each point starts from the coarse solve of its own load,
    # warm-started from the previous point's coarse pressure; the states must be those of
    # independent cold solves of the plain iteration, in load and in separation control
    n = 128
    heights = surface(n)
    operator = HalfSpace((n, n), 1.0 / n, periodic=periodic)
    loads = np.geomspace(1e-3, 3e-2, 4)
    curve = contact_curve(heights, 1.0 / n, loads=loads, periodic=periodic, operator=operator,
                          quantities=("area", "stiffness"))
    plain = [solve_contact(heights, 1.0 / n, load=load, periodic=periodic, operator=operator,
                           stiffness=True, preconditioned=False) for load in loads]
    assert curve.extras["converged"].all()
    for index, single in enumerate(plain):
        assert curve.area[index] == single.area
        assert curve.extras["pixel_area"][index] == single.pixel_area
        assert curve.load[index] == pytest.approx(single.load, rel=1e-6)
        assert curve.separation[index] == pytest.approx(single.separation, rel=1e-6)
        assert curve.extras["mean_gap"][index] == pytest.approx(single.mean_gap, rel=1e-6)
        assert curve.stiffness[index] == pytest.approx(single.stiffness, rel=1e-6)
    separations = curve.separation[::-1]
    by_separation = contact_curve(heights, 1.0 / n, separations=separations, periodic=periodic,
                                  operator=operator)
    assert by_separation.extras["converged"].all()
    np.testing.assert_allclose(by_separation.load, curve.load[::-1], rtol=1e-6)
    np.testing.assert_array_equal(by_separation.extras["pixel_area"],
                                  curve.extras["pixel_area"][::-1])


def test_interface_heavy_contact_same_state_and_fewer_iterations():
    # The interface (mirror) operator at 20-80 % contact: overlapping pixels join the contact
    # set at zero pressure before the preconditioned step. The states are the plain
    # iteration's, and the iterations stay below those of the plain rule applied with the
    # preconditioner (entering after the step with -tau g: 39 + 54 + 48 = 141 here; joining
    # first: 36 + 41 + 35 = 112).
    n = 256
    heights = surface(n)
    loads = (1e-2, 3e-2, 6e-2)
    new = contact_curve(heights, 1.0 / n, loads=loads, periodic=True, mirror=True)
    plain = contact_curve(heights, 1.0 / n, loads=loads, periodic=True, mirror=True,
                          preconditioned=False)
    assert new.extras["converged"].all() and plain.extras["converged"].all()
    assert new.area[-1] / new.nominal_area > 0.75
    np.testing.assert_array_equal(new.area, plain.area)
    np.testing.assert_allclose(new.separation, plain.separation, rtol=1e-6)
    assert int(np.sum(new.extras["iterations"])) <= 125
