"""The short report of a prediction (:class:`validation.atlas.predict.Prediction`): the scan's
descriptors, where it sits in the atlas, and per theory and quantity a strip of predicted
verdicts, one mark per load point."""

from __future__ import annotations

import math

from validation.common.labels import model_label

__all__ = ["MARKS", "prediction_lines", "strips", "terminal_lines"]

#: One mark per predicted verdict in a strip.
MARKS = {"holds": "✔", "fails": "✘", "undecided": "?", "outside atlas": "·"}


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
    lines += ["", "Not covered: the finite frame (`--nominal-size`), the leakage and the "
                  "contact count, scans far from periodic self-affine surfaces (measurement "
                  "noise, several scales of roughness, strong anisotropy).",
              f"\nPredicted in {prediction.seconds:.2g} s."]
    return lines
