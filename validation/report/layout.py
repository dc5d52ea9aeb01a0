"""Figure layout for the report: matplotlib on the Agg backend (imported lazily), figures of
equal panels with fixed margins in inches instead of a layout engine, PNG bytes, legends beside
a row of panels when they would hide a curve, and only the ticks in view on log axes (a tick
artist per location a log locator returns beyond the view was a third of a figure's cost)."""

from __future__ import annotations

import io

import numpy as np

__all__ = ["LEGEND_BESIDE", "LEGEND_INSIDE", "clip_ticks", "figure", "panels_figure", "png",
           "pyplot", "subplots", "text_width"]


def pyplot():
    """matplotlib.pyplot on the Agg backend (imported on first use)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def subplots(*args, **kwargs):
    """pyplot's subplots with constrained layout (figures outside the report)."""
    return pyplot().subplots(*args, layout="constrained", **kwargs)


def figure(rows: int, columns: int, figsize: tuple[float, float], *, left: float = 0.85,
           right: float = 0.15, bottom: float = 0.6, top: float = 0.35, wspace: float = 0.85,
           hspace: float = 0.0, colorbar: float = 0.0):
    """A figure of ``rows x columns`` equal panels with fixed margins [inches].

    Parameters
    ----------
    rows, columns : int
        Panels.
    figsize : (float, float)
        Width and height [inches].
    left, right, bottom, top : float
        Margins around the panels [inches]: room for the tick labels and axis labels (left,
        bottom) and the titles (top).
    wspace, hspace : float
        Gaps between panels [inches].
    colorbar : float
        Width [inches] kept free at the right for a colour bar axes (:func:`validity_map_figure`).

    Returns
    -------
    (matplotlib.figure.Figure, numpy.ndarray of Axes)
        The axes as a ``rows x columns`` array.
    """
    from matplotlib.figure import Figure

    width, height = figsize
    right = right + colorbar
    panel_width = (width - left - right - (columns - 1) * wspace) / columns
    panel_height = (height - bottom - top - (rows - 1) * hspace) / rows
    fig = Figure(figsize=figsize)
    axes = fig.subplots(rows, columns, squeeze=False, gridspec_kw=dict(
        left=left / width, right=1.0 - right / width, bottom=bottom / height,
        top=1.0 - top / height, wspace=wspace / panel_width, hspace=hspace / panel_height))
    return fig, axes


def png(fig, dpi: int = 100) -> bytes:
    """The figure as PNG bytes (Agg)."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=dpi)
    return buffer.getvalue()


#: Fixed margins of the report's panels [inches]: tick labels and axis label at the left and the
#: bottom (symlog labels such as -10^-1 are the widest), a title's height at the top when any
#: panel has one. Constrained layout placed the same panels 0.66-0.79 in from the left, 0.48-0.50
#: in from the bottom and 0.73-0.84 in apart.
_MARGINS = dict(left=0.85, right=0.1, bottom=0.55, top=0.1, wspace=0.9)
_TITLE_HEIGHT = 0.22


def _make_room_for_titles(fig, axes) -> None:
    if any(ax.get_title() for ax in np.ravel(axes)):
        height = fig.get_size_inches()[1]
        np.ravel(axes)[0].get_gridspec().update(
            top=1.0 - (_MARGINS["top"] + _TITLE_HEIGHT) / height)
        for ax in np.ravel(axes):  # (the update moves the axes of pyplot's figures only)
            ax.set_position(ax.get_subplotspec().get_position(fig))


def _in_view(locator):
    """``locator`` without the ticks outside the view: matplotlib makes a tick artist (two lines, a
    grid line, two labels) for every location a locator returns, and log and symlog locators
    return a decade or more beyond each end; those artists were a third of a figure's cost."""
    from matplotlib.ticker import Locator

    class InView(Locator):
        def set_axis(self, axis):
            super().set_axis(axis)
            locator.set_axis(axis)

        def __call__(self):
            low, high = sorted(self.axis.get_view_interval())
            ticks = np.asarray(locator())
            slack = 1e-9 * (high - low)
            return ticks[(ticks >= low - slack) & (ticks <= high + slack)]

        def tick_values(self, vmin, vmax):
            return locator.tick_values(vmin, vmax)

    return InView()


def clip_ticks(axes) -> None:
    """Keep only the ticks in view on every log or symlog axis of ``axes`` (see :func:`_in_view`)."""
    for ax in np.ravel(axes):
        for axis in (ax.xaxis, ax.yaxis):
            if axis.get_scale() in ("log", "symlog"):
                axis.set_major_locator(_in_view(axis.get_major_locator()))
                axis.set_minor_locator(_in_view(axis.get_minor_locator()))


def _widen(fig, axes, inches: float) -> None:
    """Add ``inches`` of free room at the right of ``fig``, its panels left as they are."""
    width = fig.get_figwidth()
    grid = np.ravel(axes)[0].get_gridspec()
    grid.update(left=grid.left * width / (width + inches),
                right=grid.right * width / (width + inches))
    fig.set_figwidth(width + inches)
    for ax in np.ravel(axes):  # (the update moves the axes of pyplot's figures only)
        ax.set_position(ax.get_subplotspec().get_position(fig))


#: Legend entries that still fit inside the first panel; a longer legend goes beside the panels.
LEGEND_INSIDE = 6
#: Width [inches] added at the right of a row of panels for a legend beside them.
LEGEND_BESIDE = 2.6


def panels_figure(draw, panels: list, *, width: float = 5.0, height: float = 4.0, legend=8):
    """One row of panels, ``draw(ax, panel)`` each; the first panel's legend on it, or beside
    the row when it has more than :data:`LEGEND_INSIDE` entries (so that it hides no curve)."""
    fig, axes = figure(1, len(panels), (width * len(panels), height), **_MARGINS)
    for ax, panel in zip(axes[0], panels):
        draw(ax, panel)
    handles, labels = axes[0][0].get_legend_handles_labels()
    if len(handles) > LEGEND_INSIDE:
        _widen(fig, axes, LEGEND_BESIDE)
        _make_room_for_titles(fig, axes)
        box = axes[0][-1].get_position()
        fig.legend(handles, labels, loc="upper left", bbox_to_anchor=(
            box.x1 + 0.1 / fig.get_figwidth(), box.y1), fontsize=legend)
    elif handles:
        axes[0][0].legend(fontsize=legend)
    _make_room_for_titles(fig, axes)
    clip_ticks(axes)
    return fig


def text_width(texts, fontsize: float, dpi: float = 100.0) -> float:
    """Width [inches] of the widest of ``texts`` at ``fontsize`` drawn at ``dpi`` (Agg's text
    metrics, which depend on the resolution through hinting)."""
    from matplotlib.backends.backend_agg import RendererAgg
    from matplotlib.font_manager import FontProperties

    renderer = RendererAgg(1, 1, dpi)
    font = FontProperties(size=fontsize)
    widths = [renderer.get_text_width_height_descent(text, font, ismath=False)[0]
              for text in texts]
    return max(widths, default=0.0) / dpi
