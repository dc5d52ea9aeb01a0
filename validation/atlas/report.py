"""What the atlas shows: the short report of a prediction
(:class:`validation.atlas.predict.Prediction`: the scan's descriptors, where it sits in the
atlas, and per theory and quantity a strip of predicted verdicts, one mark per load point), and
a report's section on the atlas with its figure.

The figure: one panel per theory (rows) and quantity (columns), the predicted verdict of one
surface at the atlas' tolerance (green holds, red fails, grey undecided: the whole 90 % interval
within the tolerance, wholly beyond it, or neither) over H (x) and p / (E* h'_rms) (y,
logarithmic), at the atlas' middle Nayak alpha and Gaussian heights (skewness 0); ticks on the
x axis mark the H of the design points' surfaces. matplotlib is imported lazily
(:mod:`validation.report.layout`).
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np

from validation.atlas.model import interval_of, verdict_of
from validation.common.labels import model_label
from validation.common.verdicts import FAILS, HOLDS, UNDECIDED
from validation.judge.verdicts import SYMBOLS

__all__ = ["ATLAS_FIGURE", "MARKS", "atlas_section", "error_atlas_figure", "prediction_lines",
           "report_section", "strips", "terminal_lines", "verdict_map"]

#: One mark per predicted verdict in a strip: the glance's symbols, and one for a load point
#: outside the atlas (:data:`validation.atlas.predict.OUTSIDE`).
MARKS = {**SYMBOLS, "outside atlas": "·"}


def _range_line(name: str, label: str, value: float, ranges: dict, gate: bool = True) -> str:
    low, high = ranges[name]
    where = ("inside" if low <= value <= high else "**outside**") if gate else "(shown only)"
    return f"| {label} | {value:.3g} | {low:.3g} to {high:.3g} | {where} |"


def strips(rows) -> dict[tuple[str, str], list]:
    """The predicted rows per (model, quantity), lightest load first."""
    out: dict[tuple[str, str], list] = {}
    for r in rows:
        out.setdefault((r.model, r.quantity), []).append(r)
    return out


def terminal_lines(prediction) -> list[str]:
    """What the check prints before its solve: one strip of predicted verdicts per theory
    and quantity (the glance's symbols), or why there is none."""
    head = (f"predicted by the error atlas in {prediction.seconds:.2g} s, before the solve "
            f"(90 % intervals, tolerance {prediction.model['tolerance']:g}, interface frame; "
            "lightest pressure first, · outside the atlas):")
    if prediction.outside:
        return ["predicted by the error atlas: no verdict, the scan is outside it ("
                + "; ".join(prediction.outside) + ")"]
    width = max(len(model_label(name)) for name, _ in strips(prediction.rows))
    return [head] + [f"  {model_label(name):{width}s}  {quantity:10s}  "
                     + "".join(MARKS[p.verdict] for p in points)
                     for (name, quantity), points in strips(prediction.rows).items()]


def prediction_lines(prediction) -> list[str]:
    """The report's Markdown lines."""
    d, model, rows = prediction.descriptors, prediction.model, prediction.rows
    ranges = model["range"]
    lines = [f"# Predicted errors: {prediction.request.name}\n",
             "**Predicted, not solved.** Every number below comes from the error atlas "
             f"(periodic {model['grid']} x {model['grid']} self-affine surfaces, "
             f"{model['design_points']} design points, {model['realizations']} realizations "
             f"each, atlas commit `{model['atlas_commit'][:10]}`), evaluated at this scan's "
             "descriptors; no boundary-element solve was made. `python -m validation check` "
             "solves this very surface. The interval is a 90 % prediction interval for one "
             f"surface; a verdict is read at tolerance {model['tolerance']:g}: holds where the "
             "whole interval is within it, fails where it is wholly beyond it.\n",
             "## Where the scan sits in the atlas\n",
             "| descriptor | this scan | atlas | |", "|---|---|---|---|",
             _range_line("hurst", f"Hurst exponent H (± {d.hurst_error:.2g})", d.hurst, ranges),
             _range_line("nayak", "Nayak's alpha", d.nayak, ranges),
             _range_line("magnification", "magnification", d.magnification, ranges),
             _range_line("skewness", "skewness", d.skewness, ranges),
             _range_line("peak", "highest point / Sq", d.peak, ranges, gate=False),
             f"| kurtosis | {d.kurtosis:.3g} | | |",
             f"| Sq, h'_rms | {d.rms_height:.4g} m, {d.rms_slope:.3g} | | |", ""]
    if prediction.outside:
        lines += ["**Outside the atlas: no verdict.** " + "; ".join(prediction.outside)
                  + ". The error model is not extrapolated.\n"]
    low_load, high_load = ranges["load_ratio"]
    lines += [f"The atlas covers p / (E* h'_rms) from {low_load:.3g} to {high_load:.3g}; load "
              "points beyond it get no verdict (·).\n",
              "## Predicted verdicts (predicted)\n",
              "One mark per load point, lightest first: ✔ holds, ✘ fails, ? undecided, "
              "· outside the atlas. Interface frame.\n",
              "| theory | quantity | predicted verdicts | error at the middle load [90 % interval] |",
              "|---|---|---|---|"]
    for (name, quantity), points in strips(rows).items():
        strip = "".join(MARKS[p.verdict] for p in points)
        middle = points[len(points) // 2]
        number = ("– (outside the atlas)" if math.isnan(middle.error) else
                  f"{middle.error:+.2f} [{middle.low:+.2f}, {middle.high:+.2f}]")
        lines.append(f"| {model_label(name)} | {quantity} | `{strip}` (predicted) | {number} |")
    check = model.get("validation", {}).get("all", {})
    if check and not math.isnan(check.get("coverage", math.nan)):
        lines += ["", f"On design points left out of the fit, {100 * check['coverage']:.0f} % "
                      "of the errors fell inside their 90 % interval, and "
                      f"{100 * check['agreement']:.0f} % of the verdicts the interval decided "
                      "agreed with the solved surface's (docs/guide/prediction.md)."]
    leakage = any(r.quantity == "leakage" for r in rows)
    lines += ["", "Not covered: the finite frame (`--nominal-size`), "
                  + ("" if leakage else "the leakage, ") + "the contact count, scans far from "
                  "the atlas' periodic self-affine and WM surfaces (measurement noise, several "
                  "scales of roughness, strong anisotropy).",
              f"\nPredicted in {prediction.seconds:.2g} s."]
    return lines


#: File name of the figure in a report folder.
ATLAS_FIGURE = "error-atlas.png"
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


def error_atlas_figure(model: dict):
    """The figure (module docstring); its ticks the design surfaces' H as the model stores them
    (``model["design_hurst"]``; none where it does not)."""
    from matplotlib.colors import ListedColormap

    from validation.report.atlas import ATLAS_COLORS
    from validation.report.layout import figure

    theories, quantities = _entries(model)
    hurst = np.linspace(*model["range"]["hurst"], 61)
    ratio = np.geomspace(*model["range"]["load_ratio"], 41)
    fig, axes = figure(len(theories), len(quantities),
                       (2.1 * len(quantities) + 1.3, 1.45 * len(theories) + 1.0),
                       left=1.1, wspace=0.35, hspace=0.25)
    axes = np.atleast_2d(axes)
    colours = ListedColormap([ATLAS_COLORS[HOLDS], ATLAS_COLORS[FAILS], ATLAS_COLORS[UNDECIDED]])
    for i, theory in enumerate(theories):
        for j, quantity in enumerate(quantities):
            ax = axes[i, j]
            key = f"{theory}/interface/{quantity}"
            if key in model["entries"]:
                codes = np.vectorize(_CODE.get)(verdict_map(model, key, hurst, ratio))
                ax.pcolormesh(hurst, ratio, codes, cmap=colours, vmin=-0.5, vmax=2.5,
                              shading="nearest")
            ax.set_yscale("log")
            for h in model.get("design_hurst", ()):
                if hurst[0] <= h <= hurst[-1]:
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
    draw = partial(error_atlas_figure, model)
    return lines, [(ATLAS_FIGURE, draw, len(model["entries"]))]
