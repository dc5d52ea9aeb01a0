"""A claim of the paper decided over the contact-area range of the load points (pure functions).

Each load point of a surface family's path supports a claim, contradicts it, or neither (the
per-point decision is the finding's own, :mod:`validation.judge.findings`); the point sits at
the reference's contact-area fraction there. :func:`decide_over_range` turns the points into a
verdict and the range over which the claim is reproduced (:data:`RANGE_RULE`):

* *reproduced*: no point contradicts it and at least half of the points support it;
* *reproduced over a range*: some point supports it, but some point contradicts it or fewer
  than half support it; the range is the run of consecutive points free of contradiction that
  holds the most supporting points (ties: the wider in area fraction, then the lighter), from
  its first to its last supporting point, and at least :data:`MIN_RANGE_POINTS` of them;
* *contradicted*: no such run, and some point contradicts it;
* *undecided*: no point decides it either way.

A claim over several quantities (or several models, samplings) is decided on the points
combined first (:func:`combine_points`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CONTRADICTED", "MIN_RANGE_POINTS", "RANGED", "RANGE_RULE", "REPRODUCED", "UNDECIDED", "ClaimRange",
           "combine_points", "decide_over_range", "fraction_text"]

REPRODUCED, CONTRADICTED, UNDECIDED = "reproduced", "contradicted", "undecided"
#: The verdict of a claim reproduced over part of the contact-area range tested.
RANGED = "reproduced over a range"
#: Fewest supporting points a stated range holds (one point is no range).
MIN_RANGE_POINTS = 2
#: How a claim is decided over its points (Markdown, part of the findings' rules).
RANGE_RULE = """A claim over a load path is decided over the contact-area range of its points
(the finite window's BEM contact-area fraction, mean over realizations): each point supports
it, contradicts it, or neither (undecided). *Reproduced* where no point contradicts it and at
least half of the points support it (the whole range tested); *reproduced over a range* where
some point supports it but some contradicts it, or fewer than half support it: the range is
the run of consecutive points without a contradicting one that holds the most supporting
points (ties: the wider, then the lighter), from its first to its last supporting point, and
the report says "reproduced from a % to b % contact" (a range holds at least two supporting
points); *contradicted* where no run free of contradiction holds two supporting points and
some point contradicts it; *undecided* where no point decides it. A claim over several
quantities is decided on the points combined: a point supports it where every quantity
supports it and contradicts it where any contradicts it."""


def fraction_text(fraction: float) -> str:
    """An area fraction in percent, two significant digits without an exponent ("0.052 %",
    "2.4 %", "30 %")."""
    if not math.isfinite(fraction):
        return "? %"
    value = 100.0 * fraction
    if value >= 10:
        return f"{value:.0f} %"
    return f"{float(f'{value:.2g}'):g} %"


@dataclass(frozen=True)
class ClaimRange:
    """A claim decided over the points of a path: the verdict, the range tested and the range
    reproduced (area fractions; NaN where there is none), and the points that support it,
    contradict it and decide neither."""

    verdict: str
    tested_from: float
    tested_to: float
    reproduced_from: float
    reproduced_to: float
    reproduced: int
    contradicted: int
    undecided: int

    @property
    def points(self) -> int:
        """The points decided over."""
        return self.reproduced + self.contradicted + self.undecided

    @property
    def verdict_text(self) -> str:
        """The verdict as the report prints it, the range in words where it is partial."""
        if self.verdict != RANGED:
            return self.verdict
        low, high = fraction_text(self.reproduced_from), fraction_text(self.reproduced_to)
        return (f"reproduced at {low} contact" if low == high
                else f"reproduced from {low} to {high} contact")

    def describe(self, fraction: np.ndarray, against: np.ndarray) -> str:
        """The range in words: where it is reproduced and where contradicted."""
        if self.points == 0:
            return "no point"
        text = (f"tested over {fraction_text(self.tested_from)}–{fraction_text(self.tested_to)}"
                f" contact: supported at {self.reproduced}, contradicted at {self.contradicted}, "
                f"undecided at {self.undecided} of {self.points} points")
        if math.isfinite(self.reproduced_from):
            text += (f"; reproduced from {fraction_text(self.reproduced_from)} to "
                     f"{fraction_text(self.reproduced_to)}")
        runs = _runs(np.asarray(against, bool))
        if runs:
            text += "; contradicted at " + ", ".join(
                fraction_text(fraction[a]) if a == b
                else f"{fraction_text(fraction[a])}–{fraction_text(fraction[b])}"
                for a, b in runs)
        return text


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """First and last index of each run of true values of ``mask``."""
    runs, start = [], None
    for index, value in enumerate(mask):
        if value and start is None:
            start = index
        if not value and start is not None:
            runs.append((start, index - 1))
            start = None
    if start is not None:
        runs.append((start, len(mask) - 1))
    return runs


def combine_points(support: list[np.ndarray], against: list[np.ndarray], *, every: bool = True
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Per-point decisions of several parts of a claim combined into one per point.

    ``every`` (a claim on each part, e.g. every quantity): a point supports the claim where
    every part supports it, contradicts it where any part contradicts it. Otherwise (a claim on
    some part, e.g. some model moves): supports where any part supports it, contradicts where
    every part contradicts it.
    """
    support, against = np.atleast_2d(np.asarray(support, bool)), np.atleast_2d(np.asarray(against, bool))
    if every:
        return support.all(axis=0), against.any(axis=0)
    return support.any(axis=0), against.all(axis=0)


def decide_over_range(fraction: np.ndarray, support: np.ndarray, against: np.ndarray) -> ClaimRange:
    """A claim decided over the points of a path (module docstring, :data:`RANGE_RULE`).

    Parameters
    ----------
    fraction : array, shape (points,)
        The reference's contact-area fraction at each point, in path order.
    support, against : bool array, shape (points,)
        The points that support and that contradict the claim (not both at one point).
    """
    fraction = np.asarray(fraction, dtype=float)
    support, against = np.asarray(support, bool), np.asarray(against, bool)
    if not fraction.shape == support.shape == against.shape:
        raise ValueError(f"fraction, support and against must have one shape, got "
                         f"{fraction.shape}, {support.shape} and {against.shape}")
    if np.any(support & against):
        raise ValueError("a point cannot both support and contradict a claim")
    counts = int(support.sum()), int(against.sum()), int(np.sum(~support & ~against))
    tested = _span(fraction)
    nowhere = (math.nan, math.nan)
    if not support.any():
        verdict = CONTRADICTED if against.any() else UNDECIDED
        return ClaimRange(verdict, *tested, *nowhere, *counts)
    if not against.any() and 2 * counts[0] >= support.size:
        return ClaimRange(REPRODUCED, *tested, *_span(fraction[support]), *counts)

    def key(run: tuple[int, int]) -> tuple:
        held = np.flatnonzero(support[run[0]:run[1] + 1]) + run[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            width = abs(np.log(fraction[held[-1]] / fraction[held[0]])) if held.size else 0.0
        return (held.size, float(np.nan_to_num(width)), -run[0])

    first, last = max(_runs(~against), key=key)
    held = np.flatnonzero(support[first:last + 1]) + first
    if held.size < MIN_RANGE_POINTS:     # one point is no range
        return ClaimRange(CONTRADICTED if against.any() else UNDECIDED, *tested, *nowhere,
                          *counts)
    return ClaimRange(RANGED, *tested, *_span(fraction[[held[0], held[-1]]]), *counts)


def _span(values: np.ndarray) -> tuple[float, float]:
    """The smallest and the largest finite value (NaN, NaN where none is finite)."""
    known = values[np.isfinite(values)]
    return (float(known.min()), float(known.max())) if known.size else (math.nan, math.nan)
