"""The validity report: Markdown, PNG figures and CSV tables in one folder.

``write_report`` compares every surface scene with its reference (:mod:`validation.judge.compare`),
reads the headline (:mod:`validation.judge.headline`), checks the paper's findings
(:mod:`validation.judge.findings`), writes the CSV tables first (so the numbers survive whatever
the figures do), then one page per scene (``SCENE.md``: its details, text from
:mod:`validation.report.sections`) and ``report.md``, the page a reader starts from: the
summary (:mod:`validation.report.summary`), the headline tables and atlas figures
(:mod:`validation.report.front`, :mod:`validation.report.atlas`), the findings at a glance and
links to the scene pages. Figures from :mod:`validation.report.figures` (matplotlib imported
lazily), placed here.
"""

from __future__ import annotations

import hashlib
import pathlib
import pickle
from dataclasses import dataclass, field, replace
from functools import partial

import numpy as np

from bem.common import checks
from validation.judge.analysis import Analysis, analyse
from validation.judge.compare import COMPARED_QUANTITIES, Comparison
from validation.report.figures import dimensionless
from validation.report.folder import REPORT_FILES, previous_report
from validation.common.labels import MODEL_LABELS, QUANTITY_LABELS, model_order, model_rank
from validation.report.sampling import sampling_section
from validation.report.sections import (REPORT_QUANTITIES, header, md_table, scene_findings,
                                        surface_text, sweep_member, timing, validity_section,
                                        verdict_table)
from validation.run.cache import Cache, cache_key
from validation.run.runner import SceneResult

__all__ = ["write_report", "md_table", "dimensionless", "MODEL_LABELS", "QUANTITY_LABELS",
           "REPORT_FILES", "previous_report"]

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
    from validation.report.figures import png

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

    from validation.run.cache import report_version, source_version

    try:
        job = hashlib.sha256(pickle.dumps(draw, protocol=5)).hexdigest()
    except (pickle.PicklingError, AttributeError, TypeError):
        return None
    # the drawing code is in the key too (source_version leaves the report's modules out)
    return cache_key("figure", source_version(), name=name, job=job, drawing=report_version(),
                     matplotlib=version("matplotlib"))


def _png_of(draw) -> bytes:
    """The PNG bytes of the figure ``draw()`` returns (a top-level function for process pools)."""
    from validation.report.figures import png

    return png(draw())


def _file_suffix(parameter: str, value: float) -> str:
    return f"-{parameter}{value:g}" if parameter else ""


def _against(results, x: str, models, length: float, logx: bool, ax, y: str):
    from validation.report.figures import plot_against

    return plot_against(ax, results, x, y, models=models, length=length, logx=logx)


def _errors(comparison: Comparison, tolerances, ax, quantity: str):
    from validation.report.figures import plot_errors

    return plot_errors(ax, comparison, quantity, tolerances)


def _theory_panel(plot: str, theory: dict, ax, C: float):
    from validation.report import figures

    return getattr(figures, plot)(ax, theory, C)


def _curve_figures(figures: _Figures, scene, results, value: float) -> None:
    from validation.report.figures import panels_figure

    models = model_order(results[0].curves)
    # what a run computed and how long it took is not drawn: left out of the figure's cache key
    results = [replace(r, computed=(), seconds={}) for r in results]
    L = results[0].task.surface.L
    conductance = "conductance" in scene.quantities
    panels = ["area", "load"] + (["conductance"] if conductance else [])
    # the paper's figures are of WM surfaces: other surfaces get the same plots, not its name
    paper = scene.surface.family == "wm"
    members = "tiles" if scene.surface.family == "file" else "realizations"
    thin = "" if len(results) == 1 else f"thin lines: {members}; "
    figures.add(partial(panels_figure, partial(_against, results, "separation", models, L, False),
                        panels),
                f"{scene.name}-fig4-separation.png",
                f"Area, load{' and conductance' if conductance else ''} against separation, "
                f"{sweep_member(scene.surface.sweep_name, value)} "
                f"({'paper Fig. 4, BEM added; ' if paper else ''}{thin}dotted: "
                f"the BEM against its mean gap ū/σ, the quantity Persson's curve is drawn "
                f"against).", len(panels))
    figures.add(partial(panels_figure, partial(_against, results, "load", models, L, True),
                        panels[::2]),
                f"{scene.name}-fig5-load.png",
                f"Area{' and conductance' if conductance else ''} against load, "
                f"{sweep_member(scene.surface.sweep_name, value)}"
                f"{' (paper Fig. 5, BEM added)' if paper else ''}.", len(panels[::2]))
    if "leakage" in scene.quantities:
        from validation.report.sealing_figures import leakage_figure

        figures.add(partial(leakage_figure, results, models=models, length=L),
                    f"{scene.name}-leakage.png",
                    f"Leakage: the effective hydraulic aperture h_eff/σ against load and against "
                    f"separation, {sweep_member(scene.surface.sweep_name, value)} ({thin}"
                    f"grey: the BEM ± its error estimate; GW, improved GW and the "
                    f"discrete model: the rigid gap at d, d₁ and the discrete model's own d; "
                    f"the theories from the spectral moments: the rigid gap of rms √m₀; all "
                    f"drawn against their separation d; Persson: its gap distribution, against "
                    f"its mean gap; docs/theory.md section 10).", 2)


def _comparison_figures(figures: _Figures, scene, comparison: Comparison,
                        one_surface: bool = False) -> None:
    from validation.report.figures import panels_figure, verdict_figure

    quantities = sorted({q for (_, q) in comparison.models}, key=REPORT_QUANTITIES.index)
    if not quantities:
        return
    at, suffix = (f(comparison.parameter, comparison.value) for f in (sweep_member, _file_suffix))
    figures.add(partial(panels_figure, partial(_errors, comparison, scene.tolerances), quantities,
                        legend=7),
                f"{scene.name}-errors{suffix}.png",
                (f"Error of each model against the BEM at equal load on this one surface, {at} "
                 f"(grey: reference band; dotted red: tolerances)." if one_surface else
                 f"Mean error of each model against the BEM at equal load, {at} "
                 f"(coloured band: 95 % interval over realizations; grey: reference band; "
                 f"dotted red: tolerances)."), len(quantities))
    figures.add(partial(verdict_figure, comparison), f"{scene.name}-verdicts{suffix}.png",
                f"Verdict per load point, {at}: ✔ holds, ✘ fails, ? undecided.",
                len(scene.tolerances))


def _surface_lines(analysis: Analysis) -> list[str]:
    """The surfaces, the reference and the realizations of a scene, in a few sentences."""
    result = analysis.result
    scene, s = result.scene, result.scene.surface
    count = len(next(iter(result.realizations.values()), []))
    lines = [surface_text(scene, count)]
    if result.refinement is not None:
        lines.append(f"Reference: {result.refinement.describe(s.sweep_name)}.\n")
    if result.sequential is not None and scene.realizations > 1:
        lines.append(f"Realizations per {s.sweep_name or 'surface'}: "
                     f"{result.sequential.describe()}.\n")
    if not analysis.comparisons:
        lines.append("No BEM reference in this scene: curves only, no verdicts.\n")
    return lines


def _surface_section(figures: _Figures, analysis: Analysis) -> None:
    """Per surface family: the curves, errors and verdicts; then the validity map, the sizes."""
    result, lines = analysis.result, figures.lines
    scene, s = result.scene, result.scene.surface
    if analysis.comparisons or result.realizations:
        lines.append("## Surfaces, curves and verdicts point by point\n")
    for value, results in sorted(result.realizations.items()):
        comparison = next((c for c in analysis.comparisons if c.value == value), None)
        lines.append(f"### {sweep_member(s.sweep_name, value)}\n")
        counts = [r.summit_count for r in results]
        if any(counts) and comparison is not None:
            summits = (f"Summits: {counts[0]}" if len(counts) == 1 else
                       f"Summits per realization: {min(counts)}–{max(counts)}")
            lines.append(f"{summits}; reference area "
                         f"fraction {100 * comparison.area_fraction[0]:.3g} % – "
                         f"{100 * comparison.area_fraction[-1]:.3g} % over the load path.\n")
        if len(s.sweep_values) == 1:
            _curve_figures(figures, scene, results, value)
        if comparison is not None:
            _comparison_figures(figures, scene, comparison, one_surface=len(results) == 1)
            lines.extend(verdict_table(comparison, scene.tolerances))
    if len(s.sweep_values) > 1 and analysis.comparisons:
        _validity_map(figures, scene, analysis.comparisons)
    if analysis.size_collapse is not None:
        from validation.report.sealing_figures import size_figure

        figures.add(partial(size_figure, result.realizations, analysis.size_collapse, scene.m),
                    f"{scene.name}-sizes.png",
                    "Finding (g): the BEM's leakage h_eff/σ against the separation d (left) and "
                    f"the effective separation d₁ = d + {scene.m:g} W/(E*√A) (right) on nested "
                    "windows of growing nominal area, σ the mean summit σ over all windows "
                    "(thin: realizations; dotted: the leakage levels at which the spread across "
                    "sizes is measured).", 2)


def _validity_map(figures: _Figures, scene, comparisons: list[Comparison]) -> None:
    from validation.report.figures import validity_map_figure

    keys = sorted({k for c in comparisons for k in c.models if k[1] in COMPARED_QUANTITIES},
                  key=lambda k: (model_rank(k[0]), COMPARED_QUANTITIES.index(k[1])))
    if keys:
        figures.add(partial(validity_map_figure, comparisons, keys=keys,
                            tolerances=scene.tolerances),
                    f"{scene.name}-validity-map.png",
                    "Validity map: |mean error| of each model against the BEM over load and "
                    f"{scene.surface.sweep_name}; contours at the tolerances "
                    f"{', '.join(f'{t:g}' for t in sorted(scene.tolerances))} (the legend says "
                    "which line is which).", len(keys))


def _theory_section(figures: _Figures, result: SceneResult) -> None:
    from validation.report.figures import panels_figure

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


def _check_arguments(results, folder, seconds, mode, command, executor, cache_dir,
                     figure_jobs=None) -> pathlib.Path:
    """The checks of :func:`write_report`'s arguments (bem.common.checks rules); returns the folder."""
    checks.instances("results", results, SceneResult)
    for name, value in (("mode", mode), ("command", command)):
        if not (isinstance(value, str) or value is None and name == "command"):
            raise checks.InputTypeError(f"{name} must be a str{' or None' * (name == 'command')}"
                                        f", got {type(value).__name__}")
    if seconds is not None:
        checks.non_negative("seconds", seconds)
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise checks.InputTypeError(f"executor must be a concurrent.futures.Executor or None, "
                                    f"got {type(executor).__name__}")
    if cache_dir is not None:
        checks.file_path("cache_dir", cache_dir)
    if figure_jobs is not None and not (isinstance(figure_jobs, (list, tuple)) and all(
            isinstance(job, tuple) and len(job) == 3 and isinstance(job[0], str)
            and callable(job[1]) for job in figure_jobs)):
        raise checks.InputTypeError(f"figure_jobs must be a list of (file name, draw, panels) "
                                    f"tuples, draw() returning a figure, or None; got "
                                    f"{figure_jobs!r}")
    return checks.file_path("folder", folder)


def _scene_page(figures: _Figures, analysis: Analysis, findings: bool = True) -> None:
    """A scene's page: where each theory holds, the findings with their numbers and rules,
    the sampling study, and per surface family its figures and verdict tables."""
    scene, lines = analysis.result.scene, figures.lines
    lines += [f"# {scene.title}\n",
              f"[← The report](report.md). Scene `{scene.name}` ({scene.source}). "
              f"{scene.description.strip()}\n"]
    if scene.kind == "theory":
        _theory_section(figures, analysis.result)
        return
    lines += _surface_lines(analysis)
    lines += validity_section(analysis)
    lines += scene_findings(analysis) if findings else []
    lines += sampling_section([analysis])
    _surface_section(figures, analysis)
    lines += timing(analysis.result)


def write_report(results: list[SceneResult], folder: str | pathlib.Path, *,
                 seconds: float | None = None, mode: str = "", command: str | None = None,
                 executor=None, cache_dir: str | pathlib.Path | None = None,
                 lead: list[str] | None = None, figure_jobs: list | None = None,
                 sections: list[str] | None = None) -> pathlib.Path:
    """Write the CSV tables, then the scene pages and ``report.md`` with their PNG figures,
    into ``folder``.

    ``lead`` (Markdown lines) are the first sections of ``report.md``, after its header: a
    one-scan check's answer (:class:`validation.check.result.CheckResult`), which then stands
    for the summary, and the paper's findings (about populations of surfaces) are left out.

    ``command`` (the command line that produced the results), the package version and the run
    time ``seconds`` head the report. A previous report in ``folder`` is replaced, its figures,
    tables and pages removed first; a folder holding other files and no report is refused
    (:func:`previous_report`). The figures are drawn on ``executor`` (a
    ``concurrent.futures`` executor, e.g. the runner's process pool) when given, else here;
    figures drawn before from the same data are read from ``cache_dir`` when given.
    ``figure_jobs`` are more figures to draw with the report's (on ``executor``, from the
    cache), as :class:`_Figures` holds them: ``(file name, draw, panels)``, ``draw()`` a
    picklable callable returning a matplotlib figure (a check's own figure, which ``lead``
    shows). ``sections`` (Markdown lines) follow the front page's, before the list of data
    files (the error atlas' section, which may show a figure of ``figure_jobs``). Returns the
    path of ``report.md``.
    """
    from validation.report.front import front_page, scene_page
    from validation.report.tables import table_rows, write_tables

    folder = _check_arguments(results, folder, seconds, mode, command, executor, cache_dir,
                              figure_jobs)
    for path in previous_report(folder):
        path.unlink()
    folder.mkdir(parents=True, exist_ok=True)
    analyses = [analyse(result) for result in results]
    rows = table_rows(analyses)
    written = write_tables(folder, analyses, rows)
    figures = _Figures(folder, header(seconds, mode, command) + list(lead or []))
    front_page(figures, analyses, rows, one_scan=bool(lead))
    pages = {}
    for analysis in analyses:
        page = _Figures(folder, [], figures.jobs)
        _scene_page(page, analysis, findings=not lead)
        pages[scene_page(analysis.result.scene.name)] = page.lines
    figures.lines += list(sections or [])
    figures.lines += ["## Data\n"] + [f"- [`{name}`]({name})" for name in written] + [""]
    path = folder / "report.md"
    try:
        figures.jobs += list(figure_jobs or [])
        figures.render(executor, cache_dir)
    except BaseException:
        # a report cut short (Ctrl-C, a failed figure) still marks its folder as a report's, so
        # that the same command replaces it (previous_report) instead of refusing the folder
        path.write_text("# Report not finished\n\nThe figures were not all drawn; the tables are "
                        "complete. Run the same command again.\n", encoding="utf-8")
        raise
    for name, lines in pages.items():
        (folder / name).write_text("\n".join(lines) + "\n", encoding="utf-8")
    path.write_text("\n".join(figures.lines) + "\n", encoding="utf-8")
    return path
