"""The short-wavelength cutoff of a measured map (validation.surfaces.cutoff): what it removes
and keeps, on sinusoids (exactly, and in the interior for any phase), planes, white noise and a
window of a larger surface, and its argument checks; read_topography's ``short_cutoff``."""

import numpy as np
import pytest

import validation
from validation.surfaces.cutoff import short_wavelength_cutoff
from validation.surfaces.self_affine import self_affine_surface
from validation.surfaces.topography import read_topography, write_gwyddion_ascii


def mirror_mode(shape, k, l):
    """cos(q_y (j + 1/2)) cos(q_x (i + 1/2)), q = pi k / N, pi l / M: a cosine of the map's
    mirror extension (zero slope at the edges), wavelength 2 / sqrt((k/N)^2 + (l/M)^2) pixels."""
    rows, columns = shape
    j, i = np.indices(shape, dtype=float)
    return np.cos(np.pi * k * (j + 0.5) / rows) * np.cos(np.pi * l * (i + 0.5) / columns)


def sinusoid(shape, wavelength, angle=0.3, phase=1.1):
    j, i = np.indices(shape, dtype=float)
    return np.cos(2 * np.pi * (i * np.cos(angle) + j * np.sin(angle)) / wavelength + phase)


def test_mirror_modes_shorter_than_the_cutoff_go_and_longer_ones_stay_exactly():
    shape = (64, 96)
    long = mirror_mode(shape, 3, 5)        # wavelength 2 / sqrt((3/64)^2 + (5/96)^2) = 28.5 px
    short = mirror_mode(shape, 20, 30)     # 4.3 px
    out = short_wavelength_cutoff(long + 0.7 * short, 0.5, cutoff=0.5 * 10)   # 10 pixels
    np.testing.assert_allclose(out, long, atol=1e-12)
    # the cutoff wavelength itself is kept: l = 16 along an 80-pixel side is 2 M / l = 10 pixels
    at_cutoff = mirror_mode((64, 80), 0, 16)
    np.testing.assert_allclose(short_wavelength_cutoff(at_cutoff, 1.0, 10.0), at_cutoff,
                               atol=1e-12)
    assert np.abs(short_wavelength_cutoff(at_cutoff, 1.0, 10.01)).max() < 1e-12


@pytest.mark.parametrize("wavelength, cutoff, expected", [(4.0, 16.0, 0.0), (5.0, 16.0, 0.0),
                                                          (32.0, 8.0, 1.0), (48.0, 12.0, 1.0)])
def test_any_sinusoid_is_removed_or_kept_away_from_the_edges(wavelength, cutoff, expected):
    """A sinusoid of any phase and direction is not a mirror mode: its window's spectrum spreads
    across the cutoff, which leaves a few per cent within a few cutoffs of the edges only."""
    heights = sinusoid((128, 128), wavelength)
    error = short_wavelength_cutoff(heights, 1.0, cutoff) - expected * heights
    margin = int(2 * cutoff)
    assert np.abs(error[margin:-margin, margin:-margin]).max() < 0.03
    assert np.sqrt(np.mean(error ** 2)) < 0.05


def test_a_window_is_filtered_as_the_whole_surface_is_without_edge_ringing():
    """On a 256^2 window of a larger periodic self-affine surface, the result is compared with
    the same window of the whole surface low-passed exactly (periodic FFT): the mirror
    extension makes no ringing at the edges, where an FFT of the window (periodic extension,
    jumps between opposite edges) errs by more than the filtered rms height."""
    whole = self_affine_surface(1024, hurst=0.8, rms_height=1.0, seed=1)
    q = 2 * np.pi * np.fft.fftfreq(1024)
    keep = q[:, None] ** 2 + q[None, :] ** 2 <= (2 * np.pi / 8.0) ** 2
    exact = np.fft.ifft2(np.fft.fft2(whole) * keep).real[100:356, 300:556]
    window = whole[100:356, 300:556]
    error = short_wavelength_cutoff(window, 1.0, 8.0) - exact
    error -= error.mean()
    scale = exact.std()
    assert np.sqrt(np.mean(error ** 2)) < 0.02 * scale
    assert np.abs(error).max() < 0.3 * scale
    q_w = 2 * np.pi * np.fft.fftfreq(256)
    periodic = np.fft.ifft2(np.fft.fft2(window) * (q_w[:, None] ** 2 + q_w[None, :] ** 2
                                                   <= (2 * np.pi / 8.0) ** 2)).real
    assert np.abs(periodic - periodic.mean() - exact + exact.mean()).max() > scale


def test_planes_constants_and_the_mean_are_left_alone():
    j, i = np.indices((40, 56), dtype=float)
    plane = 3.0 + 0.2 * i - 0.7 * j
    np.testing.assert_allclose(short_wavelength_cutoff(plane, 0.1, 0.25), plane, atol=1e-12)
    np.testing.assert_allclose(short_wavelength_cutoff(np.full((32, 32), -2.0), 1.0, 4.0), -2.0)
    rough = np.random.default_rng(0).standard_normal((40, 56)) + plane
    assert short_wavelength_cutoff(rough, 0.1, 0.5).mean() == pytest.approx(rough.mean(),
                                                                           abs=1e-12)


@pytest.mark.parametrize("cutoff", [4.0, 8.0, 16.0])
def test_white_noise_loses_height_as_its_band_and_slope_much_faster(cutoff):
    heights = np.random.default_rng(1).standard_normal((256, 256))
    before = validation.surface_statistics(heights, 1.0)
    after = validation.surface_statistics(short_wavelength_cutoff(heights, 1.0, cutoff), 1.0)
    expected = np.sqrt(np.pi / 4) * 2.0 / cutoff            # kept share of a flat spectrum
    assert after.rms_height / before.rms_height == pytest.approx(expected, rel=0.05)
    assert after.rms_gradient / before.rms_gradient < 2.5 * (2.0 / cutoff) ** 2
    assert after.rms_gradient / before.rms_gradient < after.rms_height / before.rms_height


@pytest.mark.parametrize("arguments, error, name", [
    (dict(cutoff=1.9), ValueError, "at least two pixels"),
    (dict(cutoff=32.0), ValueError, "shorter than the map's shorter side"),
    (dict(cutoff=-4.0), ValueError, "cutoff"),
    (dict(cutoff="8 nm"), TypeError, "cutoff"),
    (dict(spacing=0.0), ValueError, "spacing"),
    (dict(heights=np.full((32, 40), np.nan)), ValueError, "heights"),
    (dict(heights=np.zeros(64)), ValueError, "heights"),
])
def test_bad_arguments_name_the_parameter(arguments, error, name):
    given = dict(heights=np.zeros((32, 40)), spacing=1.0, cutoff=8.0) | arguments
    with pytest.raises(error, match=name):
        short_wavelength_cutoff(**given)


def test_read_topography_applies_the_cutoff_last_in_its_own_unit(tmp_path):
    heights = self_affine_surface(64, hurst=0.8, rms_height=1.0, seed=4)      # nm
    path = write_gwyddion_ascii(tmp_path / "scan.txt", heights * 1e-9, 2e-9)  # 2 nm pixels
    plain = read_topography(path, height_unit="nm")
    cut = read_topography(path, height_unit="nm", short_cutoff="20 nm")
    np.testing.assert_allclose(cut.heights, short_wavelength_cutoff(plain.heights, 2.0, 20.0),
                               atol=1e-9)
    in_um = read_topography(path, height_unit="um", short_cutoff=0.02)       # a number: um
    np.testing.assert_allclose(in_um.heights * 1e3, cut.heights, atol=1e-9)
    assert not cut.heights.flags.writeable
    with pytest.raises(ValueError, match=r"short_cutoff must be at least two pixels.*\[4, 128\)"
                                         r" nm, got 3 nm"):
        read_topography(path, height_unit="nm", short_cutoff="3 nm")
    with pytest.raises(ValueError, match="short_cutoff"):
        read_topography(path, short_cutoff="20 furlong")


# --- the scene key ---------------------------------------------------------------------------

SCENE = """
name = "cut"
[surface]
family = "file"
path = "scan.txt"
unit = "nm"
{cutoff}
[loads]
min = 1e-3
max = 1e-2
count = 2
[models]
use = ["gw", "bem"]
"""


@pytest.fixture()
def scan(tmp_path):
    """A 64 x 64 scan of 2 nm pixels with roughness down to the pixel (white noise added)."""
    heights = self_affine_surface(64, hurst=0.8, rms_height=1.0, seed=6)
    heights += 0.3 * np.random.default_rng(6).standard_normal(heights.shape)
    write_gwyddion_ascii(tmp_path / "scan.txt", heights * 1e-9, 2e-9)
    return tmp_path


def load(folder, cutoff=""):
    from validation import load_scene

    path = folder / "scene.toml"
    path.write_text(SCENE.format(cutoff=cutoff), encoding="utf-8")
    return load_scene(path)   # one scan, one surface: judged by the band, no warning


def test_the_scene_key_filters_every_tile_and_enters_the_cache_key(scan):
    from validation.run.cache import cache_key
    from validation.surfaces.families import surface_heights, surface_identity

    plain, cut = load(scan), load(scan, 'short_cutoff = "20 nm"')
    assert cut.surface.short_cutoff == "20 nm" and cut.surface.short_cutoff_length == 20.0
    assert plain.surface.short_cutoff is None and "short_cutoff" not in surface_identity(
        plain.surface, 0)                       # the cache keys of scenes without it are kept
    expected = short_wavelength_cutoff(read_topography(scan / "scan.txt", height_unit="nm")
                                       .heights, 2.0, 20.0)
    np.testing.assert_allclose(surface_heights(cut.surface, 0), expected - expected.mean(),
                               atol=1e-9)
    keys = {cache_key("bem", "v", surface=surface_identity(scene.surface, 0))
            for scene in (plain, cut)}
    assert len(keys) == 2
    # the same cutoff written as a number in the scene's unit, or in another unit: one key
    for same in ("short_cutoff = 20", 'short_cutoff = "0.02 um"', 'short_cutoff = "200 A"'):
        again = load(scan, same)
        assert surface_identity(again.surface, 0)["short_cutoff"] == pytest.approx(20.0)
    assert surface_identity(load(scan, "short_cutoff = 16").surface, 0) != surface_identity(
        cut.surface, 0)


@pytest.mark.parametrize("value, detail", [
    ('"3 nm"', r"'surface.short_cutoff'.*at least two pixels.*\[4, 128\) nm, got 3 nm"),
    ("200", r"'surface.short_cutoff'.*shorter than the map's shorter side"),
    ('"20 furlong"', r"'surface.short_cutoff' must be a length"),
    ("true", r"'surface.short_cutoff' must be a length"),
    ("[20, 30]", r"'surface.short_cutoff' must be a length"),
])
def test_a_bad_scene_cutoff_names_the_key(scan, value, detail):
    from validation import SceneError, load_scene

    path = scan / "scene.toml"
    path.write_text(SCENE.format(cutoff=f"short_cutoff = {value}"), encoding="utf-8")
    with pytest.raises(SceneError, match=detail):
        load_scene(path)


def test_the_report_names_the_cutoff(scan):
    from validation.report.sections import surface_text

    text = surface_text(load(scan, 'short_cutoff = "20 nm"'), 1)
    assert "short-wavelength cutoff 20 nm" in text
    assert "cutoff" not in surface_text(load(scan), 1)


def test_a_cutoff_at_eight_pixels_makes_the_bems_area_band_shrink(scan):
    """Pixel-scale roughness (white noise on a self-affine scan) leaves the BEM's contact area
    unconverged on the scan's grid (its band, the half-grid estimate, above 100 %); with the
    roughness below 8 pixels cut, the band is a few per cent."""
    from validation import compare_realizations, run_scenes

    bands = {}
    for cutoff in ("", 'short_cutoff = "16 nm"'):
        path = scan / "scene.toml"
        path.write_text(SCENE.format(cutoff=cutoff).replace("max = 1e-2", "max = 3e-2")
                        .replace("count = 2", 'count = 4\n[quantities]\nuse = ["area"]'),
                        encoding="utf-8")
        scene = validation.load_scene(path)
        (result,) = run_scenes([scene], progress=False)
        bands[cutoff] = compare_realizations(result.realizations[0.0]).models["gw", "area"].band
    plain, cut = bands[""], bands['short_cutoff = "16 nm"']
    assert np.median(plain) > 1.0 and np.median(cut) < 0.15 and np.all(cut < plain)
