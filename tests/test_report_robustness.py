"""A report that never lies and never dies: reference bands that were not estimated, summaries
that tell failing from undecided, load paths a model cannot follow, output folders."""

from __future__ import annotations

import csv
import pathlib

import numpy as np
import pytest

from validation.report.write import write_report
from validation.judge.analysis import analyse
from validation import run_scenes
from validation.scenes.reader import load_scene
from validation.surfaces.self_affine import self_affine_surface
from validation.judge.verdicts import FAILS, HOLDS


def write(folder: pathlib.Path, text: str, name: str = "scene.toml") -> pathlib.Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return list(csv.DictReader(stream))


def report_text(folder) -> str:
    """The report's front page and every scene page of ``folder``, as one text."""
    return "\n".join(p.read_text(encoding="utf-8") for p in sorted(pathlib.Path(folder).glob("*.md")))


MEASURED = """
name = "{name}"
[surface]
family = "file"
path = "map.npy"
physical_size = 9.9
file_unit = "um"
unit = "um"
tiles = {tiles}
[loads]
min = 1e-3
max = 3e-2
count = 4
[models]
use = ["gw", "improved_gw", "persson", "bem"]
[quantities]
use = ["area", "load", "separation"]
[tolerances]
levels = [0.2, 0.5]
"""


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    """A 99 x 99 measured map (odd: 2 x 2 tiles of 49 pixels, 3 x 3 of 33), as a user's .npy."""
    folder = tmp_path_factory.mktemp("measured")
    heights = self_affine_surface(99, hurst=0.8, rms_slope=0.1, L=9.9, window=198, seed=11)
    np.save(folder / "map.npy", heights)
    return folder


def test_the_band_of_odd_tiles_is_estimated_and_tilings_do_not_contradict(measured, tmp_path):
    # The same map cut 4 and 9 ways: odd cells are made even, so both carry the BEM's error
    # band, and no point gets "holds" from one tiling and "fails" from the other.
    verdicts = {}
    for tiles in (4, 9):
        scene = load_scene(write(measured, MEASURED.format(name=f"t{tiles}", tiles=tiles),
                                 f"t{tiles}.toml"))
        assert scene.surface.n == {4: 48, 9: 32}[tiles]
        (result,) = run_scenes([scene], progress=False)
        (comparison,) = analyse(result).comparisons
        assert all(not source.startswith("not") for source in comparison.band_source.values())
        for key, entry in comparison.models.items():
            assert np.all(np.isfinite(entry.band)), key
            for tolerance, verdict in zip(entry.tolerances, entry.verdicts):
                verdicts[tiles, key, tolerance] = verdict
        if tiles == 4:  # a measured map is not the paper's WM surface: no "paper Fig." caption
            write_report([result], tmp_path / "t4")
            markdown = report_text(tmp_path / "t4")
            assert "against separation, measured map (thin lines: tiles" in markdown
            assert "paper Fig" not in markdown
    keys = {key[1:] for key in verdicts}
    together = np.concatenate(list(verdicts.values()))
    assert (together == HOLDS).any() and (together == FAILS).any()  # firm verdicts to compare
    for key in keys:
        four, nine = verdicts[(4,) + key], verdicts[(9,) + key]
        contradictions = ((four == HOLDS) & (nine == FAILS)) | ((four == FAILS) & (nine == HOLDS))
        assert not contradictions.any(), (key, four, nine)


def test_odd_rows_and_columns_of_a_rectangular_map_kept_whole_are_both_made_even(measured):
    # 71 x 99 pixels, 2 x 2 tiles: cells of 35 x 49, tiles of 34 x 48 from each cell's top-left
    # corner, so the BEM's band (every second pixel along both sides) is estimated on each
    from validation.surfaces.families import surface_heights

    heights = np.load(measured / "map.npy")[:71]
    np.save(measured / "wide.npy", heights)
    text = (MEASURED.format(name="wide", tiles=4).replace("map.npy", "wide.npy")
            .replace("physical_size = 9.9", "physical_size = [9.9, 7.1]")
            .replace("count = 4", "count = 2"))
    text = text.replace('tiles = 4\n', 'tiles = 4\nsquare = "keep"\ndetrend = "none"\n')
    text = text.replace('"gw", "improved_gw", "persson", "bem"', '"gw", "bem"')
    scene = load_scene(write(measured, text, "wide.toml"))
    assert scene.surface.grid == (34, 48) and scene.surface.n == 34
    assert scene.surface.L == pytest.approx(0.1 * np.sqrt(34 * 48))
    expected = heights[35:69, 49:97] - heights[35:69, 49:97].mean()
    np.testing.assert_allclose(surface_heights(scene.surface, 3), expected, atol=1e-12)
    (result,) = run_scenes([scene], progress=False)
    for realization in result.realizations[0.0]:
        assert np.all(np.isfinite(realization.curves["bem"].extras["area_error"]))


TINY = """
name = "tiny"
[surface]
D = 2.4
rms_slope = 0.1
n = 32
[realizations]
count = 3
[loads]
min = 1e-3
max = 1e-2
count = 3
[models]
use = ["gw", "persson", "bem"]
[quantities]
use = ["area", "load", "separation"]
"""


def test_a_band_not_estimated_is_written_as_such_never_as_zero(tmp_path):
    scene = load_scene(write(tmp_path, TINY + "[bem]\nreference_error = false\n"))
    folder = tmp_path / "report"
    write_report(run_scenes([scene], progress=False), folder)
    markdown = report_text(folder)
    table = markdown[markdown.index("Verdicts per load point"):]
    # GW and Persson are judged against the interface reference; the band says of which frame
    assert "Reference band: area (interface): not estimated" in table
    assert "| not estimated |" in table and "| 0 % |" not in table
    errors = rows(folder / "errors.csv")
    assert {r["reference_band"] for r in errors} == {"not estimated"}
    assert {r["reference_band_max"] for r in rows(folder / "validity.csv")} == {"not estimated"}
    assert {r["verdict"] for r in rows(folder / "verdicts.csv")} == {"undecided"}


def test_an_odd_grid_with_a_reference_band_is_refused_with_the_reason(tmp_path):
    from validation.scenes.scene import SceneError

    with pytest.raises(SceneError, match=r"'surface.n' must be even .*every second grid point"):
        load_scene(write(tmp_path, TINY.replace("n = 32", "n = 33")))
    assert load_scene(write(tmp_path, TINY.replace("n = 32", "n = 33")
                            + "[bem]\nreference_error = false\n")).surface.n == 33


def synthetic(errors, *, band=0.0, converged=True):
    """Realizations of a BEM curve and a GW curve whose area is off by ``errors[r]`` (relative)
    at every one of 4 load points; the BEM's area band is ``band`` (NaN: not estimated)."""
    from types import SimpleNamespace

    from bem.common.curve import ContactCurve

    load, area = np.logspace(-4, -2, 4), np.array([0.01, 0.03, 0.1, 0.2])
    out = []
    for seed, error in enumerate(errors):
        extras = {"converged": np.full(4, converged)}
        if np.isfinite(band):
            extras["area_error"] = band * area
        reference = ContactCurve(separation=[3.0, 2.0, 1.5, 1.0], load=load, area=area,
                                 mean_pressure=load, nominal_area=1.0, e_star=1.0, extras=extras)
        model = ContactCurve(separation=[3.0, 2.0, 1.5, 1.0], load=load, area=area * (1 + error),
                             mean_pressure=load, nominal_area=1.0, e_star=1.0)
        task = SimpleNamespace(seed=seed, surface=SimpleNamespace(L=1.0, sweep_name="D"),
                               quantities=("area",), sweep_value=2.3)
        out.append(SimpleNamespace(task=task, curves={"bem": reference, "gw": model}, sigma=1.0))
    return out


@pytest.mark.parametrize("errors, band, converged, cell", [
    ([0.5, 0.52, 0.49], 0.0, True, "fails everywhere"),
    ([0.0, 0.01, -0.01], 0.3, True, "undecided: reference band"),
    ([0.0, 0.01, -0.01], np.nan, True, "undecided: reference band"),
    ([0.5, 0.52, 0.49], np.nan, True, "undecided: reference band"),
    ([0.3, -0.3, 0.1], 0.0, True, "undecided: too few realizations"),
    ([0.0, 0.01, -0.01], 0.0, False, "undecided: unconverged"),
    ([0.0, 0.01, -0.01], 0.0, True, "area 1 % – 20 % (Load 1.0e-04 – 1.0e-02)"),
    # one surface: judged by its band alone, never "too few realizations"
    ([0.0], 0.0, True, "area 1 % – 20 % (Load 1.0e-04 – 1.0e-02) [whole range]"),
    ([0.1], 0.15, True, "undecided: reference band"),
    ([0.5], 0.1, True, "fails everywhere"),
])
def test_the_summary_tells_failing_from_undecided_and_says_why(errors, band, converged, cell):
    from validation.judge.compare import compare_realizations
    from validation.report.sections import holds_cell

    comparison = compare_realizations(synthetic(errors, band=band, converged=converged),
                                      tolerances=(0.2,))
    assert holds_cell(comparison.models[("gw", "area")]).startswith(cell)


@pytest.mark.parametrize("errors, band, converged, cell", [
    ([0.5, 0.52, 0.49], 0.0, True, "fails everywhere"),
    ([0.5, 0.52, 0.49], np.nan, True, "undecided: reference band"),
    ([0.0, 0.01, -0.01], 0.3, True, "undecided: reference band"),
    ([0.0, 0.01], 0.0, True, "undecided: too few realizations"),
    ([0.0, 0.01, -0.01], 0.0, False, "undecided: unconverged"),
    ([0.0, 0.01, -0.01], 0.0, True, "area 1 % – 20 % (Load 1.0e-04 – 1.0e-02)"),
    ([0.0], 0.0, True, "–"),     # one surface has no per-surface reading
])
def test_the_summary_says_why_per_surface_too(errors, band, converged, cell):
    from validation.judge.compare import compare_realizations
    from validation.report.sections import holds_cell

    comparison = compare_realizations(synthetic(errors, band=band, converged=converged),
                                      tolerances=(0.2,))
    assert holds_cell(comparison.models[("gw", "area")], per_surface=True).startswith(cell)


def test_one_generated_realization_is_warned_about_and_one_scan_is_not(tmp_path, measured,
                                                                      capsys):
    # one realization of a generated family is judged as that one surface, which a scene that
    # names a family may not mean; a measured map with tiles = 1 is one surface by intent
    import warnings

    from validation.cli import main
    from validation.scenes.scene import SceneWarning

    single = write(tmp_path, TINY.replace("count = 3\n[loads]", "count = 1\n[loads]"))
    with pytest.warns(SceneWarning, match=r"1 realization.*that one surface.*"
                                          r"\[realizations\] count = 2"):
        load_scene(single)
    with warnings.catch_warnings():
        warnings.simplefilter("error", SceneWarning)
        load_scene(write(measured, MEASURED.format(name="one", tiles=1), "one.toml"))
    # the command line says it once, before computing, as a plain line
    assert main(["report", str(single), "--out", str(tmp_path / "out"), "--no-cache",
                 "--jobs", "1", "--quiet"]) == 0
    err = capsys.readouterr().err
    assert err.count("warning: scene 'tiny'") == 1 and "Traceback" not in err


SWEEP = TINY.replace("D = 2.4", "D = [2.2, 2.6]").replace("count = 3\n[loads]",
                                                             "count = 2\n[loads]")


def test_a_sweep_scene_gets_a_summary_per_swept_value(tmp_path):
    scene = load_scene(write(tmp_path, SWEEP))
    folder = tmp_path / "report"
    write_report(run_scenes([scene], progress=False), folder)
    markdown = (folder / "tiny.md").read_text(encoding="utf-8")     # the scene's page
    summary = markdown[markdown.index("## Where each theory holds"):markdown.index("## Findings")]
    assert "| model | quantity | D = 2.2 | D = 2.6 |" in summary
    assert "| GW | area |" in summary.replace("original GW", "GW")
    assert "| nowhere |" not in summary and "*Undecided* says why" in summary


def test_the_precision_of_each_scene_is_counted_from_its_headline(tmp_path):
    budget = SWEEP.replace("count = 2\n[loads]", "count = 3\nmax = 6\n[loads]") + \
        "[bem]\nmax_grid = 64\n"
    scene = load_scene(write(tmp_path, budget))
    folder = tmp_path / "report"
    (result,) = run_scenes([scene], progress=False)
    write_report([result], folder)
    markdown = (folder / "report.md").read_text(encoding="utf-8")
    section = markdown[markdown.index("## How precise the headline is"):
                       markdown.index("## Findings")]
    table = [line for line in section.splitlines() if line.startswith("| `tiny`")]
    assert len(table) == 1
    cells = [c.strip() for c in table[0].strip("|").split("|")]
    # the realizations per look and the finer reference the run spent
    looks = result.sequential.used
    assert cells[1] == (" → ".join(map(str, looks)) if len(looks) > 1 else str(looks[0]))
    levels = result.refinement.levels
    first = "" if not levels else (f"{levels[0].grid}²"
                                   + (" (interface)" if levels[0].reference != "bem" else "")
                                   + " at ")
    assert cells[2] == "none" if not levels else cells[2].startswith(first)
    # independently, from the half-widths of headline.csv (each cell once: one tolerance)
    headline = [r for r in rows(folder / "headline.csv") if float(r["tolerance"]) == 0.2]
    widths = np.array([float(r["half_width"]) for r in headline])
    widths = widths[np.isfinite(widths)]
    assert cells[3] == str(widths.size) and widths.size > 0
    assert float(cells[4]) == pytest.approx(np.median(widths), rel=5e-3)
    assert float(cells[5].split()[0]) == pytest.approx(widths.max(), rel=5e-3)


FULL_CONTACT = """
name = "full-contact"
[surface]
D = 2.8
rms_slope = 0.1
n = 64
[realizations]
count = 3
[loads]
min = 1e-3
max = 2.0
count = 8
[models]
use = ["gw", "discrete", "bem"]
[quantities]
use = ["area", "load", "separation"]
"""


@pytest.mark.filterwarnings("ignore:discrete asperity model")
def test_a_load_path_into_full_contact_is_reported_point_by_point(tmp_path):
    # Mean pressure 2 E* presses the surface flat; there the discrete model's solve ends
    # unconverged at another load (2.03 for 2.0) than the one asked: an unreachable point.
    from validation.cli import main

    scene = write(tmp_path, FULL_CONTACT)
    folder = tmp_path / "report"
    cache = str(tmp_path / "cache")
    assert main(["report", str(scene), "--out", str(folder), "--cache", cache, "--jobs", "1",
                 "--quiet"]) == 0
    (result,) = run_scenes([load_scene(scene)], cache_dir=cache, progress=False)
    reference = [r.curves["bem"] for r in result.realizations[2.8]]
    assert all(c.area_fraction[-1] == pytest.approx(1.0) for c in reference)  # full contact
    (comparison,) = analyse(result).comparisons
    discrete = comparison.models[("discrete", "area")]
    assert discrete.unreachable >= 1 and discrete.unconverged >= discrete.unreachable
    assert np.isnan(discrete.summary.mean[-1]) or discrete.interval.count[-1] < 3
    assert all(v[-1] != HOLDS for v in discrete.verdicts)
    markdown = report_text(folder)
    assert f"({discrete.unreachable} unreachable)" in markdown
    last = [r for r in rows(folder / "verdicts.csv")
            if r["model"] == "discrete" and r["point"] == "7" and r["verdict"] == "undecided"]
    assert all(r["undecided_reason"] for r in last)


NPY = """
name = "user-map"
[surface]
family = "file"
path = "user.npy"
tiles = 4
"""


@pytest.fixture()
def user_map(tmp_path):
    """A 64 x 64 .npy map with a hole (NaN), as a user's instrument export: no size, no unit."""
    heights = self_affine_surface(64, hurst=0.8, rms_slope=0.1, L=6.4, window=128, seed=3)
    heights[10:13, 20:22] = np.nan
    np.save(tmp_path / "user.npy", heights)
    return tmp_path


def test_missing_settings_are_listed_together_with_an_example(user_map):
    from validation.scenes.scene import SceneError

    with pytest.raises(SceneError) as info:
        load_scene(write(user_map, NPY))
    message = str(info.value)
    assert "height unit or its physical size" in message
    assert 'file_unit = "nm"' in message and 'physical_size = "10 um"' in message


def test_every_option_an_error_recommends_is_a_scene_key(user_map):
    from validation.scenes.scene import SceneError

    sized = NPY + 'physical_size = "6.4 um"\nfile_unit = "um"\nunit = "um"\n'
    with pytest.raises(SceneError) as info:
        load_scene(write(user_map, sized))
    message = str(info.value)
    # the advice, in the scene's words ...
    assert 'fill = "mean" or fill = "interpolate" in [surface]' in message
    assert "'surface.fill'" in message
    # ... can be followed
    scene = load_scene(write(user_map, sized + 'fill = "mean"\n'))
    assert dict(scene.surface.read_options) == {"fill": "mean"}
    # every other keyword of read_topography is a key too, handed to it unchanged (those with
    # a field of their own, such as square, are not passed through twice)
    keys = 'fill = "interpolate"\nsquare = "keep"\nreader = "builtin"\n'
    scene = load_scene(write(user_map, sized + keys + '[loads]\nmin = 1e-3\nmax = 1e-2\ncount = 2\n'
                             '[models]\nuse = ["gw", "bem"]\n'))
    assert dict(scene.surface.read_options) == {"fill": "interpolate", "reader": "builtin"}
    assert scene.surface.square == "keep"
    # and they are part of the cache key (another fill gives other heights)
    from validation.surfaces.families import surface_identity

    identity = surface_identity(scene.surface, 0)
    assert identity["read_options"] == {"fill": "interpolate", "reader": "builtin"}
    assert identity["square"] == "keep"
    assert scene.surface.n == 32
    (result,) = run_scenes([scene], progress=False)
    assert all(np.isfinite(r.sigma) for r in result.realizations[0.0])
    with pytest.raises(SceneError, match="'surface.fill'.*must be one of"):
        load_scene(write(user_map, sized + 'fill = "zero"\n'))
    # read_topography's own name of the unit is the scene's unit
    renamed = sized.replace('\nunit = "um"\n', '\nheight_unit = "nm"\n') + 'fill = "mean"\n'
    assert load_scene(write(user_map, renamed)).surface.unit == "nm"


def test_the_scene_keys_of_a_measured_map_follow_the_reader_signature():
    import inspect

    from validation.scenes.scene import FAMILY_KEYS
    from validation.surfaces.spec import READ_FIELDS
    from validation.surfaces.topography import read_topography

    keywords = {name for name, p in inspect.signature(read_topography).parameters.items()
                if p.kind is p.KEYWORD_ONLY}
    keys = set(FAMILY_KEYS["file"]) | {"height_unit"}
    assert keywords - set(READ_FIELDS) <= keys and {"fill", "square"} <= keys


ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_a_report_replaces_its_previous_report_and_refuses_other_folders(tmp_path, capsys):
    from validation.cli import main

    scene = write(tmp_path, TINY)
    folder = tmp_path / "report"
    folder.mkdir()
    (folder / "report.md").write_text("# an earlier report")
    (folder / "old-scene-errors-D2.png").write_bytes(b"stale figure")
    (folder / "theory.csv").write_text("stale table")
    (folder / "notes.txt").write_text("the user's")
    arguments = ["report", str(scene), "--no-cache", "--jobs", "1", "--quiet"]
    assert main(arguments + ["--out", str(folder)]) == 0
    assert not (folder / "old-scene-errors-D2.png").exists()
    assert not (folder / "theory.csv").exists()           # this run has no theory scene
    assert (folder / "notes.txt").read_text() == "the user's"
    assert "tiny" in (folder / "report.md").read_text(encoding="utf-8")
    # a folder of other files (and no report) is refused before anything is computed
    data = tmp_path / "data"
    data.mkdir()
    (data / "measurements.csv").write_text("1,2")
    capsys.readouterr()
    assert main(arguments + ["--out", str(data)]) == 2
    err = capsys.readouterr().err
    assert "--out" in err and "measurements.csv" in err and "not a report" in err
    assert (data / "measurements.csv").read_text() == "1,2" and len(list(data.iterdir())) == 1
    with pytest.raises(ValueError, match="not a report"):
        write_report([], data)


def test_help_and_readme_agree_with_the_program():
    import re

    from validation import cli
    from validation.cli import DEFAULT_SCENES, FULL_ONLY_SCENES

    scenes = [load_scene(name) for name in DEFAULT_SCENES if load_scene(name).kind == "surface"]
    # the counts the help and the docstring give are the default scenes' own
    doc = " ".join(cli.__doc__.split())
    parser = cli.build_parser()
    report = next(a for a in parser._subparsers._group_actions[0].choices.values()
                  if a.prog.endswith("report"))
    full = " ".join(next(a.help for a in report._actions if "--full" in a.option_strings).split())
    for scene in scenes:
        quick = scene.quick_version()
        assert f"{scene.realizations} " in full and f"{scene.realizations} " in doc
        assert f"{scene.surface.n} x {scene.surface.n} grids with {scene.loads.count} loads" in doc
        if scene.name in FULL_ONLY_SCENES:          # not in the quick default report
            continue
        assert f"{quick.realizations} " in doc
        assert f"{quick.surface.n} x {quick.surface.n} grids with {quick.loads.count} loads" in doc
    # (every option is on the site's command-line page, generated from this parser:
    # tests/test_doc_examples.py)
    # install hints name the package as pyproject does, with extras the README or the guide names
    readme = "\n".join(path.read_text(encoding="utf-8") for path in
                       [ROOT / "README.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))])
    name = next(line.split('"')[1] for line in (ROOT / "pyproject.toml").read_text().splitlines()
                if line.startswith("name ="))
    for path in (ROOT / "validation").rglob("*.py"):
        for hint in re.findall(r"pip install '([^']+)'", path.read_text(encoding="utf-8")):
            assert hint.startswith(f"{name}["), (path.name, hint)
            assert f'pip install "{hint}"' in readme, hint


def test_the_tolerance_contours_of_the_validity_map_are_told_apart():
    from validation.judge.compare import compare_realizations
    from validation.report.figures import pyplot, validity_map_figure

    comparisons = []
    for value, scale in ((2.2, 0.01), (2.6, 0.1), (2.9, 1.0)):
        results = synthetic([scale, 1.2 * scale, 0.8 * scale])
        for r in results:
            r.task.sweep_value = value
        comparisons.append(compare_realizations(results, tolerances=(0.05, 0.2)))
    figure = validity_map_figure(comparisons, [("gw", "area")], (0.05, 0.2))
    (legend,) = figure.legends
    lines = legend.get_lines()
    assert [t.get_text() for t in legend.get_texts()] == ["|mean error| = 0.05",
                                                          "|mean error| = 0.2"]
    styles = {(line.get_color(), line.get_linestyle()) for line in lines}
    assert len(styles) == 2 and len({c for c, _ in styles}) == 2
    pyplot().close(figure)
