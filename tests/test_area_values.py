"""The area estimators' exact values on small hand-made contacts (bem.contact.area): the perimeter
coefficients of each kernel, the edges across the border that count only when periodic, and
the sub-pixel edge from each crossing's own contact pressure and outside gap, computed here
independently from eq. T31."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize

from bem.contact.area import YASTREBOV_COEFFICIENT, contact_area, contact_edges


def _block(shape, rows, columns) -> np.ndarray:
    mask = np.zeros(shape, dtype=bool)
    mask[rows, columns] = True
    return mask


def test_the_yastrebov_coefficient_is_its_closed_form():
    assert YASTREBOV_COEFFICIENT == pytest.approx(0.1181141597562391, rel=1e-15)


@pytest.mark.parametrize("periodic, alpha", [(False, 0.100), (True, 0.096)])
def test_the_perimeter_estimator_of_an_inner_block(periodic, alpha):
    mask = _block((5, 5), slice(1, 3), slice(2, 4))          # 2 x 2, away from the border
    assert contact_edges(mask, periodic=periodic) == 8
    assert contact_area(mask, 0.5, periodic=periodic) == pytest.approx((4 - alpha * 8) * 0.25,
                                                                       rel=1e-15)
    assert contact_area(mask, 0.5, periodic=periodic, estimator="pixels") == 1.0


def test_the_border_is_an_edge_only_of_a_periodic_grid():
    corner = _block((5, 5), slice(0, 2), slice(0, 2))
    assert contact_edges(corner, periodic=False) == 4
    assert contact_edges(corner, periodic=True) == 8
    assert contact_area(corner, 1.0, periodic=False) == pytest.approx(4 - 0.100 * 4, rel=1e-15)
    assert contact_area(corner, 1.0, periodic=True) == pytest.approx(4 - 0.096 * 8, rel=1e-15)
    full = np.ones((4, 4), dtype=bool)
    assert contact_area(full, 1.0, periodic=True) == 16.0    # no edge at all


def _edge_fraction(pressure: float, gap: float, spacing: float, e_star: float) -> float:
    """x with (1 - x)^3 = r x, r = (3 E* g / (4 p h))^2 (eq. T31), by Brent's method."""
    r = (3.0 * e_star * gap / (4.0 * pressure * spacing)) ** 2
    return optimize.brentq(lambda x: (1.0 - x) ** 3 - r * x, 0.0, 1.0, xtol=1e-15)


def test_the_subpixel_estimator_of_one_contact_pixel_with_four_different_gaps():
    spacing, e_star, p = 2.0, 3.0, 5.0
    contact = _block((3, 3), 1, 1)
    pressure = np.where(contact, p, 0.0)
    gap = np.zeros((3, 3))
    gap[1, 0], gap[1, 2], gap[0, 1], gap[2, 1] = 0.5, 1.0, 2.0, 4.0
    crossings = [_edge_fraction(p, g, spacing, e_star) for g in (0.5, 1.0, 2.0, 4.0)]
    expected = spacing**2 * (1.0 + 0.5 * sum(x - 0.5 for x in crossings))
    area = contact_area(contact, spacing, estimator="subpixel", pressure=pressure, gap=gap,
                        e_star=e_star)
    assert area == pytest.approx(expected, rel=1e-9)
    assert abs(area - spacing**2) > 0.1   # the corrections do not cancel here


def test_the_subpixel_estimator_at_a_corner_crosses_the_border_only_when_periodic():
    spacing, e_star, p = 1.0, 2.0, 3.0
    contact = _block((3, 3), 0, 0)
    pressure = np.where(contact, p, 0.0)
    gap = np.zeros((3, 3))
    gap[0, 1], gap[1, 0], gap[0, 2], gap[2, 0] = 0.3, 0.6, 1.2, 2.4   # right, down, wrapped
    inner = [_edge_fraction(p, g, spacing, e_star) for g in (0.3, 0.6)]
    wrapped = [_edge_fraction(p, g, spacing, e_star) for g in (1.2, 2.4)]
    open_area = contact_area(contact, spacing, estimator="subpixel", pressure=pressure, gap=gap,
                             e_star=e_star)
    periodic_area = contact_area(contact, spacing, periodic=True, estimator="subpixel",
                                 pressure=pressure, gap=gap, e_star=e_star)
    assert open_area == pytest.approx(1.0 + 0.5 * sum(x - 0.5 for x in inner), rel=1e-9)
    assert periodic_area == pytest.approx(1.0 + 0.5 * sum(x - 0.5 for x in inner + wrapped),
                                          rel=1e-9)


@pytest.mark.parametrize("estimator", ["perimeter", "subpixel", "pixels"])
@pytest.mark.parametrize("periodic", [False, True])
def test_an_estimate_does_not_change_under_mirror_images_and_transposition(estimator, periodic):
    rng = np.random.default_rng(7)
    pressure = np.where(rng.random((12, 10)) < 0.35, rng.random((12, 10)) + 0.1, 0.0)
    gap = np.where(pressure > 0, 0.0, rng.random((12, 10)) + 0.05)
    contact = pressure > 0

    def area(c, p, g):
        return contact_area(c, 0.7, periodic=periodic, estimator=estimator, pressure=p, gap=g,
                            e_star=1.3)

    reference = area(contact, pressure, gap)
    assert reference > 0 and math.isfinite(reference)
    for image in (lambda a: a[::-1], lambda a: a[:, ::-1], lambda a: a.T):
        assert area(image(contact), image(pressure), image(gap)) == pytest.approx(reference,
                                                                                  rel=1e-12)
