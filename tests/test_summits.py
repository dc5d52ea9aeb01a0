"""Summit detection: positions, radii, tie rule, non-convex tops, GW fits, bad input."""

import numpy as np
import pytest

from asperity import Summits, find_summits, summits_from_arrays, summits_to_arrays

SPACING = 0.01


def grid(rows, columns, spacing=SPACING):
    """Coordinates x[j, i] = i h, y[j, i] = j h (row j is y)."""
    j, i = np.mgrid[0:rows, 0:columns]
    return i * spacing, j * spacing


def paraboloid_field(x, y, apexes):
    """Maximum of paraboloids z = h - (r^T K r) / 2 about each apex (x0, y0, h, K).

    A maximum of concave caps has no local maxima other than the apexes (any local maximum of
    max_k f_k is a local maximum of one f_k), and well-separated apexes keep their whole 3 x 3
    stencil on their own cap, where central differences are exact for a quadratic.
    """
    field = np.full(x.shape, -np.inf)
    for x0, y0, height, K in apexes:
        dx, dy = x - x0, y - y0
        cap = height - 0.5 * (K[0, 0] * dx * dx + 2 * K[0, 1] * dx * dy + K[1, 1] * dy * dy)
        field = np.maximum(field, cap)
    return field


def spherical(radius):
    return np.eye(2) / radius


def rotated_elliptic(r1, r2, angle):
    c, s = np.cos(angle), np.sin(angle)
    rotation = np.array([[c, -s], [s, c]])
    return rotation @ np.diag([1 / r1, 1 / r2]) @ rotation.T


def test_grid_of_paraboloids_exact_positions_and_radii():
    x, y = grid(60, 80)
    apexes = [  # (column, row, height, K): spherical caps of several radii and heights
        (10, 12, 0.020, spherical(0.5)),
        (40, 15, 0.030, spherical(2.0)),
        (65, 12, 0.025, spherical(0.05)),
        (15, 45, 0.028, spherical(1.0)),
        (45, 45, 0.022, spherical(0.2)),
        (70, 47, 0.026, spherical(5.0)),
    ]
    z = paraboloid_field(x, y, [(c * SPACING, r * SPACING, h, K) for c, r, h, K in apexes])
    summits = find_summits(z, SPACING)
    expected = sorted(apexes, key=lambda a: (a[1], a[0]))   # row-major order
    assert summits.count == len(apexes) and summits.rejected == 0
    np.testing.assert_array_equal(summits.column, [a[0] for a in expected])
    np.testing.assert_array_equal(summits.row, [a[1] for a in expected])
    np.testing.assert_allclose(summits.x, [a[0] * SPACING for a in expected], rtol=0, atol=0)
    np.testing.assert_allclose(summits.y, [a[1] * SPACING for a in expected], rtol=0, atol=0)
    np.testing.assert_allclose(summits.height, [a[2] for a in expected], rtol=1e-15)
    # Central differences are exact for quadratics: only rounding of h^2-scaled differences
    # (about eps * h / (h^2 / R) relative) remains.
    np.testing.assert_allclose(summits.radius, [1 / a[3][0, 0] for a in expected], rtol=1e-9)
    assert summits.area == pytest.approx(60 * 80 * SPACING**2)
    assert summits.spacing == SPACING and summits.shape == (60, 80)


@pytest.mark.parametrize("angle", [0.0, 0.3, np.pi / 4, 1.2])
def test_elliptic_paraboloid_geometric_and_mean_rule(angle):
    r1, r2 = 0.3, 2.7
    x, y = grid(41, 41)
    z = paraboloid_field(x, y, [(20 * SPACING, 20 * SPACING, 0.01,
                                 rotated_elliptic(r1, r2, angle))])
    geometric = find_summits(z, SPACING)
    mean = find_summits(z, SPACING, curvature="mean")
    assert geometric.count == mean.count == 1
    assert (geometric.row[0], geometric.column[0]) == (20, 20)
    # The mixed derivative enters for rotated ellipses: the rule must use the full Hessian.
    assert geometric.radius[0] == pytest.approx(np.sqrt(r1 * r2), rel=1e-9)
    assert mean.radius[0] == pytest.approx(2.0 / (1 / r1 + 1 / r2), rel=1e-9)
    assert mean.curvature == "mean" and geometric.curvature == "geometric"


@pytest.mark.parametrize("surface", ["flat", "plane", "monotone", "ridge"])
def test_flat_and_monotone_surfaces_have_no_summits(surface):
    x, y = grid(30, 40)
    z = {
        "flat": np.zeros_like(x),
        "plane": 0.3 * x - 0.2 * y,
        "monotone": np.exp(x) + y**3 + 0.1 * np.sin(3 * x),       # increasing in x and y
        "ridge": -(y - 0.15) ** 2,                                # a level ridge: ties only
    }[surface]
    summits = find_summits(z, SPACING)
    assert summits.count == 0
    assert summits.x.size == summits.radius.size == 0


def test_ties_first_in_row_major_order_wins():
    z = np.zeros((7, 7))
    z[3, 3] = z[3, 4] = 1.0           # two equal neighbouring maxima
    summits = find_summits(z, 1.0)
    assert summits.count == 1
    assert (summits.row[0], summits.column[0]) == (3, 3)
    z = np.zeros((8, 8))
    z[3:5, 3:5] = 1.0                 # a 2 x 2 plateau: one summit, its first point
    summits = find_summits(z, 1.0)
    assert summits.count == 1 and summits.rejected == 0
    assert (summits.row[0], summits.column[0]) == (3, 3)


def test_edges_excluded_unless_periodic():
    x, y = grid(32, 32, 1.0 / 32)
    z = np.cos(2 * np.pi * x) * np.cos(2 * np.pi * y)   # maxima at (0, 0) and (16, 16) grid points
    plain = find_summits(z, 1.0 / 32)
    periodic = find_summits(z, 1.0 / 32, periodic=True)
    assert list(zip(plain.row, plain.column)) == [(16, 16)]
    assert list(zip(periodic.row, periodic.column)) == [(0, 0), (16, 16)]
    # Periodic central differences at the corner use the wrapped neighbours: same radius.
    assert periodic.radius[0] == pytest.approx(periodic.radius[1], rel=1e-12)
    # cos(k x) cos(k y) at a maximum: z_xx = z_yy = -(2/h^2)(1 - cos kh), z_xy = 0.
    h = 1.0 / 32
    expected = h**2 / (2 * (1 - np.cos(2 * np.pi * h)))
    assert periodic.radius[1] == pytest.approx(expected, rel=1e-12)


def test_four_and_eight_neighbours():
    z = np.zeros((5, 5))
    z[2, 2] = 1.0
    z[1, 1] = 1.5                     # a higher diagonal neighbour of (2, 2)
    eight = find_summits(z, 1.0)
    four = find_summits(z, 1.0, neighbours=4)
    assert list(zip(eight.row, eight.column)) == [(1, 1)]
    assert list(zip(four.row, four.column)) == [(1, 1), (2, 2)]
    assert four.neighbours == 4 and eight.neighbours == 8


def test_non_convex_summit_is_rejected_and_reported():
    z = np.zeros((5, 5))
    z[2, 2] = 1.0
    z[1, 3] = z[3, 1] = -5.0          # strong twist: z_xy = 2.75 with z_xx = z_yy = -2
    z[1, 1] = z[3, 3] = 0.5           # still lower than the centre
    summits = find_summits(z, 1.0)
    assert summits.count == 0 and summits.rejected == 1
    assert (summits.rejected_row[0], summits.rejected_column[0]) == (2, 2)
    # The same point is a convex summit once the twist is removed.
    z[1, 3] = z[3, 1] = 0.5
    assert find_summits(z, 1.0).count == 1


def test_wm_summits_are_strict_local_maxima_with_positive_radii():
    from validation import wm_surface

    z = wm_surface(128, D=2.5, rms_slope=0.1, seed=3)
    summits = find_summits(z, 1 / 128)
    assert summits.count > 10
    assert np.all(summits.radius > 0)
    r, c = summits.row, summits.column
    for dj in (-1, 0, 1):
        for di in (-1, 0, 1):
            if dj or di:
                assert np.all(z[r, c] > z[r + dj, c + di])
    # Every strict interior 8-neighbour maximum is either kept or reported as rejected.
    centre = z[1:-1, 1:-1]
    strict = np.ones_like(centre, dtype=bool)
    for dj in (-1, 0, 1):
        for di in (-1, 0, 1):
            if dj or di:
                strict &= centre > z[1 + dj:127 + dj, 1 + di:127 + di]
    assert strict.sum() == summits.count + summits.rejected


def test_from_points_and_lattice_and_storage():
    summits = Summits.from_points([0.1, 0.2, 0.3], [0.0, 0.1, 0.2], [1e-3, 2e-3, 0.0],
                                  [0.5, 0.4, 0.3], area=1.0, spacing=0.1)
    np.testing.assert_array_equal(summits.column, [1, 2, 3])
    np.testing.assert_array_equal(summits.row, [0, 1, 2])
    again = summits_from_arrays(summits_to_arrays(summits))
    for name in ("x", "y", "height", "radius", "row", "column"):
        np.testing.assert_array_equal(getattr(again, name), getattr(summits, name))
    assert again.area == summits.area and again.spacing == summits.spacing
    plain = Summits.from_points([0.0, 0.5], [0.0, 0.25], [0.0, 1.0], [1.0, 2.0], area=2.0)
    back = Summits.from_arrays(plain.to_arrays())
    assert back.row is None and back.spacing is None and back.density == pytest.approx(1.0)
    with pytest.raises(ValueError, match="integer multiple"):
        Summits.from_points([0.15], [0.0], [0.0], [1.0], area=1.0, spacing=0.1)


def test_gw_fit_of_summits():
    rng = np.random.default_rng(0)
    n = 200
    summits = Summits.from_points(rng.random(n), rng.random(n), rng.normal(1e-3, 2e-3, n),
                                  rng.uniform(0.1, 0.3, n), area=2.0)
    gw = summits.greenwood_williamson()
    improved = summits.improved_greenwood_williamson(area=4.0, m=0.95, e_star=2.0)
    # eta = N / area, Gaussian fit by the population mean and std (ddof = 0), mean radius.
    assert gw.density == pytest.approx(n / 2.0, rel=1e-15)
    assert improved.density == pytest.approx(n / 4.0, rel=1e-15)
    for theory in (gw, improved):
        assert theory.radius == pytest.approx(np.sum(summits.radius) / n, rel=1e-14)
        assert theory.sigma == pytest.approx(
            np.sqrt(np.sum((summits.height - summits.height.mean()) ** 2) / n), rel=1e-12)
        assert theory.mean == pytest.approx(np.sum(summits.height) / n, rel=1e-12)
    assert gw.area == 2.0 and improved.area == 4.0
    assert improved.m == 0.95 and improved.e_star == 2.0
    with pytest.raises(ValueError):
        Summits.from_points([0.0], [0.0], [0.0], [1.0], area=1.0).greenwood_williamson()


@pytest.mark.parametrize("kwargs, match", [
    (dict(heights=np.array([[0.0, 1.0, np.nan]] * 3)), "finite"),
    (dict(heights=np.zeros(9)), "2-D"),
    (dict(heights=np.zeros((3, 3, 3))), "2-D"),
    (dict(heights=np.zeros((2, 5))), "3 x 3"),
    (dict(spacing=0.0), "spacing"),
    (dict(spacing=-1.0), "spacing"),
    (dict(spacing=np.inf), "spacing"),
    (dict(neighbours=6), "neighbours"),
    (dict(curvature="harmonic"), "curvature"),
])
def test_find_summits_bad_input(kwargs, match):
    arguments = dict(heights=np.zeros((5, 5)), spacing=1.0)
    arguments.update(kwargs)
    heights = arguments.pop("heights")
    spacing = arguments.pop("spacing")
    with pytest.raises(ValueError, match=match):
        find_summits(heights, spacing, **arguments)


@pytest.mark.parametrize("kwargs, match", [
    (dict(x=[0.0, 0.0], y=[1.0, 1.0]), "distinct"),
    (dict(radius=[1.0, 0.0]), "radius"),
    (dict(radius=[1.0, -1.0]), "radius"),
    (dict(height=[np.nan, 0.0]), "finite"),
    (dict(height=[0.0]), "one entry"),
    (dict(area=0.0), "area"),
])
def test_from_points_bad_input(kwargs, match):
    arguments = dict(x=[0.0, 1.0], y=[0.0, 0.0], height=[0.0, 0.0], radius=[1.0, 1.0], area=1.0)
    arguments.update(kwargs)
    area = arguments.pop("area")
    with pytest.raises(ValueError, match=match):
        Summits.from_points(**arguments, area=area)
