"""The report's CSV tables: every curve, every error with its interval and verdicts, every
validity range and every finding. Written before any figure, so the numbers of a run survive
whatever the figures do.

Two readings of every cell: ``verdict`` on the mean error over realizations
(:mod:`validation.judge.verdicts`) and ``verdict_per_surface`` on single surfaces
(:mod:`validation.judge.tolerance`: at least 90 % of surfaces within the tolerance); ``confidence``
is that of both (95 %, or split between the looks of a realization budget). A scene of one
realization is judged by the reference band alone and has no per-surface reading (empty).

``headline.csv`` holds every model's error at the headline's contact-area fractions
(:mod:`validation.judge.headline`): the mean error with its interval (``interval`` says which:
the confidence interval over realizations, or ± the reference band for one surface), the
per-surface 90 % interval, and the verdicts, one row per tolerance. ``validity.csv`` gives each
validity range in contact-area fraction first, the Load beside it."""

from __future__ import annotations

import csv
import math
import pathlib

import numpy as np

from validation.judge.compare import NOT_ESTIMATED
from validation.report import sampling
from validation.judge.verdicts import FAILS, HOLDS, UNDECIDED
from validation.report.figures import dimensionless

__all__ = ["INTERVALS", "TABLES", "records", "table_rows", "write_tables"]

#: File name -> header of every table.
TABLES = {
    "curves.csv": ["scene", "D", "H", "L", "seed", "n", "model", "frame", "point", "converged", "Load",
                   "Area", "Separation", "Conductance", "contacts", "load_W", "area",
                   "separation_d", "stiffness", "conductance", "sigma", "Mean_gap", "mean_gap",
                   "Leakage", "leakage", "leakage_error"],
    "errors.csv": ["scene", "D", "H", "L", "model", "frame", "quantity", "reference_field", "point",
                   "Load",
                   "area_fraction_reference", "mean_error", "ci95_low", "ci95_high", "std_error",
                   "realizations", "reference_band", "reference_band_surface",
                   "reference_band_source", "confidence",
                   "surfaces90_low", "surfaces90_high", "sealing_disagreements",
                   "sealing_resolved"],
    "verdicts.csv": ["scene", "D", "H", "L", "model", "frame", "quantity", "point", "Load", "tolerance",
                     "verdict", "undecided_reason", "verdict_per_surface", "confidence"],
    "headline.csv": ["scene", "D", "H", "L", "model", "frame", "quantity", "reference_field",
                     "area_fraction", "regime", "Load", "realizations", "mean_error", "low",
                     "high", "half_width", "interval", "surfaces90_low", "surfaces90_high",
                     "reference_band", "confidence", "tolerance", "verdict", "undecided_reason",
                     "verdict_per_surface"],
    "validity.csv": ["scene", "D", "H", "L", "model", "frame", "quantity", "tolerance",
                     "area_fraction_min", "area_fraction_max", "load_min", "load_max",
                     "points", "total",
                     "holds", "fails", "undecided", "reference_band_max", "unconverged",
                     "reference_field", "holds_per_surface", "fails_per_surface",
                     "undecided_per_surface", "sealing_disagreements"],
    "findings.csv": ["scene", "D", "H", "L", "finding", "claim", "evidence", "verdict",
                     "tested_from", "tested_to", "reproduced_from", "reproduced_to",
                     "points_reproduced", "points_contradicted", "points_undecided"],
    "theory.csv": ["C", "m", "separation", "effective_separation", "gw_pressure",
                   "improved_pressure", "gw_stiffness", "effective_stiffness",
                   "improved_stiffness"],
}
TABLES.update(sampling.TABLES)


def _sweep(surface) -> list:
    """The D, H and L cells of a row for a family member (``SurfaceSpec.at(value)``): its D (WM),
    its H (self-affine), its nominal side L (D and H empty for a measured map, whose seed
    column is the tile index)."""
    return [surface.D[0] if surface.family == "wm" else "",
            surface.hurst[0] if surface.family == "self-affine" else "", surface.L]


def _scene_sweep(surface) -> list:
    """The D, H and L cells of a row about a whole scene: those that do not vary over it."""
    cells = []
    for values in ((surface.D if surface.family == "wm" else None),
                   (surface.hurst if surface.family == "self-affine" else None),
                   (surface.sides or (surface.L,))):
        cells.append(values[0] if values is not None and len(values) == 1 else "")
    return cells


def _column(values: dict, name: str, k: int) -> float:
    array = values.get(name)
    return math.nan if array is None else float(array[k])


def _grid(surface) -> int | str:
    """The grid column: n, or "rows x columns" of a rectangular tile."""
    rows, columns = surface.grid
    return rows if rows == columns else f"{rows}x{columns}"


def frame_of(model: str) -> str:
    """The frame column of a model's rows ("" for a model the registry does not know)."""
    from validation.common import models

    return models.frame_of(model) if model in models.names() else ""


def _curve_rows(analysis) -> list[list]:
    from validation.judge.compare import converged_points

    result, rows = analysis.result, []
    for _, realizations in sorted(result.realizations.items()):
        for r in realizations:
            sweep = _sweep(r.task.surface)
            for model, curve in r.curves.items():
                values = dimensionless(curve, r.sigma, r.task.surface.L)
                converged = converged_points(curve)
                # the mean gap (BEM, Persson) beside the separation d; NaN where not computed
                gap = np.asarray(curve.extras.get("mean_gap", np.full(curve.load.shape, np.nan)),
                                 dtype=float)
                raw = {"s": curve.stiffness, "c": curve.conductance, "h": curve.leakage,
                       "e": curve.extras.get("leakage_error")}
                for k in range(curve.load.size):
                    rows.append([result.scene.name, *sweep, r.task.seed, _grid(r.task.surface),
                                 model, frame_of(model), k, bool(converged[k])]
                                + [_column(values, q, k) for q in
                                   ("load", "area", "separation", "conductance", "contacts")]
                                + [float(curve.load[k]), float(curve.area[k]),
                                   float(curve.separation[k]), _column(raw, "s", k),
                                   _column(raw, "c", k), r.sigma, gap[k] / r.sigma, gap[k],
                                   _column(values, "leakage", k), _column(raw, "h", k),
                                   _column(raw, "e", k)])
    return rows


def _comparison_rows(analysis) -> dict[str, list[list]]:
    name, out = analysis.result.scene.name, {"errors.csv": [], "verdicts.csv": [],
                                             "validity.csv": []}
    for c in analysis.comparisons:
        sweep = _sweep(analysis.result.scene.surface.at(c.value))
        for (model, quantity), e in c.models.items():
            band = e.band if e.band is not None else np.full(c.load.shape, math.nan)
            sealing = [("", "")] * c.load.size if e.sealing is None else \
                [(int(a), int(b)) for a, b in zip(e.sealing, e.sealing_resolved)]
            # a band that could not be estimated is written as such, never as a number
            cells = [float(b) if np.isfinite(b) else NOT_ESTIMATED for b in band]
            # the band one surface carries (the per-surface readings'; eq. T50)
            surface_band = band if e.surface_band is None else e.surface_band
            surface_cells = [float(b) if np.isfinite(b) else NOT_ESTIMATED for b in surface_band]
            reasons = [e.reasons(i) for i in range(len(e.tolerances))]
            nan = np.full(c.load.shape, math.nan)
            low, high = (nan, nan) if e.surface is None else (e.surface.low, e.surface.high)
            per_surface = e.surface_verdicts or tuple(np.full(c.load.shape, "") for _ in
                                                      e.verdicts)
            # the contact-area fraction of the reference the model is judged against
            fraction = c.area_fraction if e.area_fraction is None else e.area_fraction
            for k in range(c.load.size):
                # one surface has an error and its band, no interval over realizations: left
                # empty rather than written as +-inf and nan
                spread = ((e.interval.low[k], e.interval.high[k], e.interval.std[k])
                          if e.interval.count[k] > 1 else (None, None, None))
                out["errors.csv"].append([name, *sweep, model, e.frame, quantity,
                                          e.reference_field, k, c.load[k], fraction[k],
                                          e.interval.mean[k], *spread,
                                          int(e.interval.count[k]), cells[k],
                                          surface_cells[k], c.band_source_of(e),
                                          c.confidence, low[k], high[k], *sealing[k]])
                out["verdicts.csv"] += [[name, *sweep, model, e.frame, quantity, k, c.load[k], t,
                                         v[k],
                                         why[k], w[k], c.confidence]
                                        for t, v, why, w in zip(e.tolerances, e.verdicts,
                                                                reasons, per_surface)]
            for index, r in enumerate(e.ranges):
                counts = e.counts(index)
                surface = (e.surface_counts(index) if e.surface_verdicts
                           else dict.fromkeys((HOLDS, FAILS, UNDECIDED), ""))
                out["validity.csv"].append([name, *sweep, model, e.frame, quantity, r.tolerance,
                                            r.area_fraction_min, r.area_fraction_max, r.load_min,
                                            r.load_max, r.points, r.total, counts[HOLDS], counts[FAILS],
                                            counts[UNDECIDED],
                                            float(np.nanmax(band)) if np.any(np.isfinite(band))
                                            else NOT_ESTIMATED, e.unconverged,
                                            e.reference_field or quantity, surface[HOLDS],
                                            surface[FAILS], surface[UNDECIDED],
                                            "" if e.sealing is None else int(np.sum(e.sealing))])
    return out


#: What the interval of a headline cell is (``interval`` column of headline.csv).
INTERVALS = {False: "confidence interval", True: "reference band"}


def _headline_rows(analysis) -> list[list]:
    from validation.judge.headline import regime_of

    rows, name = [], analysis.result.scene.name
    for value, cells in sorted(analysis.headlines.items()):
        sweep = _sweep(analysis.result.scene.surface.at(value))
        for c in cells:
            band = c.band if np.isfinite(c.band) else NOT_ESTIMATED
            rows += [[name, *sweep, c.model, c.frame, c.quantity, c.reference_field, c.fraction,
                      regime_of(c.fraction), c.load, c.realizations, c.mean, c.low, c.high,
                      c.half_width, INTERVALS[c.one_surface], c.surface_low, c.surface_high, band,
                      c.confidence, t, v, why, w]
                     for t, v, why, w in zip(c.tolerances, c.verdicts, c.reasons,
                                             c.surface_verdicts)]
    return rows


def _theory_rows(analysis) -> list[list]:
    theory = analysis.result.theory
    if not theory:
        return []
    return [[C, theory["m"], c.separation[k], c.effective_separation[k], c.gw_pressure[k],
             c.improved_pressure[k], c.gw_stiffness[k], c.effective_stiffness[k],
             c.improved_stiffness[k]]
            for C in theory["C"] for c in (theory[C],) for k in range(c.separation.size)]


def _cell(value):
    """Floats with 10 significant digits (beyond any solver's tolerance; halves the files)."""
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.10g}"
    return value


def table_rows(analyses) -> dict[str, list[list]]:
    """Every table's rows (file name -> rows, in the column order of :data:`TABLES`)."""
    rows: dict[str, list[list]] = {name: [] for name in TABLES}
    for analysis in analyses:
        rows["curves.csv"] += _curve_rows(analysis)
        rows["headline.csv"] += _headline_rows(analysis)
        for name, more in _comparison_rows(analysis).items():
            rows[name] += more
        surface = analysis.result.scene.surface
        rows["findings.csv"] += [[analysis.result.scene.name, *_sweep(surface.at(value)), f.key,
                                  f.claim, f.evidence, f.verdict, *f.range_cells()]
                                 for value, found in analysis.findings.items() for f in found]
        rows["findings.csv"] += [[analysis.result.scene.name, *_scene_sweep(surface), f.key,
                                  f.claim, f.evidence, f.verdict, *f.range_cells()]
                                 for f in analysis.scene_findings]
        rows["theory.csv"] += _theory_rows(analysis)
        for name, more in sampling.table_rows(analysis).items():
            rows[name] += more
    return rows


def records(rows: dict[str, list[list]], name: str) -> list[dict]:
    """The rows of table ``name`` as dicts by column, as a CSV reader gives them back (but
    with the values unformatted)."""
    return [dict(zip(TABLES[name], row)) for row in rows.get(name, [])]


def write_tables(folder: pathlib.Path, analyses, rows: dict[str, list[list]] | None = None
                 ) -> list[str]:
    """Write every non-empty table into ``folder`` (``rows``: those of :func:`table_rows`,
    computed here when not given); returns the names written.

    Floats carry 10 significant digits."""
    rows = table_rows(analyses) if rows is None else rows
    written = []
    for name, table in rows.items():
        if table:
            with open(pathlib.Path(folder) / name, "w", newline="", encoding="utf-8") as stream:
                writer = csv.writer(stream)
                writer.writerow(TABLES[name])
                writer.writerows([_cell(value) for value in row] for row in table)
            written.append(name)
    return written
