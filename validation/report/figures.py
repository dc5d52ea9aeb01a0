"""The report's figures. matplotlib is imported lazily, with the Agg backend.

The report's figures are plain :class:`matplotlib.figure.Figure` objects (no pyplot state to
close) with a fixed layout: margins in inches, sized for the labels they hold (the verdict
chart's from its measured row labels), instead of a layout engine, which drew every figure
twice and measured every tick label on the way (about half the drawing time).

Plot functions take an ``ax`` and return what they drew; ``*_figure`` functions return a
figure. Every function draws whatever it has: points where a solver did not converge are left
out and counted on the axes, and an axes without any drawable point says so instead of
failing (a log axis with no positive value cannot be scaled).

Dimensionless quantities (the paper's Section 4, docs/theory.md eq. T4):
``Area = A_real / L^2``, ``Load = W / (E* L^2)``, ``Separation = d / sigma``,
``Conductance = C rho sigma / L^2 = 2 S sigma / (E* L^2) = -2 dLoad/dSeparation``.
"""

from __future__ import annotations

import numpy as np

from validation.judge.compare import Comparison, converged_points
from validation.common.labels import (ERROR_LABELS, MODEL_STYLES, QUANTITY_LABELS, compared_label,
                               model_label)
from validation.judge.verdicts import FAILS, HOLDS, SYMBOLS, UNDECIDED
from validation.report.layout import (clip_ticks, figure, panels_figure, png, pyplot, subplots,
                                      text_width)

__all__ = ["pyplot", "subplots", "figure", "png", "dimensionless", "show_no_data", "plot_theory_load",
           "plot_theory_stiffness", "plot_against", "plot_errors", "plot_verdicts",
           "plot_validity_map", "panels_figure", "verdict_figure", "validity_map_figure"]

VERDICT_COLORS = {HOLDS: "#4caf50", FAILS: "#e53935", UNDECIDED: "#bdbdbd"}
#: Line of each tolerance contour of the validity map, smallest tolerance first: told apart by
#: colour and dash, and each visible on both ends of the viridis colour map.
CONTOUR_STYLES = (dict(colors="white", linestyles="solid", linewidths=1.4),
                  dict(colors="tab:red", linestyles="dashed", linewidths=1.4),
                  dict(colors="black", linestyles="dotted", linewidths=1.4))
#: Axis label of each swept surface parameter (validation.scenes.scene.SWEEPS).
SWEEP_AXES = {"D": "fractal dimension D", "H": "Hurst exponent H", "L": "nominal side L"}


def dimensionless(curve, sigma: float, length: float) -> dict[str, np.ndarray]:
    """The paper's dimensionless arrays of a curve (:func:`asperity.dimensionless`), by name,
    plus the contact count, the reduced stiffness S sigma / (E* L^2) and the leakage
    h_eff / sigma when computed."""
    from asperity import dimensionless as reduce

    reduced = reduce(curve, sigma, length)
    out = {"area": reduced.area, "load": reduced.load, "separation": reduced.separation}
    if reduced.conductance is not None:
        out["conductance"] = reduced.conductance
        out["stiffness"] = reduced.conductance / 2.0
    if curve.contacts is not None:
        out["contacts"] = np.asarray(curve.contacts, dtype=float)
    if "mean_gap" in curve.extras:
        out["mean_gap"] = np.asarray(curve.extras["mean_gap"], dtype=float) / sigma
    if curve.leakage is not None:
        out["leakage"] = np.asarray(curve.leakage, dtype=float) / sigma
    return out


def show_no_data(ax, message: str) -> list:
    """Write ``message`` across an empty axes (linear scales, so nothing needs log-scaling)."""
    ax.set_xscale("linear")
    ax.set_yscale("linear")
    return [ax.text(0.5, 0.5, message, transform=ax.transAxes, ha="center", va="center",
                    fontsize=9, color="tab:red", wrap=True)]


def plot_theory_load(ax, theory: dict, C: float):
    """Figs. 1-2: reduced pressure p̄ against Separation for GW and improved GW (the theory
    scene's two models, drawn in their registered styles)."""
    curves = theory[C]
    lines = ax.semilogy(curves.separation, curves.gw_pressure, label="GW (no interaction)",
                        **MODEL_STYLES["gw"])
    lines += ax.semilogy(curves.separation, curves.improved_pressure,
                         label=f"improved GW (m = {theory['m']:g})", **MODEL_STYLES["improved_gw"])
    ax.set_xlabel("Separation (d − μs)/σ")
    ax.set_ylabel(r"$\bar p = p_{nom}\,/\,(\eta E^* R^{1/2} \sigma^{3/2})$")
    ax.set_title(f"C = {C:g}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return lines


def plot_theory_stiffness(ax, theory: dict, C: float):
    """Fig. 3: GW stiffness dW/dd₁ and the true stiffness dW/dd (reduced)."""
    curves = theory[C]
    lines = ax.semilogy(curves.separation, curves.effective_stiffness,
                        label=f"GW stiffness dW/dd₁, C = {C:g}", color="tab:blue", linestyle="--")
    lines += ax.semilogy(curves.separation, curves.improved_stiffness,
                         label=f"true stiffness dW/dd, C = {C:g}", color="tab:orange")
    ax.set_xlabel("Separation (d − μs)/σ")
    ax.set_ylabel(r"$-d\bar p/d(d/\sigma) = S\,/\,(N E^* R^{1/2} \sigma^{1/2})$")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return lines


def _drawable(results, model: str, x: str, y: str, length: float, logx: bool, logy: bool):
    """Per realization the (x, y) values that can be drawn, and the count of points left out."""
    pairs, left_out = [], 0
    for r in results:
        values = dimensionless(r.curves[model], r.sigma, length)
        if x not in values or y not in values:
            return [], 0
        keep = converged_points(r.curves[model]) & np.isfinite(values[x]) & np.isfinite(values[y])
        keep &= (values[x] > 0 if logx else True) & (values[y] > 0 if logy else True)
        left_out += int(np.count_nonzero(~keep))
        pairs.append((np.where(keep, values[x], np.nan), np.where(keep, values[y], np.nan)))
    return pairs, left_out


def plot_against(ax, results, x: str, y: str, *, models, length: float, logx=False, logy=True):
    """Every realization (thin) and the realization mean (thick) of y against x, per model."""
    drawn, notes = [], []
    for model in models:
        style = MODEL_STYLES.get(model, {})
        pairs, left_out = _drawable(results, model, x, y, length, logx, logy)
        for xs, ys in pairs:
            drawn += ax.plot(xs, ys, color=style.get("color"), alpha=0.25, linewidth=0.7)
        if pairs and not np.all(np.isnan([p[1] for p in pairs])):
            with np.errstate(invalid="ignore"), _quiet():
                mean = [np.nanmean([p[i] for p in pairs], axis=0) for i in (0, 1)]
            drawn += ax.plot(*mean, label=model_label(model), **style)
        if left_out:
            notes.append(f"{model_label(model)}: {left_out} point(s) not drawn")
    if x == "separation":
        drawn += _reference_mean_gap(ax, results, models, y, length, logy)
    ax.set_xlabel(QUANTITY_LABELS[x])
    ax.set_ylabel(QUANTITY_LABELS[y])
    if not any(len(line.get_xdata()) and np.isfinite(line.get_ydata()).any() for line in drawn):
        return drawn + show_no_data(ax, "no converged point to draw\n" + "\n".join(notes))
    ax.set_xscale("log" if logx else "linear")
    ax.set_yscale("log" if logy else "linear")
    if notes:
        drawn.append(ax.text(0.02, 0.02, "unconverged or non-positive, not drawn:\n"
                             + "\n".join(notes), transform=ax.transAxes, fontsize=6))
    ax.grid(True, which="both", alpha=0.3)
    return drawn


def _reference_mean_gap(ax, results, models, y: str, length: float, logy: bool) -> list:
    """The reference's mean gap ū/σ beside its separation d/σ (dotted): the quantity Persson's
    theory is compared with."""
    from validation.common import models as registry

    drawn = []
    for model in models:
        if model not in registry.names() or not registry.entry(model).reference:
            continue
        pairs, _ = _drawable(results, model, "mean_gap", y, length, False, logy)
        if pairs and not np.all(np.isnan([p[1] for p in pairs])):
            with np.errstate(invalid="ignore"), _quiet():
                mean = [np.nanmean([p[i] for p in pairs], axis=0) for i in (0, 1)]
            style = dict(MODEL_STYLES.get(model, {}), linestyle=":", linewidth=1.5)
            drawn += ax.plot(*mean, label=f"{model_label(model)}, mean gap ū/σ", **style)
    return drawn


class _quiet:
    """Silence numpy's 'mean of empty slice' warning for all-NaN columns (they stay NaN)."""

    def __enter__(self):
        import warnings

        self._catch = warnings.catch_warnings()
        self._catch.__enter__()
        warnings.simplefilter("ignore", RuntimeWarning)

    def __exit__(self, *exc):
        return self._catch.__exit__(*exc)


def plot_errors(ax, comparison: Comparison, quantity: str, tolerances):
    """Mean error with its 95 % interval (band) against Load per model; grey: reference band."""
    drawn, load = [], comparison.load
    entries = [(m, e) for (m, q), e in comparison.models.items() if q == quantity]
    fields = {compared_label(quantity, e.reference_field) for _, e in entries}
    for model, entry in entries:
        style = MODEL_STYLES.get(model, {})
        mean = entry.summary.mean
        label = model_label(model) + (f" ({compared_label(quantity, entry.reference_field)})"
                                      if len(fields) > 1 else "")
        drawn += ax.plot(load, mean, label=label, **style)
        if entry.interval is not None:
            half = np.where(np.isfinite(entry.interval.half_width), entry.interval.half_width, np.nan)
            drawn.append(ax.fill_between(load, mean - half, mean + half, color=style.get("color"),
                                         alpha=0.15, linewidth=0))
    if entries and entries[0][1].band is not None and np.any(entries[0][1].band > 0):
        band = entries[0][1].band
        drawn.append(ax.fill_between(load, -band, band, color="gray", alpha=0.35, linewidth=0,
                                     label="reference band"))
    for tol in tolerances:
        for sign in (-1, 1):
            drawn.append(ax.axhline(sign * tol, color="red", linewidth=0.6, linestyle=":"))
    ax.set_xscale("log")
    ax.set_xlabel(QUANTITY_LABELS["load"])
    ylabel = ERROR_LABELS.get(quantity, quantity)
    if len(fields) > 1:     # e.g. separation d of the asperity models, mean gap ū of Persson
        ylabel = f"error of {' or '.join(sorted(fields, reverse=True))} / σ"
    ax.set_ylabel(ylabel)
    if not any(np.any(np.isfinite(e.summary.mean)) for _, e in entries):
        return drawn + show_no_data(ax, "no converged point: no error to show")
    ax.set_yscale("symlog", linthresh=min(tolerances) / 2)
    ax.grid(True, which="both", alpha=0.3)
    return drawn


def plot_verdicts(ax, comparison: Comparison, index: int):
    """Verdict per load point (columns) of every model and quantity (rows): ✔ / ✘ / ?."""
    from matplotlib.colors import ListedColormap

    keys = [k for k, e in comparison.models.items() if e.verdicts]
    if not keys:
        return show_no_data(ax, "no verdicts")
    order = [HOLDS, FAILS, UNDECIDED]
    codes = np.array([[order.index(str(v)) for v in comparison.models[k].verdicts[index]]
                      for k in keys])
    cmap = ListedColormap([VERDICT_COLORS[v] for v in order])
    drawn = [ax.imshow(codes, cmap=cmap, vmin=-0.5, vmax=2.5, aspect="auto")]
    # one marker collection per symbol (glyph outlines, about 6 pt high like 8-pt text): a text
    # artist per cell cost a third of the figure's drawing
    for code, verdict in enumerate(order):
        rows, columns = np.nonzero(codes == code)
        if rows.size:
            drawn.append(ax.scatter(columns, rows, s=42, marker=f"${SYMBOLS[verdict]}$",
                                    color="black", linewidths=0))
    ax.set_yticks(range(len(keys)), [f"{model_label(m)}: {q}" for m, q in keys], fontsize=7)
    ax.set_xticks(range(comparison.load.size),
                  [f"{v:.1g}" for v in comparison.load], rotation=90, fontsize=6)
    tolerance = comparison.models[keys[0]].tolerances[index]
    ax.set_title(f"within {tolerance:g}", fontsize=9)
    ax.set_xlabel(QUANTITY_LABELS["load"])
    return drawn


def plot_validity_map(ax, comparisons: list[Comparison], model: str, quantity: str, tolerances):
    """``|mean error|`` of one model in the plane of Load and the swept parameter (D, H), with the
    tolerance contours."""
    from matplotlib.colors import LogNorm

    comparisons = sorted(comparisons, key=lambda c: c.value)
    load = comparisons[0].load
    values = np.array([c.value for c in comparisons])
    error = np.array([np.abs(c.models[(model, quantity)].summary.mean)
                      if (model, quantity) in c.models else np.full(load.shape, np.nan)
                      for c in comparisons])
    field = next((c.models[(model, quantity)].reference_field for c in comparisons
                  if (model, quantity) in c.models), "")
    ax.set_title(f"{model_label(model)}: {compared_label(quantity, field)}", fontsize=9)
    if not np.any(np.isfinite(error)):
        return show_no_data(ax, "no converged point")
    error = np.ma.masked_invalid(np.clip(error, 1e-4, 10.0))
    mesh = ax.pcolormesh(load, values, error, shading="nearest", norm=LogNorm(1e-3, 3.0),
                         cmap="viridis")
    drawn = [mesh]
    if len(values) > 1 and not np.ma.is_masked(error):
        for tolerance, style in zip(sorted(tolerances), CONTOUR_STYLES):
            if np.nanmin(error) < tolerance < np.nanmax(error):  # only contours that exist
                drawn.append(ax.contour(load, values, error, levels=[tolerance], **style))
    ax.set_xscale("log")
    ax.set_xlabel(QUANTITY_LABELS["load"])
    parameter = comparisons[0].parameter
    ax.set_ylabel(SWEEP_AXES.get(parameter, parameter))
    ax.set_yticks(values)
    return drawn


def verdict_figure(comparison: Comparison):
    """The verdict chart of one surface family: one panel per tolerance."""
    first = next((e for e in comparison.models.values() if e.verdicts), None)
    count = len(first.tolerances) if first else 1
    rows = max(1, len(comparison.models))
    labels = [f"{model_label(m)}: {q}" for (m, q), e in comparison.models.items() if e.verdicts]
    fig, axes = figure(1, count, (4.5 * count + 1.5, 0.28 * rows + 1.6),
                       left=text_width(labels, 7) + 0.15, right=0.1, bottom=0.65, top=0.3,
                       wspace=0.12)
    for index, ax in enumerate(axes[0]):
        plot_verdicts(ax, comparison, index)
    for ax in axes[0][1:]:
        ax.set_yticks([])
    return fig


#: Most models side by side in a validity map; more go one per row.
MAP_COLUMNS = 5


def validity_map_figure(comparisons: list[Comparison], keys: list, tolerances):
    """``|mean error|`` over Load and the swept parameter: rows quantities, columns models (rows
    models, columns quantities when there are more than :data:`MAP_COLUMNS` models)."""
    models = list(dict.fromkeys(k[0] for k in keys))
    quantities = list(dict.fromkeys(k[1] for k in keys))
    by_model = len(models) > MAP_COLUMNS
    rows, columns = (models, quantities) if by_model else (quantities, models)
    # fixed room [inches]: the colour bar at the right (below the panels with many models: gap,
    # bar, its tick labels and label) and the contour legend above the panels' titles
    side, below = (0.0, 0.95) if by_model else (1.2, 0.0)
    legend = _CONTOUR_LEGEND
    fig, axes = figure(len(rows), len(columns),
                       ((4.2 if by_model else 3.6) * len(columns), 3.0 * len(rows) + below + legend),
                       left=0.7, right=0.1, bottom=0.55 + below, top=0.3 + legend, wspace=0.65,
                       hspace=0.6, colorbar=side)
    meshes = [plot_validity_map(axes[i][j], comparisons, *((r, c) if by_model else (c, r)),
                                tolerances)[0]
              for i, r in enumerate(rows) for j, c in enumerate(columns)]
    for ax in axes[:-1].ravel():
        ax.set_xlabel("")
    for ax in axes[:, 1:].ravel():
        ax.set_ylabel("")
    clip_ticks(axes)
    mesh = next((m for m in meshes if hasattr(m, "get_cmap")), None)
    if mesh is not None:
        width, height = fig.get_size_inches()
        if by_model:
            bar = fig.add_axes((0.7 / width, 0.75 / height, 1.0 - 0.8 / width, 0.12 / height),
                               label="colorbar")
        else:
            bottom, top = 0.55 / height, 1.0 - (0.3 + legend) / height
            bar = fig.add_axes(((width - side + 0.25) / width, bottom, 0.2 / width, top - bottom),
                               label="colorbar")
        fig.colorbar(mesh, cax=bar, orientation="horizontal" if by_model else "vertical",
                     label="|mean error| (relative, or /σ for separation)")
    _contour_legend(fig, tolerances)
    return fig


#: Height [inches] kept above a validity map's panels for its contour legend (title and one row).
_CONTOUR_LEGEND = 0.55


def _contour_legend(fig, tolerances) -> None:
    """One legend entry per tolerance contour (:data:`CONTOUR_STYLES`), above the panels."""
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=style["colors"], linestyle=style["linestyles"],
                      linewidth=style["linewidths"], label=f"|mean error| = {tolerance:g}")
               for tolerance, style in zip(sorted(tolerances), CONTOUR_STYLES)]
    legend = fig.legend(handles=handles, loc="upper center",
                        bbox_to_anchor=(0.5, 1.0 - 0.05 / fig.get_figheight()), ncols=len(handles),
                        fontsize=8, title="tolerance contours", title_fontsize=8)
    legend.get_frame().set_facecolor("0.6")  # white and black lines both stand out on grey
