"""A report that never lies and never dies: reference bands that were not estimated, summaries
that tell failing from undecided, load paths a model cannot follow, output folders."""

from __future__ import annotations

import csv
import pathlib

import numpy as np
import pytest

from validation.report import analyse, write_report
from validation.runner import run_scenes
from validation.scene import load_scene
from validation.self_affine import self_affine_surface
from validation.verdicts import FAILS, HOLDS


def write(folder: pathlib.Path, text: str, name: str = "scene.toml") -> pathlib.Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return list(csv.DictReader(stream))


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


def test_the_band_of_odd_tiles_is_estimated_and_tilings_do_not_contradict(measured):
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
    keys = {key[1:] for key in verdicts}
    together = np.concatenate(list(verdicts.values()))
    assert (together == HOLDS).any() and (together == FAILS).any()  # firm verdicts to compare
    for key in keys:
        four, nine = verdicts[(4,) + key], verdicts[(9,) + key]
        contradictions = ((four == HOLDS) & (nine == FAILS)) | ((four == FAILS) & (nine == HOLDS))
        assert not contradictions.any(), (key, four, nine)


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
    markdown = (folder / "report.md").read_text(encoding="utf-8")
    table = markdown[markdown.index("Verdicts per load point"):]
    assert "Reference band: area: not estimated" in table
    assert "| not estimated |" in table and "| 0 % |" not in table
    errors = rows(folder / "errors.csv")
    assert {r["reference_band"] for r in errors} == {"not estimated"}
    assert {r["reference_band_max"] for r in rows(folder / "validity.csv")} == {"not estimated"}
    assert {r["verdict"] for r in rows(folder / "verdicts.csv")} == {"undecided"}


def test_an_odd_grid_with_a_reference_band_is_refused_with_the_reason(tmp_path):
    from validation.scene import SceneError

    with pytest.raises(SceneError, match=r"'surface.n' must be even .*every second grid point"):
        load_scene(write(tmp_path, TINY.replace("n = 32", "n = 33")))
    assert load_scene(write(tmp_path, TINY.replace("n = 32", "n = 33")
                            + "[bem]\nreference_error = false\n")).surface.n == 33
