"""The finer reference: the refined sample is the same surface, a refined point carries the
finer solve and its band, and the runner refines where the band decides, recursively, up to the
scene's grid limit."""

import pathlib
from dataclasses import replace

import numpy as np
import pytest

import bem
from validation.run.finer_sample import refined_heights
from validation.run.refine import merge_points, solver_tolerance, unavailable
from validation.scenes.scene import SceneError
from validation.scenes.reader import load_scene, parse_scene
from validation.surfaces.families import surface_heights
from validation.surfaces.wm import wm_surface

WM = {"surface": {"D": 2.3, "rms_slope": 0.1, "n": 32},
      "realizations": {"count": 3, "seed": 7, "max": 6},
      "loads": {"min": 1e-4, "max": 1e-2, "count": 4},
      "models": {"use": ["gw", "bem"]}, "quantities": {"use": ["area", "load", "separation"]},
      # the finer reference refines the finite window's reference: gw is judged against it here
      "bem": {"max_grid": 128, "frames": ["finite"]}}


def one(scene):
    return scene.surface.at(scene.surface.sweep_values[0])


@pytest.mark.parametrize("factor", [2, 4])
def test_refined_wm_is_eq_11_at_the_finer_points(factor):
    s = one(parse_scene(WM))
    fine = refined_heights(s, 5, factor)
    assert fine.shape == (32 * factor,) * 2
    np.testing.assert_allclose(fine[::factor, ::factor], surface_heights(s, 5), rtol=0,
                               atol=1e-12)
    # independently: eq. (11) on the finer grid with the amplitude fixed on the scene grid,
    # differing from it by a constant (the mean of the finer sample)
    direct = wm_surface(32 * factor, D=2.3, rms_slope=0.1, seed=5, slope_grid=32)
    offset = fine - direct
    assert np.ptp(offset) < 1e-12


def test_refined_self_affine_keeps_its_spectrum_and_phases():
    quick = load_scene("self-affine").quick_version()
    s = one(replace(quick, sampling=(1,), surface=replace(quick.surface, hurst=(0.5,), n=32)))
    twice, four = refined_heights(s, 2, 2), refined_heights(s, 2, 4)
    np.testing.assert_allclose(twice[::2, ::2], surface_heights(s, 2), atol=1e-12)
    # the interpolated grid passes through the generator's own fine grid: one surface
    np.testing.assert_allclose(four[::2, ::2], twice, atol=1e-10 * np.std(twice))
    # and, on a periodic surface (no window), adds no wavevector beyond the band limit (the
    # scene grid's Nyquist wavevector)
    four = refined_heights(replace(s, window=1), 2, 4)
    spectrum = np.abs(np.fft.fft2(four - four.mean()))
    q = np.hypot(*np.meshgrid(np.fft.fftfreq(128), np.fft.fftfreq(128)))
    assert spectrum[q > 0.5 / 4 * 1.5].max() < 1e-3 * spectrum.max()


def test_bad_factors_are_refused():
    with pytest.raises(ValueError, match="factor"):
        refined_heights(one(parse_scene(WM)), 0, 3)
    # a grid limit at the scene's own grid refines nothing, in the full and the quick run alike
    full = load_scene("paper-wm-d205")
    at_limit = replace(full, bem=replace(full.bem, max_grid=512))
    assert unavailable(at_limit).startswith("the scene grid 512 is already at the limit")
    quick_limit = replace(full, quick=replace(full.quick, max_grid=256))
    assert unavailable(quick_limit.quick_version()).startswith("the scene grid 256 is already")
    # the paper scenes refine to 1024^2; their quick runs are not refined unless asked for
    assert unavailable(full) is None
    assert "[quick] max_grid" in unavailable(full.quick_version())
    scene = load_scene("paper-wm-d295")
    scene = replace(scene, quick=replace(scene.quick, max_grid=512)).quick_version()
    assert unavailable(scene) is None and scene.bem.max_grid == 512
    assert "max_grid" in unavailable(replace(scene, bem=replace(scene.bem, max_grid=None)))
    assert "separation" in unavailable(replace(scene, loads=replace(scene.loads,
                                                                     quantity="separation")))
    measured = load_scene(pathlib.Path(__file__).resolve().parents[1] / "examples"
                          / "example-topography.toml")
    # a measured map refines onto its interpolation once it sets a grid limit
    assert "max_grid" in unavailable(measured)
    assert unavailable(replace(measured, bem=replace(measured.bem, max_grid=128))) is None


@pytest.mark.parametrize("factor", [2, 4])
def test_a_measured_map_is_refined_onto_its_interpolation(factor):
    """Every factor-th point is the scan's own sample, and the finer grid adds no wavelength
    shorter than two pixels of the scan: the interpolation's spectrum beyond the scan's Nyquist
    wavevector is empty (the even extension has no edge jump to ring at)."""
    measured = load_scene(pathlib.Path(__file__).resolve().parents[1] / "examples"
                          / "example-topography.toml")
    base = surface_heights(measured.surface, 0)
    fine = refined_heights(measured.surface, 0, factor)
    assert fine.shape == tuple(factor * side for side in base.shape)
    np.testing.assert_allclose(fine[::factor, ::factor], base, atol=1e-12 * np.std(base))
    assert np.std(fine) == pytest.approx(np.std(base), rel=0.05)
    extended = np.concatenate((fine, fine[::-1]), axis=0)
    extended = np.concatenate((extended, extended[:, ::-1]), axis=1)
    power = np.abs(np.fft.fft2(extended))**2
    q = np.hypot(*np.meshgrid(np.fft.fftfreq(extended.shape[0]), np.fft.fftfreq(extended.shape[1]),
                              indexing="ij"))
    # beyond the scan's Nyquist (1/2 per scan pixel = 1/(2 factor) per fine pixel) along both
    # axes lies only what the fine grid's own mirror seam adds, orders of magnitude below
    assert power[q > 0.5 / factor * 1.5].sum() < 1e-3 * power.sum()


def test_scene_grid_limit_is_validated_and_quick_mode_refines_only_when_asked():
    assert parse_scene(WM).bem.max_grid == 128
    # quick mode leaves the finer reference to the full run: no grid limit, nothing refined
    assert parse_scene(WM).quick.max_grid is None
    assert parse_scene(WM).quick_version().bem.max_grid is None
    for name in ("paper-wm-d205", "paper-wm-d295", "validity-map", "self-affine"):
        scene = load_scene(name)
        assert scene.bem.max_grid is not None and scene.quick_version().bem.max_grid is None
    # [quick] max_grid is the quick run's limit, at least its grid (min(n, quick.n))
    asked = parse_scene(WM | {"quick": {"n": 16, "max_grid": 64}})
    assert asked.quick.max_grid == 64 and asked.quick_version().bem.max_grid == 64
    assert unavailable(asked.quick_version()) is None
    assert parse_scene(WM | {"quick": {"n": 64, "max_grid": 32}}).quick.max_grid == 32
    with pytest.raises(SceneError, match="quick.max_grid"):
        parse_scene(WM | {"quick": {"n": 16, "max_grid": 8}})
    with pytest.raises(SceneError, match="quick.max_grid"):
        parse_scene(WM | {"quick": {"max_grid": 1.5}}, source="s.toml")
    with pytest.raises(SceneError, match="max_grid"):
        parse_scene(WM | {"bem": {"max_grid": 16}})
    with pytest.raises(SceneError, match="bem.max_grid"):
        parse_scene(WM | {"bem": {"max_grid": 1.5}}, source="s.toml")


def test_solver_tolerance_follows_the_band():
    assert solver_tolerance(1e-3, 1e-8) == pytest.approx(1e-3 * 0.01 / 0.1)
    assert solver_tolerance(1.0, 1e-8) == 1e-4             # never looser than 1e-4
    assert solver_tolerance(1e-9, 1e-8) == 1e-8            # never tighter than the scene's
    assert solver_tolerance(float("nan"), 1e-8) == 1e-8


def test_merged_points_carry_the_finer_solve_and_its_band():
    z = wm_surface(32, D=2.3, rms_slope=0.1, seed=1)
    loads = np.array([1e-4, 1e-3, 1e-2])
    coarse = bem.contact_curve(z, 1 / 32, loads=loads, error_estimate=True)
    s = one(parse_scene(WM | {"realizations": {"count": 3, "seed": 1}}))
    finer = bem.contact_curve(refined_heights(s, 1, 2), 1 / 64, loads=loads[[0, 2]])
    merged = merge_points(coarse, np.array([0, 2]), finer, 64, 1 / 64, 32)
    assert merged.area[[0, 2]].tolist() == finer.area.tolist()
    assert merged.area[1] == coarse.area[1]
    assert merged.extras["grid"].tolist() == [64, 32, 64]
    expected = 2.0 * np.abs(finer.separation - coarse.separation[[0, 2]])
    np.testing.assert_allclose(merged.extras["separation_error"][[0, 2]], expected)
    assert merged.extras["separation_error"][1] == coarse.extras["separation_error"][1]


def test_runner_refines_where_the_band_decides_and_new_realizations_follow(tmp_path):
    from validation import run_scenes

    scene = parse_scene(WM, source="test")
    (result,) = run_scenes([scene], progress=False, cache_dir=str(tmp_path))
    record = result.refinement
    assert [level.grid for level in record.levels] == [64, 128]
    assert record.reason.startswith("grid limit reached")
    chosen = record.levels[-1].points[2.3]
    for r in result.realizations[2.3]:  # planned and added realizations alike
        grids = r.curves["bem"].extras["grid"]
        assert grids[list(chosen)].tolist() == [128] * len(chosen)
    assert len(result.realizations[2.3]) > 3
    (again,) = run_scenes([scene], progress=False, cache_dir=str(tmp_path))
    assert not [e for r in again.realizations[2.3] for e in r.computed if e.startswith("bem")]
    assert again.refinement == record


def test_leakage_is_solved_again_only_where_a_leakage_cell_is_held_by_the_band(tmp_path,
                                                                              monkeypatch):
    from validation import run_scenes
    from validation.judge import decide
    from validation.judge.decide import _apply
    from validation.run.refine import run_job
    from validation.run.sequential import RefinementLevel

    # on 32^2 the leakage band holds everywhere: the band of the leakage cells is taken as
    # deciding nothing here, the other cells' as computed
    decides = decide.band_decides

    def no_leakage_band(scene, results, confidence, reference="bem"):
        _, band, held = decides(scene, results, confidence, reference)
        held = {q: m for q, m in held.items() if q != "leakage"}
        return np.any(np.stack(list(held.values())), axis=0), band, held

    monkeypatch.setattr(decide, "band_decides", no_leakage_band)

    leaky = WM | {"quantities": {"use": ["area", "load", "separation", "leakage"]},
                  "realizations": {"count": 3, "seed": 7}}
    scene = parse_scene(leaky, source="test")
    plain = parse_scene(leaky | {"bem": {"max_grid": 32}}, source="test")
    (refined,) = run_scenes([scene], progress=False, cache_dir=str(tmp_path / "a"))
    (base,) = run_scenes([plain], progress=False, cache_dir=str(tmp_path / "b"))
    level = refined.refinement.levels[0]
    points = list(level.points[2.3])
    assert points and not level.leakage.get(2.3)
    for r, b in zip(refined.realizations[2.3], base.realizations[2.3]):
        curve, original = r.curves["bem"], b.curves["bem"]
        assert curve.extras["grid"][points].min() > 32
        assert not np.allclose(curve.area[points], original.area[points])
        # the leakage and its band stay those of the scene's grid
        np.testing.assert_array_equal(curve.leakage, original.leakage)
        np.testing.assert_array_equal(curve.extras["leakage_error"],
                                      original.extras["leakage_error"])
    # where a leakage cell is held, the leakage of that point (only) is the finer solve's
    by_value = {2.3: list(base.realizations[2.3])}
    forced = RefinementLevel(64, {2.3: (0, 1)}, {2.3: 1e-8}, {2.3: (1,)})
    _apply(by_value, forced, lambda jobs: [run_job(job, str(tmp_path / "b")) for job in jobs])
    for r, b in zip(by_value[2.3], base.realizations[2.3]):
        new, old = r.curves["bem"].leakage, b.curves["bem"].leakage
        assert new[0] == old[0] and new[1] != old[1] and new[2] == old[2]
        assert r.curves["bem"].area[0] != b.curves["bem"].area[0]


def test_leakage_is_not_solved_again_above_its_grid_limit(tmp_path, monkeypatch):
    """On grids finer than MAX_LEAKAGE_GRID a held leakage cell keeps the leakage and band of
    the grid below (a Reynolds solve there takes minutes and gigabytes)."""
    from validation import run_scenes
    from validation.judge import decide

    leaky = WM | {"quantities": {"use": ["area", "load", "separation", "leakage"]},
                  "realizations": {"count": 1, "seed": 7},
                  "bem": {"max_grid": 64, "frames": ["finite"]}}
    scene = parse_scene(leaky, source="test")
    (held,) = run_scenes([scene], progress=False, cache_dir=str(tmp_path))
    level = held.refinement.levels[0]
    assert level.grid == 64 and level.leakage.get(2.3)   # on 32^2 the leakage band holds
    monkeypatch.setattr(decide, "MAX_LEAKAGE_GRID", 32)
    (kept,) = run_scenes([scene], progress=False, cache_dir=str(tmp_path))
    level = kept.refinement.levels[0]
    assert level.grid == 64 and level.points == held.refinement.levels[0].points
    assert not level.leakage.get(2.3)
    curve = kept.realizations[2.3][0].curves["bem"]
    base = parse_scene(leaky | {"bem": {"max_grid": 32}}, source="test")
    (original,) = run_scenes([base], progress=False, cache_dir=str(tmp_path))
    np.testing.assert_array_equal(curve.leakage, original.realizations[2.3][0].curves["bem"].leakage)


def test_the_stiffness_is_solved_again_only_where_a_stiffness_cell_is_held(tmp_path):
    from validation import run_scenes
    from validation.judge.decide import _apply
    from validation.run.refine import run_job
    from validation.run.sequential import RefinementLevel

    stiff = WM | {"quantities": {"use": ["area", "load", "separation", "conductance"]},
                  "realizations": {"count": 3, "seed": 5}, "bem": {"max_grid": 32}}
    (base,) = run_scenes([parse_scene(stiff, source="test")], progress=False,
                         cache_dir=str(tmp_path))
    solve = lambda jobs: [run_job(job, str(tmp_path)) for job in jobs]  # noqa: E731
    skipped = {2.3: list(base.realizations[2.3])}
    _apply(skipped, RefinementLevel(64, {2.3: (0, 2)}, {2.3: 1e-8}, reference="bem",
                                    stiffness={2.3: ()}), solve)
    solved = {2.3: list(base.realizations[2.3])}
    _apply(solved, RefinementLevel(64, {2.3: (0, 2)}, {2.3: 1e-8}, reference="bem"), solve)
    for a, b, original in zip(skipped[2.3], solved[2.3], base.realizations[2.3]):
        kept, finer, coarse = a.curves["bem"], b.curves["bem"], original.curves["bem"]
        np.testing.assert_array_equal(kept.area, finer.area)   # the contact is refined alike
        assert kept.extras["grid"].tolist() == finer.extras["grid"].tolist()
        # the stiffness and its band stay those of the scene's grid where it was not solved
        np.testing.assert_array_equal(kept.conductance, coarse.conductance)
        np.testing.assert_array_equal(kept.extras["conductance_error"],
                                      coarse.extras["conductance_error"])
        assert not np.allclose(finer.conductance[[0, 2]], coarse.conductance[[0, 2]])
        assert finer.conductance[1] == coarse.conductance[1]
    # per point: solved again at point 2 only, the grid below's (and its band) at point 0
    one = {2.3: list(base.realizations[2.3])}
    _apply(one, RefinementLevel(64, {2.3: (0, 2)}, {2.3: 1e-8}, reference="bem",
                                stiffness={2.3: (2,)}), solve)
    for a, b, original in zip(one[2.3], solved[2.3], base.realizations[2.3]):
        mixed, finer, coarse = a.curves["bem"], b.curves["bem"], original.curves["bem"]
        np.testing.assert_array_equal(mixed.area, finer.area)
        for values in ((mixed.conductance, finer.conductance, coarse.conductance),
                       tuple(c.extras["conductance_error"] for c in (mixed, finer, coarse))):
            assert values[0][0] == values[2][0] and values[0][1] == values[2][1]
            assert values[0][2] == values[1][2]   # the same stiffness solve


def test_a_finer_grid_is_not_asked_where_the_reference_methods_own_bound_keeps_a_cell_open():
    from types import SimpleNamespace

    from validation.judge.decide import decidable

    # one surface, tolerance 0.2, the method's own bound 0.07: an error of 0.3 is decided
    # with that bound alone (fails), 0.22 and 0.15 are not (0.22 - 0.07 <= 0.2 < 0.22 + 0.07),
    # 0.1 holds; a point whose error is not known may be known on a finer grid
    errors = np.array([[0.3, 0.22, 0.15, 0.1, np.nan]])
    one = SimpleNamespace(one_surface=True, errors=errors, band=np.full(5, 0.3))
    assert decidable(one, np.full(5, 0.07), 0.2).tolist() == [True, False, False, True, True]
    assert decidable(one, np.zeros(5), 0.2).all()      # the window's reference: no bound


def _population(mean, half_width, band, verdicts, surface=None):
    """A population comparison at the one tolerance 0.2 (only what decidable reads)."""
    from types import SimpleNamespace

    from validation.judge.verdicts import ErrorInterval

    mean, half_width = np.asarray(mean, float), np.asarray(half_width, float)
    interval = ErrorInterval(mean, half_width, np.full(mean.shape, np.nan), np.full(mean.shape, 9))
    low_high = SimpleNamespace(low=surface[0], high=surface[1]) if surface else None
    return SimpleNamespace(one_surface=False, tolerances=(0.2,), interval=interval,
                           band=np.asarray(band, float), verdicts=(np.asarray(verdicts),),
                           surface=low_high,
                           surface_verdicts=(np.asarray(verdicts),) if surface else (),
                           sealing=None, sealing_resolved=None)


def test_a_population_cell_is_refined_only_where_a_finer_grid_could_decide_it():
    from validation.judge.decide import decidable

    # tolerance 0.2, band 0.1 of which the method's own bound is 0.07 (above 0.2 / 4: no grid
    # lets a cell hold), so a cell can only fail, and only where its interval widened by the
    # band reaches beyond 0.2 + 2 * 0.07 = 0.34: 0.3 +- (0.02 + 0.1) does, 0.15 does not,
    # -0.3 does; a bound within a quarter of the tolerance (0.04) lets a cell hold; an unknown
    # mean may be known after
    entry = _population([0.3, 0.15, -0.3, 0.15, np.nan], np.full(5, 0.02), np.full(5, 0.1),
                        ["undecided"] * 5)
    floor = np.array([0.07, 0.07, 0.07, 0.04, 0.07])
    assert decidable(entry, floor, 0.2).tolist() == [True, False, True, True, True]
    assert decidable(entry, np.zeros(5), 0.2).all()      # the window's reference: no bound
    # per surface: the tolerance interval decides alike; a reading already decided does not
    # count, and a point is refined where any open reading could be decided
    entry = _population([0.15, 0.15, 0.15], np.full(3, 0.02), np.full(3, 0.1),
                        ["undecided"] * 3, surface=(np.full(3, -0.1), np.array([0.3, 0.2, 0.3])))
    entry.verdicts = (np.array(["undecided", "undecided", "fails"]),)
    assert decidable(entry, np.full(3, 0.07), 0.2).tolist() == [True, False, True]
    # leakage: a disagreement about sealing the band leaves unresolved may be resolved finer
    entry.sealing, entry.sealing_resolved = np.array([0, 2, 0]), np.array([0, 1, 0])
    assert decidable(entry, np.full(3, 0.07), 0.2).tolist() == [True, True, True]


@pytest.mark.parametrize("seed", range(20))
def test_a_cell_a_finer_grid_cannot_decide_stays_undecided_on_any_grid(seed):
    """Independent of decidable's arithmetic: a cell it calls futile is undecided by the
    verdict rules themselves (classify, classify_per_surface) whatever the error against the
    exact-grid reference within the interval widened by the band, and with the band at the
    method's bound and no scatter left."""
    from validation.judge.decide import decidable
    from validation.judge.tolerance import SurfaceInterval, classify_per_surface
    from validation.judge.verdicts import ErrorInterval, classify

    rng = np.random.default_rng(seed)
    mean = rng.uniform(-0.6, 0.6, 200)
    half_width = rng.uniform(0.0, 0.1, 200)
    floor = rng.uniform(0.0, 0.15, 200)
    band = floor + rng.uniform(0.0, 0.1, 200)
    low, high = mean - 2 * half_width, mean + 2 * half_width
    entry = _population(mean, half_width, band, ["undecided"] * 200, surface=(low, high))
    futile = ~decidable(entry, floor, 0.2)
    assert 10 < futile.sum() < 190
    shift = band - floor
    for fraction in (-1.0, -0.5, 0.0, 0.5, 1.0):
        exact = mean + fraction * (half_width + shift)       # the mean once all is known
        verdict = classify(ErrorInterval(exact, np.zeros(200), np.zeros(200), np.full(200, 99)),
                           floor, 0.2)
        assert np.all(verdict[futile] == "undecided")
        top, bottom = high + fraction * shift, low + fraction * shift
        surface = SurfaceInterval(bottom, top, upper_tail=top, lower_tail=bottom)
        assert np.all(classify_per_surface(surface, floor, 0.2)[futile] == "undecided")


@pytest.mark.filterwarnings("ignore:scene 'scene' .* has 1 realization")
def test_a_finer_reference_starts_from_the_pressures_solved_one_grid_below(tmp_path,
                                                                          monkeypatch):
    """The scene grid's reference keeps its pressures (validation.run.starts); the finer path
    starts from them instead of solving its coarse problems again, and agrees with the path
    that solves them to the solver's tolerance."""
    import bem.contact.path
    import validation.run.starts
    from validation import run_scenes

    monkeypatch.setattr(validation.run.starts, "SMALLEST_KEPT_GRID", 64)
    scene = parse_scene(WM | {"surface": {"D": 2.3, "rms_slope": 0.1, "n": 64},
                              "realizations": {"count": 1, "seed": 7},
                              "bem": {"max_grid": 128, "frames": ["finite"]}}, source="test")
    coarse_solves = []
    original = bem.contact.path._coarse_start

    def spy(operator, *args, **kwargs):
        coarse_solves.append(operator.shape)
        return original(operator, *args, **kwargs)

    monkeypatch.setattr(bem.contact.path, "_coarse_start", spy)
    (kept,) = run_scenes([scene], progress=False, cache_dir=str(tmp_path / "kept"))
    assert kept.refinement.levels and (128, 128) not in coarse_solves
    assert list((tmp_path / "kept").glob("bem-starts-*.npz"))
    monkeypatch.setattr(validation.run.starts, "SMALLEST_KEPT_GRID", 10**6)
    (own,) = run_scenes([scene], progress=False, cache_dir=str(tmp_path / "own"))
    assert (128, 128) in coarse_solves
    assert not list((tmp_path / "own").glob("bem-starts-*.npz"))
    assert own.refinement.levels == kept.refinement.levels
    refined, solved = kept.realizations[2.3][0].curves["bem"], own.realizations[2.3][0].curves["bem"]
    np.testing.assert_array_equal(refined.extras["grid"], solved.extras["grid"])
    # the same contact sets; the separations within the solver's tolerance (8e-7 apart here)
    np.testing.assert_allclose(refined.area, solved.area, rtol=1e-9)
    np.testing.assert_allclose(refined.separation, solved.separation, rtol=1e-6)


def test_kept_pressures_come_back_by_position_and_a_malformed_entry_is_dropped(tmp_path):
    from validation.run.cache import Cache
    from validation.run.starts import KeptPressures, load_starts

    cache = Cache(tmp_path)
    rng = np.random.default_rng(0)
    fields = {k: np.where(rng.random((6, 4)) < 0.3, rng.random((6, 4)), 0.0) for k in (1, 4)}
    kept = KeptPressures()
    for k, field in fields.items():
        kept.add(k, field)
    kept.store(cache, "bem-starts-x")
    starts = load_starts(cache, "bem-starts-x", (4, 2, 1))
    assert sorted(starts) == [0, 2]
    np.testing.assert_array_equal(starts[0], fields[4])
    np.testing.assert_array_equal(starts[2], fields[1])
    cache.store("bem-starts-y", {"points": np.array([1]), "shape": np.array([6, 4]),
                                 "counts": np.array([5]), "index": np.arange(3),
                                 "pressure": np.ones(3)})
    assert load_starts(cache, "bem-starts-y", (1,)) == {}
    assert not cache.path("bem-starts-y").exists()
    KeptPressures().store(cache, "bem-starts-z")   # nothing kept: nothing written
    assert not cache.path("bem-starts-z").exists()


def test_a_refined_mirror_reference_keeps_the_methods_own_bound_in_its_band(tmp_path):
    """The interface reference of a map (the mirror method) carries the method's own bound
    (eq. T50) in its band at every point; at a refined point the band is the finer grid's
    estimate (T39) plus the bound of the finer value, with no bound of the grid below's taken
    out of a new estimate that never held one."""
    from bem.interface import mirror_error
    from validation import run_scenes
    from validation.judge.decide import _apply
    from validation.run.refine import run_job
    from validation.run.sequential import RefinementLevel

    mirror = WM | {"quantities": {"use": ["area", "load", "separation", "conductance"]},
                   "realizations": {"count": 2, "seed": 7},
                   "bem": {"max_grid": 32, "frames": ["interface"]}}
    (base,) = run_scenes([parse_scene(mirror, source="test")], progress=False,
                         cache_dir=str(tmp_path))
    by_value = {2.3: list(base.realizations[2.3])}
    _apply(by_value, RefinementLevel(64, {2.3: (0, 2)}, {2.3: 1e-8}, reference="bem_interface"),
           lambda jobs: [run_job(job, str(tmp_path)) for job in jobs])
    for refined, original in zip(by_value[2.3], base.realizations[2.3]):
        fine, coarse = refined.curves["bem_interface"], original.curves["bem_interface"]
        assert np.all(coarse.extras["extension"] == "mirror")
        for name in ("area", "conductance"):
            value, error = getattr(fine, name), fine.extras[f"{name}_error"]
            bound = mirror_error(name, fine.area_fraction) * np.abs(value)
            np.testing.assert_allclose(fine.extras[f"{name}_method_error"], bound, rtol=1e-12)
            # the points not refined keep theirs
            np.testing.assert_array_equal(error[[1, 3]], coarse.extras[f"{name}_error"][[1, 3]])
            assert np.all(error >= bound * (1 - 1e-12))
        estimate = 2.0 * np.abs(fine.conductance - coarse.conductance)[[0, 2]]
        np.testing.assert_allclose(fine.extras["conductance_error"][[0, 2]],
                                   estimate + mirror_error("conductance", fine.area_fraction[[0, 2]])
                                   * np.abs(fine.conductance[[0, 2]]), rtol=1e-12)
