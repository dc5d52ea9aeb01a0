"""More realizations where the answer is open: a group-sequential plan with Bonferroni looks.

A scene with ``[realizations] max`` gets, after its planned realizations, up to
:data:`LOOKS` - 1 more looks at the data (docs/theory.md, "Sequential realizations", eq. T36):

* the look sizes grow geometrically from the planned count ``n_1`` to the budget ``n_K = max``
  (``n_j = round(n_1 (max / n_1)^((j - 1)/(K - 1)))``; 25, 50, 100 for 25 and 100), and the
  realizations of look j are those of look j - 1 plus the next seeds of the same sequence;
* every verdict of every look is taken at confidence ``1 - alpha / K`` (Bonferroni): a cell's
  reported verdict is that of the last look taken, and whatever the stopping rule, the chance
  that it is wrong is at most the chance that any of the K looks is, at most ``K alpha / K =
  alpha``;
* after each look the share of undecided cells (mean verdicts over every model, quantity,
  sweep value, load point and tolerance of the scene) decides whether to look again: stop when
  no cell is undecided, when the share did not fall since the previous look, or at the budget.

Without ``max`` there is one look, at the 95 % of :mod:`validation.verdicts`, as before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from validation.verdicts import CONFIDENCE, UNDECIDED

__all__ = ["ALPHA", "LOOKS", "LookPlan", "SequentialRecord", "extend_scene", "look_plan",
           "run_looks", "scene_plan", "scene_share", "undecided_share"]

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
    def confidence(self) -> float:
        """Confidence of every verdict at every look: ``1 - alpha / looks`` (Bonferroni)."""
        return 1.0 - self.alpha / self.looks


def look_plan(planned: int, maximum: int | None, *, looks: int = LOOKS,
              alpha: float = ALPHA) -> LookPlan:
    """The look sizes from ``planned`` realizations up to the budget ``maximum`` (eq. T36).

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
        looks = f"{len(self.used)} look{'s' if len(self.used) > 1 else ''}"
        return (f"{counts} realizations in {looks} of {self.plan.looks} (undecided {shares}; "
                f"verdicts at {100 * self.plan.confidence:.4g} % confidence); stopped: "
                f"{self.reason}")


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
    scene's cells on the realizations available, at the plan's confidence.

    Returns
    -------
    SequentialRecord
        The looks taken, the shares after each and the reason for stopping.
    """
    shares = [float(share(plan.confidence))]
    while True:
        reason = _stop_reason(plan, shares)
        if reason is not None:
            return SequentialRecord(plan, plan.sizes[:len(shares)], tuple(shares), reason)
        extend(plan.sizes[len(shares)])
        shares.append(float(share(plan.confidence)))


def scene_share(scene, by_value: dict, confidence: float) -> float:
    """Undecided share of a scene's cells: mean verdicts of every compared model and quantity,
    sweep value, load point and tolerance, on the realizations of ``by_value``."""
    from validation.compare import COMPARED_QUANTITIES, compare_realizations

    verdicts = []
    for results in by_value.values():
        comparison = compare_realizations(results, tolerances=scene.tolerances,
                                          confidence=confidence)
        verdicts += [v for (_, quantity), entry in comparison.models.items()
                     if quantity in COMPARED_QUANTITIES for v in entry.verdicts]
    return undecided_share(verdicts)


def extend_scene(scene, by_value: dict, run: Callable[[int], list]) -> SequentialRecord:
    """The looks of ``scene``'s plan on its realizations ``by_value`` (sweep value -> list of
    :class:`validation.runner.RealizationResult`, extended in place): ``run(n)`` computes the
    realizations that the first ``n`` seeds of every sweep value add to those there."""
    def extend(count: int) -> None:
        for result in run(count):
            by_value[result.task.sweep_value].append(result)

    return run_looks(scene_plan(scene), extend,
                     lambda confidence: scene_share(scene, by_value, confidence))
