"""Deciding what is open: more work where a scene's verdicts stay undecided.

After a scene's planned realizations (:func:`validation.run.runner.run_planned`), the cells
(a compared model and quantity at a load point and a tolerance) that stay undecided get

* first, where the reference band keeps them undecided (:func:`band_decides`), the reference
  solved on finer grids, level by level up to ``[bem] max_grid`` (:func:`finer_reference`,
  docs/theory.md eq. T39, :mod:`validation.run.refine`);
* then, with ``[realizations] max``, more realizations look by look, the error rate of the
  verdicts split between the looks (:func:`extend_scene`; the plan is
  :mod:`validation.run.sequential`, eq. T38); new realizations get the same refinements.

The verdicts that steer this are the judge's (:func:`validation.judge.compare.compare_realizations`);
the work is the run's, handed in as callables (``run(count)``, ``solve(jobs)``), so nothing
here touches an executor or the cache. :func:`run_scenes` runs scenes to that decision.
"""

from __future__ import annotations

import time
from concurrent.futures import Executor
from dataclasses import replace
from typing import Callable, Iterable

import numpy as np

from validation.common import models
from validation.judge.bands import method_band
from validation.judge.compare import COMPARED_QUANTITIES, compare_realizations
from validation.judge.verdicts import REFERENCE_ACCURACY, UNDECIDED
from validation.run.refine import (MAX_LEAKAGE_GRID, REFINED, STIFFNESS_FIELDS, RefineJob,
                                   merge_job, refined_extension, solver_tolerance, unavailable)
from validation.run.runner import SceneResult, more_realizations, run_planned, solve_refinements
from validation.run.sequential import (RefinementLevel, RefinementRecord, SequentialRecord,
                                       run_looks, scene_plan, undecided_share)
from validation.scenes.scene import Scene

__all__ = ["band_decides", "decide_scene", "extend_scene", "finer_reference", "run_scenes",
           "scene_share"]


def scene_share(scene, by_value: dict, confidence: float) -> float:
    """Undecided share of a scene's cells: mean verdicts of every compared model and quantity,
    sweep value, load point and tolerance, on the realizations of ``by_value``."""
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


def band_decides(scene, results: list, confidence: float, reference: str = "bem"
                 ) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """Load points of one sweep value where the reference band decides: some cell (a compared
    model and quantity at a tolerance, on the mean or per surface) is undecided while the band
    of its reference field exceeds a quarter of the tolerance (on one surface: wherever the cell
    is undecided with a band, since only the band can leave it open there, however small).
    Only the cells judged against ``reference`` count (its band is the one a finer solve of
    it narrows). Returns the mask, the smallest band at each point over the fields whose cells
    it holds there (NaN where it holds none: a finer solve need only resolve those fields' bands, eq.
    T40) and the mask of each compared quantity alone (the mask is their union)."""
    comparison = compare_realizations(results, tolerances=scene.tolerances,
                                      confidence=confidence)
    held: dict[str, np.ndarray] = {}
    smallest = np.full(comparison.load.shape, np.inf)
    for (_, quantity), entry in comparison.models.items():
        if quantity not in COMPARED_QUANTITIES or entry.band is None \
                or entry.reference_model != reference:
            continue
        # only the discretisation part: a finer grid does not narrow the method's own error
        # (its bias in the mean's band, its bound in the band one surface carries; eq. T50)
        field_name = entry.reference_field or quantity
        method = method_band(results, field_name, reference)
        bias = method if entry.one_surface else method_band(results, field_name, reference,
                                                              part="bias")
        band = np.asarray(entry.band, dtype=float) - bias
        mask = held.setdefault(quantity, np.zeros(comparison.load.shape, bool))
        for index, tolerance in enumerate(entry.tolerances):
            open_ = entry.verdicts[index] == UNDECIDED
            if entry.surface_verdicts:
                open_ |= entry.surface_verdicts[index] == UNDECIDED
            # one surface: an open cell is held by its band, whatever its size
            floor = 0.0 if entry.one_surface else REFERENCE_ACCURACY * tolerance
            with np.errstate(invalid="ignore"):
                holds_open = open_ & (band > floor) & decidable(entry, method, tolerance,
                                                                mean_floor=bias)
            mask |= holds_open
            smallest = np.fmin(smallest, np.where(holds_open, band, np.inf))
    mask = (np.any(np.stack(list(held.values())), axis=0) if held
            else np.zeros(comparison.load.shape, bool))
    return mask, np.where(np.isfinite(smallest), smallest, np.nan), held


def decidable(entry, band_floor: np.ndarray, tolerance: float, *,
              mean_floor: np.ndarray | None = None) -> np.ndarray:
    """Points whose open cells at ``tolerance`` a finer grid could decide: against the best
    reference a finer grid can give, its band down to ``band_floor``, the reference method's
    own bound that no grid narrows (zero for the window's reference, eq. T50), in the band one
    surface carries; on the mean down to ``mean_floor``, the method's bias (default: the
    bound). Where even that leaves a cell open, a finer solve is futile for it
    (docs/theory.md 11.3).

    One surface: the error judged with the band at its floor decides it (or the error is not
    known: an unconverged reference point, say, may be known on a finer grid). A population,
    on the mean and per surface alike: a cell can hold on some grid only where the floor is
    within the reference-accuracy rule (``floor <= tol / 4``), and fail only where its interval
    (the mean's confidence interval, or the tolerance interval of single surfaces) widened by
    the band reaches beyond ``tol + 2 floor``: the error against the exact-grid reference lies
    within the widened interval, and failing needs it beyond ``tol + floor``; or where a
    disagreement about sealing is not yet resolved by the band. Only the readings still
    undecided count; an unknown interval or band counts as decidable."""
    from validation.judge.verdicts import one_surface_verdicts

    floor = np.asarray(band_floor, dtype=float)
    if entry.one_surface:
        error = np.asarray(entry.errors[0], dtype=float)
        return (one_surface_verdicts(error, floor, tolerance) != UNDECIDED) | np.isnan(error)
    band = np.asarray(entry.band, dtype=float)
    surface_band = getattr(entry, "surface_band", None)
    surface_band = band if surface_band is None else np.asarray(surface_band, dtype=float)
    mean_floor = floor if mean_floor is None else np.asarray(mean_floor, dtype=float)
    index = list(entry.tolerances).index(tolerance)
    readings = [(entry.verdicts[index], entry.interval.low, entry.interval.high, band,
                 mean_floor)]
    if entry.surface_verdicts:
        readings.append((entry.surface_verdicts[index], entry.surface.low, entry.surface.high,
                         surface_band, floor))
    result = np.zeros(np.shape(band), bool)
    for verdict, low, high, band, floor in readings:
        can_hold = floor <= REFERENCE_ACCURACY * tolerance
        reach = tolerance + 2.0 * floor
        with np.errstate(invalid="ignore"):
            # NaN anywhere makes the comparison false: decidable
            within = (np.asarray(low) - band >= -reach) & (np.asarray(high) + band <= reach)
        result |= (np.asarray(verdict) == UNDECIDED) & (can_hold | ~within)
    if entry.sealing is not None:
        # a disagreement about sealing that the band leaves unresolved (leakage) may be
        # resolved on a finer grid, which fails the point
        result |= np.asarray(entry.sealing) > np.asarray(entry.sealing_resolved)
    return result


def _refined(names) -> list[str]:
    """The refinable references among ``names``, in the order of :data:`REFINED`."""
    return [name for name in REFINED if name in names]


def _apply(by_value: dict, level: RefinementLevel, solve, only: set | None = None) -> None:
    """Solve the points of ``level`` on its grid for every realization (or those in ``only``)
    and merge them into each realization's reference curve, in place: one path per
    realization, with the leakage and the stiffness solved again only at the level's leakage
    and stiffness points (elsewhere they and their band stay those of the grid below)."""
    jobs, where = [], []
    for value, points in level.points.items():
        leaky = set(level.leakage.get(value, ()))
        with_leakage = tuple(k for k in points if k in leaky)
        for index, result in enumerate(by_value[value]):
            if only is not None and result.task not in only:
                continue
            factor = level.grid // result.task.surface.n
            extension = refined_extension(level.reference, result.task)
            jobs.append(RefineJob(result.task, tuple(points), factor, level.tolerances[value],
                                  with_leakage, extension, level.stiffness.get(value)))
            where.append((value, index))
    for job, (value, index), (curve, computed) in zip(jobs, where, solve(jobs)):
        result = by_value[value][index]
        name = level.reference
        merged = merge_job(result.curves[name], job, curve, level.grid)
        log = result.computed + ((f"{name}-refined {level.grid} {result.task.describe()}",)
                                 if computed else ())
        by_value[value][index] = replace(result, curves={**result.curves, name: merged},
                                          computed=log)


def finer_reference(scene, by_value: dict, solve: Callable[[list], list],
                    confidence: float) -> RefinementRecord:
    """Refine the reference where its band decides (:func:`band_decides`), grid by grid up to
    ``scene.bem.max_grid``: each level solves the points still decided by the band among those
    solved on the level below. ``solve(jobs)`` runs :class:`validation.run.refine.RefineJob` s and
    returns ``(curve, computed)`` per job (:func:`validation.run.refine.run_job`)."""
    reason = unavailable(scene)
    references = _refined(scene.models)
    if reason is None and not references:
        reason = "the scene has no reference a finer grid can refine (bem, bem_interface)"
    if reason is not None:
        return RefinementRecord((), reason)
    levels, grid = [], 2 * scene.surface.n
    while True:
        if grid > scene.bem.max_grid:
            return RefinementRecord(tuple(levels), f"grid limit reached (max_grid = "
                                    f"{scene.bem.max_grid})")
        found = [level for level in (_level(scene, by_value, confidence, grid, name)
                                     for name in references) if level is not None]
        if not found:
            return RefinementRecord(tuple(levels), "no undecided cell is held by the band"
                                    + (" any more" if levels else ""))
        for level in found:
            _apply(by_value, level, solve)
            levels.append(level)
        grid *= 2


def _level(scene, by_value: dict, confidence: float, grid: int,
           name: str) -> RefinementLevel | None:
    """The points of reference ``name`` to solve on ``grid`` (those its band decides among the
    points solved on the grid below), or None where there are none."""
    n = scene.surface.n
    points, tolerances, leakage, stiffness = {}, {}, {}, {}
    for value, results in by_value.items():
        mask, band, held = band_decides(scene, results, confidence, name)
        reference = results[0].curves[name]
        below = np.asarray(reference.extras.get("grid", np.full(mask.shape, n))) == grid // 2
        chosen = np.flatnonzero(mask & below)
        if chosen.size:
            points[value] = tuple(int(k) for k in chosen)
            leaky = held.get("leakage", np.zeros(mask.shape, bool))
            if grid <= MAX_LEAKAGE_GRID:
                leakage[value] = tuple(int(k) for k in np.flatnonzero(leaky & below))
            stiff = np.zeros(mask.shape, bool)
            for quantity in STIFFNESS_FIELDS:
                stiff |= held.get(quantity, np.zeros(mask.shape, bool))
            stiffness[value] = tuple(int(k) for k in np.flatnonzero(stiff & mask & below))
            # the band expected on the finer grid: half the present one (first order)
            tolerances[value] = solver_tolerance(float(np.nanmin(band[chosen])) / 2.0,
                                                 scene.bem.tol)
    if not points:
        return None
    return RefinementLevel(grid, points, tolerances, leakage, name, stiffness)


def decide_scene(scene, by_value: dict, run: Callable[[int], list],
                 solve: Callable[[list], list]) -> tuple[RefinementRecord, SequentialRecord]:
    """Everything a scene with a reference does after its planned realizations, to decide its
    undecided cells: the finer reference where its band decides (:func:`finer_reference`),
    then the looks of its sequential plan (:func:`extend_scene`; new realizations get the same
    refinements). ``by_value`` is extended and updated in place; ``run`` and ``solve`` are as
    in those functions (:func:`run_scenes` gives the runner's executor, cache and progress bars
    through them)."""
    refinement = finer_reference(scene, by_value, solve, scene_plan(scene).confidence_at(0))
    return refinement, extend_scene(scene, by_value, run, refinement, solve)


def run_scenes(scenes: Iterable[Scene], *, executor: Executor | None = None,
               cache_dir: str | None = None, progress: bool = True, stream=None
               ) -> list[SceneResult]:
    """Run scenes to a decision: their planned realizations
    (:func:`validation.run.runner.run_planned`), then, for every scene with a reference, a finer
    reference and more realizations where its cells stay undecided (:func:`decide_scene`).

    Parameters
    ----------
    scenes : iterable of Scene
    executor : concurrent.futures.Executor, optional
        Where realization tasks and finer solves run; ``None`` runs them in this process, one
        after another.
    cache_dir : str, optional
        Cache folder; ``None`` disables the cache.
    progress : bool
        Draw progress bars on ``stream`` (stderr by default).

    Returns
    -------
    list of validation.run.runner.SceneResult
        One per scene, in order; ``refinement`` and ``sequential`` record what was added and
        why it stopped (None for a scene without a reference: nothing to decide).
    """
    started = time.perf_counter()
    out = run_planned(scenes, executor=executor, cache_dir=cache_dir, progress=progress,
                      stream=stream)
    where = dict(executor=executor, cache_dir=cache_dir, progress=progress, stream=stream)
    for index, result in enumerate(out):
        scene = result.scene
        if scene.kind == "theory" or not set(scene.models) & set(models.reference_names()):
            continue
        refinement, sequential = decide_scene(
            scene, result.realizations,
            run=lambda count: more_realizations(result, count, **where),
            solve=lambda jobs: solve_refinements(jobs, **where))
        out[index] = replace(result, refinement=refinement, sequential=sequential,
                             seconds=time.perf_counter() - started)
    return out
