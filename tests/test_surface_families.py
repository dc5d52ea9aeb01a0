"""Self-affine and measured-map surface families in scenes: parsing, realizations, runs, cache."""

import csv
import pathlib
import shutil

import numpy as np
import pytest

from validation.report.write import write_report
from validation.judge.analysis import analyse
from validation import run_scenes
from validation.scenes.scene import FAMILIES, SceneError, SurfaceSpec
from validation.scenes.reader import load_scene, parse_scene
from validation.surfaces.self_affine import self_affine_surface
from validation.surfaces.families import _MAKERS, surface_heights, tile
from validation.surfaces.statistics import surface_statistics
from validation.surfaces.topography import write_gwyddion_ascii

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"

SELF_AFFINE = """
[surface]
family = "self-affine"
hurst = [0.5, 0.8]
rms_slope = 0.1
n = 32
"""

FILE = """
[surface]
family = "file"
path = "scan.txt"
unit = "um"
tiles = 4
"""


@pytest.fixture()
def scan(tmp_path):
    """A 64 x 64 Gwyddion scan of 8 µm in tmp_path/scan.txt (heights in m)."""
    heights = self_affine_surface(64, hurst=0.8, rms_slope=0.1, L=8.0, window=128, seed=5)
    write_gwyddion_ascii(tmp_path / "scan.txt", heights * 1e-6, 8e-6 / 64, unit="m",
                         size_unit="µm")
    return tmp_path / "scan.txt"


def write(folder, text, name="scene.toml"):
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return list(csv.DictReader(stream))


def report_text(folder) -> str:
    """The report's front page and every scene page of ``folder``, as one text."""
    return "\n".join(p.read_text(encoding="utf-8") for p in sorted(pathlib.Path(folder).glob("*.md")))


def test_every_family_has_one_maker():
    assert set(_MAKERS) == set(FAMILIES) == {"wm", "self-affine", "file"}


def test_self_affine_scene_defaults_and_sweep(tmp_path):
    surface = load_scene(write(tmp_path, SELF_AFFINE)).surface
    assert surface.hurst == (0.5, 0.8) and surface.sweep_name == "H"
    assert surface.sweep_values == (0.5, 0.8) and surface.at(0.8).hurst == (0.8,)
    assert (surface.window, surface.L, surface.rms_height) == (2, 1.0, None)
    assert SurfaceSpec(family="self-affine", hurst=(0.3,)).rms_slope == 0.1
    assert SurfaceSpec(D=(2.3,)).sweep_name == "D"


def test_file_scene_reads_relative_to_its_folder_and_derives_the_tiles(tmp_path, scan):
    folder = tmp_path / "elsewhere"
    folder.mkdir()
    scene = load_scene(write(tmp_path, FILE))
    assert pathlib.Path(scene.surface.path) == scan
    assert (scene.surface.n, scene.realizations, scene.surface.sweep_values) == (32, 4, (0.0,))
    assert scene.surface.L == pytest.approx(4.0)  # µm: half of the 8 µm scan
    assert scene.quick_version().surface == scene.surface  # a measured map keeps its tiles
    example = load_scene(EXAMPLES / "example-topography.toml")
    assert (example.surface.n, example.realizations, example.surface.unit) == (64, 4, "um")


@pytest.mark.parametrize("text, key", [
    (SELF_AFFINE.replace("hurst = [0.5, 0.8]", "hurst = 1.5"), "surface.hurst"),
    (SELF_AFFINE.replace("hurst = [0.5, 0.8]\n", ""), "surface.hurst"),
    (SELF_AFFINE + "D = 2.3\n", "surface.D"),
    (SELF_AFFINE + "rms_height = 0.01\n", "surface.rms_slope"),
    (SELF_AFFINE.replace("rms_slope = 0.1\n", ""), "surface.rms_slope"),
    (SELF_AFFINE + "rolloff = 2.0\n", "surface.rolloff"),
    (SELF_AFFINE + "short_cutoff = 0.01\n", "surface.short_cutoff"),
    (SELF_AFFINE + "window = 0\n", "surface.window"),
    (SELF_AFFINE + "\n[bem]\nperiodic = true\n", "bem.periodic"),
    (SELF_AFFINE.replace("self-affine", "fractal"), "surface.family"),
    ("[surface]\nD = 2.3\nrms_slope = 0.1\nhurst = 0.5\n", "surface.hurst"),
    (FILE.replace("tiles = 4", "tiles = 3"), "surface.tiles"),
    (FILE.replace("tiles = 4", "tiles = 9"), "surface.tiles"),    # tiles of 21 pixels
    (FILE + "n = 64\n", "surface.n"),
    (FILE + "L = 8.0\n", "surface.L"),
    (FILE + "rms_slope = 0.1\n", "surface.rms_slope"),
    (FILE.replace("scan.txt", "missing.txt"), "surface.path"),
    (FILE.replace('unit = "um"', 'unit = "furlong"'), "surface.unit"),
    (FILE.replace('unit = "um"', 'detrend = "quadratic"'), "surface.detrend"),
    (FILE + 'physical_size = "8 um"\n', "surface.physical_size"),  # the file states its size
    (FILE + "\n[realizations]\ncount = 2\n", "realizations"),
])
def test_bad_surface_names_key_and_file(tmp_path, scan, text, key):
    with pytest.raises(SceneError) as info:
        load_scene(write(tmp_path, text, "bad-scene.toml"))
    assert f"'{key}'" in str(info.value) and "bad-scene.toml" in str(info.value)


def test_dataclass_rejects_another_familys_parameter(scan):
    with pytest.raises(SceneError, match="'D'.*not a parameter of family 'file'"):
        SurfaceSpec(family="file", path=str(scan), D=(2.3,))
    with pytest.raises(SceneError, match="'window'"):
        SurfaceSpec(D=(2.3,), window=4)


def test_tiles_partition_the_map_without_overlap():
    heights = np.arange(36.0).reshape(6, 6) ** 1.5
    parts = [tile(heights, 9, k) for k in range(9)]
    assert all(p.shape == (2, 2) and abs(p.mean()) < 1e-12 for p in parts)
    rebuilt = np.block([[parts[3 * r + c] + heights[2 * r:2 * r + 2, 2 * c:2 * c + 2].mean()
                         for c in range(3)] for r in range(3)])
    np.testing.assert_allclose(rebuilt, heights)


def test_self_affine_fine_sample_is_the_same_surface():
    surface = SurfaceSpec(family="self-affine", hurst=(0.8,), rms_slope=0.1, n=32, rolloff=0.5)
    coarse = surface_heights(surface, seed=3)
    fine = surface_heights(SurfaceSpec(**{**surface.__dict__, "n": 64}), seed=3, slope_grid=32)
    offset = fine[::2, ::2] - coarse
    np.testing.assert_allclose(offset, offset.mean(), atol=1e-12 * np.ptp(coarse))
    statistics = surface_statistics(coarse, surface.spacing, periodic=False)
    assert statistics.rms_gradient == pytest.approx(0.1, rel=1e-9)
    assert abs(coarse.mean()) < 1e-12
    assert not np.allclose(coarse, surface_heights(surface, seed=4))


def test_self_affine_scene_end_to_end(tmp_path, monkeypatch):
    import validation.report.write

    scene = parse_scene({"name": "sa", "surface": {"family": "self-affine", "hurst": [0.5, 0.8],
                                                   "rms_slope": 0.1, "n": 32},
                         "realizations": {"count": 2, "seed": 1},
                         "loads": {"min": 1e-4, "max": 1e-2, "count": 3},
                         "models": {"use": ["gw", "bem"]},
                         "quantities": {"use": ["area", "load", "separation"]}}, source="test")
    (result,) = run_scenes([scene], progress=False)
    assert sorted(result.realizations) == [0.5, 0.8]
    # every BEM curve carries its own per-point error estimate (the same path on half the grid)
    assert all(np.all(np.isfinite(r.curves["bem"].extras["area_error"]))
               for rs in result.realizations.values() for r in rs)
    assert all(r.curves["bem"].extras["converged"].all() for rs in result.realizations.values()
               for r in rs)
    assert all(r.task.describe().startswith("H=") for r in result.realizations[0.5])
    labels, add = {}, validation.report.write._Figures.add

    def remember(self, draw, name, caption, panels=1):
        labels[name] = draw().axes[0].get_ylabel()
        add(self, draw, name, caption, panels)

    monkeypatch.setattr(validation.report.write._Figures, "add", remember)
    write_report([result], tmp_path)
    for name in ("sa-validity-map", "sa-errors-H0.5", "sa-verdicts-H0.8"):
        assert (tmp_path / f"{name}.png").stat().st_size > 5_000
    assert labels["sa-validity-map.png"] == "Hurst exponent H"
    validity = rows(tmp_path / "validity.csv")
    assert {r["H"] for r in validity} == {"0.5", "0.8"} and {r["D"] for r in validity} == {""}
    assert [c.parameter for c in analyse(result).comparisons] == ["H", "H"]
    text = report_text(tmp_path)
    assert "### H = 0.8" in text and "Gaussian self-affine, H = 0.5, 0.8" in text


def computed_log(result):
    return [e for rs in result.realizations.values() for r in rs for e in r.computed]


def test_file_scene_end_to_end_and_cache_follows_the_content(tmp_path, scan):
    # a closed-form, a discrete and the reference model on the tiles
    text = FILE + ("\n[loads]\nmin = 1e-3\nmax = 1e-2\ncount = 3\n[models]\n"
                   "use = [\"improved_gw\", \"discrete\", \"bem\"]\n"
                   "[quantities]\nuse = [\"area\", \"load\", \"separation\"]\n")
    scene = load_scene(write(tmp_path, text))
    cache = str(tmp_path / "cache")
    (result,) = run_scenes([scene], cache_dir=cache, progress=False)
    assert [r.task.seed for r in result.realizations[0.0]] == [0, 1, 2, 3]
    assert len({r.sigma for r in result.realizations[0.0]}) == 4
    write_report([result], tmp_path / "report")
    markdown = report_text(tmp_path / "report")
    assert "measured map `scan.txt`" in markdown
    assert "4 non-overlapping tiles of 32 × 32" in markdown
    assert (tmp_path / "report" / "scene-errors.png").stat().st_size > 5_000
    assert {r["seed"] for r in rows(tmp_path / "report" / "curves.csv")} == {"0", "1", "2", "3"}
    # the same bytes under another path: every expensive result comes from the cache
    moved = tmp_path / "moved"
    moved.mkdir()
    shutil.copy(scan, moved / "scan.txt")
    (again,) = run_scenes([load_scene(write(moved, text))], cache_dir=cache, progress=False)
    assert computed_log(again) == []   # (improved GW too: its curves are cached)
    # other bytes under the same path: recomputed
    lines = scan.read_text(encoding="utf-8").splitlines()
    lines[-1] = "\t".join(f"{float(v) * 1.5:.6e}" for v in lines[-1].split("\t"))
    scan.write_text("\n".join(lines) + "\n", encoding="utf-8")
    (changed,) = run_scenes([load_scene(tmp_path / "scene.toml")], cache_dir=cache,
                            progress=False)
    assert sum(e.startswith("bem ") for e in computed_log(changed)) == 4
    assert sum(e.startswith("discrete ") for e in computed_log(changed)) == 4


RECTANGLE = """
name = "rect"
[surface]
family = "file"
path = "wide.txt"
unit = "um"
square = "keep"
tiles = 1
[loads]
min = 1e-3
max = 1e-2
count = 3
"""


@pytest.fixture()
def wide(tmp_path):
    """A 48 x 80 Gwyddion scan of 4.8 µm x 8 µm (rows y, columns x) in tmp_path/wide.txt."""
    heights = self_affine_surface(96, hurst=0.8, rms_slope=0.1, L=9.6, window=192, seed=5)
    write_gwyddion_ascii(tmp_path / "wide.txt", heights[:48, :80] * 1e-6, 0.1e-6, unit="m",
                         size_unit="µm")
    return tmp_path / "wide.txt"


def test_rectangular_map_is_kept_whole_or_cropped(tmp_path, wide):
    kept = load_scene(write(tmp_path, RECTANGLE)).surface
    assert kept.grid == (48, 80) and kept.n == 48
    assert kept.spacing == pytest.approx(0.1) and kept.L**2 == pytest.approx(4.8 * 8.0)
    assert surface_heights(kept, 0).shape == (48, 80)
    cropped = load_scene(write(tmp_path, RECTANGLE.replace('square = "keep"\n', ""))).surface
    assert cropped.grid == (48, 48) and cropped.L == pytest.approx(4.8)
    assert cropped.spacing == pytest.approx(0.1)
    with pytest.raises(SceneError, match="'surface.square'"):
        load_scene(write(tmp_path, RECTANGLE.replace('"keep"', '"pad"'), "bad.toml"))
    with pytest.raises(SceneError, match="'surface.tiles'.*48 x 80.*24 x 40"):
        load_scene(write(tmp_path, RECTANGLE.replace("tiles = 1", "tiles = 4"), "bad.toml"))


def test_tiles_of_a_rectangular_map_keep_its_aspect():
    heights = np.arange(6 * 10.0).reshape(6, 10) ** 1.5
    parts = [tile(heights, 4, k) for k in range(4)]
    assert all(p.shape == (3, 5) for p in parts)
    np.testing.assert_allclose(parts[3] + heights[3:, 5:].mean(), heights[3:, 5:])


def test_rectangular_map_runs_through_the_report_uncropped(tmp_path, wide):
    from validation.cli import main

    scene = write(tmp_path, RECTANGLE)
    assert main(["report", str(scene), "--quick", "--no-cache", "--jobs", "1", "--quiet",
                 "--out", str(tmp_path / "out")]) == 0
    text = report_text(tmp_path / "out")
    assert "48 × 80 (uncropped) pixels" in text and "the whole map as one surface, 48 × 80 pixels" in text
    curves = rows(tmp_path / "out" / "curves.csv")
    assert {r["n"] for r in curves} == {"48x80"}
    bem = [r for r in curves if r["model"] == "bem"]
    # Load = W / (E* A) with A the whole 8 x 4.8 µm map
    for r in bem:
        assert float(r["load_W"]) == pytest.approx(float(r["Load"]) * 8.0 * 4.8, rel=1e-9)
    (result,) = run_scenes([load_scene(scene)], progress=False)
    (realization,) = result.realizations[0.0]
    curve = realization.curves["bem"]
    assert curve.nominal_area == pytest.approx(38.4)
    assert np.all(np.isfinite(curve.extras["area_error"]))    # the half grid is 24 x 40
