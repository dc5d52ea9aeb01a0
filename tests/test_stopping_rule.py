"""The contact solver's stopping rule (T25) against the solution at a tolerance of 1e-12.

Polonsky & Keer's rule counts the pixels that still join or leave the contact set in the
pressure change; a solve that also computes the stiffness waits for a contact set that no
longer changes. The bound the finer reference relies on (eq. T40): the separation, the mean
gap and the conductance move by at most ``SOLVER_ERROR * tol`` (the first two in units of the
rms height).
"""

import numpy as np
import pytest

from bem import contact_curve
from validation import wm_surface
from validation.run.refine import SOLVER_ERROR

N = 256
LOADS = np.geomspace(1e-5, 1e-2, 8)
TOL = 1e-4


@pytest.fixture(scope="module")
def heights():
    # the WM surface of benchmarks/bench_solver_tolerance.py on which one pixel more or less
    # at one load moved the conductance by 0.3 tol when the stiffness solve did not wait
    return wm_surface(N, D=2.95, rms_slope=0.1, seed=5)


def path(heights, tol, stiffness):
    quantities = ("area", "load", "separation") + (("conductance",) if stiffness else ())
    return contact_curve(heights, 1.0 / N, loads=LOADS, quantities=quantities, tol=tol,
                         max_iter=20000)


@pytest.fixture(scope="module")
def exact(heights):
    return path(heights, 1e-12, stiffness=True)


def test_with_the_stiffness_every_field_is_within_the_bound(heights, exact):
    curve = path(heights, TOL, stiffness=True)
    sigma = float(np.std(heights))
    assert curve.extras["converged"].all()
    assert np.max(np.abs(curve.conductance / exact.conductance - 1)) <= SOLVER_ERROR * TOL
    assert np.max(np.abs(curve.separation - exact.separation)) <= SOLVER_ERROR * TOL * sigma
    # the contact set settled: at most one edge pixel off at any load
    assert np.max(np.abs(curve.area - exact.area)) * N**2 <= 1.0 + 1e-9


def test_without_the_stiffness_the_solve_stops_sooner_within_the_bound(heights, exact):
    settled = path(heights, TOL, stiffness=True)
    curve = path(heights, TOL, stiffness=False)
    sigma = float(np.std(heights))
    assert curve.extras["converged"].all()
    assert np.max(np.abs(curve.separation - exact.separation)) <= SOLVER_ERROR * TOL * sigma
    assert np.max(np.abs(curve.extras["mean_gap"] - exact.extras["mean_gap"])) \
        <= SOLVER_ERROR * TOL * sigma
    # Polonsky-Keer's rule ends some solves while edge pixels still change: fewer iterations,
    # and the area within a few pixels
    assert curve.extras["iterations"].sum() < settled.extras["iterations"].sum()
    assert np.max(np.abs(curve.area - exact.area)) * N**2 <= 4.0
