"""End to end: a tiny scene through the command line into a report folder."""

import csv
import subprocess
import sys

import numpy as np
import pytest

import asperity
import bem
from validation import wm_surface
from validation.cli import main

SCENE = """
name = "tiny-e2e"
title = "Tiny end-to-end scene"
[surface]
D = 2.4
rms_slope = 0.1
n = 32
[realizations]
count = 2
seed = 3
[loads]
min = 1e-4
max = 1e-2
count = 4
[bem]
tol = 1e-8
reference_error = true
"""


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    folder = tmp_path_factory.mktemp("e2e")
    scene = folder / "tiny.toml"
    scene.write_text(SCENE)
    out = folder / "out"
    assert main(["report", str(scene), "--out", str(out), "--no-cache", "--jobs", "1", "--quiet"]) == 0
    return out


def rows(path):
    with open(path, newline="") as stream:
        return list(csv.DictReader(stream))


def test_report_figures_and_tables_exist(report):
    text = "\n".join(p.read_text() for p in sorted(report.glob("*.md")))  # front and scene pages
    assert "Tiny end-to-end scene" in text
    assert "## Findings" in text and "Verdicts per load point" in text and "✔ / ✘ / ?" in text
    for name in ("tiny-e2e-fig4-separation.png", "tiny-e2e-fig5-load.png", "tiny-e2e-errors-D2.4.png",
                 "tiny-e2e-verdicts-D2.4.png"):
        assert (report / name).stat().st_size > 10_000
        assert f"]({name})" in text
    for name in ("curves.csv", "errors.csv", "verdicts.csv", "validity.csv", "findings.csv"):
        assert rows(report / name)
    # the error atlas' section and figure: what is predicted before any solve
    front = (report / "report.md").read_text()
    assert "## Before the solve: the error atlas" in front and "](error-atlas.png)" in front
    assert front.index("## Before the solve") < front.index("## Data")
    assert (report / "error-atlas.png").stat().st_size > 10_000


def test_csv_numbers_match_the_library(report):
    table = rows(report / "curves.csv")
    heights = wm_surface(32, D=2.4, rms_slope=0.1, seed=4)  # second realization: seed 3 + 1
    loads = np.logspace(-4, -2, 4)
    direct = bem.contact_curve(heights, 1 / 32, loads=loads, tol=1e-8,
                               quantities=("area", "load", "separation", "conductance"))
    summits = asperity.find_summits(heights, 1 / 32)
    gw = summits.greenwood_williamson(1.0).at_load(loads)
    sigma = float(np.std(summits.height))
    for model, curve in (("bem", direct), ("gw", gw)):
        mine = [r for r in table if r["model"] == model and r["seed"] == "4" and r["n"] == "32"]
        assert len(mine) == 4
        # the tables carry 10 significant digits
        np.testing.assert_allclose([float(r["Area"]) for r in mine], curve.area, rtol=1e-9)
        np.testing.assert_allclose([float(r["Load"]) for r in mine], loads, rtol=1e-9)
        np.testing.assert_allclose([float(r["Separation"]) for r in mine], curve.separation / sigma,
                                   rtol=1e-9)
        np.testing.assert_allclose([float(r["Conductance"]) for r in mine],
                                   curve.conductance * sigma, rtol=1e-9)


def test_bad_scene_exits_non_zero_with_a_message(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(SCENE.replace("D = 2.4", "D = 3.4"))
    process = subprocess.run([sys.executable, "-m", "validation", "report", str(bad), "--out",
                              str(tmp_path / "o"), "--no-cache"], capture_output=True, text=True)
    assert process.returncode == 2
    assert "surface.D" in process.stderr and "bad.toml" in process.stderr


def test_list_and_show(capsys):
    assert main(["list"]) == 0
    assert "paper-wm-d205" in capsys.readouterr().out
    assert main(["show", "validity-map"]) == 0
    assert "2.95" in capsys.readouterr().out


def test_scheduler_without_dask_says_what_to_install(tmp_path, monkeypatch):
    # dask is optional and imported only for --scheduler; without it the message says so.
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    monkeypatch.setitem(sys.modules, "dask", None)
    with pytest.raises(SystemExit, match="dask"):
        main(["report", "paper-theory", "--out", str(tmp_path), "--no-cache", "--scheduler",
              "tcp://127.0.0.1:1"])


def _run(*arguments):
    return subprocess.run([sys.executable, "-m", "validation", "report", *map(str, arguments)],
                          capture_output=True, text=True, timeout=120)


def test_unwritable_out_or_cache_fails_before_computing(tmp_path):
    # paper-wm-d205 takes minutes: a prompt exit 2 shows nothing was computed first.
    process = _run("paper-wm-d205", "--out", "/proc/nope", "--no-cache", "--jobs", "1")
    assert process.returncode == 2 and "Traceback" not in process.stderr
    assert "--out '/proc/nope' is not a writable directory" in process.stderr
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    process = _run("paper-wm-d205", "--out", tmp_path / "o", "--cache", blocker, "--jobs", "1")
    assert process.returncode == 2 and "Traceback" not in process.stderr
    assert "--cache" in process.stderr and "not a writable directory" in process.stderr


def test_binary_scene_file_is_a_clean_error(tmp_path):
    binary = tmp_path / "scene.toml"
    binary.write_bytes(bytes(range(256)) * 4)
    process = _run(binary, "--out", tmp_path / "o", "--no-cache")
    assert process.returncode == 2 and "Traceback" not in process.stderr
    assert "scene.toml" in process.stderr and "not a text scene file" in process.stderr


@pytest.mark.parametrize("arguments, size_scene, quick", [
    ([], False, True), (["--full"], True, False), (["--publish", "{out}"], True, False)])
def test_the_size_scene_runs_in_the_full_and_published_reports_only(tmp_path, monkeypatch,
                                                                    arguments, size_scene,
                                                                    quick):
    import validation.report.write
    import validation.judge.decide

    seen = {}

    def run(scenes, **kwargs):
        seen["scenes"] = list(scenes)
        return []

    monkeypatch.setattr(validation.judge.decide, "run_scenes", run)
    monkeypatch.setattr(validation.report.write, "write_report",
                        lambda results, out, **kwargs: out)
    out = str(tmp_path / "out")
    arguments = [a.replace("{out}", out) for a in arguments]
    assert main(["report", "--out", out, "--no-cache", "--jobs", "1", "--quiet", *arguments]) == 0
    names = [scene.name for scene in seen["scenes"]]
    assert ("sealing-size" in names) == size_scene
    assert {"paper-wm-d205", "paper-wm-d295", "validity-map"} <= set(names)
    paper = next(s for s in seen["scenes"] if s.name == "paper-wm-d205")
    assert ("leakage" in paper.quantities) == (not quick)
    # the quick report leaves the finer reference to the full one
    assert (paper.bem.max_grid is None) == quick


def test_the_console_script_is_the_command_line():
    import importlib
    import pathlib
    import shutil
    import subprocess
    import tomllib

    import validation.cli

    root = pathlib.Path(__file__).resolve().parents[1]
    target = tomllib.loads((root / "pyproject.toml").read_text(encoding="utf-8"))[
        "project"]["scripts"]["asperity-validation"]
    module, _, name = target.partition(":")
    assert getattr(importlib.import_module(module), name) is validation.cli.main
    script = shutil.which("asperity-validation")
    if script is None:
        pytest.skip("the package is not installed with its scripts here")
    done = subprocess.run([script, "list"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and "paper-wm-d205" in done.stdout
    usage = subprocess.run([script, "--help"], capture_output=True, text=True, timeout=120)
    assert usage.stdout.startswith("usage: asperity-validation")
