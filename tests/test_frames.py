"""Two frames: each model judged against the reference of the problem it describes.

The interface reference (bem.InterfaceModel) against the periodic solution of periodic
surfaces, the nominal contact's reference (bem.NominalContactModel) against its closed form, the
registry's frames, the scene's references and the comparison's pairing (docs/theory.md 8.10).
"""

from __future__ import annotations

import argparse

import numpy as np
import pytest

import bem
from bem.interface import mirror_error, mirror_extension
from bem.reference import UNIFORM_SQUARE_MEAN_DEFLECTION
from validation.common import models
from validation.scenes.reader import parse_scene
from validation.surfaces.self_affine import self_affine_surface

N = 256
PRESSURES = np.geomspace(3e-4, 2e-2, 6)       # p / E*: about 0.5 % to 30 % contact


def test_the_mirror_extension_is_even_about_half_a_pixel_beyond_each_edge():
    z = np.arange(12.0).reshape(3, 4)
    extended = mirror_extension(z)
    assert extended.shape == (6, 8)
    np.testing.assert_array_equal(extended[:3, :4], z)
    np.testing.assert_array_equal(extended, extended[::-1, :])
    np.testing.assert_array_equal(extended, extended[:, ::-1])
    with pytest.raises(ValueError, match="heights"):
        mirror_extension(np.zeros(4))


@pytest.fixture(scope="module")
def periodic_solutions():
    """Two periodic self-affine surfaces solved as they are, and by the mirror method."""
    out = []
    for seed in range(2):
        z = self_affine_surface(N, hurst=0.8, rms_slope=0.1, rolloff=0.25, seed=seed)
        loads = PRESSURES * 1.0
        exact = bem.InterfaceModel(z, 1.0 / N, extension="periodic", tol=1e-8).at_load(
            loads, quantities=("area", "stiffness"))
        # what a scan (a map not known to be periodic) gets: the registry's interface
        inputs = models.ModelInputs(spacing=1.0 / N, nominal_area=1.0, heights=z,
                                    bem_options=dict(tol=1e-8, error_estimate=True))
        mirror = models.build("bem_interface", inputs).at_load(
            loads, quantities=("area", "stiffness"))
        window = bem.BoundaryElementModel(z, 1.0 / N, tol=1e-8).at_load(
            loads, quantities=("area", "stiffness"))
        out.append((z, exact, mirror, window))
    return out


def test_the_periodic_extension_is_the_periodic_half_space_itself(periodic_solutions):
    z, exact, _, _ = periodic_solutions[0]
    direct = bem.contact_curve(z, 1.0 / N, loads=PRESSURES, periodic=True, tol=1e-8,
                               quantities=("area", "stiffness"))
    np.testing.assert_allclose(exact.area, direct.area, rtol=1e-12)
    np.testing.assert_allclose(exact.stiffness, direct.stiffness, rtol=1e-12)
    # zero mean displacement: the interface's separation is its mean gap
    np.testing.assert_allclose(exact.separation, exact.extras["mean_gap"], rtol=1e-6)


def test_the_interface_of_a_scan_agrees_with_the_periodic_solution(periodic_solutions):
    """The check's default reference (the mirror method on a map not known to be periodic)
    against the periodic BEM of the same periodic surfaces, at 0.5-30 % contact: area within
    5 %, mean gap within 0.1 rms height, stiffness per unit area within 20 %; the finite
    window misses the stiffness by far more (its bulk compliance)."""
    for z, exact, mirror, window in periodic_solutions:
        inside = (exact.area_fraction >= 0.005) & (exact.area_fraction <= 0.30)
        assert inside.sum() >= 4
        rms = float(np.std(z))
        area = mirror.area_fraction / exact.area_fraction - 1.0
        gap = (np.asarray(mirror.extras["mean_gap"]) - exact.extras["mean_gap"]) / rms
        stiffness = (mirror.stiffness / mirror.nominal_area) / exact.stiffness - 1.0
        assert np.all(np.abs(area[inside]) <= 0.05)
        assert np.all(np.abs(gap[inside]) <= 0.1)
        assert np.all(np.abs(stiffness[inside]) <= 0.2)
        assert np.all(mirror.extras["extension"] == "mirror")
        window_stiffness = window.stiffness / exact.stiffness - 1.0
        assert np.max(np.abs(window_stiffness[inside])) > 0.5


def test_the_band_of_the_mirror_method_holds_its_own_error(periodic_solutions):
    for z, exact, mirror, _ in periodic_solutions:
        rms = float(np.std(z))
        fraction = mirror.area_fraction
        np.testing.assert_array_less(mirror_error("separation", fraction) * rms - 1e-15,
                                     mirror.extras["separation_error"])
        np.testing.assert_array_less(mirror_error("area", fraction) * mirror.area - 1e-15,
                                     mirror.extras["area_error"] + 1e-300)
        inside = (exact.area_fraction >= 0.005) & (exact.area_fraction <= 0.30)
        assert np.all(np.abs(mirror.area - exact.area)[inside]
                      <= mirror.extras["area_error"][inside])
        assert np.all(np.abs(np.asarray(mirror.extras["mean_gap"]) - exact.extras["mean_gap"])
                      [inside] <= mirror.extras["mean_gap_error"][inside])


def test_the_nominal_contact_adds_the_sink_of_its_square_and_its_compliance_in_series():
    z = self_affine_surface(64, hurst=0.8, rms_slope=0.1, seed=4)
    loads, side = np.array([1e-3, 1e-2]), 5.0
    interface = bem.InterfaceModel(z, 1 / 64).at_load(loads, quantities=("area", "stiffness"))
    nominal = bem.NominalContactModel(z, 1 / 64, nominal_size=side).at_load(
        loads, quantities=("area", "stiffness"))
    m = UNIFORM_SQUARE_MEAN_DEFLECTION
    np.testing.assert_allclose(nominal.separation, interface.separation - m * loads * side,
                               rtol=1e-12)
    np.testing.assert_allclose(nominal.extras["mean_gap"], interface.extras["mean_gap"])
    np.testing.assert_allclose(1.0 / nominal.stiffness, 1.0 / interface.stiffness + m * side,
                               rtol=1e-12)
    np.testing.assert_array_equal(nominal.area, interface.area)
    with pytest.raises(ValueError, match="nominal_size"):
        bem.NominalContactModel(z, 1 / 64, nominal_size=0.5)
    with pytest.raises(TypeError, match="periodic"):
        bem.InterfaceModel(z, 1 / 64, periodic=False)
    with pytest.raises(ValueError, match="extension"):
        bem.InterfaceModel(z, 1 / 64, extension="zero")


def test_each_model_declares_the_frame_of_the_problem_it_describes():
    interface = {"gw", "discrete_no_interaction", "persson", "gw_spectral", "bgt",
                 "bem_interface"}
    finite = {"improved_gw", "improved_gw_one_iteration", "discrete", "improved_gw_spectral",
              "bem", "bem_nominal"}
    assert {n for n in models.names() if models.frame_of(n) == "interface"} >= interface
    assert {n for n in models.names() if models.frame_of(n) == "finite"} >= finite
    assert models.reference_for("interface") == "bem_interface"
    assert models.reference_for("finite") == "bem"
    assert models.reference_among(["gw", "bem", "bem_interface"]) == "bem"
    assert models.reference_among(["gw", "bem", "bem_interface"], "interface") == "bem_interface"
    with pytest.raises(ValueError, match="frame"):
        models.reference_for("window")
    with pytest.raises(ValueError, match="frame"):
        models.register("x_frame", lambda inputs: None, label="x", frame="half-space")


SCENE = {"surface": {"D": 2.3, "rms_slope": 0.1, "n": 32},
         "realizations": {"count": 2, "seed": 1},
         "loads": {"min": 1e-4, "max": 1e-2, "count": 3},
         "quantities": {"use": ["area", "load", "separation"]}}


def test_a_scene_computes_the_reference_of_every_frame_its_models_need():
    both = parse_scene(SCENE | {"models": {"use": ["gw", "improved_gw", "bem"]}})
    assert set(both.models) == {"gw", "improved_gw", "bem", "bem_interface"}
    assert both.frames == ("interface", "finite")
    interface = parse_scene(SCENE | {"models": {"use": ["gw", "bem_interface"]}})
    assert set(interface.models) == {"gw", "bem_interface"}
    chosen = parse_scene(SCENE | {"models": {"use": ["gw", "improved_gw", "bem"]},
                                  "bem": {"frames": ["interface"]}})
    assert set(chosen.models) == {"gw", "improved_gw", "bem_interface"}
    nominal = parse_scene(SCENE | {"models": {"use": ["gw", "improved_gw", "bem"],
                                              "nominal_size": 10.0}})
    assert set(nominal.models) == {"gw", "improved_gw", "bem_nominal", "bem_interface"}
    with pytest.raises(ValueError, match="frames"):
        parse_scene(SCENE | {"bem": {"frames": ["window"]}})
    with pytest.raises(ValueError, match="nominal_size"):
        parse_scene(SCENE | {"models": {"use": ["gw", "bem"], "nominal_size": -1.0}})


def test_each_model_is_judged_against_the_reference_of_its_frame():
    from validation import run_scenes
    from validation.judge.compare import compare_realizations
    from validation.judge.errors import pairwise_errors

    scene = parse_scene(SCENE | {"models": {"use": ["gw", "improved_gw", "bem"]}})
    (result,) = run_scenes([scene], progress=False)
    realizations = result.realizations[2.3]
    comparison = compare_realizations(realizations)
    assert comparison.models[("gw", "area")].frame == "interface"
    assert comparison.models[("improved_gw", "area")].reference_model == "bem"
    expected = pairwise_errors(realizations, "gw", "bem_interface", ("separation",))
    np.testing.assert_allclose(comparison.models[("gw", "separation")].errors,
                               expected["separation"])
    np.testing.assert_allclose(comparison.paths_of("interface"),
                               [r.curves["bem_interface"].area_fraction for r in realizations])
    # a scene that computes the finite frame only judges every model there, and says so
    finite = parse_scene(SCENE | {"models": {"use": ["gw", "bem"]},
                                  "bem": {"frames": ["finite"]}})
    (only,) = run_scenes([finite], progress=False)
    entry = compare_realizations(only.realizations[2.3]).models[("gw", "area")]
    assert entry.frame == "finite" and entry.reference_model == "bem"


def _check_args(scan, **options):
    base = dict(scan=str(scan), e_star=None, pressure=None, short_cutoff=None, fill=None,
                physical_size=None, file_unit=None, tiles=1, resample=None, nominal_size=None)
    return argparse.Namespace(**(base | options))


def test_the_check_answers_in_the_interface_frame_and_adds_the_nominal_contact(tmp_path):
    from validation.check.command import check_request
    from validation.check.request import scene_text

    scan = tmp_path / "scan.npy"
    np.save(scan, self_affine_surface(64, hurst=0.8, rms_slope=0.1, seed=2))
    plain = check_request(_check_args(scan, physical_size="64um", file_unit="nm"))
    assert plain.nominal_size is None
    text = scene_text(plain, "check-scan")
    scene = parse_scene(__import__("tomllib").loads(text))
    assert "bem_interface" in scene.models and "bem" not in scene.models
    assert not {"improved_gw", "discrete"} & set(scene.models)
    sized = check_request(_check_args(scan, physical_size="64um", file_unit="nm", nominal_size="10mm"))
    assert sized.nominal_size == pytest.approx(1e-2)
    scene = parse_scene(__import__("tomllib").loads(scene_text(sized, "check-scan")))
    assert {"improved_gw", "bem_nominal", "bem_interface"} <= set(scene.models)
    # improved GW's uniform term is the square's, with the reference's m
    assert scene.m == pytest.approx(UNIFORM_SQUARE_MEAN_DEFLECTION, rel=1e-6)
    from validation.surfaces.units import LENGTH_UNITS

    # in the scene's length unit (the answer's: nm for these heights)
    assert scene.nominal_size == pytest.approx(1e-2 / LENGTH_UNITS[scene.surface.unit])
    for bad, match in (("10", "needs a unit"), ("-1mm", "--nominal-size"),
                       ("10um", "at least the scan's longer side")):
        with pytest.raises(ValueError, match=match):
            check_request(_check_args(scan, physical_size="64um", file_unit="nm", nominal_size=bad))


def test_the_leakage_of_the_mirror_extension_is_the_maps_own_non_periodic_flow():
    """By symmetry the periodic Reynolds flow of the even extension equals the map's
    non-periodic flow through its quarter of the gap, which the interface model solves."""
    z = self_affine_surface(64, hurst=0.8, rms_slope=0.1, rolloff=0.25, window=128, seed=1)
    loads = np.array([3e-3, 1e-2])
    interface = bem.InterfaceModel(z, 1 / 64, tol=1e-10).at_load(loads, quantities=("leakage",))
    whole = bem.contact_curve(mirror_extension(z), 1 / 64, loads=4 * loads, periodic=True,
                              tol=1e-10, quantities=("leakage",))
    assert np.all(whole.leakage > 0)
    np.testing.assert_allclose(interface.leakage, whole.leakage, rtol=1e-8)


def test_the_interface_reference_is_refined_where_its_band_decides_keeping_its_method_bound(
        tmp_path):
    """A finer grid narrows the interface's discretisation band, not the mirror method's own
    bound (T50), which stays in the band of every refined point."""
    from validation import run_scenes

    scene = parse_scene(SCENE | {"models": {"use": ["gw", "bem_interface"]},
                                 "realizations": {"count": 1, "seed": 7},
                                 "bem": {"max_grid": 64}})
    (result,) = run_scenes([scene], progress=False, cache_dir=str(tmp_path))
    levels = result.refinement.levels
    assert levels and {level.reference for level in levels} == {"bem_interface"}
    curve = result.realizations[2.3][0].curves["bem_interface"]
    refined = np.flatnonzero(np.asarray(curve.extras["grid"]) == 64)
    assert refined.size
    np.testing.assert_allclose(curve.extras["area_method_error"][refined],
                               mirror_error("area", curve.area_fraction[refined])
                               * curve.area[refined])
    assert np.all(curve.extras["area_error"][refined]
                  >= curve.extras["area_method_error"][refined])
    # the finer solve is the interface's: the periodic mirror extension of the 64^2 sample
    from validation.run.finer_sample import refined_heights

    fine = refined_heights(scene.surface.at(2.3), 7, 2)
    loads = np.array(scene.loads.values())[refined]
    direct = bem.InterfaceModel(fine, 1 / 64, tol=1e-8).at_load(loads, quantities=("area",))
    # the finer solve ran at the looser tolerance its band allows (T40), not at 1e-8
    np.testing.assert_allclose(curve.area[refined], direct.area, rtol=1e-3)


def test_the_mirror_operator_is_the_periodic_operator_of_the_extension_on_its_quadrant():
    rng = np.random.default_rng(2)
    pressure = rng.random((12, 10))
    quadrant = bem.HalfSpace((12, 10), 0.3, e_star=2.0, periodic=True, mirror=True)
    whole = bem.HalfSpace((24, 20), 0.3, e_star=2.0, periodic=True)
    np.testing.assert_allclose(quadrant.displacement(pressure),
                               whole.displacement(mirror_extension(pressure))[:12, :10],
                               rtol=1e-12, atol=1e-15)
    assert not quadrant.wraps and whole.wraps
    assert quadrant.coarse().mirror
    with pytest.raises(ValueError, match="mirror"):
        bem.HalfSpace((12, 10), 0.3, mirror=True)


def test_a_mirror_path_is_the_extensions_periodic_path_per_copy():
    """The quadrant's path (cosine transforms) against the solve of the whole extension: the
    same contact problem, so separation, mean gap, stiffness and h_eff agree to the solvers'
    tolerance, and the contact pixels (the area) exactly."""
    z = self_affine_surface(64, hurst=0.8, rms_slope=0.1, rolloff=0.25, window=128, seed=3)
    loads = np.geomspace(2e-4, 2e-2, 5)
    quantities = ("area", "stiffness", "leakage")
    quadrant = bem.contact_curve(z, 1 / 64, loads=loads, periodic=True, mirror=True,
                                 tol=1e-11, quantities=quantities)
    whole = bem.contact_curve(mirror_extension(z), 1 / 64, loads=4 * loads, periodic=True,
                              tol=1e-11, quantities=quantities)
    np.testing.assert_allclose(quadrant.separation, whole.separation, rtol=1e-9)
    np.testing.assert_allclose(quadrant.extras["mean_gap"], whole.extras["mean_gap"], rtol=1e-9)
    np.testing.assert_allclose(quadrant.stiffness, whole.stiffness / 4, rtol=1e-9)
    np.testing.assert_allclose(quadrant.leakage, whole.leakage, rtol=1e-8)
    np.testing.assert_array_equal(quadrant.area, whole.area / 4)
    with pytest.raises(ValueError, match="mirror"):
        bem.contact_curve(z, 1 / 64, loads=loads, mirror=True)


def test_the_local_interaction_is_the_pairwise_one_without_the_windows_uniform_part():
    """One summit: no pair, so the local model is the independent summit raised back by the
    uniform term m W / (E* sqrt(A)); many summits: between the full interaction and none."""
    import asperity
    from validation.surfaces.wm import wm_surface

    one = asperity.Summits.from_points([0.5], [0.5], [1e-3], [0.05], area=4.0)
    loads = np.array([1e-4, 1e-3])
    alone = asperity.DiscreteAsperityModel(one, e_star=2.0, interaction=False).at_load(loads)
    local = asperity.DiscreteAsperityModel(one, e_star=2.0, local=True).at_load(loads)
    np.testing.assert_allclose(local.separation - alone.separation,
                               UNIFORM_SQUARE_MEAN_DEFLECTION * loads / (2.0 * 2.0), rtol=1e-9)
    summits = asperity.find_summits(wm_surface(64, D=2.3, rms_slope=0.1, seed=3), 1 / 64)
    loads = np.geomspace(1e-4, 1e-2, 4)
    d = {name: asperity.DiscreteAsperityModel(summits, **options).at_load(loads).separation
         for name, options in (("full", {}), ("local", {"local": True}),
                               ("none", {"interaction": False}))}
    assert np.all(d["full"] <= d["local"] + 1e-12) and np.all(d["local"] <= d["none"] + 1e-12)
    assert models.frame_of("discrete_local") == "interface"
    with pytest.raises(ValueError, match="local"):
        asperity.DiscreteAsperityModel(summits, interaction=False, local=True)
