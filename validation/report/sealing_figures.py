"""The report's leakage figures: h_eff against load and separation for every model with the
reference's band, and the size sweep's curves against d and d1 (finding g).

Functions draw on an ``ax`` and return what they drew, or return a figure (``*_figure``), as in
:mod:`validation.report.figures` (matplotlib imported lazily, Agg backend).
"""

from __future__ import annotations

import numpy as np

from validation.judge.compare import converged_points
from validation.judge.sealing import SizeCollapse, effective_separation
from validation.report.figures import _quiet, dimensionless, panels_figure, plot_against, subplots
from validation.common.labels import QUANTITY_LABELS, model_label
from validation.common import models as registry

__all__ = ["leakage_figure", "plot_leakage", "plot_reference_leakage_band", "size_figure"]


def _reference(names) -> str | None:
    known = [name for name in names if name in registry.names()]
    return registry.reference_among(known)


def plot_reference_leakage_band(ax, results, x: str, length: float) -> list:
    """The reference's mean h_eff/σ ± its mean per-point error estimate (grey band) against
    ``x`` ("load" or "separation"), where the estimates exist."""
    reference = _reference(results[0].curves)
    if reference is None:
        return []
    xs, lows, highs = [], [], []
    for r in results:
        curve = r.curves[reference]
        error = curve.extras.get("leakage_error")
        values = dimensionless(curve, r.sigma, length)
        if error is None or "leakage" not in values:
            return []
        keep = converged_points(curve)
        half = np.asarray(error, dtype=float) / r.sigma
        xs.append(np.where(keep, values[x], np.nan))
        lows.append(np.where(keep, values["leakage"] - half, np.nan))
        highs.append(np.where(keep, values["leakage"] + half, np.nan))
    with np.errstate(invalid="ignore"), _quiet():
        x_mean, low, high = (np.nanmean(v, axis=0) for v in (xs, lows, highs))
    order = np.argsort(x_mean)
    return [ax.fill_between(x_mean[order], np.maximum(low[order], 0.0), high[order],
                            color="gray", alpha=0.35, linewidth=0,
                            label=f"{model_label(reference)}: ± its error estimate")]


def plot_leakage(ax, results, x: str, *, models, length: float) -> list:
    """h_eff/σ of every model against Load (log) or Separation (linear), realizations thin,
    their mean thick, the reference's band grey; linear in h_eff so that a sealed point (0)
    is drawn."""
    drawn = plot_against(ax, results, x, "leakage", models=models, length=length,
                         logx=x == "load", logy=False)
    drawn += plot_reference_leakage_band(ax, results, x, length)
    ax.set_ylim(bottom=0.0)
    return drawn


def leakage_figure(results, *, models, length: float):
    """Leakage against load and against separation (improved GW's curve against its d,
    although it is computed at its d1; Persson's drawn against its mean gap's separation)."""
    return panels_figure(lambda ax, x: plot_leakage(ax, results, x, models=models, length=length),
                         ["load", "separation"])


def size_figure(by_side: dict, collapse: SizeCollapse, m: float):
    """Finding (g): the reference's h_eff against d and against d1 = d + mW/(E*√A), one colour
    per nominal side (realizations thin, their mean thick), in units of the mean σ; the
    leakage levels at which the sizes are compared are dotted."""
    import matplotlib

    fig, axes = subplots(1, 2, figsize=(10.0, 4.0), squeeze=False)
    colours = matplotlib.colormaps["viridis"](np.linspace(0.0, 0.85, len(collapse.sides)))
    reference = _reference(by_side[collapse.sides[0]][0].curves)
    sigma = collapse.sigma
    for ax, name in zip(axes[0], ("d", "d1")):
        for side, colour in zip(collapse.sides, colours):
            xs, ys = [], []
            for r in by_side[side]:
                curve = r.curves[reference]
                keep = converged_points(curve)
                separation = curve.separation if name == "d" else effective_separation(curve, m)
                xs.append(np.where(keep, separation / sigma, np.nan))
                ys.append(np.where(keep, np.asarray(curve.leakage, dtype=float) / sigma, np.nan))
                ax.plot(xs[-1], ys[-1], color=colour, alpha=0.25, linewidth=0.7)
            with np.errstate(invalid="ignore"), _quiet():
                ax.plot(np.nanmean(xs, axis=0), np.nanmean(ys, axis=0), color=colour,
                        linewidth=2.0, marker=".",
                        label=f"L = {side:g} (area {side * side:g})")
        for level in collapse.levels:
            ax.axhline(level, color="gray", linewidth=0.5, linestyle=":")
        ax.set_xlabel("separation d/σ" if name == "d" else f"effective separation d₁/σ, "
                      f"d₁ = d + {m:g} W/(E*√A)")
        ax.set_ylabel(QUANTITY_LABELS["leakage"])
        ax.set_ylim(bottom=0.0)
        ax.grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=8)
    return fig
