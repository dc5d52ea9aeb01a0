"""The names of the verdicts and the confidence they are given at.

Shared by the verdicts themselves (:mod:`validation.judge.verdicts`), the plan of realizations
that spends their error rate over its looks (:mod:`validation.run.sequential`) and the report.
"""

from __future__ import annotations

__all__ = ["CONFIDENCE", "FAILS", "HOLDS", "UNDECIDED"]

#: A model holds at a load point, fails there, or the question is open.
HOLDS, FAILS, UNDECIDED = "holds", "fails", "undecided"
#: Confidence level of the interval over realizations (of a scene without a realization budget;
#: with one, the error rate ``1 - CONFIDENCE`` is split between its looks).
CONFIDENCE = 0.95
