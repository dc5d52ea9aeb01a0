"""A load path dealt to concurrent sub-paths (bem.concurrent_path): the same curve as one path."""

import numpy as np
import pytest

import bem
from bem.concurrent_path import CONCURRENT_LIMIT, concurrent_curve, path_parts
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


def test_one_part_is_the_plain_path(heights):
    one = bem.contact_curve(heights, 1.0 / N, loads=LOADS)
    same = concurrent_curve(heights, 1.0 / N, loads=LOADS, parts=1)
    np.testing.assert_array_equal(same.area, one.area)
    np.testing.assert_array_equal(same.separation, one.separation)


def test_parts_follow_the_free_cpus(monkeypatch):
    import bem.concurrent_path as concurrent

    monkeypatch.setattr(concurrent, "default_threads", lambda: 4)
    monkeypatch.setattr(concurrent, "running", lambda: 1)
    assert path_parts(12, (512, 512)) == 3 and path_parts(2, (512, 512)) == 2
    assert path_parts(12, (2 * CONCURRENT_LIMIT, 2 * CONCURRENT_LIMIT)) == 1
    monkeypatch.setattr(concurrent, "running", lambda: 4)
    assert path_parts(12, (512, 512)) == 1


@pytest.mark.parametrize("options, match", [
    ({"parts": 0}, "parts"), ({"error_estimate": True}, "error_estimate"),
    ({"separations": [0.1]}, "separations"), ({"callback": 3}, "callback"),
])
def test_bad_arguments_are_named(heights, options, match):
    with pytest.raises((ValueError, TypeError), match=match):
        concurrent_curve(heights, 1.0 / N, loads=LOADS, **options)


def test_bad_heights_are_named_by_the_path_not_by_numpy():
    with pytest.raises((ValueError, TypeError), match="heights"):
        concurrent_curve([["a", "b"], ["c", "d"]], 1.0, loads=LOADS)
