"""Finding (h): the asperity models' answers depend on the sampling interval (pure functions).

A scene with ``[sampling] factors = [1, 2, 4]`` carries, per realization, the summit-fitted
models at the sampling intervals h, 2h, 4h (:mod:`validation.run.sampling`), all at the loads of
the one BEM solution on the finest grid. Per sampling this module compares them with that
solution (:func:`validation.judge.compare.compare_realizations`: errors, verdicts and validity
ranges, separations in units of the finest sampling's summit sigma), and per load point the
paired shift of each model's answer from the finest sampling (docs/theory.md, "Sampling
interval", eq. S14)::

    Δ_k = (q(kh) − q(h)) / q_BEM        (area, conductance, stiffness)
    Δ_k = (d(kh) − d(h)) / σ_h          (separation)

realization by realization, with its 95 % Student-t interval over realizations. :data:`RULE`
states how the finding is decided (:func:`sampling_verdict`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from validation.judge.compare import (ABSOLUTE_QUANTITIES, COMPARED_QUANTITIES, Comparison,
                                      compare_realizations, pairwise_errors)
from validation.judge.claims import combine_points, decide_over_range
from validation.judge.findings import UNDECIDED, Finding, ranged_finding
from validation.judge.verdicts import FAILS, HOLDS, ErrorInterval, classify, confidence_interval
from validation.common.labels import compared_label, model_label, model_order
from validation.common import models

__all__ = ["KEY", "CLAIM", "RULE", "SUMMIT_RATIOS", "SamplingStudy", "sampling_study",
           "sampling_points", "sampling_verdict", "sampling_finding", "factor_label"]

KEY = "h"
CLAIM = "the asperity models' answers depend on the sampling interval"
#: Summit statistics compared with the finest sampling's, as ratios.
SUMMIT_RATIOS = ("density", "radius", "sigma")
#: How finding (h) is decided (Markdown, printed under the findings table).
RULE = """(h) The summit-fitted models (original and improved GW, the discrete models) on the
same surface sampled at h (the scene's grid, on which the BEM is solved) and at each coarser
interval k h of the scene (every k-th point, the mean plane kept; 2h and 4h by default), at the
BEM's loads. At each load point the paired shift from h to k h, (q(kh) − q(h))/q_BEM for area
and conductance and (d(kh) − d(h))/σ for separation (σ of the summits at h), with its 95 %
Student-t interval over realizations, against the scene's smallest tolerance: a model's quantity
*moves* at k h where the interval lies wholly outside ± the tolerance at more than half of the
load points, and *stays* where it lies wholly inside at more than half (the smallest k at which
some model's quantity moves is named). Decided over the contact-area range (the rule above): a
load point supports the claim where some model's quantity at some k lies wholly outside ± the
tolerance there, and contradicts it where every one lies wholly inside. Summit density, mean
radius and height deviation at each sampling are given as ratios to those at h."""


@dataclass(frozen=True)
class _View:
    """A realization seen with a chosen set of curves (what the comparison reads)."""

    task: object
    curves: dict
    sigma: float


@dataclass(frozen=True)
class SamplingStudy:
    """The samplings of one surface family (one sweep value) of a scene.

    ``summits[k][name]``: (mean, 95 % low, 95 % high) over realizations of the ratio of summit
    statistic ``name`` (:data:`SUMMIT_RATIOS`, and ``count``) at k h to that at h;
    ``comparisons[k]``: the models at k h against the reference; ``shifts[(model, quantity,
    k)]``: the paired shift from h to k h per load point (k > 1).
    """

    factors: tuple[int, ...]
    models: tuple[str, ...]
    quantities: tuple[str, ...]
    tolerances: tuple[float, ...]
    grids: dict[int, tuple[int, int]]
    summits: dict[int, dict[str, tuple[float, float, float]]]
    comparisons: dict[int, Comparison]
    shifts: dict[tuple[str, str, int], ErrorInterval]


def factor_label(factor: int) -> str:
    """``h``, ``2h``, ``4h``."""
    return "h" if factor == 1 else f"{factor}h"


def _interval(values: np.ndarray) -> tuple[float, float, float]:
    summary = confidence_interval(np.asarray(values, float).reshape(-1, 1))
    return float(summary.mean[0]), float(summary.low[0]), float(summary.high[0])


def _summit_ratios(results, factors) -> dict[int, dict[str, tuple[float, float, float]]]:
    out = {}
    for index, factor in enumerate(factors):
        ratios = {}
        for name in ("count",) + SUMMIT_RATIOS:
            with np.errstate(divide="ignore", invalid="ignore"):
                values = [getattr(r.sampled[index].summits, name) / getattr(r.sampled[0].summits, name)
                          for r in results]
            ratios[name] = _interval(np.array(values, float))
        out[factor] = ratios
    return out


def sampling_study(results, tolerances) -> SamplingStudy | None:
    """The sampling study of the realizations of one surface family; ``None`` when they carry
    one sampling only or no reference curve."""
    if not results or len(getattr(results[0], "sampled", ())) < 2:
        return None
    if models.reference_among(results[0].curves) is None:
        return None
    references = {frame: models.reference_among(results[0].curves, frame)
                  for frame in models.FRAMES}
    references = {frame: name for frame, name in references.items() if name is not None}

    def reference_of(name: str) -> str:
        """Each model against the reference of its own frame (docs/theory.md 8.10)."""
        frame = models.frame_of(name) if name in models.names() else "finite"
        return references.get(frame) or next(iter(references.values()))
    tolerances = tuple(float(t) for t in tolerances)
    factors = tuple(s.factor for s in results[0].sampled)
    names = tuple(model_order(results[0].sampled[0].curves))
    quantities = tuple(q for q in COMPARED_QUANTITIES if q in results[0].task.quantities)
    views = {factor: [_View(r.task, {**{ref: r.curves[ref] for ref in references.values()},
                                     **r.sampled[i].curves}, r.sigma) for r in results]
             for i, factor in enumerate(factors)}
    comparisons = {factor: compare_realizations(view, tolerances=tolerances)
                   for factor, view in views.items()}
    finest = {name: pairwise_errors(views[1], name, reference_of(name), quantities)
              for name in names}
    shifts = {}
    for factor in factors[1:]:
        for name in names:
            errors = pairwise_errors(views[factor], name, reference_of(name), quantities)
            for quantity, stack in errors.items():
                shifts[(name, quantity, factor)] = confidence_interval(stack - finest[name][quantity])
    grid = results[0].task.surface.grid
    return SamplingStudy(factors, names, quantities, tolerances,
                         {k: (grid[0] // k, grid[1] // k) for k in factors},
                         _summit_ratios(results, factors), comparisons, shifts)


def _moves(outside: np.ndarray) -> np.ndarray:
    """Per row: the shift lies wholly outside ± the tolerance at more than half of the points."""
    return 2 * np.sum(outside, axis=-1) > np.shape(outside)[-1]


def sampling_points(outside: np.ndarray, inside: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Finding (h) per load point from per-point decisions, one row per (model, quantity,
    coarsening k), one column per load point: ``outside`` where the shift's interval lies wholly
    outside ± the tolerance, ``inside`` where wholly inside. A point supports the claim where
    some row is outside, contradicts it where every row is inside (:data:`RULE`)."""
    outside, inside = np.atleast_2d(np.asarray(outside, bool)), np.atleast_2d(np.asarray(inside, bool))
    if outside.shape != inside.shape or outside.size == 0:
        raise ValueError(f"outside and inside must be non-empty arrays of one shape, got "
                         f"{outside.shape} and {inside.shape}")
    return combine_points(outside, inside, every=False)


def sampling_verdict(outside: np.ndarray, inside: np.ndarray) -> str:
    """Finding (h)'s verdict from per-point decisions (:func:`sampling_points`), decided over
    the load points (:data:`validation.judge.claims.RANGE_RULE`; the verdict does not depend
    on where the points lie, only the range it states)."""
    support, against = sampling_points(outside, inside)
    return decide_over_range(np.full(support.size, np.nan), support, against).verdict


def _shift_text(interval: ErrorInterval, quantity: str) -> str:
    mean = interval.mean[np.isfinite(interval.mean)]
    if mean.size == 0:
        return "no shift known"
    median = float(np.median(mean))
    return f"{median:+.2g} σ" if quantity in ABSOLUTE_QUANTITIES else f"{100 * median:+.2g} %"


def _ratio_text(study: SamplingStudy) -> str:
    parts = []
    for name in SUMMIT_RATIOS:
        cells = [f"×{study.summits[k][name][0]:.2g} ({factor_label(k)})" for k in study.factors[1:]]
        parts.append(f"{'σ' if name == 'sigma' else name} " + ", ".join(cells))
    return "summits against h: " + "; ".join(parts)


def sampling_finding(study: SamplingStudy | None) -> Finding:
    """Finding (h) of one surface family from its :func:`sampling_study`."""
    if study is None:
        return Finding(KEY, CLAIM, "not tested: the scene samples each surface at one interval "
                       "only ([sampling] factors), or has no BEM reference", UNDECIDED)
    tolerance = min(study.tolerances)
    outside, inside, parts, moving = [], [], [], []
    for factor in study.factors[1:]:
        cells = []
        for name in study.models:
            texts = []
            for quantity in study.quantities:
                interval = study.shifts.get((name, quantity, factor))
                if interval is None:
                    continue
                verdict = classify(interval, 0.0, tolerance)
                outside.append(verdict == FAILS)
                inside.append(verdict == HOLDS)
                if _moves(outside[-1]):
                    moving.append((factor, f"{model_label(name)} {compared_label(quantity)}"))
                texts.append(f"{compared_label(quantity)} {_shift_text(interval, quantity)} "
                             f"({int(np.sum(verdict == FAILS))}/{int(np.sum(verdict == HOLDS))})")
            cells.append(f"{model_label(name)}: " + ", ".join(texts))
        parts.append(f"{factor_label(factor)} against h, median shift (load points outside/"
                     f"inside ±{tolerance:g} of {study.comparisons[1].load.size}): "
                     + "; ".join(cells))
    if moving:
        first = min(k for k, _ in moving)
        parts.insert(0, f"moves from {factor_label(first)} on: "
                     + ", ".join(what for k, what in moving if k == first))
    evidence = " — ".join(parts + [_ratio_text(study)])
    if not outside:
        return Finding(KEY, CLAIM, evidence, UNDECIDED)
    support, against = sampling_points(outside, inside)
    return ranged_finding(KEY, CLAIM, evidence, study.comparisons[1].area_fraction,
                          support, against)
