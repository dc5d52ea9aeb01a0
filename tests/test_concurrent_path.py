"""A load path dealt to concurrent sub-paths (bem.contact.concurrent_path): the same curve as one path."""

import numpy as np
import pytest

import bem
from bem.contact.concurrent_path import CONCURRENT_LIMIT, concurrent_curve, dealt, path_parts
from validation import self_affine_surface

N = 64
LOADS = np.array([0.02, 0.002, 0.05, 0.01, 0.005, 0.001, 0.03])   # not sorted: caller's order


@pytest.fixture(scope="module")
def heights():
    return self_affine_surface(N, hurst=0.8, rms_slope=0.1, rolloff=0.25, seed=3)


@pytest.mark.parametrize("parts", [2, 3, 7])
def test_sub_paths_give_the_path_in_the_callers_order(heights, parts):
    options = dict(quantities=("area", "load", "separation", "conductance", "contacts"),
                   tol=1e-10)
    one = bem.contact_curve(heights, 1.0 / N, loads=LOADS, **options)
    seen = {}
    split = concurrent_curve(heights, 1.0 / N, loads=LOADS, parts=parts,
                             callback=lambda index, solution: seen.__setitem__(index, solution),
                             **options)
    # each point solved to the tolerance from another start: equal to the solver's accuracy
    np.testing.assert_allclose(split.load, LOADS, rtol=1e-12)
    for name in ("area", "separation", "conductance"):
        np.testing.assert_allclose(getattr(split, name), getattr(one, name), rtol=1e-7)
    np.testing.assert_array_equal(split.contacts, one.contacts)
    np.testing.assert_allclose(split.extras["mean_gap"], one.extras["mean_gap"], rtol=1e-7)
    assert split.extras["converged"].all() and split.extras["iterations"].shape == LOADS.shape
    # the callback names each point by its index into the caller's loads
    assert sorted(seen) == list(range(LOADS.size))
    for index, solution in seen.items():
        assert solution.load == pytest.approx(LOADS[index], rel=1e-12)


def test_each_sub_path_starts_from_its_own_points_coarse_pressures(monkeypatch):
    """Coarse pressures given by the caller's index reach the sub-path that solves that point
    (by its own index there): no coarse solve is left, and the curve is the one path's."""
    import bem.contact.path

    fine = self_affine_surface(2 * N, hurst=0.8, rms_slope=0.1, rolloff=0.25, seed=3)
    kept = {}
    bem.contact_curve(fine[::2, ::2], 2.0 / (2 * N), loads=LOADS, tol=1e-10,
                      callback=lambda index, solution: kept.__setitem__(index, solution.pressure))
    solves = []
    original = bem.contact.path._coarse_start
    monkeypatch.setattr(bem.contact.path, "_coarse_start",
                        lambda *args, **kwargs: solves.append(1) or original(*args, **kwargs))
    one = bem.contact_curve(fine, 1.0 / (2 * N), loads=LOADS, tol=1e-10, coarse_pressures=kept)
    plain = bem.contact.concurrent_path.contact_curve
    routed = []

    def sub_path(heights, spacing, *, loads, coarse_pressures, **options):
        # each start carries its own load: sum p (2h)^2 = W
        routed.extend(float(np.sum(coarse_pressures[k])) * (2.0 / (2 * N))**2 / load
                      for k, load in enumerate(loads))
        return plain(heights, spacing, loads=loads, coarse_pressures=coarse_pressures,
                     **options)

    monkeypatch.setattr(bem.contact.concurrent_path, "contact_curve", sub_path)
    split = concurrent_curve(fine, 1.0 / (2 * N), loads=LOADS, parts=3, tol=1e-10,
                             coarse_pressures=kept)
    assert solves == [] and len(routed) == LOADS.size
    np.testing.assert_allclose(routed, 1.0, rtol=1e-9)
    for name in ("load", "area", "separation"):
        np.testing.assert_allclose(getattr(split, name), getattr(one, name), rtol=1e-7)


def test_loads_are_dealt_back_and_forth_by_increasing_load():
    """Sorted by load, the points go to sub-paths 0, 1, 1, 0, 0, 1, ...: each gets a like
    share of the heavy points (their solves take the most iterations)."""
    loads = np.array([5.0, 1.0, 12.0, 3.0, 8.0, 2.0, 4.0])
    order = np.argsort(loads)
    two = dealt(loads, 2)
    np.testing.assert_array_equal(two[0], np.sort(order[[0, 3, 4]]))
    np.testing.assert_array_equal(two[1], np.sort(order[[1, 2, 5, 6]]))
    three = dealt(loads, 3)
    assert sorted(np.concatenate(three).tolist()) == list(range(loads.size))
    assert [len(part) for part in three] == [3, 2, 2]
    # the heaviest point of each round of 2p goes to the sub-path that got its lightest
    np.testing.assert_array_equal(dealt(np.arange(12.0), 2)[0], [0, 3, 4, 7, 8, 11])


def test_each_sub_path_solves_the_stiffness_at_its_share_of_the_points(heights):
    options = dict(quantities=("area", "stiffness"), tol=1e-10)
    one = bem.contact_curve(heights, 1.0 / N, loads=LOADS, **options)
    split = concurrent_curve(heights, 1.0 / N, loads=LOADS, parts=3, stiffness_at=[1, 4, 6],
                             **options)
    np.testing.assert_allclose(split.stiffness[[1, 4, 6]], one.stiffness[[1, 4, 6]], rtol=1e-7)
    assert np.isnan(np.delete(split.stiffness, [1, 4, 6])).all()
    with pytest.raises(ValueError, match="stiffness_at"):
        concurrent_curve(heights, 1.0 / N, loads=LOADS, parts=2, stiffness_at=[7], **options)


def test_one_part_is_the_plain_path(heights):
    one = bem.contact_curve(heights, 1.0 / N, loads=LOADS)
    same = concurrent_curve(heights, 1.0 / N, loads=LOADS, parts=1)
    np.testing.assert_array_equal(same.area, one.area)
    np.testing.assert_array_equal(same.separation, one.separation)


def test_parts_follow_the_free_cpus(monkeypatch):
    import bem.contact.concurrent_path as concurrent

    monkeypatch.setattr(concurrent, "default_threads", lambda: 4)
    monkeypatch.setattr(concurrent, "running", lambda: 1)
    assert path_parts(12, (512, 512)) == 3 and path_parts(2, (512, 512)) == 2
    assert path_parts(12, (2 * CONCURRENT_LIMIT, 2 * CONCURRENT_LIMIT)) == 1
    monkeypatch.setattr(concurrent, "running", lambda: 4)
    assert path_parts(12, (512, 512)) == 1


@pytest.mark.parametrize("options, match", [
    ({"parts": 0}, "parts"), ({"error_estimate": True}, "error_estimate"),
    ({"separations": [0.1]}, "separations"), ({"callback": 3}, "callback"),
    # checked before the points are dealt, as a single path checks them (64^2 has no coarse
    # level: none may be given, even for a point no sub-path would have been dealt)
    ({"parts": 2, "coarse_pressures": {99: np.zeros((32, 32))}}, "coarse_pressures"),
    ({"parts": 2, "coarse_pressures": [np.zeros((32, 32))]}, "coarse_pressures"),
])
def test_bad_arguments_are_named(heights, options, match):
    with pytest.raises((ValueError, TypeError), match=match):
        concurrent_curve(heights, 1.0 / N, loads=LOADS, **options)


def test_bad_heights_are_named_by_the_path_not_by_numpy():
    with pytest.raises((ValueError, TypeError), match="heights"):
        concurrent_curve([["a", "b"], ["c", "d"]], 1.0, loads=LOADS)
