"""The paper's sealing claims as findings (f) and (g), from the results (pure functions, no I/O).

The paper: "it is the effective separation d1 which is a measure of the leakage, while the
nominal separation d measures the load", hence "it is harder to seal a large area than a small
one" [CGP, Sections 2 and 5]. With d1 = d + m W / (E* sqrt A) (docs/theory.md, eq. T11):

* (f) :func:`d1_measures_leakage`: on every realization, the rigid gap at the BEM's own d (GW's
  rule, eq. L5) and at its own d1 (improved GW's rule) against the BEM's exact h_eff. At equal
  load GW's and improved GW's own curves predict the *same* leakage (GW's d and improved GW's
  d1 solve the same load equation, docs/theory.md 10.3), so the claim can only be judged at
  the exact contact state: one separation, one load, two rules.
* (g) :func:`sealing_size`: the BEM's h_eff against d and against d1 on nested windows of one
  surface of growing nominal area (the built-in scene ``sealing-size``): at equal h_eff, the
  spread of d and of d1 across the sizes. The claim holds where the curves collapse on d1 and
  not on d.

Errors are the log ratio of eq. (L7); :data:`RULES` states how each finding is decided.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from asperity.common.leakage import log_aperture_error, rigid_gaussian_aperture
from bem.common.curve import ContactCurve
from validation.judge.compare import converged_points
from validation.judge.findings import IMPROVED_GW, ORIGINAL_GW, Finding, majority
from validation.judge.verdicts import (
    FAILS,
    HOLDS,
    UNDECIDED,
    classify,
    confidence_interval,
    verdict_strip,
)
from validation.common import models

__all__ = ["LEVELS", "RULES", "SizeCollapse", "d1_measures_leakage", "effective_separation",
           "sealing_size", "size_collapse"]

#: Leakage levels at which the sizes are compared in finding (g).
LEVELS = 8
#: How findings (f) and (g) are decided (Markdown, printed in the report below (a)-(e)).
RULES = """(f) Per realization and load point, the log error ln(h/h_BEM) (eq. L7) of the rigid gap
at the BEM's separation d (GW's rule) and at d1 = d + mW/(E*√A) with the BEM's load W (improved
GW's rule); a rule that seals where the BEM leaks (or leaks where it is sealed) is infinitely
wrong there. A point supports the claim where |error at d1| < |error at d| with the 95 %
Student-t interval of the paired difference over realizations above 0, contradicts it where
that interval lies below 0; where an error is infinite the interval is undefined and a
two-sided sign test at 95 % over realizations decides instead. Majority rule as above. (At
equal load GW's and improved GW's own curves predict the same leakage by construction, so the
models are not compared there.)
(g) On nested windows of one surface (sides L, 2L, 4L, the same grid spacing), at 8 leakage
levels h_eff common to every size (geometric between the largest of the sizes' smallest and the
smallest of their largest values, open points only), the BEM's d and d1 at each level by
linear interpolation along the load path, and their spread across sizes (largest − smallest,
in units of the mean σ), per realization. A level supports the claim where the curves collapse
on d1 (95 % interval of the d1 spread within ± the scene's largest tolerance) and the d1 spread
is smaller than the d spread (95 % interval of the paired difference above 0); it contradicts
it where they do not collapse on d1 (interval wholly outside) or the d1 spread is the larger.
Majority rule as above."""


def effective_separation(curve: ContactCurve, m: float) -> np.ndarray:
    """The effective separation ``d1 = d + m W / (E* sqrt(A))`` [length] of a curve at its own
    loads (docs/theory.md, eq. T11): the separation shifted by the mean elastic displacement
    of its load spread uniformly over the nominal area A."""
    return (np.asarray(curve.separation, dtype=float)
            + m * np.asarray(curve.load, dtype=float) / (curve.e_star * np.sqrt(curve.nominal_area)))


def _magnitude(error: np.ndarray, counted: np.ndarray) -> np.ndarray:
    """|log error|, infinite where it is undefined on a counted point (one side sealed), NaN
    where the point does not count."""
    return np.where(counted, np.where(np.isnan(error), np.inf, np.abs(error)), np.nan)


def _paired_decision(difference: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per point: whether a paired difference over realizations is above / below 0 at 95 %.

    Finite columns: the Student-t interval of the mean. Columns with an infinite entry: a
    two-sided sign test (NaN entries, and ties, left out)."""
    finite = np.where(np.isfinite(difference), difference, np.nan)
    interval = confidence_interval(finite)
    above, below = interval.low > 0, interval.high < 0
    infinite = np.any(np.isinf(difference), axis=0)
    for k in np.flatnonzero(infinite):
        column = difference[:, k]
        plus, minus = int(np.sum(column > 0)), int(np.sum(column < 0))
        if plus + minus == 0:
            above[k] = below[k] = False
            continue
        significant = stats.binomtest(plus, plus + minus, 0.5).pvalue < 0.05
        above[k], below[k] = significant and plus > minus, significant and minus > plus
    return above, below


def _median_text(values: np.ndarray) -> str:
    finite = values[np.isfinite(values)]
    return f"{np.median(finite):.3g}" if finite.size else "–"


def d1_measures_leakage(results, tolerance: float, reference_model: str | None = None):
    """Finding (f): the rigid gap at d1 against the rigid gap at d, both against the BEM's
    exact leakage at its own separation and load (see the module docstring and :data:`RULES`).

    ``results``: realizations of one surface family whose reference curve has ``leakage`` and
    whose ``sigma`` (standard deviation of the summit heights, the s of eq. L5) is known.
    """
    claim = "the effective separation d1, not d, measures the leakage"
    if results and reference_model is None:
        # the paper's claim is about its finite window: d1 = d + m p L/E* of that window
        window = models.reference_for("finite")
        reference_model = window if window in results[0].curves else None
    if not results or reference_model is None \
            or results[0].curves[reference_model].leakage is None:
        return Finding("f", claim, "not tested: needs the BEM's leakage of the finite window",
                       UNDECIDED)
    if not all(np.isfinite(r.sigma) and r.sigma > 0 for r in results):
        return Finding("f", claim, "not tested: needs σ (no asperity model in the scene)",
                        UNDECIDED)
    rows = {"d": [], "d1": []}
    errors = {"d": [], "d1": []}
    for r in results:
        bem = r.curves[reference_model]
        exact = np.asarray(bem.leakage, dtype=float)
        counted = converged_points(bem) & np.isfinite(exact)
        for name, separation in (("d", np.asarray(bem.separation, dtype=float)),
                                 ("d1", effective_separation(bem, r.task.m))):
            error = log_aperture_error(rigid_gaussian_aperture(separation, r.sigma), exact)
            errors[name].append(np.where(counted, error, np.nan))
            rows[name].append(_magnitude(error, counted))
    magnitude = {name: np.vstack(value) for name, value in rows.items()}
    closer_d1, closer_d = _paired_decision(magnitude["d"] - magnitude["d1"])
    strip = np.where(closer_d1, HOLDS, np.where(closer_d, FAILS, UNDECIDED))
    parts = []
    m = results[0].task.m
    for name, rule in (("d", "GW's rule"), ("d1", f"improved GW's rule, m = {m:g}")):
        stack = np.vstack(errors[name])
        sealed = int(np.sum(np.isinf(magnitude[name])))
        holds = classify(confidence_interval(stack), 0.0, tolerance)
        parts.append(f"rigid gap at {name} ({rule}): median |ln(h/h_BEM)| "
                     f"{_median_text(magnitude[name])}, within ±{tolerance:g} at "
                     f"{int(np.sum(holds == HOLDS))} of {holds.size} points"
                     + (f", disagrees with the BEM about sealing at {sealed} "
                        f"(realization, point) pair(s)" if sealed else ""))
    evidence = ("; ".join(parts) + f"; d1 closer at {int(closer_d1.sum())}, d closer at "
                f"{int(closer_d.sum())} of {strip.size} points, low → high load "
                f"[{verdict_strip(strip)}]" + _equal_load_text(results))
    return Finding("f", claim, evidence, majority(closer_d1, closer_d))


def _equal_load_text(results) -> str:
    """The two models' own curves at equal load, when the scene has both (identical leakage by
    construction: said with the number)."""
    if not {IMPROVED_GW, ORIGINAL_GW} <= set(results[0].curves) \
            or results[0].curves[ORIGINAL_GW].leakage is None \
            or results[0].curves[IMPROVED_GW].leakage is None:
        return ""
    ratios = np.concatenate([log_aperture_error(r.curves[IMPROVED_GW].leakage,
                                                r.curves[ORIGINAL_GW].leakage)
                             for r in results])
    largest = np.nanmax(np.abs(ratios)) if np.any(np.isfinite(ratios)) else np.nan
    return (f"; at equal load improved GW's and original GW's own curves differ by at most "
            f"|ln ratio| = {largest:.2g} (identical by construction)")


@dataclass(frozen=True)
class SizeCollapse:
    """The BEM's separations at common leakage levels on nested windows of several sizes.

    ``d`` and ``d1`` have shape (sizes, realizations, levels) and, like ``levels`` (h_eff) and
    the spreads (realizations, levels: largest minus smallest over the sizes), are in units of
    ``sigma``, the mean standard deviation of the summit heights over every realization."""

    sides: tuple[float, ...]
    seeds: tuple[int, ...]
    sigma: float
    levels: np.ndarray
    d: np.ndarray
    d1: np.ndarray

    @property
    def spread_d(self) -> np.ndarray:
        return np.ptp(self.d, axis=0)

    @property
    def spread_d1(self) -> np.ndarray:
        return np.ptp(self.d1, axis=0)


def _open_points(curve: ContactCurve) -> np.ndarray:
    leakage = np.asarray(curve.leakage, dtype=float)
    return converged_points(curve) & np.isfinite(leakage) & (leakage > 0)


def size_collapse(by_side: dict, m: float, reference_model: str | None = None
                  ) -> SizeCollapse | None:
    """The reference's d and d1 at :data:`LEVELS` leakage levels common to every size.

    Parameters
    ----------
    by_side : dict
        Nominal side L [length] -> realizations (:class:`validation.run.realization.RealizationResult`)
        of one surface on windows of that side; realizations of equal seed are paired.
    m : float
        Interaction factor of d1 = d + m W / (E* sqrt A) (eq. T11).

    Returns
    -------
    SizeCollapse or None
        None when fewer than two sizes, no seed common to all, no leakage or no σ, or no
        leakage range common to every curve.
    """
    sides = tuple(sorted(by_side))
    if len(sides) < 2:
        return None
    first = by_side[sides[0]]
    if reference_model is None and first:
        reference_model = models.reference_among(first[0].curves)
    seeds = sorted(set.intersection(*({r.task.seed for r in by_side[s]} for s in sides)))
    if reference_model is None or not seeds:
        return None
    pick = {(s, r.task.seed): r for s in sides for r in by_side[s]}
    cells = [[pick[(s, k)] for k in seeds] for s in sides]
    curves = [r.curves[reference_model] for row in cells for r in row]
    sigmas = np.array([r.sigma for row in cells for r in row], dtype=float)
    if any(c.leakage is None for c in curves) or not np.all(np.isfinite(sigmas) & (sigmas > 0)):
        return None
    sigma = float(np.mean(sigmas))
    opened = [np.asarray(c.leakage, dtype=float)[_open_points(c)] for c in curves]
    if any(o.size < 2 for o in opened):
        return None
    low, high = max(o.min() for o in opened), min(o.max() for o in opened)
    if not low < high:
        return None
    levels = np.geomspace(low, high, LEVELS)

    def at_levels(curve: ContactCurve, separation: np.ndarray) -> np.ndarray:
        keep = _open_points(curve)
        h = np.asarray(curve.leakage, dtype=float)[keep]
        order = np.argsort(h)
        return np.interp(levels, h[order], separation[keep][order]) / sigma

    d = np.array([[at_levels(r.curves[reference_model],
                             np.asarray(r.curves[reference_model].separation, dtype=float))
                   for r in row] for row in cells])
    d1 = np.array([[at_levels(r.curves[reference_model],
                              effective_separation(r.curves[reference_model], m))
                    for r in row] for row in cells])
    return SizeCollapse(sides, tuple(seeds), sigma, levels / sigma, d, d1)


def sealing_size(by_side: dict, m: float, tolerance: float,
                 reference_model: str | None = None):
    """Finding (g): "it is harder to seal a large area than a small one", on nested windows of
    growing size (see the module docstring and :data:`RULES`)."""
    claim = "it is harder to seal a large area than a small one"
    collapse = size_collapse(by_side, m, reference_model)
    if collapse is None:
        return Finding("g", claim, "not tested: needs the BEM's leakage and σ on at least two "
                       "sizes of the same realizations, with a leakage range common to all",
                       UNDECIDED), None
    d1_collapses = classify(confidence_interval(collapse.spread_d1), 0.0, tolerance)
    smaller, larger = _paired_decision(collapse.spread_d - collapse.spread_d1)
    support = (d1_collapses == HOLDS) & smaller
    against = (d1_collapses == FAILS) | larger
    strip = np.where(support, HOLDS, np.where(against, FAILS, UNDECIDED))
    mean_d = collapse.d.mean(axis=1)                          # (sizes, levels)
    deeper = np.all(np.diff(mean_d, axis=0) < 0, axis=0)      # larger area: smaller d
    spread = {name: confidence_interval(value).mean for name, value in
              (("d", collapse.spread_d), ("d1", collapse.spread_d1))}
    with np.errstate(divide="ignore", invalid="ignore"):
        removed = 1.0 - spread["d1"] / spread["d"]
    sides = ", ".join(f"{s:g}" for s in collapse.sides)
    evidence = (f"BEM on windows of side {sides} ({len(collapse.seeds)} realization(s) each), "
                f"d1 = d + {m:g} W/(E*√A), at {LEVELS} leakage levels h_eff/σ = {collapse.levels[0]:.3g}–"
                f"{collapse.levels[-1]:.3g}: spread of d across sizes {_span(spread['d'])} σ, "
                f"of d1 {_span(spread['d1'])} σ (d1 removes {_span(100 * removed)} % of the "
                f"spread of d); at equal leakage d falls with the size (a "
                f"larger area needs a deeper approach) at {int(deeper.sum())} of {LEVELS} "
                f"levels; d1 collapses within ±{tolerance:g} σ at "
                f"{int(np.sum(d1_collapses == HOLDS))}, its spread is below that of d at "
                f"{int(smaller.sum())} of {LEVELS} levels, high → low leakage "
                f"[{verdict_strip(strip[::-1])}]")
    return Finding("g", claim, evidence, majority(support, against)), collapse


def _span(values: np.ndarray) -> str:
    finite = values[np.isfinite(values)]
    return f"{finite.min():.3g}–{finite.max():.3g}" if finite.size else "–"
