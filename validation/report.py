"""The validity report: Markdown, PNG figures and CSV tables in one folder.

``write_report`` compares every surface scene with its reference (:mod:`validation.compare`),
checks the paper's findings (:mod:`validation.findings`), writes the CSV tables first (so the
numbers survive whatever the figures do), then ``report.md``: its text from
:mod:`validation.report_sections`, its figures from :mod:`validation.figures` (matplotlib
imported lazily), placed here.
"""

from __future__ import annotations

import hashlib
import pathlib
import pickle
from dataclasses import dataclass, field, replace
from functools import partial

import numpy as np

from validation import models
from validation.cache import Cache, cache_key
from validation.compare import COMPARED_QUANTITIES, Comparison, compare_realizations
from validation.figures import dimensionless
from validation.findings import Finding, check_findings
from validation.labels import MODEL_LABELS, QUANTITY_LABELS, model_order, model_rank
from validation.report_sections import (REPORT_QUANTITIES, findings_section, header,
                                        holds_section, md_table, surface_text, sweep_member,
                                        timing, verdict_table)
from validation.runner import SceneResult

__all__ = ["write_report", "analyse", "Analysis", "md_table", "dimensionless", "MODEL_LABELS",
           "QUANTITY_LABELS"]

@dataclass(frozen=True)
class Analysis:
    """One scene's results with its comparisons and findings, by sweep value (D, H)."""

    result: SceneResult
    comparisons: list[Comparison] = field(default_factory=list)
    findings: dict[float, list[Finding]] = field(default_factory=dict)


def analyse(result: SceneResult) -> Analysis:
    """Compare every sweep value (D, H) of a surface scene with the reference (the BEM) and
    check the paper's findings; a scene without a reference model gets no comparison."""
    scene = result.scene
    if scene.kind == "theory" or not set(scene.models) & set(models.reference_names()):
        return Analysis(result)
    comparisons, findings = [], {}
    for value, realizations in sorted(result.realizations.items()):
        comparison = compare_realizations(realizations, tolerances=scene.tolerances)
        comparisons.append(comparison)
        findings[value] = check_findings(realizations, comparison, scene.tolerances)
    return Analysis(result, comparisons, findings)


# --------------------------------------------------------------------------------------------
# figures


@dataclass
class _Figures:
    """Collects the report's figures with their Markdown lines; :meth:`render` draws them.

    Each figure is a job ``draw()`` that returns a matplotlib figure: a picklable callable
    (partials of module-level functions), so that the figures can be drawn in other processes.
    """

    folder: pathlib.Path
    lines: list
    jobs: list = field(default_factory=list)  # (file name, draw, panels) in report order

    def add(self, draw, name: str, caption: str, panels: int = 1) -> None:
        """Queue ``draw`` (``panels``: its number of axes, the cost estimate that orders the
        parallel drawing) and its Markdown lines."""
        self.jobs.append((name, draw, panels))
        self.lines += [f"![{caption}]({name})\n", f"*{caption}*\n"]

    def render(self, executor=None, cache_dir=None) -> None:
        """Draw every figure into the folder: here, or on ``executor`` (a
        ``concurrent.futures`` executor; the PNG bytes come back and are written here).

        With ``cache_dir``, a figure drawn before from the same job (the pickled ``draw`` with
        all the data it draws), file name, code and matplotlib version is read from the cache.
        """
        cache = Cache(cache_dir)
        keys = {name: _figure_key(name, draw) for name, draw, _ in self.jobs} if cache.enabled \
            else {}
        todo = []
        for job in self.jobs:
            stored = cache.load(keys[job[0]]) if keys.get(job[0]) else None
            if stored is not None and "png" in stored:
                (self.folder / job[0]).write_bytes(stored["png"].tobytes())
            else:
                todo.append(job)
        for name, data in _drawn(todo, executor):
            (self.folder / name).write_bytes(data)
            if keys.get(name):
                cache.store(keys[name], {"png": np.frombuffer(data, dtype=np.uint8)})


def _drawn(jobs: list, executor):
    """(file name, PNG bytes) of every job, drawn here or on ``executor``."""
    from validation.figures import png

    if executor is None:
        for name, draw, _ in jobs:
            yield name, png(draw())
        return
    # the costliest figures (most panels) first, so that no worker is left with one at the end
    order = sorted(jobs, key=lambda job: -job[2])
    futures = [(name, executor.submit(_png_of, draw)) for name, draw, _ in order]
    for name, future in futures:
        yield name, future.result()


def _figure_key(name: str, draw) -> str | None:
    """Cache key of a figure job, None when it cannot be pickled (it is then drawn anyway)."""
    from importlib.metadata import version

    from validation.runner import _version

    try:
        job = hashlib.sha256(pickle.dumps(draw, protocol=5)).hexdigest()
    except (pickle.PicklingError, AttributeError, TypeError):
        return None
    return cache_key("figure", _version(), name=name, job=job, matplotlib=version("matplotlib"))


def _png_of(draw) -> bytes:
    """The PNG bytes of the figure ``draw()`` returns (a top-level function for process pools)."""
    from validation.figures import png

    return png(draw())


def _file_suffix(parameter: str, value: float) -> str:
    return f"-{parameter}{value:g}" if parameter else ""


def _against(results, x: str, models, length: float, logx: bool, ax, y: str):
    from validation.figures import plot_against

    return plot_against(ax, results, x, y, models=models, length=length, logx=logx)


def _errors(comparison: Comparison, tolerances, ax, quantity: str):
    from validation.figures import plot_errors

    return plot_errors(ax, comparison, quantity, tolerances)


def _theory_panel(plot: str, theory: dict, ax, C: float):
    from validation import figures

    return getattr(figures, plot)(ax, theory, C)


def _curve_figures(figures: _Figures, scene, results, value: float) -> None:
    from validation.figures import panels_figure

    models = model_order(results[0].curves)
    # what a run computed and how long it took is not drawn: left out of the figure's cache key
    results = [replace(r, computed=(), seconds={}) for r in results]
    L = scene.surface.L
    conductance = "conductance" in scene.quantities
    panels = ["area", "load"] + (["conductance"] if conductance else [])
    figures.add(partial(panels_figure, partial(_against, results, "separation", models, L, False),
                        panels),
                f"{scene.name}-fig4-separation.png",
                f"Area, load{' and conductance' if conductance else ''} against separation, "
                f"{sweep_member(scene.surface.sweep_name, value)} (paper Fig. 4, BEM added; thin "
                f"lines: realizations; dotted: the BEM against its mean gap ū/σ, the quantity "
                f"Persson's curve is drawn against).", len(panels))
    figures.add(partial(panels_figure, partial(_against, results, "load", models, L, True),
                        panels[::2]),
                f"{scene.name}-fig5-load.png",
                f"Area{' and conductance' if conductance else ''} against load, "
                f"{sweep_member(scene.surface.sweep_name, value)} (paper Fig. 5, BEM added).",
                len(panels[::2]))


def _comparison_figures(figures: _Figures, scene, comparison: Comparison) -> None:
    from validation.figures import panels_figure, verdict_figure

    quantities = sorted({q for (_, q) in comparison.models}, key=REPORT_QUANTITIES.index)
    if not quantities:
        return
    at, suffix = (f(comparison.parameter, comparison.value) for f in (sweep_member, _file_suffix))
    figures.add(partial(panels_figure, partial(_errors, comparison, scene.tolerances), quantities,
                        legend=7),
                f"{scene.name}-errors{suffix}.png",
                f"Mean error of each model against the BEM at equal load, {at} "
                f"(coloured band: 95 % interval over realizations; grey: reference band; dotted "
                f"red: tolerances).", len(quantities))
    figures.add(partial(verdict_figure, comparison), f"{scene.name}-verdicts{suffix}.png",
                f"Verdict per load point, {at}: ✔ holds, ✘ fails, ? undecided.",
                len(scene.tolerances))


def _surface_section(figures: _Figures, analysis: Analysis) -> None:
    result, lines = analysis.result, figures.lines
    scene, s = result.scene, result.scene.surface
    count = len(next(iter(result.realizations.values()), []))
    lines.append(surface_text(scene, count))
    if not analysis.comparisons:
        lines.append("No BEM reference in this scene: curves only, no verdicts.\n")
    for value, results in sorted(result.realizations.items()):
        comparison = next((c for c in analysis.comparisons if c.value == value), None)
        lines.append(f"### {sweep_member(s.sweep_name, value)}\n")
        counts = [r.summit_count for r in results]
        if any(counts) and comparison is not None:
            lines.append(f"Summits per realization: {min(counts)}–{max(counts)}; reference area "
                         f"fraction {100 * comparison.area_fraction[0]:.3g} % – "
                         f"{100 * comparison.area_fraction[-1]:.3g} % over the load path.\n")
        if len(s.sweep_values) == 1:
            _curve_figures(figures, scene, results, value)
        if comparison is not None:
            _comparison_figures(figures, scene, comparison)
            lines.extend(verdict_table(comparison, scene.tolerances))
    if len(s.sweep_values) > 1 and analysis.comparisons:
        _validity_map(figures, scene, analysis.comparisons)


def _validity_map(figures: _Figures, scene, comparisons: list[Comparison]) -> None:
    from validation.figures import validity_map_figure

    keys = sorted({k for c in comparisons for k in c.models if k[1] in COMPARED_QUANTITIES},
                  key=lambda k: (model_rank(k[0]), COMPARED_QUANTITIES.index(k[1])))
    if keys:
        figures.add(partial(validity_map_figure, comparisons, keys=keys,
                            tolerances=scene.tolerances),
                    f"{scene.name}-validity-map.png",
                    "Validity map: |mean error| of each model against the BEM over load and "
                    f"{scene.surface.sweep_name}; "
                    f"white contours at the tolerances {', '.join(f'{t:g}' for t in scene.tolerances)}.",
                    len(keys))


def _theory_section(figures: _Figures, result: SceneResult) -> None:
    from validation.figures import panels_figure

    theory = result.theory
    for index, C in enumerate(theory["C"]):
        figures.add(partial(panels_figure, partial(_theory_panel, "plot_theory_load", theory), [C],
                            width=5.5),
                    f"{result.scene.name}-fig{index + 1}-C{C:g}.png",
                    f"Load against separation, GW and improved GW, C = {C:g} "
                    f"(paper Fig. {index + 1}).")
    figures.add(partial(panels_figure, partial(_theory_panel, "plot_theory_stiffness", theory),
                        list(theory["C"]), width=5.5),
                f"{result.scene.name}-fig3-stiffness.png",
                "GW stiffness dW/dd₁ and the true stiffness dW/dd with interaction (paper Fig. 3).",
                len(theory["C"]))
    rows = [[f"{C:g}", f"{np.min(theory[C].improved_stiffness / theory[C].effective_stiffness):.3g}",
             f"{np.max(theory[C].effective_separation - theory[C].separation):.3g}"]
            for C in theory["C"]]
    figures.lines += md_table(["C", "smallest ratio of true to GW stiffness dW/dd ÷ dW/dd₁",
                               "largest separation shift (d₁ − d)/σ"], rows)


def write_report(results: list[SceneResult], folder: str | pathlib.Path, *,
                 seconds: float | None = None, mode: str = "", command: str | None = None,
                 executor=None, cache_dir: str | pathlib.Path | None = None) -> pathlib.Path:
    """Write the CSV tables, then ``report.md`` with its PNG figures, into ``folder``.

    ``command`` (the command line that produced the results), the package version and the run
    time ``seconds`` head the report. The figures are drawn on ``executor`` (a
    ``concurrent.futures`` executor, e.g. the runner's process pool) when given, else here;
    figures drawn before from the same data are read from ``cache_dir`` when given. Returns the
    path of ``report.md``.
    """
    from validation.tables import write_tables

    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    analyses = [analyse(result) for result in results]
    written = write_tables(folder, analyses)
    figures = _Figures(folder, header(seconds, mode, command))
    figures.lines += holds_section(analyses)
    figures.lines += findings_section(analyses)
    for analysis in analyses:
        scene = analysis.result.scene
        figures.lines += [f"## {scene.title}\n",
                          f"Scene `{scene.name}` ({scene.source}). {scene.description.strip()}\n"]
        if scene.kind == "theory":
            _theory_section(figures, analysis.result)
            continue
        _surface_section(figures, analysis)
        figures.lines += timing(analysis.result)
    figures.lines += ["## Data\n"] + [f"- [`{name}`]({name})" for name in written] + [""]
    figures.render(executor, cache_dir)
    path = folder / "report.md"
    path.write_text("\n".join(figures.lines) + "\n", encoding="utf-8")
    return path

