"""The report's sampling-interval section and tables: how the summits and each summit-fitted
model's validity range move when the same surface is sampled at h, 2h, 4h (finding (h),
:mod:`validation.judge.sampling`). Pure text and rows: :mod:`validation.report.write` and
:mod:`validation.report.tables` write them."""

from __future__ import annotations

import numpy as np

from validation.judge.compare import ABSOLUTE_QUANTITIES
from validation.judge.sampling import SUMMIT_RATIOS, SamplingStudy, factor_label
from validation.judge.verdicts import FAILS, HOLDS, UNDECIDED, ValidityRange
from validation.common.labels import compared_label, model_label, model_order
from validation.report.sections import md_table, sweep_member

__all__ = ["TABLES", "table_rows", "sampling_section"]

#: File name -> header of the sampling tables (written only for scenes sampled at several
#: intervals).
TABLES = {
    "sampling-summits.csv": ["scene", "D", "H", "factor", "grid", "seed", "summits", "density",
                             "radius", "sigma", "mean", "density_ratio", "radius_ratio",
                             "sigma_ratio"],
    "sampling-errors.csv": ["scene", "D", "H", "factor", "model", "quantity", "point", "Load",
                            "mean_error", "ci95_low", "ci95_high", "shift_mean", "shift_ci95_low",
                            "shift_ci95_high", "realizations"],
    "sampling-validity.csv": ["scene", "D", "H", "factor", "model", "quantity", "tolerance",
                              "load_min", "load_max", "area_fraction_min", "area_fraction_max",
                              "points", "total", "holds", "fails", "undecided"],
}


def _sweep(parameter: str, value: float) -> list:
    return [value if parameter == name else "" for name in ("D", "H")]


def _grid(grid: tuple[int, int]) -> str:
    return " × ".join(map(str, grid)) if grid[0] != grid[1] else f"{grid[0]} × {grid[0]}"


def _summit_rows(scene: str, sweep: list, realizations) -> list[list]:
    rows = []
    for r in realizations:
        finest = r.sampled[0].summits
        for s in r.sampled:
            grid = "x".join(str(side // s.factor) for side in r.task.surface.grid)
            ratios = [getattr(s.summits, name) / getattr(finest, name) if getattr(finest, name)
                      else np.nan for name in SUMMIT_RATIOS]
            rows.append([scene, *sweep, s.factor, grid, r.task.seed, s.summits.count,
                         s.summits.density, s.summits.radius, s.summits.sigma, s.summits.mean,
                         *ratios])
    return rows


def _study_rows(scene: str, sweep: list, study: SamplingStudy) -> dict[str, list[list]]:
    out = {"sampling-errors.csv": [], "sampling-validity.csv": []}
    for factor, comparison in study.comparisons.items():
        for (model, quantity), entry in comparison.models.items():
            shift = study.shifts.get((model, quantity, factor))
            for k in range(comparison.load.size):
                moved = [shift.mean[k], shift.low[k], shift.high[k]] if shift else [0.0] * 3
                out["sampling-errors.csv"].append(
                    [scene, *sweep, factor, model, quantity, k, comparison.load[k],
                     entry.interval.mean[k], entry.interval.low[k], entry.interval.high[k],
                     *moved, int(entry.interval.count[k])])
            for index, rng in enumerate(entry.ranges):
                counts = entry.counts(index)
                out["sampling-validity.csv"].append(
                    [scene, *sweep, factor, model, quantity, rng.tolerance, rng.load_min,
                     rng.load_max, rng.area_fraction_min, rng.area_fraction_max, rng.points,
                     rng.total, counts[HOLDS], counts[FAILS], counts[UNDECIDED]])
    return out


def table_rows(analysis) -> dict[str, list[list]]:
    """Rows of :data:`TABLES` for one analysed scene (empty lists without a sampling study)."""
    out: dict[str, list[list]] = {name: [] for name in TABLES}
    scene = analysis.result.scene
    for value, study in sorted(analysis.sampling.items()):
        sweep = _sweep(scene.surface.sweep_name, value)
        out["sampling-summits.csv"] += _summit_rows(scene.name, sweep,
                                                    analysis.result.realizations[value])
        for name, rows in _study_rows(scene.name, sweep, study).items():
            out[name] += rows
    return out


# --------------------------------------------------------------------------------------------
# Markdown


def _compact(rng: ValidityRange) -> str:
    if not rng.holds_anywhere:
        return "nowhere"
    if rng.points == rng.total:
        return "whole range"
    if rng.first == rng.last:
        return f"only at {rng.load_min:.1e}"
    return f"{rng.load_min:.1e} – {rng.load_max:.1e}"


def _ratio_cell(interval: tuple[float, float, float]) -> str:
    mean, low, high = interval
    if not np.isfinite(mean):
        return "–"
    if mean == low == high:             # the finest sampling against itself
        return f"{mean:.2g}"
    return f"{mean:.2g} ({low:.2g} – {high:.2g})" if np.isfinite(low) else f"{mean:.2g}"


def _summit_table(study: SamplingStudy, realizations) -> list[str]:
    rows = []
    for index, factor in enumerate(study.factors):
        counts = [r.sampled[index].summits.count for r in realizations]
        rows.append([factor_label(factor), _grid(study.grids[factor]), f"{np.mean(counts):.0f}"]
                    + [_ratio_cell(study.summits[factor][name]) for name in SUMMIT_RATIOS])
    return md_table(["sampling", "grid", "summits per realization (mean)",
                     "summit density ÷ at h", "mean summit radius ÷ at h",
                     "summit height deviation σ ÷ at h"], rows)


def _shift_cell(study: SamplingStudy, model: str, quantity: str, factor: int) -> str:
    interval = study.shifts.get((model, quantity, factor))
    if interval is None or not np.any(np.isfinite(interval.mean)):
        return "–"
    median = float(np.nanmedian(interval.mean))
    return f"{median:+.2g} σ" if quantity in ABSOLUTE_QUANTITIES else f"{100 * median:+.2g} %"


def _range_table(study: SamplingStudy) -> list[str]:
    high, low = max(study.tolerances), min(study.tolerances)
    index_high, index_low = study.tolerances.index(high), study.tolerances.index(low)
    header = ["model", "quantity"] + [f"{factor_label(k)}: within {high:g} / {low:g}"
                                      for k in study.factors]
    header += [f"median shift {factor_label(k)} − h" for k in study.factors[1:]]
    rows = []
    for model in model_order(study.models):
        for quantity in study.quantities:
            cells = [model_label(model), compared_label(quantity)]
            for factor in study.factors:
                entry = study.comparisons[factor].models.get((model, quantity))
                cells.append("–" if entry is None else
                             f"{_compact(entry.ranges[index_high])} / "
                             f"{_compact(entry.ranges[index_low])}")
            cells += [_shift_cell(study, model, quantity, k) for k in study.factors[1:]]
            rows.append(cells)
    return md_table(header, rows)


def sampling_section(analyses) -> list[str]:
    """The report's section on the sampling interval (empty when no scene samples its
    surfaces at several intervals)."""
    studied = [(a, value, study) for a in analyses for value, study in sorted(a.sampling.items())]
    if not studied:
        return []
    lines = ["## The sampling interval\n",
             "The summit-fitted models on the same surfaces sampled at the scene's grid step h "
             "and at coarser intervals k h (every k-th point, the mean plane kept), against the "
             "one BEM solution on the finest grid at its loads; separations in units of the "
             'summit σ at h (finding (h); docs/theory.md, "Sampling interval"). Summit '
             "statistics as ratios to those at h, mean over realizations with its 95 % "
             "interval. Validity ranges (Load) as in the verdict tables, at the largest and "
             "smallest tolerance; the median over the load path of the paired shift "
             "(q(kh) − q(h))/q_BEM, or (d(kh) − d(h))/σ. Every number per realization and "
             "load point is in `sampling-summits.csv`, `sampling-errors.csv` and "
             "`sampling-validity.csv`.\n"]
    for analysis, value, study in studied:
        scene = analysis.result.scene
        lines.append(f"### {scene.name}, {sweep_member(scene.surface.sweep_name, value)}\n")
        lines += _summit_table(study, analysis.result.realizations[value])
        lines += _range_table(study)
    return lines
