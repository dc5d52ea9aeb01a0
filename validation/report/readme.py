"""The README's compact results: the paper scenes' headline at 1 % and 10 % contact, generated
from a published report's ``headline.csv`` (``python docs/readme_results.py`` writes it between
the README's results markers; a test checks that the README holds exactly this text)."""

from __future__ import annotations

import csv
import math
import pathlib

from validation.common.labels import compared_label, model_label, model_rank
from validation.judge.verdicts import SYMBOLS
from validation.report.summary import error_text

__all__ = ["README_FRACTIONS", "README_SCENES", "readme_results"]

#: Scenes and contact-area fractions of the README's table.
README_SCENES = ("paper-wm-d205", "paper-wm-d295")
README_FRACTIONS = (0.01, 0.1)
_QUANTITIES = ("area", "separation", "conductance", "leakage")


def _cell(row: dict | None) -> str:
    if row is None:
        return "–"
    q = row["quantity"]
    value = {k: float(row[k]) for k in ("mean_error", "low", "high")}
    if not all(math.isfinite(v) for v in value.values()):
        return "–"
    return (f"{error_text(value['mean_error'], q, unit=False)} "
            f"({error_text(value['low'], q, unit=False)}, {error_text(value['high'], q, unit=False)})"
            f" {SYMBOLS.get(row['verdict'], '?')}")


def readme_results(folder: str | pathlib.Path, tolerance: float = 0.2) -> str:
    """The README's results block (without its markers) from ``folder/headline.csv``.

    Raises
    ------
    ValueError
        When the folder's headline has none of :data:`README_SCENES` at ``tolerance``.
    """
    path = pathlib.Path(folder) / "headline.csv"
    with path.open(newline="", encoding="utf-8") as stream:
        rows = [r for r in csv.DictReader(stream) if r["scene"] in README_SCENES
                and math.isclose(float(r["tolerance"]), tolerance)]
    if not rows:
        raise ValueError(f"{path} holds no headline of {', '.join(README_SCENES)} at tolerance "
                         f"{tolerance:g}")
    cells = {(r["scene"], r["model"], r["quantity"], float(r["area_fraction"])): r for r in rows}
    realizations = max(int(r["realizations"]) for r in rows)
    quantities = [q for q in _QUANTITIES if any(r["quantity"] == q for r in rows)]
    lines = [f"Each model's mean error against the exact solution where the BEM's real contact area "
             f"is {' and '.join(f'{100 * f:g} %' for f in README_FRACTIONS)} of the nominal area, "
             f"over {realizations} realizations of WM surfaces, with its 95 % interval; ✔ within "
             f"{tolerance:g}, ✘ beyond, ? undecided (the reference's own error allowed for). "
             f"Area and conductance in %, separation in σ (Persson: its mean gap), leakage as "
             f"ln(h_eff/h_eff,BEM).", ""]
    for scene in README_SCENES:
        present = [r for r in rows if r["scene"] == scene]
        if not present:
            continue
        D = present[0]["D"]
        fields = [q for q in quantities if any(r["quantity"] == q for r in present)]
        header = ["model"] + [f"{compared_label(q)} {100 * f:g} %" for q in fields
                              for f in README_FRACTIONS]
        lines += [f"**D = {float(D):g}** (`{scene}`):", "",
                  "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
        models = sorted({r["model"] for r in present}, key=model_rank)
        for model in models:
            gap = any(r["model"] == model and r["reference_field"] == "mean_gap" for r in present)
            row = [model_label(model) + (" (mean gap ū)" if gap else "")] + [_cell(cells.get((scene, model, q, f)))
                                          for q in fields for f in README_FRACTIONS]
            lines.append("| " + " | ".join(row) + " |")
        lines.append("")
    return "\n".join(lines)
