"""The report's front page, ``report.md`` (:mod:`validation.report.write`): the summary, the
headline table and atlas figure of each scene, how precise each scene's headline is, the
findings at a glance and the list of scene pages. Text, and the atlas figures queued on the
report's figure list (drawn, like every figure, by :mod:`validation.report.write`)."""

from __future__ import annotations

import math
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from validation.judge.compare import COMPARED_QUANTITIES
from validation.judge.findings import NEW
from validation.judge.headline import HeadlineCell
from validation.judge.verdicts import SYMBOLS, UNCONVERGED, UNDECIDED
from validation.common.labels import compared_label, model_label, model_rank
from validation.common.models import FRAME_LABELS, FRAMES
from validation.report.conventions import conventions
from validation.report.sections import md_table, sweep_member
from validation.report.summary import error_text

if TYPE_CHECKING:  # the report imports this module
    from validation.judge.analysis import Analysis
    from validation.run.runner import SceneResult

__all__ = ["HEADLINE_INTRO", "findings_overview", "headline_intro", "front_page", "headline_cell_text", "headline_table",
           "largest_tolerance", "precision_section", "scene_page", "scenes_section"]

HEADLINE_INTRO = (
    "Each model's error against the BEM where the BEM's contact area is {fractions} of the "
    "nominal area (those of 0.1 %, 1 %, 10 % and 30 % that every realization's load path "
    "reaches), interpolated along each realization's path in ln(area fraction). A cell reads **mean error (95 % interval over "
    "realizations) mark [interval holding 90 % of single surfaces] mark**, the marks ✔ holds, "
    "✘ fails, ? undecided at the scene's largest tolerance, on the mean and per surface; for one "
    "surface (one realization) it reads **error ± reference band mark**; an undecided mean says "
    "why in brackets (reference band: a finer reference decides it; too few realizations; not "
    "converged). Errors in % (area, "
    "conductance), in σ (separation d; Persson: mean gap ū), as ln(h_eff/h_eff,BEM) (leakage). "
    "Below each table the scene's atlas: every cell's verdict along the whole load path. Every "
    "number, and the verdicts at each tolerance, are in `headline.csv`.\n")


def scene_page(name: str) -> str:
    """File name of a scene's page in the report's folder (never ``report.md``)."""
    return f"{name}.md" if name != "report" else "report-scene.md"


def largest_tolerance(analysis: Analysis) -> int:
    """Index of the scene's largest tolerance (the front page's reading)."""
    return int(np.argmax(analysis.result.scene.tolerances))


def _unit(quantity: str) -> str:
    return {"separation": "σ", "leakage": "ln"}.get(quantity, "%")


def headline_cell_text(cell: HeadlineCell | None, index: int) -> str:
    """One headline cell (:data:`HEADLINE_INTRO`), its verdicts at ``tolerances[index]``."""
    if cell is None:
        return "–"
    q = cell.quantity
    mark = SYMBOLS.get(cell.verdicts[index], "?")
    if not math.isfinite(cell.mean):   # no realization's error is known at this fraction
        reason = cell.reasons[index] if index < len(cell.reasons) else ""
        return (f"not converged {mark}" if reason == UNCONVERGED
                else f"not known{f' ({reason})' if reason else ''} {mark}")
    mean = error_text(cell.mean, q, unit=False)
    if cell.one_surface:
        band = error_text(cell.band, q, signed=False, unit=False) if math.isfinite(cell.band) \
            else "not estimated"
        return f"{mean} ± {band} {mark}"
    text = f"{mean} ({error_text(cell.low, q, unit=False)}, {error_text(cell.high, q, unit=False)})" \
           f" {mark}"
    reason = cell.reasons[index] if index < len(cell.reasons) else ""
    if cell.verdicts[index] == UNDECIDED and reason:   # why, where the interval alone would not say
        text += f" ({reason})"
    if math.isfinite(cell.surface_low):
        text += (f" [{error_text(cell.surface_low, q, unit=False)}, "
                 f"{error_text(cell.surface_high, q, unit=False)}] "
                 f"{SYMBOLS.get(cell.surface_verdicts[index], '?')}")
    return text


#: The headline's introduction in a check's report: one scan, its own reference.
ONE_SCAN_INTRO = (
    "Each model's error against the reference of this scan where the reference's contact "
    "area is {fractions} of the nominal area (those of 0.1 %, 1 %, 10 % and 30 % that the "
    "scan's load path reaches; the column names the nominal pressure there), interpolated "
    "along the load path in ln(area fraction). A cell reads **error ± reference band mark**, "
    "the mark ✔ holds, ✘ fails, ? undecided (the band straddles the tolerance) at the "
    "largest tolerance. Errors in % (area, stiffness), in σ, the rms of the scan's summit "
    "heights (separation d; Persson: mean gap ū), as ln(h_eff/h_eff,BEM) (leakage). Below the "
    "table the atlas: every cell's verdict along the whole load path. Every number, and the "
    "verdicts at each tolerance, are in `headline.csv`.\n")


def headline_intro(analyses: list[Analysis], one_scan: bool = False) -> str:
    """:data:`HEADLINE_INTRO` (:data:`ONE_SCAN_INTRO` for a check's report) with the fractions
    the headline tables show (those some scene's paths reach; a quick run's shorter paths may
    not reach 30 %)."""
    fractions = sorted({c.fraction for a in analyses for cells in a.headlines.values()
                        for c in (cells or ())})
    named = [f"{100 * f:g} %" for f in fractions] or ["none of the headline fractions"]
    text = named[0] if len(named) == 1 else ", ".join(named[:-1]) + " and " + named[-1]
    return (ONE_SCAN_INTRO if one_scan else HEADLINE_INTRO).replace("{fractions}", text)


def headline_table(analysis: Analysis) -> list[str]:
    """The scene's headline table: a row per model and quantity, a column per fraction (and
    swept value, fraction first); empty when no fraction is reached."""
    index = largest_tolerance(analysis)
    by_value = {v: c for v, c in sorted(analysis.headlines.items()) if c}
    if not by_value:
        return []
    scene = analysis.result.scene
    sweep = len(scene.surface.sweep_values) > 1
    parameter = analysis.comparisons[0].parameter if analysis.comparisons else ""
    fractions = sorted({c.fraction for cells in by_value.values() for c in cells})
    frames = [f for f in FRAMES if any(c.frame == f for cells in by_value.values()
                                       for c in cells)]
    framed = len(frames) > 1   # each frame's reference reaches a fraction at its own load
    columns, header = [], ["model"] + (["frame"] if framed else []) + ["quantity"]
    for fraction in fractions:
        for value, cells in by_value.items():
            at = [c for c in cells if c.fraction == fraction]
            if not at:
                continue
            columns.append((fraction, value))
            header.append(f"{100 * fraction:g} %, {sweep_member(parameter, value)}" if sweep
                          else f"{100 * fraction:g} %" if framed
                          else f"{100 * fraction:g} % ({_load_text(at[0].load, scene)})")
    keys = sorted({(c.model, c.quantity, c.reference_field, c.frame)
                   for cells in by_value.values() for c in cells},
                  key=lambda k: (FRAMES.index(k[3]) if k[3] in FRAMES else 0,
                                 model_rank(k[0]), COMPARED_QUANTITIES.index(k[1])))
    found = {(c.model, c.quantity, c.fraction, value): c
             for value, cells in by_value.items() for c in cells}
    rows = [[model_label(m)] + ([FRAME_LABELS.get(frame, frame)] if framed else [])
            + [f"{compared_label(q, field)} ({_unit(q)})"]
            + [headline_cell_text(found.get((m, q, f, v)), index) for f, v in columns]
            for m, q, field, frame in keys]
    tolerance = analysis.result.scene.tolerances[index]
    loads = [] if not framed or sweep else [
        ("Nominal pressure" if getattr(scene, "physical_e_star", None) else "Load")
        + " at each fraction, per frame (its reference's): " + "; ".join(
            f"{FRAME_LABELS[frame]} " + ", ".join(
                f"{100 * f:g} % at {_load_text(at[0].load, scene)}" for f in fractions
                for at in ([c for cells in by_value.values() for c in cells
                            if c.fraction == f and c.frame == frame],) if at)
            for frame in frames) + ".\n"]
    return ([f"Verdicts at the tolerance {tolerance:g}: an error within ±{100 * tolerance:g} % "
             f"(area, stiffness), ±{tolerance:g} σ (separation, mean gap), ±{tolerance:g} in "
             f"ln h_eff (leakage); {_realizations(analysis.result)}.\n"]
            + md_table(header, rows) + ([""] + loads if loads else []))


def _load_text(load: float, scene) -> str:
    """The load at a headline fraction: the nominal pressure where the scene has a physical E*
    (a check), else ``Load`` = p/E*."""
    e_star = getattr(scene, "physical_e_star", None)
    if e_star:
        from validation.surfaces.units import format_pressure

        return format_pressure(load * e_star)
    return f"Load {load:.1e}"


def _realizations(result: SceneResult) -> str:
    counts = sorted({len(r) for r in result.realizations.values()})
    if counts == [1]:
        return "one surface, judged by the reference band alone"
    used = str(counts[0]) if counts[0] == counts[-1] else f"{counts[0]}–{counts[-1]}"
    return f"{used} realizations"


def _effort(result: SceneResult) -> tuple[str, str]:
    """Realizations used (per look) and the finer reference of a scene, in a few words."""
    counts = sorted({len(r) for r in result.realizations.values()})
    used = str(counts[0]) if counts[0] == counts[-1] else f"{counts[0]}–{counts[-1]}"
    if result.sequential is not None and len(result.sequential.used) > 1:
        used = " → ".join(map(str, result.sequential.used))
    levels = result.refinement.levels if result.refinement is not None else ()
    finer = ", ".join(f"{level.grid}²{' (interface)' if level.reference != 'bem' else ''} "
                      f"at {sum(map(len, level.points.values()))} point(s)"
                      for level in levels) or "none"
    return used, finer


def precision_section(analyses: list[Analysis], one_scan: bool = False) -> list[str]:
    """How precise each scene's headline is: the median and the largest half-width of its
    intervals (the confidence intervals, or the band of one surface), with the realizations
    and finer reference it spent; for a check's one scan, its reference band and finer
    reference alone."""
    rows = []
    for analysis in analyses:
        cells = [c for cells in analysis.headlines.values() for c in cells
                 if math.isfinite(c.half_width)]
        if not cells:
            continue
        widths = np.array([c.half_width for c in cells])
        worst = cells[int(np.argmax(widths))]
        parameter = analysis.comparisons[0].parameter
        value = next(v for v, found in analysis.headlines.items() if worst in found)
        where = (f"{model_label(worst.model)}, {compared_label(worst.quantity, worst.reference_field)}"
                 f" at {100 * worst.fraction:g} %"
                 + (f", {sweep_member(parameter, value)}" if parameter else ""))
        rows.append([f"`{analysis.result.scene.name}`", *_effort(analysis.result),
                     str(len(cells)), f"{np.median(widths):.3g}",
                     f"{worst.half_width:.3g} ({where})"])
    if not rows:
        return []
    if one_scan:
        return (["## How precise the headline is\n",
                 "Half-width of the reference band at the headline's cells (relative for area "
                 "and stiffness, in σ for separation, ln for leakage): the reference's own error "
                 "on this scan. A half-width well below the tolerance means the error is known "
                 "whether or not the verdict is; the load points solved again on a finer "
                 "reference grid are beside it.\n"]
                + md_table(["scan", "finer reference", "headline cells", "median half-width",
                            "largest half-width"], [[r[0], *r[2:]] for r in rows]))
    return (["## How precise the headline is\n",
             "Half-width of the headline intervals of each scene (relative for area and "
             "conductance, in σ for separation, ln for leakage): the 95 % interval over "
             "realizations, or the reference band of one surface. A half-width well below the "
             "tolerance means the error is known whether or not the verdict is; the "
             "realizations each scene used (→: the looks of its sequential plan) and the load "
             "points solved again on a finer reference grid are beside it.\n"]
            + md_table(["scene", "realizations", "finer reference", "headline cells",
                        "median half-width", "largest half-width"], rows))


def findings_overview(analyses: list[Analysis]) -> list[str]:
    """The paper's findings at a glance: a row per finding, a column per surface family
    checked, the verdict in each cell; the numbers and rules are on the scene pages."""
    chosen = [a for a in analyses if a.findings and len(a.result.scene.surface.sweep_values) == 1] \
        or [a for a in analyses if a.findings]
    columns, cells, claims = [], {}, {}
    for analysis in chosen:
        name, parameter = analysis.result.scene.name, analysis.result.scene.surface.sweep_name
        for value, found in analysis.findings.items():
            column = (f"[{name}]({scene_page(name)}), {sweep_member(parameter, value)}")
            columns.append(column)
            for f in found:
                claims.setdefault(f.key, f.claim)
                cells[f.key, column] = f.verdict_text
    for analysis in analyses:
        if analysis.scene_findings:
            surface, name = analysis.result.scene.surface, analysis.result.scene.name
            column = (f"[{name}]({scene_page(name)}), {surface.sweep_name} = "
                      + ", ".join(f"{v:g}" for v in surface.sweep_values))
            columns.append(column)
            for f in analysis.scene_findings:
                claims.setdefault(f.key, f.claim)
                cells[f.key, column] = f.verdict_text
    lines = ["## Findings\n"]
    if not claims:
        return lines + ["No surface scene with a BEM reference in this run: nothing to check.\n"]
    rows = [[f"({key}) {claims[key]}"]
            + [(f"**{cells[key, c]}**" if cells[key, c] != NEW else NEW)
               if (key, c) in cells else "–" for c in columns]
            for key in sorted(claims)]
    skipped = [key for key in ABSENT_FINDINGS if key not in claims]
    why = sorted({ABSENT_FINDINGS[key] for key in skipped}, key=list(ABSENT_FINDINGS.values()).index)
    absent = (["Not in this run: " + "; ".join(
        f"{', '.join(f'({k})' for k in skipped if ABSENT_FINDINGS[k] == reason)} {reason}"
        for reason in why) + ".\n"] if skipped else [])
    return lines + ["The paper's findings, checked point by point on this run; the numbers that "
                    "decide each, and the rules, are on the scene pages.\n"] \
        + md_table(["finding"] + columns, rows) + absent


#: Why a finding may be absent from a run: what it needs.
ABSENT_FINDINGS = {
    "a": "need a surface scene with the BEM reference (the paper's scenes)",
    "b": "need a surface scene with the BEM reference (the paper's scenes)",
    "c": "need a surface scene with the BEM reference (the paper's scenes)",
    "d": "need a surface scene with the BEM reference (the paper's scenes)",
    "e": "need a surface scene with the BEM reference (the paper's scenes)",
    "f": "need a scene of nested windows with the BEM's leakage (sealing-size, in the full "
         "report)",
    "g": "need a scene of nested windows with the BEM's leakage (sealing-size, in the full "
         "report)",
    "h": "needs a scene sampled at several intervals ([sampling] factors)",
}


def scenes_section(analyses: list[Analysis]) -> list[str]:
    """Links to every scene's page, one line each."""
    lines = ["## Scenes\n", "Every scene's details (surfaces, figures, per-point verdict "
             "tables, validity ranges, the findings' numbers and rules) are on its page:\n"]
    for analysis in analyses:
        scene = analysis.result.scene
        lines.append(f"- [{scene.title}]({scene_page(scene.name)}) (`{scene.name}`)")
    return lines + [""]


def _atlas(figures, analysis: Analysis) -> None:
    from validation.report.atlas import atlas_figure

    scene = analysis.result.scene
    if not analysis.comparisons:
        return
    swept = f", one panel per {analysis.comparisons[0].parameter}" \
        if len(analysis.comparisons) > 1 else ""
    framed = len(analysis.comparisons[0].frame_paths) > 1
    frames = (" Each row is judged in its frame (in brackets) at the same loads; the axis is "
              "the finite contact's reference's area fraction." if framed else "")
    figures.add(partial(atlas_figure, analysis.comparisons, scene.tolerances),
                f"{scene.name}-atlas.png",
                f"Atlas of `{scene.name}`{swept}: each model and quantity along the BEM's "
                f"contact-area fraction, green where it holds, red where it fails, grey where "
                f"undecided within {max(scene.tolerances):g} (thin strip: per surface); dotted: "
                f"the headline's fractions.{frames}", len(analysis.comparisons))


def front_page(figures, analyses: list[Analysis], rows: dict, *, one_scan: bool = False) -> None:
    """``report.md`` after its header, appended to ``figures.lines`` (``figures``: the report's
    figure list, :class:`validation.report.write._Figures`, which queues the atlas figures):
    the summary, each scene's headline table and atlas, the precision of the headline, the
    findings at a glance, the scene pages, the conventions. ``one_scan``: a check's report,
    whose own sections (before these) give its answer: no summary and no paper's findings,
    which speak of populations of surfaces."""
    from validation.report import summary
    from validation.report.tables import records

    lines = figures.lines
    answer = [] if one_scan else summary.summary_lines(records(rows, "headline.csv"),
                                                       records(rows, "findings.csv"))
    if answer:
        lines += ["## Summary\n"] + answer
    judged = [a for a in analyses if a.comparisons]
    if judged:
        lines += ["## Headline: each model's error at fixed contact-area fractions\n",
                  headline_intro(judged, one_scan)]
    for analysis in judged:
        scene = analysis.result.scene
        lines.append(f"### [{scene.title}]({scene_page(scene.name)})\n")
        lines += (headline_table(analysis)
                  or ["No headline fraction is crossed by every realization's load path.\n"])
        _atlas(figures, analysis)
    lines += precision_section(analyses, one_scan)
    lines += [] if one_scan else findings_overview(analyses)
    lines += scenes_section(analyses)
    lines += conventions(populations=not judged or any(
        len(results) > 1 for a in judged for results in a.result.realizations.values()),
        one_scan=one_scan)
