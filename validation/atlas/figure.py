"""The error atlas at a glance: where each theory is predicted to hold over the Hurst exponent and
the load, before any solve (:mod:`validation.atlas.model`), and its section of a report.

One panel per theory (rows) and quantity (columns): the predicted verdict of one surface at the
atlas' tolerance (green holds, red fails, grey undecided: the whole 90 % interval within the
tolerance, wholly beyond it, or neither) over H (x) and p / (E* h'_rms) (y, logarithmic), at the
atlas' middle Nayak alpha and Gaussian heights (skewness 0); ticks on the x axis mark the H of
the design points' surfaces. matplotlib is imported lazily (:mod:`validation.report.layout`).
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np

from validation.atlas.model import interval_of, verdict_of
from validation.common.labels import model_label
from validation.common.verdicts import FAILS, HOLDS, UNDECIDED

__all__ = ["ATLAS_FIGURE", "atlas_section", "design_hurst", "error_atlas_figure", "report_section",
           "verdict_map"]

#: File name of the figure in a report folder.
ATLAS_FIGURE = "error-atlas.png"
_COLORS = {HOLDS: "#4caf50", FAILS: "#e53935", UNDECIDED: "#bdbdbd"}
_CODE = {HOLDS: 0, FAILS: 1, UNDECIDED: 2}


def _entries(model: dict) -> tuple[list[str], list[str]]:
    """The theories and quantities of the model's interface entries, in a stable order."""
    keys = [k.split("/") for k in model["entries"] if k.split("/")[1] == "interface"]
    theories = sorted({k[0] for k in keys}, key=model_label)
    order = ("area", "separation", "stiffness", "leakage")
    quantities = [q for q in order if any(k[2] == q for k in keys)]
    return theories, quantities


def verdict_map(model: dict, key: str, hurst: np.ndarray, load_ratio: np.ndarray
                ) -> np.ndarray:
    """The predicted verdicts of ``key`` on the grid ``load_ratio`` (rows) x ``hurst``
    (columns), at the middle of the atlas' log10 alpha and skewness 0."""
    low_alpha, high_alpha = model["range"]["nayak"]
    alpha = math.sqrt(low_alpha * high_alpha)
    h, x = np.meshgrid(hurst, np.log10(load_ratio))
    covariates = np.column_stack([h.ravel(), np.full(h.size, math.log10(alpha)),
                                  np.zeros(h.size), x.ravel()])
    _, low, high = interval_of(model, key, covariates)
    return verdict_of(low, high, float(model["tolerance"])).reshape(h.shape)


def design_hurst(model: dict) -> tuple[float, ...]:
    """The H of the design points the model stores (``model["design_hurst"]``), else none."""
    return tuple(model.get("design_hurst", ()))


def error_atlas_figure(model: dict, design_hurst: tuple[float, ...] = ()):
    """The figure (module docstring); ``design_hurst``: the design surfaces' H, as ticks."""
    from matplotlib.colors import ListedColormap

    from validation.report.layout import figure

    theories, quantities = _entries(model)
    hurst = np.linspace(*model["range"]["hurst"], 61)
    ratio = np.geomspace(*model["range"]["load_ratio"], 41)
    fig, axes = figure(len(theories), len(quantities),
                       (2.1 * len(quantities) + 1.3, 1.45 * len(theories) + 1.0),
                       left=1.1, wspace=0.35, hspace=0.25)
    axes = np.atleast_2d(axes)
    colours = ListedColormap([_COLORS[HOLDS], _COLORS[FAILS], _COLORS[UNDECIDED]])
    for i, theory in enumerate(theories):
        for j, quantity in enumerate(quantities):
            ax = axes[i, j]
            key = f"{theory}/interface/{quantity}"
            if key in model["entries"]:
                codes = np.vectorize(_CODE.get)(verdict_map(model, key, hurst, ratio))
                ax.pcolormesh(hurst, ratio, codes, cmap=colours, vmin=-0.5, vmax=2.5,
                              shading="nearest")
            ax.set_yscale("log")
            for h in design_hurst:
                ax.axvline(h, ymin=0, ymax=0.04, color="k", lw=0.6)
            if i == 0:
                ax.set_title(quantity, fontsize=9)
            if j == 0:
                ax.set_ylabel(f"{model_label(theory)}\np/(E* h'rms)", fontsize=8)
            if i == len(theories) - 1:
                ax.set_xlabel("Hurst exponent H", fontsize=8)
            ax.tick_params(labelsize=7)
    return fig


def atlas_section(model: dict) -> tuple[list[str], str]:
    """The report's section on the atlas (Markdown lines) and the figure's caption."""
    check = model.get("validation", {}).get("all", {})
    alpha = math.sqrt(model["range"]["nayak"][0] * model["range"]["nayak"][1])
    measured = ("" if not check else
                f" Left out of the fit, {100 * check['coverage']:.0f} % of the design "
                f"surfaces' errors fell inside their 90 % interval, and "
                f"{100 * check['agreement']:.0f} % of the verdicts both decided agreed.")
    names = {"self-affine": "Gaussian self-affine", "plateau": "plateau-honed", "wm": "WM"}
    kinds = [f"{count} {names.get(kind, kind)}"
             for kind, count in model.get("families", {}).items()]
    kinds = "" if not kinds else ": " + (kinds[0] if len(kinds) == 1 else
                                         ", ".join(kinds[:-1]) + " and " + kinds[-1])
    lines = ["## Before the solve: the error atlas\n",
             f"Each theory's error on one surface predicted from its descriptors (the error "
             f"model of {model['design_points']} design points{kinds}, with "
             f"{model['realizations']} periodic {model['grid']}² realizations each; "
             f"docs/guide/prediction.md), no boundary-element solve: "
             f"`python -m validation predict SCAN` gives it for any scan in a second, and "
             f"`check` prints it before it solves.{measured}\n"]
    caption = (f"Where each theory is predicted to hold on one surface (interface frame, "
               f"tolerance {model['tolerance']:g}): green holds, red fails, grey undecided (the "
               f"90 % interval straddles the tolerance), over the Hurst exponent and the load "
               f"p/(E* h'rms) (at light load about half the contact-area fraction: A/A0 ≈ 2 p/(E* h'rms)), at Nayak's "
               f"alpha {alpha:.3g} and Gaussian heights; ticks: the design surfaces' H.")
    return lines, caption


def report_section(model: dict | None = None) -> tuple[list[str], list[tuple]]:
    """The section of a report on the atlas, its figure included, and the figure's job for
    :func:`validation.report.write.write_report` (``sections``, ``figure_jobs``); ``model``
    default the package's."""
    from validation.atlas.model import load_error_model

    model = load_error_model() if model is None else model
    lines, caption = atlas_section(model)
    lines += [f"![{caption}]({ATLAS_FIGURE})\n", f"*{caption}*\n"]
    draw = partial(error_atlas_figure, model, design_hurst(model))
    return lines, [(ATLAS_FIGURE, draw, len(model["entries"]))]
