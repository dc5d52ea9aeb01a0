"""The atlas: one figure per scene that shows where every model holds, at a glance.

One row per model and quantity, the BEM's contact-area fraction on a logarithmic x axis, each
load point's stretch of the row coloured by its verdict (holds / fails / undecided) at the
scene's largest tolerance, and beside it, below the row, a thin strip with the per-surface
verdict (none for one surface). A scene that sweeps a parameter gets one panel per swept value,
side by side. Dotted lines mark the headline's fractions (:mod:`validation.judge.headline`).
matplotlib is imported lazily (:mod:`validation.report.layout`).
"""

from __future__ import annotations

import numpy as np

from validation.judge.compare import COMPARED_QUANTITIES, Comparison
from validation.judge.headline import HEADLINE_FRACTIONS
from validation.judge.verdicts import FAILS, HOLDS, UNDECIDED
from validation.common.labels import compared_label, model_label, model_rank
from validation.report.layout import clip_ticks, figure, text_width

__all__ = ["ATLAS_COLORS", "atlas_figure", "atlas_keys", "cell_edges", "plot_atlas"]

#: Colour of each verdict (those of the verdict charts).
ATLAS_COLORS = {HOLDS: "#4caf50", FAILS: "#e53935", UNDECIDED: "#bdbdbd"}
_ORDER = (HOLDS, FAILS, UNDECIDED)
# Vertical layout of one row (row i spans i - 0.5 ... i + 0.5): the verdict bar, a gap, the
# per-surface strip, a gap to the next row.
_BAR, _GAP, _STRIP = 0.55, 0.05, 0.18


def atlas_keys(comparisons: list[Comparison]) -> list[tuple[str, str]]:
    """The (model, quantity) rows of an atlas, in report order."""
    return sorted({k for c in comparisons for k in c.models if k[1] in COMPARED_QUANTITIES},
                  key=lambda k: (model_rank(k[0]), COMPARED_QUANTITIES.index(k[1])))


def cell_edges(area_fraction: np.ndarray) -> np.ndarray:
    """Edges of each point's stretch on a log axis: geometric midpoints between neighbours,
    half a step beyond each end. ``area_fraction`` must be positive and increasing."""
    logs = np.log(np.asarray(area_fraction, dtype=float))
    if logs.size == 1:
        return np.exp(logs[0] + np.array([-0.5, 0.5]))
    middle = 0.5 * (logs[1:] + logs[:-1])
    return np.exp(np.concatenate(([logs[0] - (middle[0] - logs[0])], middle,
                                  [logs[-1] + (logs[-1] - middle[-1])])))


def _codes(verdicts) -> np.ndarray:
    return np.array([_ORDER.index(str(v)) if str(v) in _ORDER else np.nan for v in verdicts],
                    dtype=float)


def plot_atlas(ax, comparison: Comparison, keys: list[tuple[str, str]], index: int, *,
               labels: bool = True):
    """The atlas panel of one surface family: verdicts at ``tolerances[index]`` of the rows
    ``keys`` against the mean contact-area fraction of the BEM, the rows named when
    ``labels``. Returns what it drew."""
    from matplotlib.colors import ListedColormap
    from matplotlib.ticker import NullLocator

    from validation.report.figures import show_no_data

    area = np.asarray(comparison.area_fraction, dtype=float)
    keep = np.isfinite(area) & (area > 0)
    if not keep.any() or np.any(np.diff(area[keep]) <= 0):
        return show_no_data(ax, "no increasing contact-area fraction to draw against")
    edges = cell_edges(area[keep])
    rows = len(keys)
    # sub-rows per row: bar, gap, strip, gap (the gaps masked)
    heights = np.array([_BAR, _GAP, _STRIP, 1.0 - _BAR - _GAP - _STRIP])
    y = np.concatenate(([-0.5], -0.5 + np.cumsum(np.tile(heights, rows))))
    codes = np.full((4 * rows, int(keep.sum())), np.nan)
    for i, key in enumerate(keys):
        entry = comparison.models.get(key)
        if entry is None or not entry.verdicts:
            continue
        codes[4 * i] = _codes(entry.verdicts[index])[keep]
        if entry.surface_verdicts:
            codes[4 * i + 2] = _codes(entry.surface_verdicts[index])[keep]
    cmap = ListedColormap([ATLAS_COLORS[v] for v in _ORDER])
    drawn = [ax.pcolormesh(edges, y, np.ma.masked_invalid(codes), cmap=cmap, vmin=-0.5,
                           vmax=2.5)]
    for fraction in HEADLINE_FRACTIONS:
        if edges[0] < fraction < edges[-1]:
            drawn.append(ax.axvline(fraction, color="black", linestyle=":", linewidth=0.8))
    ax.set_xscale("log")
    ax.xaxis.set_minor_locator(NullLocator())   # decades only: a tick artist each costs
    ax.set_xlim(edges[0], edges[-1])
    ax.set_ylim(rows - 0.5, -0.5)
    if labels:
        ax.set_yticks(np.arange(rows) - 0.5 + _BAR / 2, row_labels(comparison, keys),
                      fontsize=7)
        ax.tick_params(axis="y", length=0)
    else:
        ax.yaxis.set_major_locator(NullLocator())
    ax.set_xlabel("BEM contact-area fraction A/A₀")
    return drawn


def row_labels(comparison: Comparison, keys: list[tuple[str, str]]) -> list[str]:
    """The atlas rows' names: model and compared field, and the frame where a scene has two."""
    from validation.common.models import FRAME_LABELS

    framed = len({e.frame for e in comparison.models.values()}) > 1
    out = []
    for m, q in keys:
        entry = comparison.models.get((m, q))
        frame = f" [{FRAME_LABELS.get(entry.frame, entry.frame)}]" if framed and entry else ""
        out.append(f"{model_label(m)}: {compared_label(q, _field(comparison, m, q))}{frame}")
    return out


def _field(comparison: Comparison, model: str, quantity: str) -> str:
    entry = comparison.models.get((model, quantity))
    return "" if entry is None else entry.reference_field


def atlas_figure(comparisons: list[Comparison], tolerances):
    """The atlas of a scene: one panel per surface family (swept value), side by side, at the
    scene's largest tolerance; a legend of the colours above the panels."""
    from matplotlib.patches import Patch

    from validation.report.sections import sweep_member

    comparisons = sorted(comparisons, key=lambda c: c.value)
    keys = atlas_keys(comparisons)
    index = int(np.argmax(tolerances))
    labels = row_labels(comparisons[0], keys)
    columns = len(comparisons)
    left, legend = text_width(labels, 7) + 0.2, 0.55
    titles = 0.35 if columns > 1 else 0.1         # room for the panels' titles
    width = left + columns * (6.0 if columns == 1 else 2.6) + (columns - 1) * 0.2 + 0.2
    height = 0.26 * max(len(keys), 1) + 0.65 + titles + legend
    fig, axes = figure(1, columns, (width, height), left=left, right=0.2, bottom=0.65,
                       top=titles + legend, wspace=0.2)
    for i, (ax, comparison) in enumerate(zip(axes[0], comparisons)):
        plot_atlas(ax, comparison, keys, index, labels=i == 0)
        if columns > 1:
            ax.set_title(sweep_member(comparison.parameter, comparison.value), fontsize=9)
    clip_ticks(axes)
    one = all(not e.surface_verdicts for c in comparisons for e in c.models.values())
    handles = [Patch(color=ATLAS_COLORS[v], label=v) for v in _ORDER]
    title = (f"within {tolerances[index]:g}" + ("" if one else
             "; thick bar: the mean error, thin strip below it: 90 % of single surfaces"))
    legend_artist = fig.legend(handles=handles, loc="upper center", ncols=3, fontsize=8,
                               title=title, title_fontsize=8,
                               bbox_to_anchor=(0.5, 1.0 - 0.05 / height))
    legend_artist.get_frame().set_linewidth(0.0)
    return fig
