"""A prediction set against the solved check of the same scan: how often the check's error lies
inside the predicted 90 % interval (the coverage) and how often the two verdicts agree where
both decide (docs/guide/prediction.md)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from validation.atlas.predict import OUTSIDE, Prediction
from validation.common.verdicts import FAILS, HOLDS

__all__ = ["PredictionCheck", "against_check"]

#: The comparison's quantity of a check table's field (Persson's mean gap is its separation).
_QUANTITY = {"mean_gap": "separation", "conductance": "stiffness"}


@dataclass(frozen=True)
class PredictionCheck:
    """The prediction of a scan against its check, cell by cell (theory, quantity, pressure of
    the interface frame, inside the atlas).

    Attributes
    ----------
    cells : int
        Predicted cells the check solved and judged.
    inside : int
        Of those, the cells whose solved error lies inside the predicted 90 % interval.
    decided : int
        Cells where both the prediction and the check decide (holds or fails).
    agree : int
        Of those, the cells with the same verdict.
    """

    cells: int
    inside: int
    decided: int
    agree: int

    @property
    def coverage(self) -> float:
        """Share of the cells whose solved error lies inside the interval (NaN without any)."""
        return self.inside / self.cells if self.cells else math.nan

    @property
    def agreement(self) -> float:
        """Share of the cells both decide with the same verdict (NaN without any)."""
        return self.agree / self.decided if self.decided else math.nan

    def sentence(self) -> str:
        """One sentence for the command line and the report."""
        if not self.cells:
            return "The atlas predicted no cell the check judged (the scan is outside it)."
        agreement = ("" if not self.decided else
                     f"; the verdicts agree at {self.agree} of the {self.decided} cells both "
                     f"decide ({100 * self.agreement:.0f} %)")
        return (f"Prediction against the solve: the solved error lies inside the predicted "
                f"90 % interval at {self.inside} of {self.cells} cells "
                f"({100 * self.coverage:.0f} %){agreement}.")


def _solved(run, tables) -> dict[tuple[str, str], tuple[np.ndarray, np.ndarray, float]]:
    """Per (model, quantity) of the interface frame: the solved error of the scan at each
    pressure, the check's verdict there and the tolerance of its table."""
    from validation.judge.analysis import analyse

    comparison = analyse(run).comparisons[0]
    out = {}
    for table in tables:
        if table.frame != "interface" or not table.judged:
            continue
        quantity = _QUANTITY.get(table.field, table.field)
        for model, verdicts in table.verdicts.items():
            found = comparison.models.get((model, quantity))
            if found is not None and found.errors is not None and found.frame == "interface":
                out[(model, quantity)] = (np.asarray(found.errors)[0], np.asarray(verdicts),
                                          table.tolerance)
    return out


def against_check(prediction: Prediction, result) -> PredictionCheck:
    """Compare ``prediction`` with ``result``, a :class:`validation.check.result.CheckResult` of
    the same scan and pressures (its whole scan, interface frame, at the tolerance of both).

    Raises
    ------
    ValueError
        Where the two have different load points.
    """
    solved = _solved(result.runs[0], result.tables)
    cells = inside = decided = agree = 0
    for row in prediction.rows:
        if row.verdict == OUTSIDE or (row.model, row.quantity) not in solved:
            continue
        errors, verdicts, tolerance = solved[(row.model, row.quantity)]
        if row.point >= errors.size:
            raise ValueError("the prediction and the check have different load points")
        error, verdict = float(errors[row.point]), str(verdicts[row.point])
        if not math.isfinite(error):
            continue
        cells += 1
        inside += row.low <= error <= row.high
        if row.verdict in (HOLDS, FAILS) and verdict in (HOLDS, FAILS) \
                and math.isclose(tolerance, row.tolerance):
            decided += 1
            agree += row.verdict == verdict
    return PredictionCheck(cells, inside, decided, agree)
