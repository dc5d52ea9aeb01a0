"""Holm-Greenwood constriction resistance, eq. (6): limits, an independent sum, invariances."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from asperity import holm_greenwood


def direct_sum(x, y, a):
    """Eq. (6) written out as a dense double sum (the slow, independent oracle)."""
    dx = x[:, None] - x[None, :]
    dy = y[:, None] - y[None, :]
    s = np.hypot(dx, dy)
    np.fill_diagonal(s, np.inf)
    total = a.sum()
    return 1 / (2 * total) + (a @ (1 / s) @ a) / (math.pi * total ** 2)


def test_single_spot():
    assert holm_greenwood([3.0], [-1.0], [0.25]) == pytest.approx(1 / (2 * 0.25), rel=1e-15)


def test_two_spots_exact_and_far_apart_limit():
    a1, a2 = 0.3, 0.7
    for s in (2.0, 10.0, 1e3, 1e9):
        expected = 1 / (2 * (a1 + a2)) + (2 / math.pi) * a1 * a2 / (s * (a1 + a2) ** 2)
        assert holm_greenwood([0.0, s], [0.0, 0.0], [a1, a2]) == pytest.approx(expected,
                                                                               rel=1e-14)
    # Far apart: the parallel resistance 1/(2 sum a) of independent spots.
    assert holm_greenwood([0.0, 1e12], [0.0, 0.0], [a1, a2]) == pytest.approx(
        1 / (2 * (a1 + a2)), rel=1e-12)


def test_many_far_apart_spots_tend_to_the_parallel_value():
    rng = np.random.default_rng(3)
    a = rng.uniform(0.5, 1.5, 50)
    for spacing in (1e2, 1e4, 1e6):
        x = spacing * np.arange(50.0)
        parallel = 1 / (2 * a.sum())
        excess = holm_greenwood(x, np.zeros(50), a) - parallel
        # The interaction term is at most (1/pi)/min(s_ij) and positive.
        assert 0 < excess <= 1 / (math.pi * spacing) * (1 + 1e-12)


@pytest.mark.parametrize("count", [1, 2, 7, 300, 2500])
def test_against_the_dense_double_sum(count):
    # 2500 spots span ten blocks of 256: the off-diagonal block pairs are exercised.
    rng = np.random.default_rng(count)
    x, y = rng.uniform(-1, 1, count), rng.uniform(-1, 1, count)
    a = rng.uniform(1e-3, 5e-3, count)
    # Sums of up to 3e6 positive terms in different orders: rounding ~ sqrt(N) eps.
    assert holm_greenwood(x, y, a) == pytest.approx(direct_sum(x, y, a), rel=1e-12)


def test_uniform_cluster_approaches_holm_equation_5():
    # n equal spots on a square lattice of spacing delta filling a circle of radius alpha.
    # Greenwood's double sum tends to the uniform-flux value 16/(3 pi^2 alpha) = 0.540/alpha;
    # the lattice misses each spot's own cell, int_cell dA/r = 4 ln(1 + sqrt 2) delta, which
    # lowers the sum by 4 ln(1+sqrt2)/(pi n delta) (relative 1.17/sqrt(n)). What remains is
    # O(1/n) plus boundary cells: below 5e-4 relative at n ~ 7800 (measured 1.3e-4).
    alpha, delta, a = 1.0, 0.02, 1e-3
    grid = np.arange(-alpha, alpha + delta / 2, delta)
    x, y = np.meshgrid(grid, grid)
    inside = x ** 2 + y ** 2 <= alpha ** 2
    x, y = x[inside], y[inside]
    n = x.size
    resistance = holm_greenwood(x, y, np.full(n, a))
    interaction = resistance - 1 / (2 * n * a)
    continuum = 16 / (3 * math.pi ** 2 * alpha)
    own_cell = 4 * math.log(1 + math.sqrt(2)) / (math.pi * n * delta)
    assert interaction == pytest.approx(continuum - own_cell, rel=5e-4)
    # ... and Holm's equivalent-spot formula (5) is within the 8% that separates 16/(3 pi^2)
    # from 1/2.
    holm = 1 / (2 * n * a) + 1 / (2 * alpha)
    assert abs(resistance / holm - 1) < 0.08


def test_order_symmetry_and_rigid_motions():
    rng = np.random.default_rng(11)
    x, y, a = rng.uniform(0, 1, 400), rng.uniform(0, 1, 400), rng.uniform(0.001, 0.01, 400)
    reference = holm_greenwood(x, y, a)
    order = rng.permutation(400)
    assert holm_greenwood(x[order], y[order], a[order]) == pytest.approx(reference, rel=1e-13)
    angle = 0.7
    xr = np.cos(angle) * x - np.sin(angle) * y + 5.0
    yr = np.sin(angle) * x + np.cos(angle) * y - 2.0
    assert holm_greenwood(xr, yr, a) == pytest.approx(reference, rel=1e-12)
    # Units: R/rho is 1/length.
    assert holm_greenwood(10 * x, 10 * y, 10 * a) == pytest.approx(reference / 10, rel=1e-13)


def test_zero_radius_spots_are_ignored_and_no_contact_is_infinite():
    x, y, a = np.array([0.0, 1.0, 1.0]), np.array([0.0, 0.0, 0.0]), np.array([0.2, 0.3, 0.0])
    assert holm_greenwood(x, y, a) == holm_greenwood(x[:2], y[:2], a[:2])
    assert holm_greenwood([0.0, 0.0], [0.0, 0.0], [0.0, 0.0]) == math.inf
    assert holm_greenwood([], [], []) == math.inf


def test_bad_input():
    with pytest.raises(ValueError, match="same centre"):
        holm_greenwood([0.0, 1.0, 0.0], [0.0, 0.0, 0.0], [0.1, 0.1, 0.2])
    with pytest.raises(ValueError, match="same size"):
        holm_greenwood([0.0, 1.0], [0.0], [0.1, 0.1])
    with pytest.raises(ValueError, match="radii"):
        holm_greenwood([0.0, 1.0], [0.0, 0.0], [0.1, -0.1])
    with pytest.raises(ValueError, match="x must be finite"):
        holm_greenwood([0.0, float("nan")], [0.0, 0.0], [0.1, 0.1])
    with pytest.raises(ValueError, match="radii must be finite"):
        holm_greenwood([0.0, 1.0], [0.0, 0.0], [0.1, float("inf")])


@given(st.lists(st.tuples(st.integers(-10**6, 10**6), st.integers(-10**6, 10**6),
                          st.floats(1e-3, 10)),
                min_size=1, max_size=40, unique_by=lambda t: (t[0], t[1])))
def test_property_matches_the_double_sum_and_exceeds_the_parallel_value(spots):
    x, y, a = (np.array(v, dtype=float) for v in zip(*spots))
    x, y = 1e-3 * x, 1e-3 * y                       # distinct centres at least 1e-3 apart
    resistance = holm_greenwood(x, y, a)
    assert resistance >= 1 / (2 * a.sum())
    assert resistance == pytest.approx(direct_sum(x, y, a), rel=1e-12)
