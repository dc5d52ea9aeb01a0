"""Load paths: same states as single solves, caller's order, quantities on demand, spot counts."""

import numpy as np
import pytest

from bem import CURVE_QUANTITIES, ContactCurve, HalfSpace, contact_curve, count_contacts, solve_contact


def random_surface(n, seed, *, rms_slope=0.1):
    rng = np.random.default_rng(seed)
    q = np.hypot(np.fft.fftfreq(n)[:, None], np.fft.fftfreq(n)[None, :])
    filter_ = np.divide(1.0, q**1.8, out=np.zeros_like(q), where=q > 0)
    heights = np.fft.ifft2(np.fft.fft2(rng.normal(size=(n, n))) * filter_).real
    return heights * (rms_slope / np.sqrt(np.mean(np.gradient(heights, 1.0 / n, axis=1) ** 2) * 2))


HEIGHTS = random_surface(32, 0)
SPACING = 1.0 / 32


@pytest.mark.parametrize("periodic", [False, True])
def test_load_path_matches_single_solves_in_callers_order(periodic):
    loads = [3e-3, 1e-4, 1e-2, 1e-3]
    curve = contact_curve(HEIGHTS, SPACING, loads=loads, periodic=periodic,
                          quantities=CURVE_QUANTITIES)
    assert isinstance(curve, ContactCurve) and len(curve) == 4
    np.testing.assert_allclose(curve.load, loads, rtol=1e-12)
    for index, load in enumerate(loads):
        single = solve_contact(HEIGHTS, SPACING, load=load, periodic=periodic, stiffness=True)
        # warm and cold starts stop at tol = 1e-9 relative pressure change: same contact set
        assert curve.area[index] == single.area
        assert curve.separation[index] == pytest.approx(single.separation, rel=1e-7, abs=1e-12)
        assert curve.stiffness[index] == pytest.approx(single.stiffness, rel=1e-7)
        assert curve.contacts[index] == count_contacts(single.contact, periodic=periodic)
        assert curve.extras["mean_gap"][index] == pytest.approx(single.mean_gap, rel=1e-7)
    np.testing.assert_allclose(curve.conductance, 2 * curve.stiffness / curve.e_star, rtol=1e-15)
    np.testing.assert_allclose(curve.mean_pressure, curve.load / curve.nominal_area, rtol=1e-15)
    assert curve.nominal_area == pytest.approx(1.0)
    assert curve.extras["converged"].dtype == bool and curve.extras["converged"].all()
    assert np.all(curve.extras["iterations"] >= 1) and np.all(curve.extras["residual"] <= 1e-9)


def test_separation_path_and_stiffness_is_the_slope_of_the_load():
    top = float(HEIGHTS.max())
    separations = top - np.linspace(0.0, 0.3, 31)[::-1] * float(np.ptp(HEIGHTS))
    curve = contact_curve(HEIGHTS, SPACING, separations=separations,
                          quantities=("load", "stiffness", "separation"))
    np.testing.assert_array_equal(curve.separation, separations)
    assert curve.load[-1] == 0.0 and curve.area[-1] == 0.0  # d = max(z): no contact
    assert np.all(np.diff(curve.load) < 0)  # load falls as the plane withdraws
    # S = -dW/dd: the trapezoidal integral of S over d reproduces the load change to the
    # second-order error of the rule on this 31-point path (observed 0.3 %; bound 2 %).
    integral = np.trapezoid(curve.stiffness, curve.separation)  # d increases along the path
    assert integral == pytest.approx(curve.load[0] - curve.load[-1], rel=2e-2)


def test_only_requested_quantities_are_computed():
    curve = contact_curve(HEIGHTS, SPACING, loads=[1e-3, 2e-3])
    assert curve.contacts is None and curve.stiffness is None and curve.conductance is None
    assert curve.area.shape == (2,) and curve.separation.shape == (2,)
    curve = contact_curve(HEIGHTS, SPACING, loads=[1e-3], quantities=("conductance",))
    assert curve.conductance is not None and curve.stiffness is None


def test_the_stiffness_is_solved_only_at_the_points_asked_for():
    loads = [2e-3, 1e-3, 5e-3, 3e-3]
    options = dict(loads=loads, quantities=("area", "stiffness", "conductance"), tol=1e-10,
                   error_estimate=True)
    every = contact_curve(HEIGHTS, SPACING, **options)
    some = contact_curve(HEIGHTS, SPACING, stiffness_at=[2, 0], **options)
    np.testing.assert_array_equal(some.area, every.area)   # the same contact solves
    for name in ("stiffness", "conductance"):
        np.testing.assert_array_equal(getattr(some, name)[[0, 2]], getattr(every, name)[[0, 2]])
        assert np.isnan(getattr(some, name)[[1, 3]]).all()
    # the half grid's path solves the same points: the band where the stiffness is, NaN elsewhere
    np.testing.assert_array_equal(some.extras["stiffness_error"][[0, 2]],
                                  every.extras["stiffness_error"][[0, 2]])
    assert np.isnan(some.extras["stiffness_error"][[1, 3]]).all()
    none = contact_curve(HEIGHTS, SPACING, stiffness_at=[], **options)
    assert np.isnan(none.stiffness).all()
    for bad in ([4], [-1], [0.5]):
        with pytest.raises(ValueError, match="stiffness_at"):
            contact_curve(HEIGHTS, SPACING, stiffness_at=bad, **options)


def test_callback_sees_every_point_with_the_callers_index():
    seen = {}
    contact_curve(HEIGHTS, SPACING, loads=[2e-3, 1e-3, 5e-3],
                  callback=lambda index, solution: seen.setdefault(index, solution.load))
    assert seen == pytest.approx({0: 2e-3, 1: 1e-3, 2: 5e-3})


def test_a_prebuilt_operator_is_used_and_checked():
    operator = HalfSpace((32, 32), SPACING, periodic=True)
    curve = contact_curve(HEIGHTS, SPACING, loads=[1e-3], periodic=True, operator=operator)
    assert curve.area[0] > 0
    with pytest.raises(ValueError, match="operator"):
        contact_curve(HEIGHTS, SPACING, loads=[1e-3], operator=operator)


@pytest.mark.parametrize("kwargs, name", [
    (dict(loads=[1e-3], quantities=("area", "summits")), "quantities"),
    (dict(loads=[-1e-3]), "loads"),
    (dict(loads=[np.nan]), "loads"),
    (dict(loads=[]), "loads"),
    (dict(separations=[np.inf]), "separations"),
    (dict(separations=[-10.0], periodic=True), "separations"),
    (dict(), "exactly one"),
    (dict(loads=[1e-3], separations=[0.0]), "exactly one"),
    (dict(loads=[1e-3], spacing=0.0), "spacing"),
])
def test_bad_path_input_is_rejected(kwargs, name):
    kwargs.setdefault("spacing", SPACING)
    with pytest.raises(ValueError, match=name):
        contact_curve(HEIGHTS, **kwargs)


def test_count_contacts_connectivity_and_periodic_wrap():
    contact = np.zeros((8, 8), dtype=bool)
    contact[1, 1] = contact[2, 2] = True  # corner-touching pixels are two spots
    assert count_contacts(contact) == 2
    contact[1, 2] = True  # now edge-connected: one spot
    assert count_contacts(contact) == 1
    wrap = np.zeros((8, 8), dtype=bool)
    wrap[3, 0] = wrap[3, 7] = True  # one spot across the left/right edge
    wrap[0, 5] = wrap[7, 5] = True  # one spot across the top/bottom edge
    wrap[5, 5] = True
    assert count_contacts(wrap) == 5
    assert count_contacts(wrap, periodic=True) == 3
    corner = np.zeros((8, 8), dtype=bool)
    corner[0, 0] = corner[0, 7] = corner[7, 0] = corner[7, 7] = True  # the four corners
    assert count_contacts(corner, periodic=True) == 1
    assert count_contacts(np.zeros((4, 4), dtype=bool), periodic=True) == 0


def test_given_coarse_pressures_replace_the_paths_coarse_solves(monkeypatch):
    """Pressures of the same loads on every other grid point (the path one grid below) start
    those points instead of coarse solves of their own; the path agrees with its own to the
    solver's tolerance."""
    import bem.contact.path

    heights, spacing = random_surface(128, 3), 1.0 / 128
    loads = [1e-4, 1e-3, 1e-2]
    tol = 1e-8
    kept = {}
    contact_curve(heights[::2, ::2], 2 * spacing, loads=loads, tol=tol,
                  callback=lambda index, solution: kept.__setitem__(index, solution.pressure))
    coarse_solves = []
    original = bem.contact.path._coarse_start

    def spy(*args, **kwargs):
        coarse_solves.append(kwargs["load"])
        return original(*args, **kwargs)

    monkeypatch.setattr(bem.contact.path, "_coarse_start", spy)
    own = contact_curve(heights, spacing, loads=loads, tol=tol)
    assert len(coarse_solves) == 3
    coarse_solves.clear()
    given = contact_curve(heights, spacing, loads=loads, tol=tol,
                          coarse_pressures={0: kept[0], 2: kept[2]})
    assert coarse_solves == [loads[1]]   # the point without a given pressure solves its own
    np.testing.assert_allclose(given.load, own.load, rtol=1e-12)
    np.testing.assert_allclose(given.area, own.area, rtol=1e-6)
    np.testing.assert_allclose(given.separation, own.separation, rtol=1e-6)


@pytest.mark.parametrize("pressures, error, match", [
    ([np.zeros((64, 64))], TypeError, "mapping"),
    ({0: np.zeros((32, 32))}, ValueError, r"half grid's shape \(64, 64\)"),
    ({3: np.zeros((64, 64))}, ValueError, "point indices 0..1"),
    ({0: -np.ones((64, 64))}, ValueError, "non-negative"),
    ({0: np.full((64, 64), np.nan)}, ValueError, "finite"),
])
def test_bad_coarse_pressures_are_named(pressures, error, match):
    heights = random_surface(128, 3)
    with pytest.raises(error, match=match):
        contact_curve(heights, 1.0, loads=[1e-3, 1e-2], coarse_pressures=pressures)


def test_coarse_pressures_need_a_grid_the_nested_iteration_halves():
    with pytest.raises(ValueError, match="coarse_pressures need the nested iteration"):
        contact_curve(HEIGHTS, SPACING, loads=[1e-3], coarse_pressures={0: np.ones((16, 16))})
    heights = random_surface(128, 3)
    with pytest.raises(ValueError, match="coarse_pressures need the nested iteration"):
        contact_curve(heights, 1.0, loads=[1e-3], preconditioned=False,
                      coarse_pressures={0: np.ones((64, 64))})
