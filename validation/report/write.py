"""The validity report: Markdown, PNG figures and CSV tables in one folder.

``write_report`` compares every surface scene with its reference (:mod:`validation.judge.compare`),
checks the paper's findings (:mod:`validation.judge.findings`), writes the CSV tables first (so the
numbers survive whatever the figures do), then ``report.md``: its text from
:mod:`validation.report.sections`, its figures from :mod:`validation.report.figures` (matplotlib
imported lazily), placed here.
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass

import numpy as np

from validation.judge.analysis import Analysis, analyse
from validation.judge.compare import COMPARED_QUANTITIES, Comparison
from validation.report.figures import dimensionless
from validation.report.labels import MODEL_LABELS, QUANTITY_LABELS, model_order, model_rank
from validation.report.sampling import sampling_section
from validation.report.sections import (REPORT_QUANTITIES, findings_section, header,
                                        holds_section, md_table, surface_text, sweep_member,
                                        timing, verdict_table)
from validation.run.runner import SceneResult

__all__ = ["write_report", "md_table", "dimensionless", "MODEL_LABELS", "QUANTITY_LABELS",
           "REPORT_FILES", "previous_report"]

#: What a report writes into its folder, and so what it replaces there: its Markdown, figures
#: and tables.
REPORT_FILES = ("report.md", "*.png", "*.csv")


def previous_report(folder: str | pathlib.Path) -> list[pathlib.Path]:
    """The files of the previous report in ``folder``, which a new report replaces.

    A report owns the files it writes (:data:`REPORT_FILES`), so that no figure or table of an
    earlier run survives beside a new one. It writes into a new or empty folder (hidden files
    aside), or one holding a previous report (a ``report.md``): that report's Markdown, PNG
    and CSV files are replaced, anything else there is left alone. Any other folder is refused,
    so that a report never deletes or mixes with files it did not write.

    Raises
    ------
    ValueError
        When ``folder`` is a file, or holds files but no previous report.
    """
    folder = pathlib.Path(folder)
    if not folder.exists():
        return []
    if not folder.is_dir():
        raise ValueError(f"{str(folder)!r} is a file, not a folder for a report")
    entries = sorted(p.name for p in folder.iterdir() if not p.name.startswith("."))
    if entries and not (folder / "report.md").is_file():
        shown = ", ".join(entries[:4]) + (f" and {len(entries) - 4} more" if len(entries) > 4
                                          else "")
        raise ValueError(f"{str(folder)!r} holds files that are not a report ({shown}); a "
                         f"report replaces the files of a previous report in its folder, so it "
                         f"needs a new or empty folder, or one holding only an earlier report")
    return sorted({path for pattern in REPORT_FILES for path in folder.glob(pattern)
                   if path.is_file()})


# --------------------------------------------------------------------------------------------
# figures


@dataclass
class _Figures:
    """Saves figures into the report folder and links them from the Markdown lines."""

    folder: pathlib.Path
    lines: list

    def add(self, fig, name: str, caption: str) -> None:
        from validation.report.figures import pyplot

        fig.savefig(self.folder / name, dpi=100)
        pyplot().close(fig)
        self.lines += [f"![{caption}]({name})\n", f"*{caption}*\n"]


def _file_suffix(parameter: str, value: float) -> str:
    return f"-{parameter}{value:g}" if parameter else ""


def _curve_figures(figures: _Figures, scene, results, value: float) -> None:
    from validation.report.figures import panels_figure, plot_against

    models = model_order(results[0].curves)
    L = results[0].task.surface.L
    conductance = "conductance" in scene.quantities
    panels = ["area", "load"] + (["conductance"] if conductance else [])
    # the paper's figures are of WM surfaces: other surfaces get the same plots, not its name
    paper = scene.surface.family == "wm"
    members = "tiles" if scene.surface.family == "file" else "realizations"
    figures.add(panels_figure(lambda ax, y: plot_against(ax, results, "separation", y,
                                                         models=models, length=L), panels),
                f"{scene.name}-fig4-separation.png",
                f"Area, load{' and conductance' if conductance else ''} against separation, "
                f"{sweep_member(scene.surface.sweep_name, value)} "
                f"({'paper Fig. 4, BEM added; ' if paper else ''}thin lines: {members}; dotted: "
                f"the BEM against its mean gap ū/σ, the quantity Persson's curve is drawn "
                f"against).")
    figures.add(panels_figure(lambda ax, y: plot_against(ax, results, "load", y, models=models,
                                                         length=L, logx=True), panels[::2]),
                f"{scene.name}-fig5-load.png",
                f"Area{' and conductance' if conductance else ''} against load, "
                f"{sweep_member(scene.surface.sweep_name, value)}"
                f"{' (paper Fig. 5, BEM added)' if paper else ''}.")
    if "leakage" in scene.quantities:
        from validation.report.sealing_figures import leakage_figure

        figures.add(leakage_figure(results, models=models, length=L),
                    f"{scene.name}-leakage.png",
                    f"Leakage: the effective hydraulic aperture h_eff/σ against load and against "
                    f"separation, {sweep_member(scene.surface.sweep_name, value)} (thin lines: "
                    f"realizations; grey: the BEM ± its error estimate; GW, improved GW and the "
                    f"discrete model: the rigid gap at d, d₁ and the discrete model's own d; "
                    f"the theories from the spectral moments: the rigid gap of rms √m₀; all "
                    f"drawn against their separation d; Persson: its gap distribution, against "
                    f"its mean gap; docs/theory.md section 10).")


def _comparison_figures(figures: _Figures, scene, comparison: Comparison) -> None:
    from validation.report.figures import panels_figure, plot_errors, verdict_figure

    quantities = sorted({q for (_, q) in comparison.models}, key=REPORT_QUANTITIES.index)
    if not quantities:
        return
    at, suffix = (f(comparison.parameter, comparison.value) for f in (sweep_member, _file_suffix))
    figures.add(panels_figure(lambda ax, q: plot_errors(ax, comparison, q, scene.tolerances),
                              quantities, legend=7),
                f"{scene.name}-errors{suffix}.png",
                f"Mean error of each model against the BEM at equal load, {at} "
                f"(coloured band: 95 % interval over realizations; grey: reference band; dotted "
                f"red: tolerances).")
    figures.add(verdict_figure(comparison), f"{scene.name}-verdicts{suffix}.png",
                f"Verdict per load point, {at}: ✔ holds, ✘ fails, ? undecided.")


def _surface_section(figures: _Figures, analysis: Analysis) -> None:
    result, lines = analysis.result, figures.lines
    scene, s = result.scene, result.scene.surface
    count = len(next(iter(result.realizations.values()), []))
    lines.append(surface_text(scene, count))
    if result.refinement is not None:
        lines.append(f"Reference: {result.refinement.describe(s.sweep_name)}.\n")
    if result.sequential is not None:
        lines.append(f"Realizations per {s.sweep_name or 'surface'}: "
                     f"{result.sequential.describe()}.\n")
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
    if analysis.size_collapse is not None:
        from validation.report.sealing_figures import size_figure

        figures.add(size_figure(result.realizations, analysis.size_collapse, scene.m),
                    f"{scene.name}-sizes.png",
                    "Finding (g): the BEM's leakage h_eff/σ against the separation d (left) and "
                    f"the effective separation d₁ = d + {scene.m:g} W/(E*√A) (right) on nested "
                    "windows of growing nominal area, σ the mean summit σ over all windows "
                    "(thin: realizations; dotted: the leakage levels at which the spread across "
                    "sizes is measured).")


def _validity_map(figures: _Figures, scene, comparisons: list[Comparison]) -> None:
    from validation.report.figures import validity_map_figure

    keys = sorted({k for c in comparisons for k in c.models if k[1] in COMPARED_QUANTITIES},
                  key=lambda k: (model_rank(k[0]), COMPARED_QUANTITIES.index(k[1])))
    if keys:
        figures.add(validity_map_figure(comparisons, keys, scene.tolerances),
                    f"{scene.name}-validity-map.png",
                    "Validity map: |mean error| of each model against the BEM over load and "
                    f"{scene.surface.sweep_name}; contours at the tolerances "
                    f"{', '.join(f'{t:g}' for t in sorted(scene.tolerances))} (the legend says "
                    "which line is which).")


def _theory_section(figures: _Figures, result: SceneResult) -> None:
    from validation.report.figures import panels_figure, plot_theory_load, plot_theory_stiffness

    theory = result.theory
    for index, C in enumerate(theory["C"]):
        figures.add(panels_figure(lambda ax, c: plot_theory_load(ax, theory, c), [C], width=5.5),
                    f"{result.scene.name}-fig{index + 1}-C{C:g}.png",
                    f"Load against separation, GW and improved GW, C = {C:g} "
                    f"(paper Fig. {index + 1}).")
    figures.add(panels_figure(lambda ax, c: plot_theory_stiffness(ax, theory, c),
                              list(theory["C"]), width=5.5),
                f"{result.scene.name}-fig3-stiffness.png",
                "GW stiffness dW/dd₁ and the true stiffness dW/dd with interaction (paper Fig. 3).")
    rows = [[f"{C:g}", f"{np.min(theory[C].improved_stiffness / theory[C].effective_stiffness):.3g}",
             f"{np.max(theory[C].effective_separation - theory[C].separation):.3g}"]
            for C in theory["C"]]
    figures.lines += md_table(["C", "smallest ratio of true to GW stiffness dW/dd ÷ dW/dd₁",
                               "largest separation shift (d₁ − d)/σ"], rows)


def write_report(results: list[SceneResult], folder: str | pathlib.Path, *,
                 seconds: float | None = None, mode: str = "", command: str | None = None
                 ) -> pathlib.Path:
    """Write the CSV tables, then ``report.md`` with its PNG figures, into ``folder``.

    ``command`` (the command line that produced the results), the package version and the run
    time ``seconds`` head the report. A previous report in ``folder`` is replaced, its figures
    and tables removed first; a folder holding other files and no report is refused
    (:func:`previous_report`). Returns the path of ``report.md``.
    """
    from validation.report.tables import write_tables

    folder = pathlib.Path(folder)
    for path in previous_report(folder):
        path.unlink()
    folder.mkdir(parents=True, exist_ok=True)
    analyses = [analyse(result) for result in results]
    written = write_tables(folder, analyses)
    figures = _Figures(folder, header(seconds, mode, command))
    figures.lines += holds_section(analyses)
    figures.lines += findings_section(analyses)
    figures.lines += sampling_section(analyses)
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
    path = folder / "report.md"
    path.write_text("\n".join(figures.lines) + "\n", encoding="utf-8")
    return path

