"""The plan of realizations where the answer is open, and the records of what was done.

A scene with ``[realizations] max`` gets, after its planned realizations, up to :data:`LOOKS` - 1
more looks at the data: a group-sequential plan with Bonferroni looks (docs/theory.md,
"Sequential realizations", eq. T38):

* the look sizes grow geometrically from the planned count ``n_1`` to the budget ``n_K = max``
  (``n_j = round(n_1 (max / n_1)^((j - 1)/(K - 1)))``; 25, 50, 100 for 25 and 100), and the
  realizations of look j are those of look j - 1 plus the next seeds of the same sequence;
* the verdicts of look j are taken at confidence ``1 - alpha_j`` with ``alpha_j = alpha n_j /
  (n_1 + ... + n_K)`` (the error rate spent in proportion to the realizations, Bonferroni): a
  cell's reported verdict is that of the last look taken, and whatever the stopping rule, the
  chance that it is wrong is at most the chance that any of the K looks is, at most
  ``alpha_1 + ... + alpha_K = alpha``;
* after each look the share of undecided cells (mean verdicts over every model, quantity,
  sweep value, load point and tolerance of the scene) decides whether to look again: stop when
  no cell is undecided, when the share did not fall since the previous look, or at the budget.

Without ``max`` there is one look, at the 95 % of :mod:`validation.common.verdicts`, as before.

This module holds the plan (:func:`look_plan`, :func:`run_looks`) and the records a scene's
result keeps (:class:`SequentialRecord`, and :class:`RefinementRecord` of the finer reference
solved first, :mod:`validation.run.refine`); the verdicts that steer them are the judge's, so
the loop that takes the looks and refines the reference is :mod:`validation.judge.decide`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from validation.common.verdicts import CONFIDENCE, UNDECIDED

__all__ = ["ALPHA", "LOOKS", "LookPlan", "RefinementLevel", "RefinementRecord",
           "SequentialRecord", "look_plan", "run_looks", "scene_plan", "undecided_share"]

#: Total error rate of the verdicts of a scene's cells (one minus the confidence).
ALPHA = 1.0 - CONFIDENCE
#: Looks at the data of a scene with a realization budget (the planned one included).
LOOKS = 3


@dataclass(frozen=True)
class LookPlan:
    """Realizations at each look (increasing; the first is the planned count) and the error
    rate they share."""

    sizes: tuple[int, ...]
    alpha: float = ALPHA

    def __post_init__(self) -> None:
        sizes = tuple(int(n) for n in self.sizes)
        if not sizes or sizes[0] < 1 or any(b <= a for a, b in zip(sizes, sizes[1:])):
            raise ValueError(f"sizes must be increasing positive counts, got {self.sizes!r}")
        if not 0.0 < self.alpha < 1.0:
            raise ValueError(f"alpha must be in (0, 1), got {self.alpha!r}")
        object.__setattr__(self, "sizes", sizes)

    @property
    def looks(self) -> int:
        return len(self.sizes)

    @property
    def alphas(self) -> tuple[float, ...]:
        """Error rate of each look, ``alpha n_j / sum(n)``: spent in proportion to the
        realizations, most of it at the budget, where most cells are decided."""
        total = sum(self.sizes)
        return tuple(self.alpha * n / total for n in self.sizes)

    def confidence_at(self, look: int) -> float:
        """Confidence of the verdicts of look ``look`` (0 for the planned realizations)."""
        return 1.0 - self.alphas[look]

    def confidence_for(self, count: int) -> float:
        """Confidence of verdicts on ``count`` realizations: that of the look of that size, else
        (results not made by this plan) the strictest of the plan."""
        if count in self.sizes:
            return self.confidence_at(self.sizes.index(count))
        return 1.0 - min(self.alphas)


def look_plan(planned: int, maximum: int | None, *, looks: int = LOOKS,
              alpha: float = ALPHA) -> LookPlan:
    """The look sizes from ``planned`` realizations up to the budget ``maximum`` (eq. T38).

    Parameters
    ----------
    planned : int
        Realizations of the first look (>= 1).
    maximum : int or None
        Budget; ``None`` or ``<= planned`` means one look.
    looks : int
        Looks at most (>= 1); fewer when the geometric steps round to equal counts.
    alpha : float
        Total error rate split equally between the looks.
    """
    if isinstance(planned, bool) or not isinstance(planned, int) or planned < 1:
        raise ValueError(f"planned must be an integer >= 1, got {planned!r}")
    if isinstance(looks, bool) or not isinstance(looks, int) or looks < 1:
        raise ValueError(f"looks must be an integer >= 1, got {looks!r}")
    if maximum is None or maximum <= planned or looks == 1:
        return LookPlan((planned,), alpha)
    ratio = maximum / planned
    sizes = [round(planned * ratio ** (j / (looks - 1))) for j in range(looks)]
    sizes[-1] = maximum
    return LookPlan(tuple(sorted(set(sizes))), alpha)


def scene_plan(scene) -> LookPlan:
    """The look plan of a scene (its planned realizations and ``max_realizations``)."""
    return look_plan(scene.realizations, getattr(scene, "max_realizations", None))


@dataclass(frozen=True)
class SequentialRecord:
    """What the sequential plan did for one scene: realizations per look taken, the undecided
    share after each, and why it stopped."""

    plan: LookPlan
    used: tuple[int, ...]        # realizations at each look taken
    shares: tuple[float, ...]    # undecided share of the scene's cells after each look taken
    reason: str

    @property
    def realizations(self) -> int:
        return self.used[-1]

    def describe(self) -> str:
        """E.g. ``8 → 16 → 32 realizations in 3 looks (undecided 40 % → 31 % → 25 %); stopped:
        budget reached``."""
        counts = " → ".join(str(n) for n in self.used)
        shares = " → ".join(f"{100 * s:.0f} %" for s in self.shares)
        levels = " → ".join(f"{100 * self.plan.confidence_at(j):.4g} %"
                            for j in range(len(self.used)))
        looks = f"{len(self.used)} look{'s' if len(self.used) > 1 else ''}"
        return (f"{counts} realizations in {looks} of {self.plan.looks} (undecided {shares}; "
                f"verdicts at {levels} confidence); stopped: {self.reason}")


def undecided_share(verdicts) -> float:
    """Share of undecided cells among all the verdict arrays given (NaN when there are none)."""
    arrays = [np.asarray(v).ravel() for v in verdicts]
    total = sum(a.size for a in arrays)
    if total == 0:
        return math.nan
    return sum(int(np.count_nonzero(a == UNDECIDED)) for a in arrays) / total


def _stop_reason(plan: LookPlan, shares: list[float]) -> str | None:
    if plan.looks == 1:
        return "planned realizations only (no realization budget)"
    if not shares[-1] > 0.0:
        return "no undecided cell"
    if len(shares) > 1 and shares[-1] >= shares[-2]:
        return (f"the undecided share stopped falling ({100 * shares[-2]:.1f} % → "
                f"{100 * shares[-1]:.1f} %)")
    if len(shares) == plan.looks:
        return f"budget reached ({plan.sizes[-1]} realizations)"
    return None


def run_looks(plan: LookPlan, extend: Callable[[int], None],
              share: Callable[[float], float]) -> SequentialRecord:
    """Take the looks of ``plan``: after the first, ``extend(n)`` makes the first ``n``
    realizations available and ``share(confidence)`` returns the undecided share of the
    scene's cells on the realizations available, at the confidence of the look.

    Returns
    -------
    SequentialRecord
        The looks taken, the shares after each and the reason for stopping.
    """
    shares = [float(share(plan.confidence_at(0)))]
    while True:
        reason = _stop_reason(plan, shares)
        if reason is not None:
            return SequentialRecord(plan, plan.sizes[:len(shares)], tuple(shares), reason)
        extend(plan.sizes[len(shares)])
        shares.append(float(share(plan.confidence_at(len(shares)))))


@dataclass(frozen=True)
class RefinementLevel:
    """One refinement: the grid, and per sweep value the load points solved on it and the
    solver tolerance they were solved to (eq. T40)."""

    grid: int
    points: dict                  # sweep value -> tuple of load point indices
    tolerances: dict              # sweep value -> solver tolerance
    # sweep value -> the points among ``points`` whose leakage is solved again too (a leakage
    # cell is held by the band there); elsewhere the leakage and its band stay those of the
    # grid below: a Reynolds solve costs a 1024^2 reference about three times its contact solve
    leakage: dict = field(default_factory=dict)
    # the reference refined: the finite window's ("bem") or the interface's ("bem_interface")
    reference: str = "bem"
    # sweep value -> the points among ``points`` whose stiffness (and conductance) is solved
    # again (a stiffness cell is held by the band there; absent: all of them); elsewhere they
    # and their band stay those of the grid below
    stiffness: dict = field(default_factory=dict)


def _solved_again(level: RefinementLevel, value, count: int) -> str:
    """E.g. `` (stiffness at 3, leakage at 1)``: where some but not all of a level's points of
    sweep value ``value`` solve the stiffness again, and where any solves the leakage again."""
    parts = []
    stiffness = level.stiffness.get(value)
    if stiffness and len(stiffness) < count:
        parts.append(f"stiffness at {len(stiffness)}")
    if level.leakage.get(value):
        parts.append(f"leakage at {len(level.leakage[value])}")
    return f" ({', '.join(parts)})" if parts else ""


@dataclass(frozen=True)
class RefinementRecord:
    """The refinements of a scene's reference and why they stopped."""

    levels: tuple[RefinementLevel, ...]
    reason: str

    def describe(self, parameter: str = "") -> str:
        """E.g. ``refined on 512²: 3 load point(s) (leakage at 1) at D = 2.05 (solver
        tolerance 1.0e-04); stopped: grid limit reached (max_grid = 512)``: the leakage is solved
        again only where a leakage cell is held by the band, on grids up to
        :data:`validation.run.refine.MAX_LEAKAGE_GRID`."""
        if not self.levels:
            return f"not refined: {self.reason}"
        parts = []
        for level in self.levels:
            per_value = ", ".join(
                f"{len(points)} load point(s)" + _solved_again(level, value, len(points))
                + (f" at {parameter} = {value:g}" if parameter else "")
                for value, points in sorted(level.points.items()))
            tolerances = sorted(set(level.tolerances.values()))
            which = " (interface)" if level.reference != "bem" else ""
            parts.append(f"{level.grid}²{which}: {per_value} (solver tolerance "
                         f"{tolerances[0]:.1e}"
                         + (f"–{tolerances[-1]:.1e}" if len(tolerances) > 1 else "") + ")")
        return "refined on " + "; ".join(parts) + f"; stopped: {self.reason}"
