"""The report renders whatever it has: unconverged points, empty ranges, no converged BEM."""

import csv
import pathlib

import numpy as np
import pytest

from validation.cli import main
from validation.report.write import write_report
from validation import run_scenes
from validation.scenes.reader import parse_scene

NEVER_CONVERGED = {
    "name": "never-converged",
    "title": "A BEM that stops after five iterations",
    "surface": {"D": 2.4, "rms_slope": 0.1, "n": 32},
    "realizations": {"count": 3, "seed": 3},
    "loads": {"min": 1e-4, "max": 1e-2, "count": 4},
    "bem": {"tol": 1e-10, "max_iter": 5, "reference_error": True},
}


@pytest.fixture(scope="module")
def unconverged():
    import warnings

    import bem

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bem.ConvergenceWarning)
        return run_scenes([parse_scene(NEVER_CONVERGED, source="test")], progress=False)


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return list(csv.DictReader(stream))


def report_text(folder) -> str:
    """The report's front page and every scene page of ``folder``, as one text."""
    return "\n".join(p.read_text(encoding="utf-8") for p in sorted(pathlib.Path(folder).glob("*.md")))


def test_report_with_no_converged_bem_point(unconverged, tmp_path):
    # Regression: every BEM point unconverged used to stop the report at the first log-scaled
    # figure ("Data cannot be log-scaled"); now every figure and table is written.
    (result,) = unconverged
    assert not any(r.curves["bem"].extras["converged"].any()
                   for r in result.realizations[2.4])
    write_report(unconverged, tmp_path, seconds=12.0, command="python -m validation x")
    text = report_text(tmp_path)
    for name in ("fig4-separation", "fig5-load", "errors-D2.4", "verdicts-D2.4"):
        assert (tmp_path / f"never-converged-{name}.png").stat().st_size > 5_000
    verdicts = rows(tmp_path / "verdicts.csv")
    assert verdicts and {v["verdict"] for v in verdicts} == {"undecided"}
    bem_rows = [r for r in rows(tmp_path / "curves.csv") if r["model"] == "bem"]
    assert len(bem_rows) == 12 and {r["converged"] for r in bem_rows} == {"False"}
    assert "`????`" in text and "undecided: unconverged" in text and "**0 / 0 /" in text
    assert "fewer than two converged BEM realizations" in text  # finding (c) says why
    assert "Command: `python -m validation x`" in text and "run time 0.2 min" in text


def test_persson_row_is_compared_by_its_mean_gap(tmp_path):
    # Persson's separation is a mean gap: its rows say so, and are computed against the BEM's
    # mean gap, which curves.csv lists beside the BEM's separation d
    scene = parse_scene({"name": "persson-row", "title": "Persson beside GW",
                         "surface": {"D": 2.4, "rms_slope": 0.1, "n": 32},
                         "realizations": {"count": 2, "seed": 1},
                         "loads": {"min": 1e-4, "max": 1e-2, "count": 3},
                         "models": {"use": ["gw", "persson", "bem"]}}, source="test")
    results = run_scenes([scene], progress=False)
    write_report(results, tmp_path)
    text = report_text(tmp_path)
    validity = rows(tmp_path / "validity.csv")
    fields = {(r["model"], r["quantity"]): r["reference_field"] for r in validity}
    assert fields[("persson", "separation")] == "mean_gap"
    assert fields[("gw", "separation")] == "separation"
    assert "| Persson | mean gap ū |" in text and "| original GW | separation d |" in text
    holds = text.split("## Where each theory holds")[1].split("##")[0]   # one table, per scene
    assert "| Persson |" in holds and "| original GW |" in holds and "mean gap ū:" in holds
    curves = rows(tmp_path / "curves.csv")
    errors = [r for r in rows(tmp_path / "errors.csv")
              if r["model"] == "persson" and r["quantity"] == "separation"]
    for realization in results[0].realizations[2.4]:
        bem = realization.curves["bem"]
        gap = [float(r["mean_gap"]) for r in curves
               if r["model"] == "bem" and int(r["seed"]) == realization.task.seed]
        np.testing.assert_allclose(gap, bem.extras["mean_gap"], rtol=1e-9)
        assert not np.allclose(bem.extras["mean_gap"], bem.separation)   # two different fields
    # Persson describes an unbounded interface: it is judged against the interface reference,
    # whose separation is its mean gap (zero mean displacement on the periodic half-space)
    assert {r["frame"] for r in errors} == {"interface"}
    expected = np.mean([(r.curves["persson"].separation
                         - r.curves["bem_interface"].extras["mean_gap"])
                        / r.sigma for r in results[0].realizations[2.4]], axis=0)
    for r in results[0].realizations[2.4]:
        interface = r.curves["bem_interface"]
        np.testing.assert_allclose(interface.extras["mean_gap"], interface.separation,
                                   rtol=1e-6, atol=1e-9 * r.sigma)
    np.testing.assert_allclose([float(r["mean_error"]) for r in errors], expected, rtol=1e-8)


def test_tables_are_written_before_the_figures(unconverged, tmp_path, monkeypatch):
    import validation.report.figures

    def broken(*args, **kwargs):
        raise RuntimeError("figure failed")

    monkeypatch.setattr(validation.report.figures, "panels_figure", broken)
    with pytest.raises(RuntimeError, match="figure failed"):
        write_report(unconverged, tmp_path)
    for name in ("curves.csv", "errors.csv", "verdicts.csv", "validity.csv", "findings.csv"):
        assert rows(tmp_path / name)
    # the folder of the unfinished report is still a report's: the next report replaces it
    assert "not finished" in (tmp_path / "report.md").read_text(encoding="utf-8")
    monkeypatch.undo()
    assert "not finished" not in write_report(unconverged, tmp_path).read_text(encoding="utf-8")


@pytest.mark.slow
def test_publish_replaces_the_previous_report(tmp_path, monkeypatch):
    # the theory scene alone: a published report in seconds, header with the exact command
    folder = tmp_path / "results"
    folder.mkdir()
    (folder / "report.md").write_text("# an earlier report")
    (folder / "stale-figure.png").write_bytes(b"old")
    (folder / "notes.txt").write_text("kept")
    assert main(["report", "paper-theory", "--publish", str(folder), "--no-cache", "--quiet"]) == 0
    text = (folder / "report.md").read_text(encoding="utf-8")
    assert not (folder / "stale-figure.png").exists() and (folder / "notes.txt").exists()
    assert f"Command: `python -m validation report paper-theory --publish {folder} " in text
    assert "mode: full" in text and "## Findings" in text


def test_report_only_modules_do_not_compute_results():
    # The cache hash leaves out the modules that only read results; none of them may be
    # imported by a module that computes the cached results.
    import ast
    import pathlib

    from validation.run.cache import REPORT_ONLY_MODULES

    package = pathlib.Path(__file__).resolve().parents[1] / "validation"

    def files(module: str) -> set[str]:
        """The module's path relative to the validation folder (and that of a sub-package)."""
        if not module.startswith("validation."):
            return set()
        stem = module.removeprefix("validation.").replace(".", "/")
        return {f"{stem}.py", f"{stem}/__init__.py"}

    for path in package.rglob("*.py"):
        name = path.relative_to(package).as_posix()
        if name in REPORT_ONLY_MODULES:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        imported = {file for node in ast.walk(tree) if isinstance(node, ast.Import)
                    for alias in node.names for file in files(alias.name)}
        imported |= {file for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and node.module
                     for alias in node.names
                     for file in files(node.module) | files(f"{node.module}.{alias.name}")}
        # entry points, not result makers
        allowed = {"campaigns/bench.py", "campaigns/stress.py", "__init__.py"}
        # the progress bar, the task order/ETA and the sequential plan (how many realizations
        # run, never what one computes) never touch a result
        imported -= {"run/progress.py", "run/cost.py", "run/sequential.py"}
        if name not in allowed:
            assert not imported & REPORT_ONLY_MODULES, (name, imported & REPORT_ONLY_MODULES)


SEALING = {
    "name": "tiny-sealing",
    "title": "Leakage on nested windows",
    "surface": {"D": 2.3, "rms_slope": 0.1, "n": 32, "n_max": 4, "wavelength": 1.0,
                "sides": [1.0, 2.0]},
    "realizations": {"count": 2, "seed": 1},
    "loads": {"min": 1e-3, "max": 3e-2, "count": 4},
    "models": {"use": ["gw", "improved_gw", "bem"], "m": 0.9464},
    "quantities": {"use": ["area", "load", "separation", "leakage"]},
    "bem": {"tol": 1e-8, "reference_error": True},
}


def test_a_leakage_size_scene_reports_its_findings_figures_and_columns(tmp_path):
    results = run_scenes([parse_scene(SEALING, source="test")], progress=False)
    write_report(results, tmp_path, seconds=1.0)
    text = (tmp_path / "tiny-sealing.md").read_text(encoding="utf-8")
    # finding (g) spans the sizes; (f) is checked per size (shown in findings.csv)
    assert "| (g) it is harder to seal a large area than a small one | L = 1, 2 |" in text
    front = (tmp_path / "report.md").read_text(encoding="utf-8")
    assert "| (g) it is harder to seal a large area than a small one |" in front
    assert "[tiny-sealing](tiny-sealing.md), L = 1, 2" in front
    findings = rows(tmp_path / "findings.csv")
    assert {(r["finding"], r["L"]) for r in findings if r["finding"] in "fg"} == {
        ("f", "1"), ("f", "2"), ("g", "")}
    assert (tmp_path / "tiny-sealing-sizes.png").stat().st_size > 5_000
    errors = [r for r in rows(tmp_path / "errors.csv") if r["quantity"] == "leakage"]
    assert {r["model"] for r in errors} == {"gw", "improved_gw"}
    assert all(r["sealing_disagreements"].isdigit() for r in errors)
    bem_rows = [r for r in rows(tmp_path / "curves.csv") if r["model"] == "bem"]
    assert {r["L"] for r in bem_rows} == {"1", "2"} and {r["n"] for r in bem_rows} == {"32", "64"}
    for r in bem_rows:   # h_eff / sigma beside h_eff and its error estimate
        np.testing.assert_allclose(float(r["Leakage"]) * float(r["sigma"]), float(r["leakage"]),
                                   rtol=1e-8)
        assert float(r["leakage_error"]) >= 0


def test_a_figure_drawn_by_other_drawing_code_is_not_read_from_the_cache(monkeypatch):
    import functools

    from validation.report import write
    from validation.run import cache

    draw = functools.partial(len, [1, 2])
    key = write._figure_key("figure.png", draw)
    assert key == write._figure_key("figure.png", draw)
    monkeypatch.setattr(cache, "_REPORT_VERSION", "another drawing code")
    assert write._figure_key("figure.png", draw) != key
    # the modules that draw are the ones report_version hashes
    assert {"report/figures.py", "report/atlas.py", "report/sealing_figures.py",
            "report/layout.py", "check/figure.py"} <= cache.REPORT_ONLY_MODULES
