"""More realizations where the answer is open: a group-sequential plan with Bonferroni looks.

First, where the reference band keeps cells undecided, the reference is solved on finer grids
(:func:`finer_reference`, :mod:`validation.run.refine`). Then a scene with ``[realizations] max``
gets, after its planned realizations, up to :data:`LOOKS` - 1 more looks at the data
(docs/theory.md, "Sequential realizations", eq. T38):

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

Without ``max`` there is one look, at the 95 % of :mod:`validation.judge.verdicts`, as before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from validation.common import models
from validation.run.refine import RefineJob, merge_points, solver_tolerance, unavailable
from validation.judge.verdicts import CONFIDENCE, REFERENCE_ACCURACY, UNDECIDED

__all__ = ["ALPHA", "LOOKS", "LookPlan", "RefinementLevel", "RefinementRecord",
           "SequentialRecord", "band_decides", "decide_scene", "extend_scene", "finer_reference", "look_plan",
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


def scene_share(scene, by_value: dict, confidence: float) -> float:
    """Undecided share of a scene's cells: mean verdicts of every compared model and quantity,
    sweep value, load point and tolerance, on the realizations of ``by_value``."""
    from validation.judge.compare import COMPARED_QUANTITIES, compare_realizations

    verdicts = []
    for results in by_value.values():
        comparison = compare_realizations(results, tolerances=scene.tolerances,
                                          confidence=confidence)
        verdicts += [v for (_, quantity), entry in comparison.models.items()
                     if quantity in COMPARED_QUANTITIES for v in entry.verdicts]
    return undecided_share(verdicts)


def extend_scene(scene, by_value: dict, run: Callable[[int], list],
                 refinement: "RefinementRecord | None" = None,
                 solve: Callable[[list], list] | None = None) -> SequentialRecord:
    """The looks of ``scene``'s plan on its realizations ``by_value`` (sweep value -> list of
    :class:`validation.run.realization.RealizationResult`, extended in place): ``run(n)`` computes the
    realizations that the first ``n`` seeds of every sweep value add to those there; each new
    one gets the finer reference of ``refinement`` at the same points (``solve`` as in
    :func:`finer_reference`)."""
    def extend(count: int) -> None:
        new = run(count)
        for result in new:
            by_value[result.task.sweep_value].append(result)
        for level in (refinement.levels if refinement is not None else ()):
            _apply(by_value, level, solve, only={r.task for r in new})

    return run_looks(scene_plan(scene), extend,
                     lambda confidence: scene_share(scene, by_value, confidence))


def band_decides(scene, results: list, confidence: float
                 ) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """Load points of one sweep value where the reference band decides: some cell (a compared
    model and quantity at a tolerance, on the mean or per surface) is undecided while the band
    of its reference field exceeds a quarter of the tolerance. Returns the mask, the smallest
    band over the fields at each point (NaN where none is known) and the mask of each compared
    quantity alone (the mask is their union)."""
    from validation.judge.compare import COMPARED_QUANTITIES, compare_realizations

    comparison = compare_realizations(results, tolerances=scene.tolerances,
                                      confidence=confidence)
    held: dict[str, np.ndarray] = {}
    smallest = np.full(comparison.load.shape, np.inf)
    for (_, quantity), entry in comparison.models.items():
        if quantity not in COMPARED_QUANTITIES or entry.band is None:
            continue
        band = np.asarray(entry.band, dtype=float)
        smallest = np.fmin(smallest, np.where(band > 0, band, np.inf))
        mask = held.setdefault(quantity, np.zeros(comparison.load.shape, bool))
        for index, tolerance in enumerate(entry.tolerances):
            open_ = entry.verdicts[index] == UNDECIDED
            if entry.surface_verdicts:
                open_ |= entry.surface_verdicts[index] == UNDECIDED
            with np.errstate(invalid="ignore"):
                mask |= open_ & (band > REFERENCE_ACCURACY * tolerance)
    mask = (np.any(np.stack(list(held.values())), axis=0) if held
            else np.zeros(comparison.load.shape, bool))
    return mask, np.where(np.isfinite(smallest), smallest, np.nan), held


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


@dataclass(frozen=True)
class RefinementRecord:
    """The refinements of a scene's reference and why they stopped."""

    levels: tuple[RefinementLevel, ...]
    reason: str

    def describe(self, parameter: str = "") -> str:
        """E.g. ``refined on 512²: 3 load point(s) (leakage at 1) at D = 2.05 (solver
        tolerance 1.0e-04); stopped: grid limit reached (max_grid = 512)``: the leakage is solved
        again only where a leakage cell is held by the band."""
        if not self.levels:
            return f"not refined: {self.reason}"
        parts = []
        for level in self.levels:
            per_value = ", ".join(
                f"{len(points)} load point(s)"
                + (f" (leakage at {len(level.leakage[value])})" if level.leakage.get(value)
                   else "")
                + (f" at {parameter} = {value:g}" if parameter else "")
                for value, points in sorted(level.points.items()))
            tolerances = sorted(set(level.tolerances.values()))
            parts.append(f"{level.grid}²: {per_value} (solver tolerance {tolerances[0]:.1e}"
                         + (f"–{tolerances[-1]:.1e}" if len(tolerances) > 1 else "") + ")")
        return "refined on " + "; ".join(parts) + f"; stopped: {self.reason}"


def _reference_name(result) -> str:
    return models.reference_among(result.curves)


def _apply(by_value: dict, level: RefinementLevel, solve, only: set | None = None) -> None:
    """Solve the points of ``level`` on its grid for every realization (or those in ``only``)
    and merge them into each realization's reference curve, in place."""
    from dataclasses import replace as replaced

    jobs, where = [], []
    for value, points in level.points.items():
        with_leakage = tuple(level.leakage.get(value, ()))
        without = tuple(k for k in points if k not in with_leakage)
        parts = [(part, leakage) for part, leakage in ((without, False), (with_leakage, True))
                 if part]
        for index, result in enumerate(by_value[value]):
            if only is not None and result.task not in only:
                continue
            factor = level.grid // result.task.surface.n
            for part, leakage in parts:
                jobs.append(RefineJob(result.task, part, factor, level.tolerances[value],
                                      leakage))
                where.append((value, index, part))
    for (value, index, part), (curve, computed) in zip(where, solve(jobs)):
        result = by_value[value][index]
        name = _reference_name(result)
        merged = merge_points(result.curves[name], np.array(part), curve,
                              level.grid, result.task.surface.L / level.grid,
                              result.task.surface.n)
        log = result.computed + ((f"{name}-refined {level.grid} {result.task.describe()}",)
                                 if computed else ())
        by_value[value][index] = replaced(result, curves={**result.curves, name: merged},
                                          computed=log)


def finer_reference(scene, by_value: dict, solve: Callable[[list], list],
                    confidence: float) -> RefinementRecord:
    """Refine the reference where its band decides (:func:`band_decides`), grid by grid up to
    ``scene.bem.max_grid``: each level solves the points still decided by the band among those
    solved on the level below. ``solve(jobs)`` runs :class:`validation.run.refine.RefineJob` s and
    returns ``(curve, computed)`` per job (:func:`validation.run.refine.run_job`)."""
    reason = unavailable(scene)
    if reason is not None:
        return RefinementRecord((), reason)
    n, levels = scene.surface.n, []
    grid = 2 * n
    while True:
        if grid > scene.bem.max_grid:
            return RefinementRecord(tuple(levels), f"grid limit reached (max_grid = "
                                    f"{scene.bem.max_grid})")
        points, tolerances, leakage = {}, {}, {}
        for value, results in by_value.items():
            mask, band, held = band_decides(scene, results, confidence)
            reference = results[0].curves[_reference_name(results[0])]
            below = np.asarray(reference.extras.get("grid", np.full(mask.shape, n))) == grid // 2
            chosen = np.flatnonzero(mask & below)
            if chosen.size:
                points[value] = tuple(int(k) for k in chosen)
                leaky = held.get("leakage", np.zeros(mask.shape, bool))
                leakage[value] = tuple(int(k) for k in np.flatnonzero(leaky & below))
                # the band expected on the finer grid: half the present one (first order)
                tolerances[value] = solver_tolerance(float(np.nanmin(band[chosen])) / 2.0,
                                                     scene.bem.tol)
        if not points:
            return RefinementRecord(tuple(levels), "no undecided cell is held by the band"
                                    + (" any more" if levels else ""))
        level = RefinementLevel(grid, points, tolerances, leakage)
        _apply(by_value, level, solve)
        levels.append(level)
        grid *= 2


def decide_scene(scene, by_value: dict, run: Callable[[int], list],
                 solve: Callable[[list], list]) -> tuple[RefinementRecord, SequentialRecord]:
    """Everything a scene with a reference does after its planned realizations, to decide its
    undecided cells: the finer reference where its band decides (:func:`finer_reference`),
    then the looks of its sequential plan (:func:`extend_scene`; new realizations get the same
    refinements). ``by_value`` is extended and updated in place; ``run`` and ``solve`` are as
    in those functions (the runner gives its executor, cache and progress bars through them)."""
    refinement = finer_reference(scene, by_value, solve, scene_plan(scene).confidence_at(0))
    return refinement, extend_scene(scene, by_value, run, refinement, solve)
