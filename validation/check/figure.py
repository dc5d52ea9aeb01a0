"""The check's figure: every theory against the reference, in physical units, one panel per
quantity (matplotlib imported here only)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from validation.common.labels import model_label
from validation.common import models

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["physical_figure"]


def _panel(ax, table) -> None:
    x = table.pressure if table.pressure is not None else table.load
    percent = 100.0 if table.unit == "" else 1.0
    styles = models.styles()
    for model, values in table.models.items():
        ax.plot(x, values * percent, label=model_label(model), **styles.get(model, {}))
    ax.errorbar(x, table.reference * percent, yerr=table.band * percent, fmt="o", color="black",
                markersize=3, capsize=2, label="BEM (reference, with band)")
    ax.set_xscale("log")
    positive = table.reference[np.isfinite(table.reference)] > 0
    if positive.any() and table.field in ("area", "stiffness", "conductance"):
        ax.set_yscale("log")
    ax.set_xlabel("nominal pressure p [Pa]" if table.pressure is not None else "p / E*")
    unit = "%" if table.unit == "" else table.unit
    ax.set_ylabel(f"{table.heading.split(' (')[0]} [{unit}]", fontsize=8)
    ax.grid(True, which="both", alpha=0.3)


def physical_figure(tables) -> Figure:
    """One panel per table of :func:`validation.check.physical.physical_tables`: a matplotlib
    Figure not attached to pyplot (no display needed; a notebook shows it)."""
    from validation.report.layout import figure as panels

    count = len(tables)
    columns = 2 if count > 1 else 1
    rows = -(-count // columns)
    # fixed margins [inches] (tight_layout placed the same panels in 0.7 s of a check's 5 s of
    # figures): tick and axis labels left of and below each panel, the legend's rows below all
    legend_columns = 4 if columns > 1 else 2
    legend_rows = -(-(len(tables[0].models) + 1) // legend_columns) if tables else 0
    figure, axes = panels(rows, columns, (5.2 * columns, 3.6 * rows + 0.2 * legend_rows),
                          left=0.8, right=0.15, bottom=0.65 + 0.2 * legend_rows, top=0.15,
                          wspace=0.85, hspace=0.65)
    for ax, table in zip(axes.flat, tables):
        _panel(ax, table)
    for ax in list(axes.flat)[count:]:
        ax.set_visible(False)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="lower center", ncol=legend_columns, fontsize=7,
                  frameon=False)
    return figure
