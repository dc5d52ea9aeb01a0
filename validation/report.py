"""The validity report: Markdown, PNG figures and CSV tables in one folder.

``write_report`` compares every surface scene with its reference (:mod:`validation.compare`),
checks the paper's findings (:mod:`validation.findings`), writes the CSV tables first (so the
numbers survive whatever the figures do), then ``report.md`` with its figures
(:mod:`validation.figures`, matplotlib imported lazily).
"""

from __future__ import annotations

import datetime
import pathlib
import platform
from dataclasses import dataclass, field

import numpy as np

from validation import models
from validation.compare import Comparison, compare_realizations
from validation.figures import dimensionless
from validation.findings import Finding, check_findings
from validation.labels import (MODEL_LABELS, QUANTITY_LABELS, compared_label, model_label,
                               model_order, model_rank)
from validation.runner import SceneResult
from validation.verdicts import (FAILS, HOLDS, SYMBOLS, UNDECIDED, verdict_counts,
                                 verdict_strip)

__all__ = ["write_report", "analyse", "Analysis", "md_table", "dimensionless", "MODEL_LABELS",
           "QUANTITY_LABELS"]

QUANTITY_ORDER = ("area", "separation", "conductance", "stiffness", "contacts")
#: Quantities drawn on the validity map (contact counts are too noisy to map).
MAP_QUANTITIES = ("area", "separation", "conductance", "stiffness")


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
# Markdown helpers

def md_table(header: list[str], rows: list[list[str]]) -> list[str]:
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return out + ["| " + " | ".join(row) + " |" for row in rows] + [""]


@dataclass
class _Figures:
    """Saves figures into the report folder and links them from the Markdown lines."""

    folder: pathlib.Path
    lines: list

    def add(self, fig, name: str, caption: str) -> None:
        from validation.figures import pyplot

        fig.savefig(self.folder / name, dpi=100)
        pyplot().close(fig)
        self.lines += [f"![{caption}]({name})\n", f"*{caption}*\n"]


def _at(parameter: str, value: float) -> str:
    """Which member of a scene's family: "D = 2.05", "H = 0.8", or "measured map"."""
    return f"{parameter} = {value:g}" if parameter else "measured map"


def _file_suffix(parameter: str, value: float) -> str:
    return f"-{parameter}{value:g}" if parameter else ""


def _percent_or_sigma(value: float, quantity: str) -> str:
    if not np.isfinite(value):
        return "–"
    return f"{value:.2g} σ" if quantity in ("separation", "mean_gap") else f"{100 * value:.2g} %"


# --------------------------------------------------------------------------------------------
# sections

def _git_commit() -> str:
    """The source tree's git commit (with "+changes" when it has uncommitted edits), or ""."""
    import subprocess

    root = pathlib.Path(__file__).resolve().parents[1]
    try:
        commit = subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True, timeout=10, check=True).stdout
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--",
                                "asperity", "bem", "validation"], capture_output=True, text=True,
                               timeout=10, check=True).stdout
    except (OSError, subprocess.SubprocessError):
        return ""
    return f"git {commit.strip()}" + ("+changes" if dirty.strip() else "")


def _header(seconds, mode, command) -> list[str]:
    import bem.fft
    from validation.runner import _version

    commit = _git_commit()
    run = [f"Command: `{command}`" if command else "",
           f"asperity-validation {_version()}" + (f" ({commit})" if commit else ""),
           f"run time {seconds / 60:.1f} min ({seconds:.0f} s)" if seconds is not None else "",
           f"mode: {mode}" if mode else ""]
    return [
        "# Where do asperity models and Persson's theory hold? Validation against the exact "
        "half-space solution\n",
        "; ".join(part for part in run if part) + ".\n",
        f"Generated {datetime.datetime.now().isoformat(timespec='seconds')} (Python "
        f"{platform.python_version()}, numpy {np.__version__}, FFT backend "
        f"{'pyFFTW' if bem.fft.have_pyfftw() else 'scipy.fft'}).\n",
        "Dimensionless quantities as in the paper: Area = A/L², Load = W/(E* L²), Separation = "
        "d/σ (σ: standard deviation of the summit heights of each realization), Conductance = "
        "Cρσ/L² = −2 ∂Load/∂Separation. Errors are taken at equal load against the "
        "boundary-element (BEM) solution of the same realization: relative for area and "
        "conductance, in units of σ for separation.\n",
        "**Separation and mean gap.** The asperity models (GW, improved GW, discrete) predict "
        "the separation d between the rigid plane and the mean plane of the undeformed rough "
        "surface; they are compared with the BEM's separation d (rows \"separation d\"). "
        "Persson's theory predicts the mean gap ū, the average distance between the rigid "
        "plane and the *deformed* surface; it is compared with the BEM's mean gap (rows "
        "\"mean gap ū\"), also in units of σ. On the non-periodic half-space the two differ by "
        "the mean elastic displacement, which grows with the load; curves.csv lists both for "
        "the BEM (columns separation_d and mean_gap). Persson's conductance is 2S/E* with "
        "S = −dW/dū, compared with the BEM's 2S/E*, S = −dW/dd.\n",
        "**How a verdict is reached.** At each load point the errors over realizations give a "
        "mean and its 95 % confidence interval, mean ± t₀.₉₇₅,ₙ₋₁ · s/√n (Student t, s the "
        "sample standard deviation, n the realizations that converged there). The interval is "
        "widened on both sides by the reference band, the BEM's own error at that point in the "
        "same measure. A model **holds** (✔) where the widened interval lies inside ± the "
        "tolerance, the band is at most a quarter of the tolerance and every realization "
        "converged; it **fails** (✘) where the widened interval lies wholly outside; otherwise "
        "the point is **undecided** (?). A validity range is the longest run of ✔. Contact "
        "counts are plotted but not judged: the BEM counts connected contact patches, the "
        "asperity models asperities in contact.\n",
    ]


def _findings_section(analyses: list[Analysis]) -> list[str]:
    from validation import findings as module

    chosen = [a for a in analyses
              if a.findings and len(a.result.scene.surface.sweep_values) == 1] or \
        [a for a in analyses if a.findings]
    lines = ["## Findings\n"]
    if not chosen:
        return lines + ["No surface scene with a BEM reference in this run: nothing to check.\n"]
    lines.append("The paper's findings, checked point by point on the results of this run "
                 "(rules and thresholds below the table).\n")
    rows = []
    for analysis in chosen:
        parameter = analysis.result.scene.surface.sweep_name
        for value, found in analysis.findings.items():
            for f in found:
                rows.append([f"({f.key}) {f.claim}",
                             f"{analysis.result.scene.name}, {_at(parameter, value)}",
                             f.evidence.replace("|", "/"), f"**{f.verdict}**"])
    lines += md_table(["finding", "surface", "numbers that decide it", "verdict"], rows)
    rules = module.RULES.replace("\n(", "\n\n(").split("\n\n")
    return lines + [" ".join(part.split()) + "\n" for part in rules]


def _holds_section(analyses: list[Analysis]) -> list[str]:
    """One table for every model: where it holds, per surface and quantity, at the largest
    tolerance (asperity models and Persson's theory side by side)."""
    columns = [c for a in analyses for c in a.comparisons
               if len(a.result.scene.surface.sweep_values) == 1]
    if not columns:
        return []
    keys = {k for c in columns for k in c.models if k[1] in MAP_QUANTITIES}
    quantities = sorted({q for _, q in keys}, key=MAP_QUANTITIES.index)
    names = model_order({m for m, _ in keys})
    header, rows = ["model"], {m: [model_label(m)] for m in names}
    for comparison in columns:
        for quantity in quantities:
            header.append(f"{quantity}, {_at(comparison.parameter, comparison.value)}")
            for model in names:
                entry = comparison.models.get((model, quantity))
                if entry is None or not entry.ranges:
                    rows[model].append("–")
                    continue
                index = int(np.argmax(entry.tolerances))
                what = compared_label(quantity, entry.reference_field)
                cell = entry.ranges[index].describe(".1e")
                rows[model].append(cell if what == compared_label(quantity) else f"{what}: {cell}")
    tolerance = max(max(c.models[k].tolerances) for c in columns for k in c.models
                    if c.models[k].tolerances)
    return (["## Where each theory holds\n",
             f"Load range (longest run of ✔, with the BEM's area fraction over it) within the "
             f"tolerance {tolerance:g} (relative for area and conductance, in units of σ for "
             "separation); the asperity models are judged by the separation d, Persson's theory "
             "by the mean gap ū, each against the BEM's own field of that name. Per-point "
             "verdicts and the other tolerances are in the sections below and in "
             "`validity.csv`.\n"]
            + md_table(header, list(rows.values())))


def _verdict_rows(comparison: Comparison) -> list[list[str]]:
    rows = []
    keys = sorted(comparison.models, key=lambda k: (model_rank(k[0]), QUANTITY_ORDER.index(k[1])))
    for key in keys:
        entry = comparison.models[key]
        cells = [model_label(entry.model), compared_label(entry.quantity, entry.reference_field)]
        for index, rng in enumerate(entry.ranges):
            counts = entry.counts(index)
            cells += [f"`{verdict_strip(entry.verdicts[index])}`",
                      f"{counts[HOLDS]} / {counts[FAILS]} / {counts[UNDECIDED]}", rng.describe()]
        band = entry.band if entry.band is not None else np.array([np.nan])
        cells.append(_percent_or_sigma(float(np.nanmax(band)) if np.any(np.isfinite(band))
                                       else np.nan, entry.quantity))
        cells.append(str(entry.unconverged) if entry.unconverged else "–")
        rows.append(cells)
    return rows


def _verdict_table(comparison: Comparison, tolerances) -> list[str]:
    header = ["model", "quantity"]
    for t in tolerances:
        header += [f"verdicts within {t:g}, low → high load", "✔ / ✘ / ?", "holds (Load range)"]
    header += ["reference band (max)", "unconverged points"]
    rows = _verdict_rows(comparison)
    totals = [verdict_counts(np.concatenate([e.verdicts[i] for e in comparison.models.values()]))
              for i in range(len(tolerances))] if comparison.models else []
    total_row = ["**all**", ""]
    for counts in totals:
        total_row += ["", f"**{counts[HOLDS]} / {counts[FAILS]} / {counts[UNDECIDED]}**", ""]
    sources = "; ".join(f"{q}: {s}" for q, s in comparison.band_source.items())
    return ([f"Verdicts per load point ({SYMBOLS[HOLDS]} holds, {SYMBOLS[FAILS]} fails, "
             f"{SYMBOLS[UNDECIDED]} undecided; separation tolerances in units of σ). Reference "
             f"band: {sources or 'not estimated'}.\n"]
            + md_table(header, rows + ([total_row + ["", ""]] if totals else [])))


def _curve_figures(figures: _Figures, scene, results, value: float) -> None:
    from validation.figures import panels_figure, plot_against

    models = model_order(results[0].curves)
    L = scene.surface.L
    conductance = "conductance" in scene.quantities
    panels = ["area", "load"] + (["conductance"] if conductance else [])
    figures.add(panels_figure(lambda ax, y: plot_against(ax, results, "separation", y,
                                                         models=models, length=L), panels),
                f"{scene.name}-fig4-separation.png",
                f"Area, load{' and conductance' if conductance else ''} against separation, "
                f"{_at(scene.surface.sweep_name, value)} (paper Fig. 4, BEM added; thin lines: "
                f"realizations; dotted: the BEM against its mean gap ū/σ, the quantity Persson's "
                f"curve is drawn against).")
    figures.add(panels_figure(lambda ax, y: plot_against(ax, results, "load", y, models=models,
                                                         length=L, logx=True), panels[::2]),
                f"{scene.name}-fig5-load.png",
                f"Area{' and conductance' if conductance else ''} against load, "
                f"{_at(scene.surface.sweep_name, value)} (paper Fig. 5, BEM added).")


def _comparison_figures(figures: _Figures, scene, comparison: Comparison) -> None:
    from validation.figures import panels_figure, plot_errors, verdict_figure

    quantities = sorted({q for (_, q) in comparison.models}, key=QUANTITY_ORDER.index)
    if not quantities:
        return
    at, suffix = (f(comparison.parameter, comparison.value) for f in (_at, _file_suffix))
    figures.add(panels_figure(lambda ax, q: plot_errors(ax, comparison, q, scene.tolerances),
                              quantities, legend=7),
                f"{scene.name}-errors{suffix}.png",
                f"Mean error of each model against the BEM at equal load, {at} "
                f"(coloured band: 95 % interval over realizations; grey: reference band; dotted "
                f"red: tolerances).")
    figures.add(verdict_figure(comparison), f"{scene.name}-verdicts{suffix}.png",
                f"Verdict per load point, {at}: ✔ holds, ✘ fails, ? undecided.")


def _surface_text(scene, count: int) -> str:
    """One sentence on the surface family, grid, realizations, material and BEM."""
    s = scene.surface
    if s.family == "wm":
        family = (f"WM, D = {', '.join(f'{d:g}' for d in s.D)}, γ = {s.gamma:g}, M = {s.M}, "
                  f"n_max = {s.n_max}, rms slope = {s.rms_slope or 'from G'}, grid {s.n} × "
                  f"{s.n}, {count} realization(s)")
    elif s.family == "self-affine":
        amplitude = (f"rms slope {s.rms_slope:g}" if s.rms_slope is not None
                     else f"rms height {s.rms_height:g}")
        cutoffs = "".join(f", {name} wavelength {value:g}" for name, value in (
            ("long cut-off", s.long_cutoff), ("rolloff", s.rolloff),
            ("short cut-off", s.short_cutoff)) if value is not None)
        family = (f"Gaussian self-affine, H = {', '.join(f'{h:g}' for h in s.hurst)}, "
                  f"{amplitude}{cutoffs}, L = {s.L:g}, "
                  f"{'periodic' if s.window == 1 else f'window of a periodic surface {s.window} L wide'}, "
                  f"grid {s.n} × {s.n}, {count} realization(s)")
    else:
        from validation.surface_families import file_digest, read_map

        scan = read_map(s)
        side = scan.heights.shape[0]
        family = (f"measured map `{pathlib.Path(s.path).name}` (SHA-256 "
                  f"{file_digest(s.path)[:12]}…), {side} × {side} pixels of "
                  f"{scan.spacing:.4g} {s.unit}, detrend {s.detrend}; realizations: {s.tiles} "
                  f"non-overlapping tile(s) of {s.n} × {s.n} pixels, L = {s.L:.4g} {s.unit}; "
                  f"lengths in {s.unit}")
    return (f"Surface: {family}; E* = {scene.e_star:g}; BEM "
            f"{'periodic' if scene.bem.periodic else 'non-periodic'}, tol {scene.bem.tol:g}.\n")


def _surface_section(figures: _Figures, analysis: Analysis) -> None:
    result, lines = analysis.result, figures.lines
    scene, s = result.scene, result.scene.surface
    count = len(next(iter(result.realizations.values()), []))
    lines.append(_surface_text(scene, count))
    if not analysis.comparisons:
        lines.append("No BEM reference in this scene: curves only, no verdicts.\n")
    for value, results in sorted(result.realizations.items()):
        comparison = next((c for c in analysis.comparisons if c.value == value), None)
        lines.append(f"### {_at(s.sweep_name, value)}\n")
        counts = [r.summit_count for r in results]
        if any(counts) and comparison is not None:
            lines.append(f"Summits per realization: {min(counts)}–{max(counts)}; reference area "
                         f"fraction {100 * comparison.area_fraction[0]:.3g} % – "
                         f"{100 * comparison.area_fraction[-1]:.3g} % over the load path.\n")
        if len(s.sweep_values) == 1:
            _curve_figures(figures, scene, results, value)
        if comparison is not None:
            _comparison_figures(figures, scene, comparison)
            lines.extend(_verdict_table(comparison, scene.tolerances))
    if len(s.sweep_values) > 1 and analysis.comparisons:
        _validity_map(figures, scene, analysis.comparisons)


def _validity_map(figures: _Figures, scene, comparisons: list[Comparison]) -> None:
    from validation.figures import validity_map_figure

    keys = sorted({k for c in comparisons for k in c.models if k[1] in MAP_QUANTITIES},
                  key=lambda k: (model_rank(k[0]), MAP_QUANTITIES.index(k[1])))
    if keys:
        figures.add(validity_map_figure(comparisons, keys, scene.tolerances),
                    f"{scene.name}-validity-map.png",
                    "Validity map: |mean error| of each model against the BEM over load and "
                    f"{scene.surface.sweep_name}; "
                    f"white contours at the tolerances {', '.join(f'{t:g}' for t in scene.tolerances)}.")


def _theory_section(figures: _Figures, result: SceneResult) -> None:
    from validation.figures import panels_figure, plot_theory_load, plot_theory_stiffness

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


def _timing(result: SceneResult) -> list[str]:
    times: dict[str, list[float]] = {}
    for realizations in result.realizations.values():
        for r in realizations:
            for model, t in r.seconds.items():
                times.setdefault(model, []).append(t)
    if not times:
        return []
    return ["Wall time per realization and model (median over realizations; 0 means read from "
            "the cache): " + ", ".join(f"{model_label(m)} {np.median(t):.2f} s"
                                      for m, t in times.items()) + ".\n"]


def write_report(results: list[SceneResult], folder: str | pathlib.Path, *,
                 seconds: float | None = None, mode: str = "", command: str | None = None
                 ) -> pathlib.Path:
    """Write the CSV tables, then ``report.md`` with its PNG figures, into ``folder``.

    ``command`` (the command line that produced the results), the package version and the run
    time ``seconds`` head the report. Returns the path of ``report.md``.
    """
    from validation.tables import write_tables

    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    analyses = [analyse(result) for result in results]
    written = write_tables(folder, analyses)
    figures = _Figures(folder, _header(seconds, mode, command))
    figures.lines += _holds_section(analyses)
    figures.lines += _findings_section(analyses)
    for analysis in analyses:
        scene = analysis.result.scene
        figures.lines += [f"## {scene.title}\n",
                          f"Scene `{scene.name}` ({scene.source}). {scene.description.strip()}\n"]
        if scene.kind == "theory":
            _theory_section(figures, analysis.result)
            continue
        _surface_section(figures, analysis)
        figures.lines += _timing(analysis.result)
    figures.lines += ["## Data\n"] + [f"- [`{name}`]({name})" for name in written] + [""]
    path = folder / "report.md"
    path.write_text("\n".join(figures.lines) + "\n", encoding="utf-8")
    return path

