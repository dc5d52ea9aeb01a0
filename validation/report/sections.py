"""The Markdown text of the validity report (:mod:`validation.report.write`): the header with the
provenance of the run and the conventions of its numbers, and on each scene's page the
where-each-theory-holds table (validity ranges in contact-area fraction, the Load beside), the
findings with their numbers and rules, the verdict tables, the surface sentence and the
timings. Pure text: no figures, no files."""

from __future__ import annotations

import datetime
import pathlib
import platform
from typing import TYPE_CHECKING

import numpy as np

from validation.judge.compare import (ABSOLUTE_QUANTITIES, COMPARED_QUANTITIES, NOT_ESTIMATED,
                                      Comparison)
from validation.judge.verdicts import (FAILS, HOLDS, SYMBOLS, UNDECIDED, verdict_counts,
                                       verdict_strip)
from validation.common.labels import compared_label, model_label, model_rank
from validation.surfaces.units import readable

if TYPE_CHECKING:  # the report imports this module
    from validation.judge.analysis import Analysis
    from validation.run.runner import SceneResult

__all__ = ["REPORT_QUANTITIES", "md_table", "sweep_member", "header", "conventions", "holds_cell",
           "validity_section", "scene_findings", "verdict_table", "surface_text", "timing"]

#: Quantities in the report's order: the compared ones, then the contact counts (shown, never
#: judged: the BEM counts patches, the asperity models asperities).
REPORT_QUANTITIES = COMPARED_QUANTITIES + ("contacts",)


def md_table(header: list[str], rows: list[list[str]]) -> list[str]:
    """Lines of a Markdown table (header, rule, one line per row, then a blank line)."""
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return out + ["| " + " | ".join(row) + " |" for row in rows] + [""]


def sweep_member(parameter: str, value: float) -> str:
    """Which member of a scene's family: "D = 2.05", "H = 0.8", or "measured map"."""
    return f"{parameter} = {value:g}" if parameter else "measured map"


def _percent_or_sigma(value: float, quantity: str) -> str:
    if not np.isfinite(value):
        return "–"
    return f"{value:.2g} σ" if quantity in ABSOLUTE_QUANTITIES else f"{100 * value:.2g} %"


def _git_commit() -> str:
    """The source tree's git commit (with "+changes" when it has uncommitted edits), or ""."""
    import subprocess

    root = pathlib.Path(__file__).resolve().parents[2]
    try:
        commit = subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True, timeout=10, check=True).stdout
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--",
                                "asperity", "bem", "validation"], capture_output=True, text=True,
                               timeout=10, check=True).stdout
    except (OSError, subprocess.SubprocessError):
        return ""
    return f"git {commit.strip()}" + ("+changes" if dirty.strip() else "")


def version_text() -> str:
    """The code that ran, by one hash: its git commit where the tree is clean, else the hash
    of its sources (the cache's version, :func:`validation.run.cache.source_version`)."""
    from validation._version import __version__
    from validation.run.cache import source_version

    commit = _git_commit()
    if commit and not commit.endswith("+changes"):
        return f"asperity-validation {__version__} ({commit})"
    return f"asperity-validation {source_version()}" + (
        " (uncommitted changes)" if commit else "")


def header(seconds, mode, command) -> list[str]:
    """The report's title and the provenance of the run (command, version, time, platform)."""
    import bem.elastic.fft

    run = [f"Command: `{command}`" if command else "", version_text(),
           f"run time {seconds / 60:.1f} min ({seconds:.0f} s)" if seconds is not None else "",
           f"mode: {mode}" if mode else ""]
    return [
        "# Where do asperity models and Persson's theory hold? Validation against the exact "
        "half-space solution\n",
        "; ".join(part for part in run if part) + ".\n",
        f"Generated {datetime.datetime.now().isoformat(timespec='seconds')} (Python "
        f"{platform.python_version()}, numpy {np.__version__}, FFT backend "
        f"{'pyFFTW' if bem.elastic.fft.have_pyfftw() else 'scipy.fft'}).\n",
    ]


def conventions(populations: bool = True) -> list[str]:
    """How to read the report's numbers: the dimensionless quantities, the error measures,
    separation against mean gap, and how a verdict is reached (on the mean, per surface, and
    on one surface); without ``populations`` (every judged scene has one realization, e.g. a
    check of one scan) the rules over realizations are left out."""
    lines = [
        "## How to read the numbers\n",
        "Dimensionless quantities as in the paper: Area = A/L², Load = W/(E* L²), Separation = "
        "d/σ (σ: standard deviation of the summit heights of each realization), Conductance = "
        "Cρσ/L² = −2 ∂Load/∂Separation (C the electrical or thermal contact conductance, ρ "
        "the sum of the two bodies' resistivities: by Barber's analogy Cρ = 2S/E*, S the "
        "normal contact stiffness). Errors are taken at equal load against the "
        "boundary-element (BEM) solution of the same realization: relative for area and "
        "conductance, in units of σ for separation, and for the leakage (the effective "
        "hydraulic aperture h_eff, leak rate ∝ h_eff³) the logarithm of the ratio, "
        "ln(h_eff/h_eff,BEM) = ln(Q/Q_BEM)/3, equal to the relative error of h_eff to first "
        "order. Where exactly one of the two is sealed (h_eff = 0) that error is undefined: "
        "the point fails when the BEM's own error estimate resolves its state, and is "
        "undecided otherwise (docs/theory.md, eq. L7).\n",
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
        "same measure (for the interface of a non-periodic window, solved through its mirror "
        "image, the mirror method's bias is in it: its scatter from surface to surface is in "
        "the realizations' errors already; docs/theory.md, eq. T50). A model **holds** (✔) where the widened interval lies inside ± the "
        "tolerance, the band is at most a quarter of the tolerance and every realization "
        "converged; it **fails** (✘) where the widened interval lies wholly outside; otherwise "
        "the point is **undecided** (?). A validity range is the longest run of ✔. Contact "
        "counts are plotted but not judged: the BEM counts connected contact patches, the "
        "asperity models asperities in contact.\n",
        "**Two readings: on the mean and per surface.** The verdict above is on the *mean* "
        "error over realizations. The verdict **per surface** asks whether the model holds on "
        "single surfaces: it holds per surface where, with the same confidence, at least 90 % "
        "of surfaces have an error within the tolerance (the normal tolerance interval "
        "m ± k₂ s of 90 % content, widened by the band one surface carries, with the mirror "
        "method's whole bound in it, inside ± the tolerance); it "
        "fails per surface where, with that confidence, more than 10 % of surfaces miss "
        '(docs/theory.md, "Per-surface validity"). A scene with a realization budget looks '
        "at its data up to three times, adding realizations while cells are undecided, and "
        "splits the 5 % between the looks (in proportion to their realizations) so that it "
        "holds over all of them "
        '(docs/theory.md, "Sequential realizations").\n',
        "**One surface.** A scene of one realization (one measured scan) is judged on that "
        "surface alone: the BEM solves that very surface, so the only open thing is the BEM's "
        "own band b (the band one surface carries: for a scan's interface, the mirror method's "
        "whole bound in it). A point **holds** where |error| + b ≤ the tolerance, **fails** where "
        "|error| − b > the tolerance, and is undecided only where the band straddles the "
        "tolerance (reason: reference band); no interval over realizations and no per-surface "
        "reading.\n",
    ]
    if populations:
        return lines
    return [line for line in lines if not line.startswith(("**How a verdict is reached.**",
                                                            "**Two readings"))]


def holds_cell(entry, index: int | None = None, load_format: str = ".1e", *,
               per_surface: bool = False) -> str:
    """Where one model holds in one quantity at ``tolerances[index]`` (default the largest),
    on the mean error or, with ``per_surface``, on single surfaces: its validity range; else
    "fails everywhere", or why it could not be decided (the undecided points' reasons,
    :func:`validation.judge.verdicts.undecided_reasons`,
    :func:`validation.judge.tolerance.surface_reasons`, most frequent first), never a bare
    "nowhere" that hides which."""
    if entry is None or not entry.ranges or (per_surface and not entry.surface_ranges):
        return "–"
    index = int(np.argmax(entry.tolerances)) if index is None else index
    found = (entry.surface_ranges if per_surface else entry.ranges)[index]
    if found.holds_anywhere:
        return found.describe(load_format)
    counts = entry.surface_counts(index) if per_surface else entry.counts(index)
    if counts[FAILS] == found.total:
        return "fails everywhere"
    reasons = [r for r in (entry.surface_reasons(index) if per_surface
                           else entry.reasons(index)) if r]
    why = " / ".join(sorted(set(reasons), key=lambda r: (-reasons.count(r), r)))
    if not counts[FAILS]:
        return f"undecided: {why}"
    return f"nowhere: fails at {counts[FAILS]} of {found.total} points, undecided at " \
           f"{counts[UNDECIDED]} ({why})"


def _holds_cells(entry, quantity: str) -> str:
    """:func:`holds_cell` on the mean and per surface, prefixed with the reference field where
    it is not the quantity's."""
    if entry is None or not entry.ranges:
        return "–"
    cell = f"mean: {holds_cell(entry)}"
    if entry.surface_ranges:
        cell += f"; per surface: {holds_cell(entry, per_surface=True)}"
    what = compared_label(quantity, entry.reference_field)
    return cell if what == compared_label(quantity) else f"{what}: {cell}"


def _largest_tolerance(comparisons) -> float:
    return max(max(c.models[k].tolerances) for c in comparisons for k in c.models
               if c.models[k].tolerances)


#: What decides an undecided cell, printed under the summary.
_ADVICE = ("*Undecided* says why: **reference band**: the BEM's own error is unknown or above a "
           "quarter of the tolerance (for one surface: straddles it; a finer grid decides it: a "
           "larger `surface.n`, or `[bem] max_grid` to solve again on finer grids where the band "
           "decides), and for the leakage where model and BEM disagree about sealing but the "
           "BEM's estimate cannot tell whether it seals; {few}**unconverged**: a solver did not "
           "converge there, or a model did not reach the load (unreachable: past full contact, "
           "or an unconverged solve that ended at another load); the verdict tables count these "
           "points.")
_FEW = ("**too few realizations**: the interval straddles the tolerance (more realizations "
        "decide it: `[realizations] count`, or a budget `[realizations] max` spent where cells "
        "are undecided; a scene needs at least 2, a per-surface verdict 3); ")


def validity_section(analysis: Analysis) -> list[str]:
    """Where each model holds in one scene, per quantity and swept value, at the largest
    tolerance: its validity range in contact-area fraction with the Load beside it, on the mean
    and per surface, or why it holds nowhere."""
    comparisons = analysis.comparisons
    keys = sorted({k for c in comparisons for k in c.models if k[1] in COMPARED_QUANTITIES},
                  key=lambda k: (model_rank(k[0]), COMPARED_QUANTITIES.index(k[1])))
    if not keys:
        return []
    header = ["model", "quantity"] + [sweep_member(c.parameter, c.value) for c in comparisons]
    rows = [[model_label(m), q] + [_holds_cells(c.models.get((m, q)), q) for c in comparisons]
            for m, q in keys]
    one = all(e.one_surface for c in comparisons for e in c.models.values())
    return (["## Where each theory holds\n",
             f"Validity range within {_largest_tolerance(comparisons):g} (relative for area and "
             "conductance, in units of σ for separation, ln of the ratio for leakage): the "
             "longest run of ✔, as the BEM's contact-area fraction over it with the Load "
             "beside it, in two readings: **mean**, the mean error over realizations within the "
             "tolerance; **per surface**, at least 90 % of single surfaces within it (one "
             "surface has the first reading only, from its error and the reference band). The "
             "asperity models are judged by the separation d, Persson's theory by the mean gap "
             "ū. Other tolerances: `validity.csv`.\n"]
            + md_table(header, rows) + [_ADVICE.format(few="" if one else _FEW) + "\n"])


def scene_findings(analysis: Analysis) -> list[str]:
    """The paper's findings on one scene: the numbers that decide each, and the rules."""
    from validation.judge import findings as module
    from validation.judge import sampling, sealing

    parameter = analysis.result.scene.surface.sweep_name
    rows = [[f"({f.key}) {f.claim}", sweep_member(parameter, value),
             f.evidence.replace("|", "/"), f"**{f.verdict}**"]
            for value, found in analysis.findings.items() for f in found]
    surface = analysis.result.scene.surface
    rows += [[f"({f.key}) {f.claim}", f"{surface.sweep_name} = "
              + ", ".join(f"{v:g}" for v in surface.sweep_values),
              f.evidence.replace("|", "/"), f"**{f.verdict}**"] for f in analysis.scene_findings]
    if not rows:
        return []
    lines = ["## Findings\n", "The paper's findings, checked point by point on this scene "
             "(rules and thresholds below the table).\n"]
    lines += md_table(["finding", "surface", "numbers that decide it", "verdict"], rows)
    keys = {row[0][1] for row in rows}
    rules = (module.RULES + ("\n" + sealing.RULES if keys & {"f", "g"} else "")
             + "\n" + sampling.RULE)
    parts = rules.replace("\n(", "\n\n(").split("\n\n")
    parts = [part for part in parts if not part.startswith("(") or part[1] in keys]
    return lines + [" ".join(part.split()) + "\n" for part in parts]


def _band_cell(band: np.ndarray | None, quantity: str) -> str:
    """The largest reference band of a row; "not estimated" where it is unknown (NaN), never a
    number standing in for it."""
    band = np.full(1, np.nan) if band is None else np.asarray(band, dtype=float)
    known = np.isfinite(band)
    if not known.any():
        return NOT_ESTIMATED
    text = _percent_or_sigma(float(np.max(band[known])), quantity)
    return text if known.all() else f"{text} ({NOT_ESTIMATED} at {np.count_nonzero(~known)} of {band.size} points)"


def _verdict_rows(comparison: Comparison) -> list[list[str]]:
    rows = []
    keys = sorted(comparison.models,
                  key=lambda k: (model_rank(k[0]), REPORT_QUANTITIES.index(k[1])))
    for key in keys:
        entry = comparison.models[key]
        cells = [model_label(entry.model), compared_label(entry.quantity, entry.reference_field)]
        for index in range(len(entry.ranges)):
            counts = entry.counts(index)
            cells += [f"`{verdict_strip(entry.verdicts[index])}`",
                      f"{counts[HOLDS]} / {counts[FAILS]} / {counts[UNDECIDED]}",
                      holds_cell(entry, index, ".2e")]
            if entry.surface_verdicts:
                single = entry.surface_counts(index)
                cells += [f"`{verdict_strip(entry.surface_verdicts[index])}`",
                          f"{single[HOLDS]} / {single[FAILS]} / {single[UNDECIDED]}"]
            else:
                cells += ["–", "–"]
        cells.append(_band_cell(entry.band, entry.quantity))
        unreachable = getattr(entry, "unreachable", 0)
        cells.append((f"{entry.unconverged}" + (f" ({unreachable} unreachable)" if unreachable
                                                 else "")) if entry.unconverged else "–")
        rows.append(cells)
    return rows


def verdict_table(comparison: Comparison, tolerances) -> list[str]:
    header = ["model", "quantity"]
    for t in tolerances:
        header += [f"mean: verdicts within {t:g}, low → high load", "mean ✔ / ✘ / ?",
                   "mean holds (Load range)", f"per surface: verdicts within {t:g}",
                   "per surface ✔ / ✘ / ?"]
    header += ["reference band (max)", "unconverged or unreachable points"]
    rows = _verdict_rows(comparison)
    totals = [verdict_counts(np.concatenate([e.verdicts[i] for e in comparison.models.values()]))
              for i in range(len(tolerances))] if comparison.models else []
    single = [verdict_counts(np.concatenate([e.surface_verdicts[i] for e in
                                             comparison.models.values() if e.surface_verdicts]
                                            or [np.array([], str)]))
              for i in range(len(tolerances))] if comparison.models else []
    total_row = ["**all**", ""]
    for counts, alone in zip(totals, single):
        total_row += ["", f"**{counts[HOLDS]} / {counts[FAILS]} / {counts[UNDECIDED]}**", "",
                      "", f"**{alone[HOLDS]} / {alone[FAILS]} / {alone[UNDECIDED]}**"]
    sources = "; ".join(f"{q}: {s}" for q, s in comparison.band_source.items())
    sealing = [f"{model_label(e.model)} at {int(np.count_nonzero(e.sealing))} point(s) "
               f"({int(e.sealing.sum())} realization(s), {int(e.sealing_resolved.sum())} "
               f"resolved by the BEM's error estimate)"
               for e in comparison.models.values() if e.sealing is not None and e.sealing.any()]
    note = ([f"Disagreements about sealing (one of model and BEM sealed, h_eff = 0): "
             f"{'; '.join(sealing)}.\n"] if sealing else [])
    one = bool(comparison.models) and all(e.one_surface for e in comparison.models.values())
    reading = ("on this one surface, from its error and the reference band alone (no "
               "per-surface reading)" if one else
               f"on the mean error and per surface (at least 90 % of surfaces), at "
               f"{100 * comparison.confidence:.4g} % confidence")
    return ([f"Verdicts per load point ({SYMBOLS[HOLDS]} holds, {SYMBOLS[FAILS]} fails, "
             f"{SYMBOLS[UNDECIDED]} undecided; separation tolerances in units of σ), "
             f"{reading}. Reference band: {sources or 'not estimated'}.\n"]
            + md_table(header, rows + ([total_row + ["", ""]] if totals else [])) + note)


def surface_text(scene, count: int) -> str:
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
        from validation.surfaces.families import file_digest, read_map

        scan = read_map(s)
        rows, columns = s.grid
        cutoff = ("" if s.short_cutoff is None else
                  f", short-wavelength cutoff {readable(s.short_cutoff_length, 4)} {s.unit} (shorter "
                  f"wavelengths removed before every model and the BEM see the map)")
        family = (f"measured map `{pathlib.Path(s.path).name}` (SHA-256 "
                  f"{file_digest(s.path)[:12]}…), {' × '.join(map(str, scan.heights.shape))}"
                  f"{' (uncropped)' if s.square == 'keep' else ''} pixels of "
                  f"{readable(scan.spacing, 4)} {s.unit}"
                  f"{'' if s.resample == 'none' else f' (resampled to the {s.resample} spacing)'}"
                  f", detrend {s.detrend}{cutoff}; realizations: {s.tiles} "
                  f"non-overlapping tile(s) of {rows} × {columns} pixels, "
                  f"{readable(columns * s.spacing, 4)} × {readable(rows * s.spacing, 4)} {s.unit}; "
                  f"lengths in {s.unit}")
    return (f"Surface: {family}; E* = {scene.e_star:g}; BEM "
            f"{'periodic' if scene.bem.periodic else 'non-periodic'}, tol {scene.bem.tol:g}.\n")


def timing(result: SceneResult) -> list[str]:
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
