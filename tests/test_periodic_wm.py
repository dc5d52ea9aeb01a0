"""The periodic WM surface (docs/theory.md eq. T52): the generator and a scene's path with it."""

from dataclasses import replace

import numpy as np
import pytest

from validation import run_scenes, surface_statistics, wm_surface
from validation.common.checks import SceneError
from validation.run.finer_sample import refined_heights
from validation.scenes.reader import load_scene, parse_scene
from validation.surfaces.families import surface_heights, surface_identity
from validation.surfaces.spec import SurfaceSpec
from validation.surfaces.wm import wm_amplitude, wm_lattice


def _fft_lines(heights):
    """Grid indices (row ky, column kx) of the FFT modes with power above rounding."""
    spectrum = np.abs(np.fft.fft2(heights))
    return {tuple(map(int, k)) for k in np.argwhere(spectrum > 1e-9 * spectrum.max())}


def test_the_lattice_is_the_nearest_lattice_point_of_each_term():
    lattice = wm_lattice(gamma=1.5, M=10, n_max=8)
    assert lattice.shape == (10, 9, 2) and lattice.dtype.kind == "i"
    angles = np.pi * np.arange(1, 11) / 10
    exact = np.stack((np.cos(angles)[:, None] * 1.5 ** np.arange(9),
                      np.sin(angles)[:, None] * 1.5 ** np.arange(9)), axis=-1)
    assert np.all(np.abs(lattice - exact) <= 0.5)
    assert np.all(np.any(lattice != 0, axis=-1))         # no term on (0, 0)
    # the longest waves: ten directions on five lattice vectors; the shortest ones hardly move
    assert {tuple(v) for v in lattice[:, 0]} == {(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0)}
    assert np.max(np.hypot(*(lattice[:, 8] - exact[:, 8]).T)) / 1.5**8 < 0.02
    np.testing.assert_array_equal(wm_lattice(gamma=2.0, M=1, n_max=3)[0],
                                  [[-1, 0], [-2, 0], [-4, 0], [-8, 0]])


def test_a_periodic_wm_surface_wraps_onto_itself():
    one = wm_surface(64, D=2.4, G=1e-4, seed=3, periodic=True)
    two = wm_surface(128, D=2.4, G=1e-4, seed=3, periodic=True, side=2.0)  # two periods
    for rows in (slice(0, 64), slice(64, 128)):
        for columns in (slice(0, 64), slice(64, 128)):
            np.testing.assert_allclose(two[rows, columns], one, rtol=0,
                                       atol=1e-12 * np.abs(one).max())
    # eq. (11) itself does not
    plain = wm_surface(128, D=2.4, G=1e-4, seed=3, side=2.0)
    assert np.max(np.abs(plain[:64, :64] - plain[:64, 64:])) > 0.1 * np.std(plain)


def test_its_spectrum_has_power_only_on_the_lattice_vectors_it_lists():
    n, M, n_max = 64, 10, 8                   # every |i|, |j| <= 26 < n / 2: no aliasing
    heights = wm_surface(n, D=2.5, G=1e-3, seed=5, M=M, n_max=n_max, periodic=True)
    lattice = wm_lattice(M=M, n_max=n_max).reshape(-1, 2)
    listed = {(int(j) % n, int(i) % n) for i, j in lattice} | {
        (-int(j) % n, -int(i) % n) for i, j in lattice}
    assert _fft_lines(heights) <= listed
    assert len(_fft_lines(heights)) >= 0.9 * len(listed)  # (a mode may cancel by chance)
    # eq. (11) leaks everywhere
    assert len(_fft_lines(wm_surface(n, D=2.5, G=1e-3, seed=5))) > n * n // 2


def test_each_lattice_mode_carries_the_amplitudes_and_phases_of_its_terms():
    """FFT of z = B sum_t w_t [cos phi_t - cos(k_t.x + phi_t)] at the lattice vector q:
    -(n^2 / 2) B (sum over k_t = q of w_t e^{i phi_t} + sum over k_t = -q of w_t e^{-i phi_t})."""
    n, D, G, M, n_max = 64, 2.3, 1e-3, 4, 5
    phases = np.random.default_rng(1).uniform(0, 2 * np.pi, (M, n_max + 1))
    heights = wm_surface(n, D=D, G=G, M=M, n_max=n_max, phases=phases, periodic=True)
    spectrum = np.fft.fft2(heights)
    B = wm_amplitude(G, D=D, M=M)
    weights = 1.5 ** ((D - 3) * np.arange(n_max + 1))
    lattice = wm_lattice(M=M, n_max=n_max)
    expected = {}
    for m in range(M):
        for k in range(n_max + 1):
            i, j = (int(v) for v in lattice[m, k])
            term = weights[k] * np.exp(1j * phases[m, k])
            expected[(j % n, i % n)] = expected.get((j % n, i % n), 0) + term
            expected[(-j % n, -i % n)] = expected.get((-j % n, -i % n), 0) + np.conj(term)
    for (row, column), value in expected.items():
        np.testing.assert_allclose(spectrum[row, column], -n * n / 2 * B * value,
                                   atol=1e-9 * np.abs(spectrum).max())
    assert M * (n_max + 1) == lattice.shape[0] * lattice.shape[1]   # every term kept


def test_its_amplitude_by_rms_slope_and_its_seeds():
    heights = wm_surface(128, D=2.05, rms_slope=0.1, seed=7, periodic=True)
    assert surface_statistics(heights, 1 / 128, periodic=True).rms_gradient == \
        pytest.approx(0.1, rel=1e-12)
    assert abs(heights.mean()) < 1e-15
    np.testing.assert_array_equal(heights, wm_surface(128, D=2.05, rms_slope=0.1, seed=7,
                                                      periodic=True))
    assert not np.allclose(heights, wm_surface(128, D=2.05, rms_slope=0.1, seed=8,
                                               periodic=True))
    # the same phases as eq. (11) for the same seed, only the wave vectors moved: a fine grid
    # and its every-second sample are one surface (the finer reference's sample)
    fine = wm_surface(256, D=2.05, rms_slope=0.1, seed=7, periodic=True, slope_grid=128)
    np.testing.assert_allclose(fine[::2, ::2] - fine[::2, ::2].mean(), heights,
                               atol=1e-12 * np.abs(heights).max())


@pytest.mark.parametrize("periodic", [1, "yes", None])
def test_a_periodic_flag_that_is_not_a_bool_is_refused(periodic):
    with pytest.raises(TypeError, match="periodic"):
        wm_surface(32, D=2.5, rms_slope=0.1, seed=0, periodic=periodic)


@pytest.mark.parametrize("kwargs, match", [(dict(gamma=1.0), "gamma"), (dict(M=0), "M"),
                                           (dict(n_max=-1), "n_max")])
def test_bad_lattice_arguments_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        wm_lattice(**kwargs)


# --- the scene path --------------------------------------------------------------------------

TINY = {
    "name": "tiny-periodic",
    "surface": {"D": 2.3, "rms_slope": 0.1, "n": 32, "periodic": True},
    "realizations": {"count": 1, "seed": 4},
    "loads": {"min": 1e-3, "max": 1e-2, "count": 3},
    "models": {"use": ["gw", "improved_gw", "bem"]},
    "quantities": {"use": ["area", "load", "separation"]},
    # with the reference band: the mirror method would add its bound to it (*_method_error)
    "bem": {"tol": 1e-8, "reference_error": True},
}


def test_a_periodic_wm_scene_solves_the_interface_on_the_period_itself(tmp_path):
    scene = parse_scene(TINY, source="test")
    assert scene.surface.periodic and scene.surface.one_period and not scene.bem.periodic
    assert {"bem", "bem_interface"} <= set(scene.models)
    (result,) = run_scenes([scene], cache_dir=str(tmp_path), progress=False)
    (realization,) = result.realizations[2.3]
    heights = surface_heights(scene.surface.at(2.3), 4)
    np.testing.assert_array_equal(
        heights, wm_surface(32, D=2.3, rms_slope=0.1, seed=4, periodic=True))
    interface = realization.curves["bem_interface"]
    assert np.all(np.asarray(interface.extras["extension"]) == "periodic")
    assert "area_error" in interface.extras      # the band: the discretisation's alone
    assert not [key for key in interface.extras if key.endswith("_method_error")]
    # the finite frame: the same map pressed as a whole (the non-periodic BEM)
    import bem
    finite = bem.BoundaryElementModel(heights, 1 / 32, e_star=1.0, periodic=False, tol=1e-8)
    direct = finite.at_load(realization.curves["bem"].load, quantities=("area",))
    np.testing.assert_allclose(realization.curves["bem"].area, direct.area, rtol=1e-9)
    periodic = bem.InterfaceModel(heights, 1 / 32, e_star=1.0, extension="periodic", tol=1e-8)
    np.testing.assert_allclose(interface.area, periodic.at_load(
        interface.load, quantities=("area",)).area, rtol=1e-9)
    # the summit models see the same map: GW's sigma is that of its summits
    import asperity
    summits = asperity.find_summits(heights, 1 / 32)
    assert realization.sigma == pytest.approx(float(np.std(summits.height)), rel=1e-12)


def test_the_same_scene_without_periodic_keeps_the_mirror_method(tmp_path):
    data = {k: (dict(v) if isinstance(v, dict) else v) for k, v in TINY.items()}
    del data["surface"]["periodic"]
    scene = parse_scene(data, source="test")
    assert not scene.surface.one_period
    (result,) = run_scenes([scene], cache_dir=str(tmp_path), progress=False)
    interface = result.realizations[2.3][0].curves["bem_interface"]
    assert np.all(np.asarray(interface.extras["extension"]) == "mirror")
    assert "area_method_error" in interface.extras


def test_periodic_is_in_the_cache_identity_and_the_finer_sample():
    spec = SurfaceSpec(D=(2.3,), n=32, periodic=True)
    assert surface_identity(spec, 1)["periodic"] is True
    assert "periodic" not in surface_identity(replace(spec, periodic=False), 1)
    fine = refined_heights(spec, 1, 2)
    np.testing.assert_allclose(fine[::2, ::2], surface_heights(spec, 1), atol=1e-14)
    # the finer sample is periodic too: its FFT has no power off the lattice
    assert {(r % 64, c % 64) for r, c in _fft_lines(fine)} <= {
        (j % 64, i % 64) for i, j in np.concatenate(
            (wm_lattice().reshape(-1, 2), -wm_lattice().reshape(-1, 2)))}


def _surface_error(surface: dict) -> str:
    data = dict(TINY, surface=surface)
    with pytest.raises(SceneError) as error:
        parse_scene(data, source="test")
    return str(error.value)


def test_the_scene_reader_refuses_periodic_where_it_cannot_hold():
    message = _surface_error({"family": "self-affine", "hurst": 0.8, "rms_slope": 0.1,
                              "n": 32, "periodic": True})
    assert "surface.periodic" in message and "window = 1" in message
    message = _surface_error({"D": 2.3, "rms_slope": 0.1, "n": 32, "periodic": True,
                              "sides": [1.0, 2.0]})
    assert "surface.periodic" in message and "nested windows" in message
    message = _surface_error({"D": 2.3, "rms_slope": 0.1, "n": 32, "periodic": True,
                              "wavelength": 2.0})
    assert "surface.periodic" in message and "wavelength" in message
    message = _surface_error({"D": 2.3, "rms_slope": 0.1, "n": 32, "periodic": "yes"})
    assert "surface.periodic" in message and "boolean" in message
    with pytest.raises(SceneError, match="window = 1"):
        SurfaceSpec(family="self-affine", hurst=(0.8,), periodic=True)
    # a wavelength equal to the period is the same surface
    assert SurfaceSpec(D=(2.3,), periodic=True, wavelength=1.0).one_period


def test_the_built_in_wm_scenes_are_periodic_where_they_can_be():
    for name in ("paper-wm-d205", "paper-wm-d295", "validity-map", "self-affine"):
        scene = load_scene(name)
        assert scene.surface.one_period, name
        assert "periodic" in scene.description, name
    sealing = load_scene("sealing-size")
    assert sealing.surface.sides and not sealing.surface.one_period
