"""The exact leakage reference: bem.hydraulic_aperture against closed forms and invariants.

The scheme (bem.leakage.flow) is exact for gaps that vary in one direction only: harmonic-mean faces
add the resistances 1/g^3 of the cells along a row exactly, and the boundary half-cells
(conductance 2 g^3 over half a pixel) complete the row's sum. Those checks are therefore held to
round-off, far inside the 0.2 % one would allow a scheme with other boundary rules.
"""

import numpy as np
import pytest
import scipy.ndimage
import scipy.stats

import bem
from bem.leakage.background_flow import BackgroundLeakage
from bem.leakage.flow import hydraulic_aperture, leakage_aperture, spanning_cells

BOTH = pytest.mark.parametrize("periodic", [False, True])


@BOTH
@pytest.mark.parametrize("direction", ["x", "y"])
def test_a_uniform_gap_is_its_own_aperture(periodic, direction):
    gap = np.full((24, 40), 0.37)          # rectangular grids work too
    assert hydraulic_aperture(gap, 0.1, direction=direction, periodic=periodic) == \
        pytest.approx(0.37, rel=1e-13)


@BOTH
def test_gap_varying_along_the_flow_adds_resistances_in_series(periodic):
    profile = np.random.default_rng(3).uniform(0.2, 2.0, 256)
    gap = np.tile(profile, (256, 1))       # g depends on x only
    series = np.mean(profile**-3.0) ** (-1.0 / 3.0)
    parallel = np.mean(profile**3.0) ** (1.0 / 3.0)
    assert hydraulic_aperture(gap, 1.0, direction="x", periodic=periodic) == \
        pytest.approx(series, rel=1e-10)
    # the same field with the pressure drop along y: the columns carry flow in parallel
    assert hydraulic_aperture(gap, 1.0, direction="y", periodic=periodic) == \
        pytest.approx(parallel, rel=1e-10)
    assert series < 0.9 * parallel         # the check can tell the two apart


@BOTH
def test_a_contact_wall_across_the_flow_seals_exactly(periodic):
    gap = np.random.default_rng(4).uniform(0.5, 1.5, (32, 32))
    gap[:, 13] = 0.0                       # a wall across the x flow
    assert hydraulic_aperture(gap, 1.0, direction="x", periodic=periodic) == 0.0
    assert hydraulic_aperture(gap, 1.0, direction="y", periodic=periodic) > 0.5


@BOTH
def test_a_wall_of_gaps_at_most_the_closed_fraction_seals(periodic):
    # a wall across the x flow of gaps at and below CLOSED_GAP of the largest is closed; one
    # just above it still conducts (in series, the wall sets the aperture)
    gap = np.random.default_rng(5).uniform(0.5, 1.5, (32, 32))
    largest = float(gap.max())
    gap[:, 13] = np.geomspace(1e-12, bem.leakage.flow.CLOSED_GAP, 32) * largest
    assert hydraulic_aperture(gap, 1.0, direction="x", periodic=periodic) == 0.0
    gap[:, 13] = 2.0 * bem.leakage.flow.CLOSED_GAP * largest
    assert hydraulic_aperture(gap, 1.0, direction="x", periodic=periodic) > 0.0
    # closed cells along the flow change nothing but their own share
    assert hydraulic_aperture(gap, 1.0, direction="y", periodic=periodic) > 0.5


@BOTH
def test_a_contact_wall_along_the_flow_only_removes_its_share(periodic):
    gap = np.full((40, 40), 2.0)
    gap[:, 7] = 0.0                        # one column of 40 closed, along the y flow
    expected = 2.0 * (39 / 40) ** (1 / 3)
    assert hydraulic_aperture(gap, 1.0, direction="y", periodic=periodic) == \
        pytest.approx(expected, rel=1e-12)


def test_a_cluster_across_the_periodic_edge_that_does_not_wind_carries_nothing():
    gap = np.ones((20, 30))
    gap[:, 5] = gap[:, 20] = 0.0           # the open band 21..29, 0..4 crosses the edge
    assert hydraulic_aperture(gap, 1.0, periodic=True) == 0.0
    gap[3, 20] = 1.0                       # one open pixel in one wall: still sealed
    assert hydraulic_aperture(gap, 1.0, periodic=True) == 0.0
    gap[3, 5] = 1.0                        # and in the other: a path winds around
    assert hydraulic_aperture(gap, 1.0, periodic=True) > 0.0


@pytest.mark.parametrize("turns", [1, 2])
def test_a_diagonal_channel_that_winds_around_the_torus_leaks(turns):
    # A 4-connected staircase channel winding `turns` times along x for once along y: every
    # closed path through it crosses both periodic edges, and it spans along x.
    n = 24
    gap = np.zeros((n, n))
    columns = np.arange(n * turns)
    rows = (columns // turns) % n
    gap[rows, columns % n] = 1.0
    gap[(rows + 1) % n, columns % n] = 1.0     # two pixels thick: 4-connected steps
    assert hydraulic_aperture(gap, 1.0, periodic=True) > 0.0
    assert spanning_cells(gap > 0, periodic=True).sum() == np.count_nonzero(gap)


def test_an_isolated_pocket_changes_nothing():
    gap = np.random.default_rng(5).uniform(0.5, 1.5, (48, 48))
    ring = np.zeros_like(gap, dtype=bool)
    ring[10:20, 10:20] = True
    ring[12:18, 12:18] = False             # an open pocket inside a contact ring
    gap[ring] = 0.0
    dead_end = gap.copy()
    dead_end[30:40, 0:5] = 0.0
    dead_end[32:38, 0:4] = 1.0             # a pocket open to the inlet only
    for periodic in (False, True):
        with_pocket = hydraulic_aperture(gap, 1.0, periodic=periodic)
        filled = gap.copy()
        filled[12:18, 12:18] = 0.0
        assert with_pocket == pytest.approx(hydraulic_aperture(filled, 1.0, periodic=periodic),
                                            rel=1e-12)
    closed = dead_end.copy()
    closed[32:38, 0:4] = 0.0
    assert hydraulic_aperture(dead_end, 1.0) == pytest.approx(hydraulic_aperture(closed, 1.0),
                                                              rel=1e-12)


def _random_gap(n: int, seed: int, correlation=(2.0, 2.0)) -> np.ndarray:
    """A smooth random gap (white noise filtered by a periodic Gaussian of widths
    ``correlation`` along y and x, in pixels) with about 16 % of its pixels in contact."""
    noise = np.random.default_rng(seed).standard_normal((n, n))
    z = scipy.ndimage.gaussian_filter(noise, correlation, mode="wrap")
    z /= z.std()
    return np.maximum(1.0 - z, 0.0)        # zero where z > 1


def _log_anisotropy(correlation) -> np.ndarray:
    return np.array([np.log(hydraulic_aperture(gap, 1.0, direction="x", periodic=True)
                            / hydraulic_aperture(gap, 1.0, direction="y", periodic=True))
                     for gap in (_random_gap(128, seed, correlation) for seed in range(10))])


def test_x_and_y_agree_on_isotropic_gaps_within_their_scatter():
    # Over seeds, log(h_x / h_y) has mean zero for an isotropic field; the bound is the 99.9 %
    # Student-t interval of that mean from the seeds' own scatter (about 0.11 per seed).
    ratios = _log_anisotropy((2.0, 2.0))
    bound = scipy.stats.t.ppf(0.9995, ratios.size - 1) * ratios.std(ddof=1) / np.sqrt(ratios.size)
    assert abs(ratios.mean()) < bound
    # and the same bound sees a field twice as long along x as along y: it leaks more along x
    assert _log_anisotropy((2.0, 4.0)).mean() > bound


@BOTH
def test_refining_a_smooth_gap_converges_at_second_order(periodic):
    apertures = []
    for n in (16, 32, 64, 128):
        x = (np.arange(n) + 0.5) / n       # cell centres of the unit square
        X, Y = np.meshgrid(x, x)
        gap = 1 + 0.6 * np.sin(2 * np.pi * X) * np.sin(2 * np.pi * Y) \
            + 0.3 * np.cos(2 * np.pi * (X + 2 * Y))
        apertures.append(hydraulic_aperture(gap, 1.0 / n, periodic=periodic))
    changes = np.abs(np.diff(apertures))
    assert np.all(changes[1:] < changes[:-1])
    assert np.all((changes[:-1] / changes[1:] > 3.0) & (changes[:-1] / changes[1:] < 5.0))


def test_the_aperture_scales_with_the_gap_and_ignores_the_spacing():
    gap = _random_gap(64, 11)
    h = hydraulic_aperture(gap, 1.0, periodic=True)
    assert hydraulic_aperture(1e-7 * gap, 1.0, periodic=True) == pytest.approx(1e-7 * h, rel=1e-10)
    assert hydraulic_aperture(gap, 3e-6, periodic=True) == pytest.approx(h, rel=1e-12)
    assert bem.hydraulic_aperture is hydraulic_aperture


def test_a_closed_gap_does_not_leak():
    assert hydraulic_aperture(np.zeros((8, 8)), 1.0) == 0.0
    assert hydraulic_aperture(np.zeros((8, 8)), 1.0, periodic=True) == 0.0


@pytest.mark.parametrize("gap, match", [
    (-np.ones((4, 4)), "gap"), (np.full((4, 4), np.nan), "gap"), (np.full((4, 4), np.inf), "gap"),
    (np.ones(16), "gap"), (np.ones((2, 2, 2)), "gap"), (np.ones((1, 8)), "gap"),
    ("1.0", "gap"), (None, "gap"), (np.ones((4, 4), dtype=complex), "gap"),
])
def test_bad_gaps_are_refused_by_name(gap, match):
    with pytest.raises(ValueError, match=match):
        hydraulic_aperture(gap, 1.0)


@pytest.mark.parametrize("keywords, match", [
    ({"spacing": 0.0}, "spacing"), ({"spacing": -1.0}, "spacing"),
    ({"spacing": np.nan}, "spacing"), ({"spacing": "1"}, "spacing"),
    ({"direction": "z"}, "direction"), ({"direction": None}, "direction"),
    ({"periodic": "yes"}, "periodic"),
])
def test_bad_options_are_refused_by_name(keywords, match):
    arguments = {"spacing": 1.0, **keywords}
    with pytest.raises(ValueError, match=match):
        hydraulic_aperture(np.ones((4, 4)), **arguments)


def test_a_periodic_field_and_its_tiling_leak_alike():
    # The periodic solution of a 2 x 3 tiling is the tiled solution of one period.
    gap = _random_gap(48, 12)
    assert hydraulic_aperture(gap, 1.0, periodic=True) > 0.0
    for direction in ("x", "y"):
        single = hydraulic_aperture(gap, 1.0, direction=direction, periodic=True)
        tiled = hydraulic_aperture(np.tile(gap, (2, 3)), 1.0, direction=direction, periodic=True)
        assert tiled == pytest.approx(single, rel=1e-9)


@BOTH
def test_reversing_or_transposing_the_field_changes_nothing(periodic):
    gap = _random_gap(40, 13)
    h_x = hydraulic_aperture(gap, 1.0, direction="x", periodic=periodic)
    assert h_x > 0.0
    assert hydraulic_aperture(gap[:, ::-1], 1.0, periodic=periodic) == pytest.approx(h_x, rel=1e-10)
    assert hydraulic_aperture(gap[::-1, :], 1.0, periodic=periodic) == pytest.approx(h_x, rel=1e-10)
    assert hydraulic_aperture(gap.T, 1.0, direction="y", periodic=periodic) == \
        pytest.approx(h_x, rel=1e-12)


@BOTH
@pytest.mark.parametrize("pending", [1, 2, 5])
def test_background_leakage_gives_each_gap_its_own_aperture(periodic, pending):
    """Gaps solved in background threads, several in flight, come back under their own keys
    with exactly the aperture of the direct call (the two directions' mean leak rate)."""
    rng = np.random.default_rng(11)
    gaps = {key: np.clip(scipy.ndimage.gaussian_filter(rng.standard_normal((48, 48)), 2,
                                                       mode="wrap") + shift, 0.0, None)
            for key, shift in zip("abcdef", (0.3, 0.2, 0.1, 0.05, 0.0, -0.05))}
    flow = BackgroundLeakage(0.5, periodic=periodic, pending=pending)
    for key, gap in gaps.items():
        flow.submit(key, gap)
    results = flow.results()
    expected = {key: leakage_aperture(gap, 0.5, periodic=periodic) for key, gap in gaps.items()}
    assert results == expected
    values = list(expected.values())
    assert len(set(values)) == len(values)   # distinct gaps: a mixed-up key would show


def test_background_leakage_keeps_only_the_last_solve_of_each_direction(monkeypatch):
    """The solved gaps of a path keep their apertures; a solve's pressure field (32 MB at
    2048^2) lives on only as the next start of its direction, not until the path's end."""
    import gc
    import weakref

    import bem.leakage.background_flow

    starts = []
    original = bem.leakage.background_flow._flow_solution

    def spy(*args):
        aperture, start = original(*args)
        starts.append(weakref.ref(start))
        return aperture, start

    monkeypatch.setattr(bem.leakage.background_flow, "_flow_solution", spy)
    rng = np.random.default_rng(8)
    gaps = {key: np.clip(scipy.ndimage.gaussian_filter(rng.standard_normal((48, 48)), 2) + shift,
                         0.0, None) for key, shift in enumerate((0.3, 0.2, 0.1, 0.05))}
    flow = BackgroundLeakage(0.5, pending=len(gaps))
    for key, gap in gaps.items():
        flow.submit(key, gap)
    with flow._condition:   # every gap solved, the results not read yet
        flow._condition.wait_for(lambda: flow._unsolved == 0)
    gc.collect()
    assert len(starts) == 2 * len(gaps)
    assert sum(ref() is not None for ref in starts) == 2   # the last gap's, one per direction
    assert flow.results() == {key: leakage_aperture(gap, 0.5) for key, gap in gaps.items()}


def test_background_leakage_reports_a_bad_gap_and_bad_options():
    flow = BackgroundLeakage(1.0)
    flow.submit(0, np.full((4, 4), -1.0))   # raised where the result is read
    with pytest.raises(ValueError, match="gap"):
        flow.results()
    for keywords, match in (({"pending": 0}, "pending"),
                            ({"periodic": "yes"}, "periodic"),
                            ({"parallel": 1}, "parallel")):
        with pytest.raises((ValueError, TypeError), match=match):
            BackgroundLeakage(1.0, **keywords)
    with pytest.raises(ValueError, match="spacing"):
        BackgroundLeakage(-1.0)


def test_background_leakage_of_a_large_gap_solves_its_directions_in_turn(monkeypatch):
    """Above the size limit one thread solves both directions (one factor in memory at a
    time); the aperture is the same."""
    import bem.leakage.background_flow

    gap = np.clip(scipy.ndimage.gaussian_filter(
        np.random.default_rng(5).standard_normal((40, 40)), 2, mode="wrap") + 0.1, 0.0, None)
    names = []
    original = bem.leakage.background_flow._apertures

    def spy(gap, spacing, directions, periodic, starts):
        names.append(directions)
        return original(gap, spacing, directions, periodic, starts)

    monkeypatch.setattr(bem.leakage.background_flow, "_apertures", spy)
    monkeypatch.setattr(bem.leakage.background_flow, "FINAL_PARALLEL_LIMIT", 0)
    monkeypatch.setattr(bem.leakage.background_flow, "PARALLEL_DIRECTIONS_LIMIT", 40 * 40 - 1)
    flow = BackgroundLeakage(1.0)
    flow.submit("large", gap)
    assert flow.results()["large"] == leakage_aperture(gap, 1.0)
    monkeypatch.setattr(bem.leakage.background_flow, "PARALLEL_DIRECTIONS_LIMIT", 40 * 40)
    flow.submit("small", gap)
    assert flow.results()["small"] == leakage_aperture(gap, 1.0)
    assert sorted(names) == [("x",), ("x", "y"), ("y",)]
    # parallel=True splits a gap above the limit, parallel=False keeps one below it together
    names.clear()
    monkeypatch.setattr(bem.leakage.background_flow, "PARALLEL_DIRECTIONS_LIMIT", 40 * 40 - 1)
    flow = BackgroundLeakage(1.0, parallel=True)
    flow.submit("large", gap)
    assert flow.results()["large"] == leakage_aperture(gap, 1.0)
    monkeypatch.setattr(bem.leakage.background_flow, "PARALLEL_DIRECTIONS_LIMIT", 40 * 40)
    flow = BackgroundLeakage(1.0, parallel=False)
    flow.submit("small", gap)
    assert flow.results()["small"] == leakage_aperture(gap, 1.0)
    assert sorted(names) == [("x",), ("x", "y"), ("y",)]


def test_background_leakage_lets_the_caller_run_ahead_and_splits_the_final_gaps(monkeypatch):
    """Up to ``pending`` gaps wait while the caller goes on (the submits return before any
    solve has ended); the gaps still waiting when results() is called have their two
    directions solved at once where two CPUs may be used, up to FINAL_PARALLEL_LIMIT cells."""
    import threading

    import bem.leakage.background_flow

    gap = np.clip(scipy.ndimage.gaussian_filter(
        np.random.default_rng(5).standard_normal((40, 40)), 2, mode="wrap") + 0.1, 0.0, None)
    release, events = threading.Event(), []
    original = bem.leakage.background_flow._apertures

    def held(gap, spacing, directions, periodic, starts):
        release.wait(30)
        events.append(directions)
        return original(gap, spacing, directions, periodic, starts)

    monkeypatch.setattr(bem.leakage.background_flow, "_apertures", held)
    monkeypatch.setattr(bem.leakage.background_flow, "PARALLEL_DIRECTIONS_LIMIT", 40 * 40 - 1)
    flow = BackgroundLeakage(1.0, pending=3)
    for key in range(3):
        flow.submit(key, gap)
    assert events == []   # three submits returned, no solve has ended
    release.set()
    assert flow.results() == {key: leakage_aperture(gap, 1.0) for key in range(3)}
    # which gaps are split: by size while the caller works, up to the final limit once the
    # caller waits and two CPUs are there, never with parallel=False
    large = np.zeros((40, 40))
    monkeypatch.setattr(bem.leakage.background_flow, "default_threads", lambda: 2)
    assert flow._together(large, {})
    flow._finishing = True
    assert not flow._together(large, {})
    monkeypatch.setattr(bem.leakage.background_flow, "FINAL_PARALLEL_LIMIT", 40 * 40 - 1)
    assert flow._together(large, {})
    monkeypatch.setattr(bem.leakage.background_flow, "FINAL_PARALLEL_LIMIT", 40 * 40)
    # a periodic gap follows the same limits (the same multigrid)
    periodic = BackgroundLeakage(1.0, periodic=True)
    periodic._finishing = True
    assert not periodic._together(large, {})
    monkeypatch.setattr(bem.leakage.background_flow, "FINAL_PARALLEL_LIMIT", 40 * 40 - 1)
    assert periodic._together(large, {})
    monkeypatch.setattr(bem.leakage.background_flow, "FINAL_PARALLEL_LIMIT", 40 * 40)
    monkeypatch.setattr(bem.leakage.background_flow, "default_threads", lambda: 1)
    assert flow._together(large, {})
    assert BackgroundLeakage(1.0, parallel=False)._together(np.zeros((4, 4)), {})
    # two sparse LU factorisations at once only up to PARALLEL_FACTOR_LIMIT cells
    from bem.leakage.flow_solver import FlowStart

    monkeypatch.setattr(bem.leakage.background_flow, "default_threads", lambda: 2)
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SOLVE_LIMIT", 0)
    slow = {direction: FlowStart(np.zeros((40, 40)), None) for direction in ("x", "y")}
    fast = {"x": FlowStart(np.zeros((40, 40)), 3), "y": slow["y"]}
    assert not flow._together(large, fast)       # (finishing, within the final limit)
    assert not flow._together(large, slow)       # both LU, within the factor limit
    monkeypatch.setattr(bem.leakage.background_flow, "PARALLEL_FACTOR_LIMIT", 40 * 40 - 1)
    assert flow._together(large, slow)
    assert not flow._together(large, fast)
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SWITCH_LIMIT", 40 * 40 - 1)
    assert not flow._together(large, slow)       # too large to switch: multigrid both


@BOTH
@pytest.mark.parametrize("seed", [1, 2])
@pytest.mark.parametrize("slow", [False, True])
def test_the_multigrid_solve_of_large_gaps_gives_the_direct_aperture(monkeypatch, periodic, seed,
                                                                     slow):
    """Above DIRECT_SOLVE_LIMIT cells, periodic or not, the flow system is solved by
    multigrid-preconditioned conjugate gradients; forced on smaller gaps (about 16 % contact,
    g^3 over many decades near the contact edges), with three levels of pixel blocks and two
    after a slow neighbour, it must
    give the sparse LU's aperture to well within its tolerance (the dissipation's error is of
    second order in the pressure's)."""
    import bem.leakage.flow
    import bem.leakage.flow_solver
    from bem.leakage.flow_solver import FlowStart

    gap = _random_gap(96, seed)
    gap[gap > 0] **= 3   # a wider contrast of g^3 than the smooth gap alone
    direct = [hydraulic_aperture(gap, 1.0, direction=d, periodic=periodic) for d in "xy"]
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SOLVE_LIMIT", 0)
    used = []
    original = bem.leakage.flow_solver._hierarchy
    monkeypatch.setattr(bem.leakage.flow_solver, "_hierarchy",
                        lambda scaled, scale, cells, count: used.append(count)
                        or original(scaled, scale, cells, count))
    start = FlowStart(None, 1, slow)
    multigrid = [bem.leakage.flow._flow_solution(gap, 1.0, d, periodic, start)[0] for d in "xy"]
    # (96^2: the coarsest at most 24^2, a sixteenth of the grid, or 48^2 when slow)
    assert used == [2 if slow else 3] * 2 and min(direct) > 0
    # the pixel blocks stop once the dissipation's estimated error is 1e-6 (the aperture's a
    # third of it; 1.2e-7 to 2.5e-7 measured here) and the residual 1e-6 (the residual alone at
    # 1e-6 left 6e-6 here)
    np.testing.assert_allclose(multigrid, direct, rtol=bem.leakage.flow_cg.DISSIPATION_TOLERANCE)


def test_a_large_gap_whose_pixel_blocks_stop_short_goes_on_algebraically(monkeypatch):
    """Above DIRECT_SWITCH_LIMIT cells, a solve of the pixel blocks that stops short of its
    rule goes on from its last iterate with algebraic coarsening (no warning), to the LU's
    aperture (here from the very start: the algebraic solve alone), its iterations counted
    with the first's; up to the limit the sparse LU takes over."""
    import warnings

    import bem.leakage.flow
    import bem.leakage.flow_solver
    from bem.common.warnings import ConvergenceWarning

    gap = _random_gap(96, 4)
    direct = hydraulic_aperture(gap, 1.0)
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SOLVE_LIMIT", 0)
    monkeypatch.setattr(bem.leakage.flow_solver, "COARSEST_LIMIT", 40 * 40)
    original, calls = bem.leakage.flow_solver._conjugate_gradients, []

    def stalled_first(matrix, rhs, preconditioner, dissipation, tolerance, start=None,
                      most=None):
        calls.append(preconditioner)
        if len(calls) == 1:   # the pixel blocks: their start back, after "1000 iterations"
            return np.array(start), most or 1000, False
        return original(matrix, rhs, preconditioner, dissipation, tolerance, start, most=most)

    monkeypatch.setattr(bem.leakage.flow_solver, "_conjugate_gradients", stalled_first)
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SWITCH_LIMIT", 0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        aperture, solved = bem.leakage.flow._flow_solution(gap, 1.0, "x", False)
    # the pixel blocks' one-sided sweeps, then the algebraic hierarchy's symmetric ones
    assert len(calls) == 2 and len(calls[0].before) == 1 and len(calls[1].before) == 2
    assert solved.iterations > 1000
    assert aperture == pytest.approx(direct, rel=1e-8)
    calls.clear()
    # up to the limit: the sparse LU instead, exact and without a warning
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SWITCH_LIMIT", gap.size)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        aperture, solved = bem.leakage.flow._flow_solution(gap, 1.0, "x", False)
    assert len(calls) == 1 and solved.iterations is None
    assert aperture == pytest.approx(direct, rel=1e-12)


def test_a_large_grid_with_few_open_cells_is_solved_directly(monkeypatch):
    """Above DIRECT_SOLVE_LIMIT grid cells but with at most COARSEST_LIMIT unknowns, and at
    most a quarter of the grid's cells, the multigrid has one level: the sparse LU solves the
    (unscaled) system, exactly."""
    import bem.leakage.flow_solver

    gap = _random_gap(96, 2)
    gap *= (np.arange(96) < 20)[:, None]    # 20 of 96 rows open: a fifth of the grid
    direct = hydraulic_aperture(gap, 1.0)
    assert direct > 0
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SOLVE_LIMIT", 0)
    monkeypatch.setattr(bem.leakage.flow_solver, "COARSEST_LIMIT", gap.size)
    calls = []
    monkeypatch.setattr(bem.leakage.flow_solver, "_hierarchy", lambda *args: calls.append(args))
    assert hydraulic_aperture(gap, 1.0) == pytest.approx(direct, rel=1e-12)
    assert not calls                              # no multigrid was built


@pytest.mark.parametrize("slow", [False, True])
def test_a_256_gap_is_solved_by_pixel_blocks_to_the_multigrids_accuracy(monkeypatch, slow):
    """A 256^2 gap: three levels (the coarsest 64^2 by LU), two after a slow neighbour along its
    path (the coarsest 128^2), the aperture within the multigrid's stopping rule (3e-7,
    DISSIPATION_TOLERANCE) of the sparse LU's either way."""
    import bem.leakage.flow
    import bem.leakage.flow_solver
    from bem.leakage.flow_solver import FlowStart

    gap = _random_gap(256, 11)
    levels = []
    original = bem.leakage.flow_solver._hierarchy
    monkeypatch.setattr(bem.leakage.flow_solver, "_hierarchy",
                        lambda scaled, scale, cells, count: levels.append(count)
                        or original(scaled, scale, cells, count))
    start = FlowStart(None, 1, slow) if slow else None
    iterative, solved = bem.leakage.flow._flow_solution(gap, 1.0, "x", False, start)
    assert levels == [2 if slow else 3] and solved.slow == slow
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SOLVE_LIMIT", gap.size)
    assert iterative == pytest.approx(hydraulic_aperture(gap, 1.0), rel=3e-7)
    assert len(levels) == 1                                   # the LU: no hierarchy built


def test_a_slow_multigrid_solve_makes_the_rest_of_its_path_slow():
    """The FlowStart a solve hands on is slow once it took FEWER_LEVELS_ITERATIONS or more, was
    solved by the LU, or followed a slow one (the gaps of a path close towards percolation)."""
    from bem.leakage.flow_solver import FEWER_LEVELS_ITERATIONS, FlowStart, next_start

    pressure = np.zeros((4, 4))
    assert not next_start(pressure, FEWER_LEVELS_ITERATIONS - 1, None).slow
    assert next_start(pressure, FEWER_LEVELS_ITERATIONS, None).slow
    assert next_start(pressure, None, None).slow
    light = FlowStart(pressure, 3)
    assert not next_start(pressure, FEWER_LEVELS_ITERATIONS - 1, light).slow
    assert next_start(pressure, 3, FlowStart(pressure, 3, True)).slow
    kept = next_start(pressure, 5, light)
    assert kept.pressure is pressure and kept.iterations == 5


def test_multigrid_levels_halve_the_grid_down_to_the_coarsest_limit():
    from bem.leakage.flow_solver import COARSEST_LIMIT, MULTIGRID_LEVELS, multigrid_levels

    assert multigrid_levels(COARSEST_LIMIT) == 1
    assert multigrid_levels(COARSEST_LIMIT + 1) == 2
    assert multigrid_levels(4 * COARSEST_LIMIT) == 2
    assert multigrid_levels(16 * COARSEST_LIMIT) == 3
    assert multigrid_levels(64 * COARSEST_LIMIT) == 4
    assert multigrid_levels(4096 * COARSEST_LIMIT) == MULTIGRID_LEVELS == 4
    # on a grid, at most a sixteenth of it on the coarsest level, a quarter once slow
    assert multigrid_levels(256 * 256, 256 * 256) == 3       # coarsest 64^2
    assert multigrid_levels(256 * 256, 256 * 256, slow=True) == 2   # coarsest 128^2
    assert multigrid_levels(512 * 512, 512 * 512) == 3       # coarsest 128^2
    assert multigrid_levels(512 * 512, 512 * 512, slow=True) == 2   # coarsest 256^2
    assert multigrid_levels(1024 * 1024, 1024 * 1024) == 3   # coarsest 256^2 either way
    assert multigrid_levels(1024 * 1024, 1024 * 1024, slow=True) == 3
    assert multigrid_levels(2048 * 2048, 2048 * 2048) == 4
    assert multigrid_levels(2048 * 2048, 2048 * 2048, slow=True) == 4
    # few unknowns (within a slow path's coarsest level): the LU alone, slow or not
    assert multigrid_levels(128 * 128, 256 * 256) == 1
    assert multigrid_levels(128 * 128 + 1, 256 * 256) == 3
    assert multigrid_levels(128 * 128 + 1, 256 * 256, slow=True) == 2


def test_a_multigrid_solve_that_stops_short_goes_on_by_lu_or_warns(monkeypatch):
    """Up to DIRECT_SWITCH_LIMIT cells a multigrid solve that has not met its rule in
    LU_FALLBACK_ITERATIONS is abandoned for the sparse LU: the LU's aperture, no warning, and
    the path goes on by the LU; above it the algebraic solve takes over, and if that too
    stops short, the last iterate is returned with a warning."""
    import warnings

    import bem.leakage.flow
    import bem.leakage.flow_solver

    gap = _random_gap(96, 3)
    direct = hydraulic_aperture(gap, 1.0)
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SOLVE_LIMIT", 0)
    monkeypatch.setattr(bem.leakage.flow_solver, "COARSEST_LIMIT", 48 * 48)
    monkeypatch.setattr(bem.leakage.flow_solver, "LU_FALLBACK_ITERATIONS", 1)
    with warnings.catch_warnings():
        warnings.simplefilter("error", bem.ConvergenceWarning)
        aperture, solved = bem.leakage.flow._flow_solution(gap, 1.0, "x", False)
    assert aperture == pytest.approx(direct, rel=1e-12)
    assert solved.iterations is None and solved.slow
    # (not abandoned when the solve needs no more than the fall-back allows)
    monkeypatch.setattr(bem.leakage.flow_solver, "LU_FALLBACK_ITERATIONS", 1000)
    assert bem.leakage.flow._flow_solution(gap, 1.0, "x", False)[1].iterations is not None
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SWITCH_LIMIT", 0)
    monkeypatch.setattr(bem.leakage.flow_cg, "MULTIGRID_MAX_ITERATIONS", 1)
    with pytest.warns(bem.ConvergenceWarning,
                      match="multigrid solve of 9216 cells did not converge in 2 iterations"):
        value = hydraulic_aperture(gap, 1.0)
    assert value > 0 and np.isfinite(value)


def test_the_multigrid_hierarchy_is_held_in_compressed_rows(monkeypatch):
    """The pixel blocks' coarse levels are built in CSR (the finest is the system held by its
    faces, bem.leakage.face_matrix, when not periodic), the restriction a view of the
    interpolation; smoothed aggregation (the fall-back of a large gap whose pixel blocks stop
    short) builds its coarse levels as 1 x 1 BSR, which are converted to CSR (faster products,
    and the form the compiled Gauss-Seidel sweeps take)."""
    import scipy.sparse

    import bem.leakage.flow_solver
    from bem.leakage.flow import _flow_system, spanning_cells

    gap = _random_gap(96, 1)
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SOLVE_LIMIT", 0)
    built = []
    blocks = bem.leakage.flow_solver.block_hierarchy
    monkeypatch.setattr(bem.leakage.flow_solver, "block_hierarchy",
                        lambda *args: built.append(blocks(*args)) or built[-1])
    hierarchies = []
    for periodic in (False, True):
        assert hydraulic_aperture(gap, 1.0, periodic=periodic) > 0.0
        hierarchies.append(built[-1])
    # the algebraic fall-back's hierarchy, of the same Jacobi-scaled system in CSR
    k = (gap / gap.max()) ** 3
    cells = spanning_cells(k > 0)
    matrix = _flow_system(k, cells, False)[0].tocsr()
    scale = 1.0 / np.sqrt(matrix.diagonal())
    scaled = scipy.sparse.csr_array(matrix * scale[:, None] * scale[None, :])
    algebraic = bem.leakage.flow_solver._hierarchy(scaled, scale, cells, 0)
    # (a periodic system's aggregates are read from its compressed rows)
    for hierarchy, faces in zip(hierarchies + [algebraic], (True, False, False)):
        levels = hierarchy.levels
        assert len(levels) >= 2
        # the pixel blocks' finest operator is the system held by its faces, as assembled
        assert (levels[0].A.format == "faces") == faces
        assert all(scipy.sparse.issparse(level.A) and level.A.format == "csr"
                   for level in levels[1 if faces else 0:])
        for level in levels[:-1]:
            # the restriction is the interpolation's transpose, a view of its arrays
            assert level.P.format == "csr" and level.R.format == "csc"
            assert np.shares_memory(level.R.data, level.P.data)


def test_the_energy_left_is_the_geometric_tail_of_the_last_decrements():
    from bem.leakage.flow_cg import ESTIMATE_STEPS, _remaining

    geometric = [2.0 * 0.5**k for k in range(ESTIMATE_STEPS + 3)]
    assert _remaining(geometric) == pytest.approx(geometric[-1])   # rho / (1 - rho) = 1
    assert _remaining(geometric[:ESTIMATE_STEPS]) == np.inf        # too few to tell
    assert _remaining(geometric[:-1] + [geometric[-2] * 1.1]) == np.inf   # one grew
    # the largest recent ratio rules: a slow step makes the tail longer
    mixed = geometric[:-1] + [geometric[-2] * 0.9]
    assert _remaining(mixed) == pytest.approx(mixed[-1] * 0.9 / 0.1)


def test_the_conjugate_gradients_stop_when_the_dissipation_is_known():
    """On a system whose energy minimum is known (a conductance chain with leaks to ground,
    random conductances), the iteration stops with the energy within its tolerance, long before
    the residual reaches rounding; without the energy it stops at the residual asked for."""
    import scipy.sparse
    import scipy.sparse.linalg

    from bem.leakage.flow_cg import DISSIPATION_TOLERANCE, _conjugate_gradients

    rng = np.random.default_rng(4)
    t = 10.0 ** rng.uniform(-1, 0, 401)
    main = t[:-1] + t[1:] + 0.05
    matrix = scipy.sparse.diags([main, -t[1:-1], -t[1:-1]], [0, 1, -1], format="csr")
    rhs = rng.uniform(0.0, 1.0, 400)
    solution = scipy.sparse.linalg.spsolve(matrix.tocsc(), rhs)
    lowest = float(rhs @ solution)               # the minimum of x.A x - 2 b.x + 2 b.A^-1 b

    def dissipation(x):
        return float(x @ (matrix @ x) - 2.0 * rhs @ x) + 2.0 * lowest

    identity = scipy.sparse.identity(400, format="csr")
    x, iterations, settled = _conjugate_gradients(matrix, rhs, identity, dissipation, 1e-6)
    _, exact_iterations, _ = _conjugate_gradients(matrix, rhs, identity, None, 1e-12)
    assert settled and iterations < exact_iterations
    assert 0.0 <= dissipation(x) / lowest - 1.0 <= DISSIPATION_TOLERANCE
    assert np.linalg.norm(rhs - matrix @ x) <= 1e-6 * np.linalg.norm(rhs)
    x, _, settled = _conjugate_gradients(matrix, rhs, identity, None, 1e-12)
    assert settled and dissipation(x) == pytest.approx(lowest, rel=1e-12)


def test_background_leakage_starts_each_solve_from_the_last_pressure(monkeypatch):
    """Along a sequence of gaps each direction's iterative solve begins at the pressure the
    previous gap's solve found (with the linear drop where that gap had no open cell); the
    apertures are those of a solve from the linear drop, to the solver's tolerance."""
    import bem.leakage.background_flow
    import bem.leakage.flow_solver

    rng = np.random.default_rng(8)
    surface = scipy.ndimage.gaussian_filter(rng.standard_normal((264, 264)), 4, mode="wrap")
    gaps = [np.clip(surface + level, 0.0, None) for level in (0.3, 0.2, 0.1)]
    assert gaps[0].size > bem.leakage.flow_solver.DIRECT_SOLVE_LIMIT   # the multigrid's path
    seen = []
    original = bem.leakage.background_flow._flow_solution

    def spy(gap, spacing, direction, periodic, start=None):
        aperture, pressure = original(gap, spacing, direction, periodic, start)
        seen.append((direction, start, pressure))
        return aperture, pressure

    monkeypatch.setattr(bem.leakage.background_flow, "_flow_solution", spy)
    flow = BackgroundLeakage(1.0)
    for key, gap in enumerate(gaps):
        flow.submit(key, gap)
    results = flow.results()
    for direction in ("x", "y"):
        solves = [(start, pressure) for d, start, pressure in seen if d == direction]
        assert solves[0][0] is None
        for (_, previous), (start, _) in zip(solves, solves[1:]):
            assert start is previous
    monkeypatch.setattr(bem.leakage.background_flow, "_flow_solution", original)
    for key, gap in enumerate(gaps):
        assert results[key] == pytest.approx(leakage_aperture(gap, 1.0), rel=1e-6)


@pytest.mark.parametrize("slow", [False, True])
@pytest.mark.parametrize("above_switch", [False, True])
def test_a_slow_paths_large_gap_starts_from_the_linear_drop(monkeypatch, slow, above_switch):
    """Along a path each multigrid solve starts from the previous gap's pressure; on a grid
    above the LU switch's limit, once the path is slow, from the linear drop, and the map is
    not kept (near percolation the previous pressure can be wrong where regions hang on thin
    necks: a 2048^2 gap at 22 % contact took 532 iterations from it and 177 from the drop)."""
    import bem.leakage.flow
    import bem.leakage.flow_solver
    from bem.leakage.flow_solver import FEWER_LEVELS_ITERATIONS, next_start

    gap = _random_gap(96, 2)
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SOLVE_LIMIT", 0)
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SWITCH_LIMIT", 0 if above_switch else gap.size)
    given, original = [], bem.leakage.flow_solver._start
    monkeypatch.setattr(bem.leakage.flow_solver, "_start",
                        lambda start, *rest: given.append(start) or original(start, *rest))
    previous = np.full(gap.shape, 0.5)
    start = next_start(previous, FEWER_LEVELS_ITERATIONS if slow else 3, None)
    assert start.slow == slow and (start.pressure is None) == (slow and above_switch)
    value, _ = bem.leakage.flow._flow_solution(gap, 1.0, "x", False, start)
    assert len(given) == 1 and (given[0] is None) == (slow and above_switch)
    assert value == pytest.approx(hydraulic_aperture(gap, 1.0), rel=1e-6)


def test_the_start_of_a_flow_solve():
    """The given pressure where it has a value, the linear drop (or zero, periodic) elsewhere;
    a map of another grid is not used."""
    from bem.leakage.flow_solver import _start

    cells = np.ones((2, 4), dtype=bool)
    cells[0, 0] = False
    linear = np.array([0.875, 0.625, 0.375, 0.125])
    np.testing.assert_allclose(_start(None, cells, False), np.concatenate([linear[1:], linear]))
    np.testing.assert_array_equal(_start(None, cells, True), np.zeros(7))
    known = np.full((2, 4), np.nan)
    known[1, 2] = 0.5
    np.testing.assert_allclose(_start(known, cells, False),
                               np.concatenate([linear[1:], [0.875, 0.625, 0.5, 0.125]]))
    np.testing.assert_allclose(_start(np.zeros((3, 3)), cells, False),
                               np.concatenate([linear[1:], linear]))


def test_the_estimate_must_hold_at_consecutive_iterations(monkeypatch):
    """The estimate of the energy left stops the iteration only once it has held at
    ESTIMATE_CONFIRMATIONS consecutive iterations: a single low estimate, as after fast modes
    have gone and before a slow one shows, does not stop it."""
    import scipy.sparse

    import bem.leakage.flow_solver

    matrix = scipy.sparse.diags(np.linspace(1.0, 2.0, 50), format="csr")
    rhs = np.ones(50)
    estimates = iter([np.inf, 0.0, np.inf, np.inf, 0.0, 0.0] + [np.inf] * 50)
    monkeypatch.setattr(bem.leakage.flow_cg, "_remaining", lambda decrements: next(estimates))
    monkeypatch.setattr(bem.leakage.flow_cg, "ESTIMATE_CONFIRMATIONS", 2)
    identity = scipy.sparse.identity(50, format="csr")
    _, iterations, settled = bem.leakage.flow_cg._conjugate_gradients(
        matrix, rhs, identity, lambda x: 1.0, 1.0)
    assert settled and iterations == 6


def test_a_gap_that_leaks_through_one_neck_is_solved_to_its_tolerance(monkeypatch):
    """A contact wall across the flow with one narrow cell open: the dissipation is decades
    below where the linear pressure drop starts it, so a residual relative to the inlet's scale
    says little; the multigrid's aperture stays within its tolerance of the LU's (with the
    residual floor at 1e-7 it was 2e-4 off)."""
    import bem.leakage.flow_solver

    rng = np.random.default_rng(0)
    gap = np.exp(rng.normal(0.0, 0.5, (192, 192)))
    gap[:, 96] = 0.0
    gap[64, 96] = 3e-3
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SOLVE_LIMIT", gap.size)
    exact = hydraulic_aperture(gap, 1.0)
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SOLVE_LIMIT", 0)
    assert hydraulic_aperture(gap, 1.0) == pytest.approx(exact, rel=1e-6)
    # the neck carries the flow: about its own gap
    assert 1e-3 < exact < 1e-2


def test_conjugate_gradients_from_a_start_reach_the_same_solution():
    """The multigrid's conjugate gradients from any start stop at the same rule: the solution
    of a system of known energy, from zero and from a start, within the tolerance."""
    import scipy.sparse

    from bem.leakage.flow_cg import _conjugate_gradients

    n = 400
    matrix = scipy.sparse.diags([-np.ones(n - 1), 2.0 * np.ones(n), -np.ones(n - 1)],
                                [-1, 0, 1], format="csr")
    rhs = np.zeros(n)
    rhs[0] = 1.0
    exact = scipy.sparse.linalg.spsolve(matrix.tocsc(), rhs)
    identity = scipy.sparse.identity(n, format="csr")
    energy = lambda x: float(x @ (matrix @ x) - 2 * rhs @ x)   # noqa: E731
    cold, cold_steps, settled = _conjugate_gradients(matrix, rhs, identity, energy, 1e-10)
    warm, warm_steps, settled_warm = _conjugate_gradients(
        matrix, rhs, identity, energy, 1e-10, start=exact + 1e-3 * np.sin(np.arange(n)))
    assert settled and settled_warm
    np.testing.assert_allclose(cold, exact, rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(warm, exact, rtol=1e-6, atol=1e-8)
    assert warm_steps != cold_steps   # the start was used


def test_the_v_cycle_is_pyamgs():
    """The multigrid preconditioner's own V-cycle applies pyAMG's cycle (same smoothers,
    interpolations and coarse solve from a zero guess): the same vector as pyAMG's
    preconditioner, which also evaluates residual norms around it; its compiled sweeps give
    pyAMG's Gauss-Seidel iterates, the pixel hierarchy's one-sided sweeps and the algebraic
    hierarchy's symmetric ones alike."""
    import pyamg

    from bem.leakage.flow_solver import _compressed_rows
    from bem.leakage.multigrid_cycle import VCycle
    from bem.leakage.pixel_blocks import aggregates as blocks

    matrix = pyamg.gallery.poisson((32, 32), format="csr")
    aggregates, level, (rows, columns) = [], matrix, np.nonzero(np.ones((32, 32), dtype=bool))
    for _ in range(2):
        operator, rows, columns = blocks(level, rows, columns)
        aggregates.append(("predefined", {"AggOp": operator}))
        level = (operator.T @ level @ operator).tocsr()
    hierarchy = pyamg.smoothed_aggregation_solver(
        matrix, aggregate=aggregates, smooth=None, max_levels=3, max_coarse=1,
        improve_candidates=None, presmoother=("gauss_seidel", {"sweep": "forward"}),
        postsmoother=("gauss_seidel", {"sweep": "backward"}), coarse_solver="splu")
    _compressed_rows(hierarchy)   # (as the solver holds it: the sweeps take CSR only)
    assert len(hierarchy.levels) == 3
    residual = np.random.default_rng(2).standard_normal(32 * 32)
    np.testing.assert_allclose(VCycle(hierarchy) @ residual,
                               hierarchy.aspreconditioner(cycle="V") @ residual,
                               rtol=1e-12, atol=1e-12)
    # the algebraic hierarchy: pyAMG's default smoother, symmetric sweeps on either side
    conductance = np.random.default_rng(3).uniform(0.1, 10.0, matrix.nnz)
    varied = matrix.copy()
    varied.data *= conductance
    varied = (varied + varied.T).tocsr()
    algebraic = pyamg.smoothed_aggregation_solver(varied, max_coarse=10, coarse_solver="splu")
    _compressed_rows(algebraic)
    assert len(algebraic.levels) >= 3
    expected = algebraic.aspreconditioner(cycle="V") @ residual
    np.testing.assert_allclose(VCycle(algebraic, symmetric=True) @ residual, expected,
                               rtol=1e-12, atol=1e-12)
    assert not np.allclose(VCycle(algebraic) @ residual, expected, rtol=1e-6)


def test_a_path_goes_on_by_lu_after_a_slow_multigrid_solve(monkeypatch):
    """A gap whose neighbour's multigrid took DIRECT_SWITCH_ITERATIONS or more (or was itself
    solved by the LU) is solved by the LU, with the LU's aperture to rounding; below that, and
    on periodic gaps and above DIRECT_SWITCH_LIMIT cells, by the iteration."""
    import bem.leakage.flow
    import bem.leakage.flow_solver
    from bem.leakage.flow_solver import DIRECT_SWITCH_ITERATIONS, FlowStart

    gap = _random_gap(96, 3)
    direct, solved = bem.leakage.flow._flow_solution(gap, 1.0, "x", False)
    assert solved.iterations is None   # (96^2 is below DIRECT_SOLVE_LIMIT)
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SOLVE_LIMIT", 0)
    monkeypatch.setattr(bem.leakage.flow_solver, "COARSEST_LIMIT", 40 * 40)   # (two levels)
    previous = solved.pressure
    for iterations, switched in ((None, True), (DIRECT_SWITCH_ITERATIONS, True),
                                 (DIRECT_SWITCH_ITERATIONS - 1, False), (0, False)):
        aperture, now = bem.leakage.flow._flow_solution(gap, 1.0, "x", False,
                                                FlowStart(previous, iterations))
        assert (now.iterations is None) == switched
        assert aperture == pytest.approx(direct, rel=1e-12 if switched else 1e-6)
    # a periodic gap switches alike
    periodic = bem.leakage.flow._flow_solution(gap, 1.0, "x", True, FlowStart(previous, None))[1]
    assert periodic.iterations is None
    monkeypatch.setattr(bem.leakage.flow_solver, "DIRECT_SWITCH_LIMIT", gap.size - 1)
    large = bem.leakage.flow._flow_solution(gap, 1.0, "x", False, FlowStart(previous, None))[1]
    assert large.iterations is not None


def _random_systems(rng, shape, periodic):
    """(conductivity, spanning cells) of the first four random gaps of ``shape`` (about 30 %
    in contact) that leak, drawn one after the other (on a 2 x 5 grid most do not)."""
    systems = []
    for _ in range(100):
        gap = np.maximum(rng.standard_normal(shape) + 0.4, 0.0)
        k = (gap / gap.max()) ** 3
        cells = spanning_cells(k > 0, periodic=periodic)
        if cells.any():
            systems.append((k, cells))
        if len(systems) == 4:
            return systems
    raise AssertionError(f"fewer than four of 100 random {shape} gaps leak")


def _listed_faces(k, cells, periodic):
    """The open faces of the definition, one by one: (tail, head, conductance, drop) arrays of
    every pair of 4-neighbours in the system (the head after the tail along an axis, across the
    edges when periodic) with a positive harmonic-mean conductance, and the mean gradient's
    drop on the faces along axis 1 when periodic."""
    rows, columns = k.shape
    index = -np.ones(k.shape, dtype=int)
    index[cells] = np.arange(int(cells.sum()))
    listed = []
    for j in range(rows):
        for i in range(columns):
            for dj, di, drop in ((0, 1, 1.0 / columns if periodic else 0.0), (1, 0, 0.0)):
                jj, ii = j + dj, i + di
                if not periodic and (jj >= rows or ii >= columns):
                    continue
                jj, ii = jj % rows, ii % columns
                a, b = k[j, i], k[jj, ii]
                if index[j, i] >= 0 and index[jj, ii] >= 0 and a + b > 0 and 2 * a * b / (a + b) > 0:
                    listed.append((index[j, i], index[jj, ii], 2 * a * b / (a + b), drop))
    tail, head, t, drop = (np.array(column) for column in zip(*listed)) if listed else [np.empty(0)] * 4
    return tail.astype(int), head.astype(int), t, drop


@BOTH
@pytest.mark.parametrize("shape", [(2, 2), (2, 5), (3, 2), (9, 7), (40, 31)])
def test_the_dissipation_is_the_sum_over_the_listed_faces(periodic, shape):
    """The compiled walk over the grid (bem.leakage.flow_faces) sums T (p_tail - p_head + drop)^2
    over exactly the faces of the definition, and the Jacobi-scaled form is the same sum."""
    from bem.leakage.flow import _dissipation, _flow_system

    rng = np.random.default_rng(sum(shape) + 7)
    for k, cells in _random_systems(rng, shape, periodic):
        _, _, faces, boundary = _flow_system(k, cells, periodic)
        pressure = rng.standard_normal(int(cells.sum()))
        tail, head, t, drop = _listed_faces(k, cells, periodic)
        cell, t_edge, edge_pressure = boundary
        expected = (np.sum(t * (pressure[tail] - pressure[head] + drop) ** 2)
                    + np.sum(t_edge * (edge_pressure - pressure[cell]) ** 2))
        assert _dissipation(pressure, faces, boundary) == pytest.approx(expected, rel=1e-13)
        scale = rng.uniform(0.5, 2.0, pressure.size)
        assert _dissipation(pressure / scale, faces, boundary, scale) == pytest.approx(
            expected, rel=1e-13)


@BOTH
@pytest.mark.parametrize("shape", [(2, 2), (2, 5), (3, 2), (9, 7), (40, 31)])
def test_the_assembled_system_is_the_sum_of_its_faces(periodic, shape):
    """The system held by its faces, in compressed rows, equals the definition: one 2 x 2 block
    ``T [[1, -1], [-1, 1]]`` per open face and the boundary half-faces on the diagonal, summed
    from coordinate triplets (where a periodic side of two cells joins two cells twice)."""
    import scipy.sparse

    from bem.leakage.flow import _flow_system

    for k, cells in _random_systems(np.random.default_rng(sum(shape)), shape, periodic):
        matrix, _, faces, boundary = _flow_system(k, cells, periodic)
        n = int(cells.sum())
        tail, head, t, _ = _listed_faces(k, cells, periodic)
        expected = scipy.sparse.coo_array(
            (np.concatenate([t, t, -t, -t, boundary[1]]),
             (np.concatenate([tail, head, tail, head, boundary[0]]),
              np.concatenate([tail, head, head, tail, boundary[0]]))), shape=(n, n)).toarray()
        rows = matrix.tocsr()   # (the system is held by its faces, bem.leakage.face_matrix)
        assembled = rows.toarray()
        if periodic:   # one grounded cell per cluster: its diagonal doubled
            grounded = np.flatnonzero(~np.isclose(np.diag(assembled), np.diag(expected),
                                                  rtol=1e-12, atol=0.0))
            np.testing.assert_allclose(np.diag(assembled)[grounded],
                                       2 * np.diag(expected)[grounded], rtol=1e-12)
            np.fill_diagonal(assembled, np.diag(expected))
            assert grounded.size >= 1
        np.testing.assert_allclose(assembled, expected, rtol=1e-12, atol=1e-15)
        assert rows.has_canonical_format   # sorted columns, no duplicates
        assert np.all(np.diff(rows.indptr) <= 5)
