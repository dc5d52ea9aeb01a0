"""The paper's findings checked point by point, from the results (pure functions, no I/O).

Each check returns a :class:`Finding` with the numbers that decide it and a verdict:
``reproduced``, ``contradicted`` or ``undecided``; :data:`RULES` states the thresholds (the
report prints it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

from validation.common import models
from validation.judge.claims import (CONTRADICTED, RANGE_RULE, RANGED, REPRODUCED, UNDECIDED,
                                     ClaimRange, combine_points, decide_over_range)
from validation.judge.compare import Comparison, converged_points, pairwise_errors
from validation.common.labels import model_label
from validation.judge.verdicts import (
    FAILS,
    HOLDS,
    ErrorInterval,
    classify,
    confidence_interval,
    true_runs,
    verdict_counts,
    verdict_strip,
)

__all__ = [
    "CONTRADICTED",
    "NEW",
    "RANGED",
    "REPRODUCED",
    "UNCHANGED_TOLERANCE",
    "UNDECIDED",
    "Finding",
    "area_load_unchanged",
    "check_findings",
    "closest_models",
    "improved_follows_discrete",
    "interaction_shift",
    "majority",
    "scatter_shrinks",
]

NEW = "not in the paper"
#: Largest relative area difference still "nearly unchanged" in finding (a).
UNCHANGED_TOLERANCE = 0.10
# The paper's findings are claims about these particular models (not about whatever a scene
# lists), so they are named here; the exact reference comes from the registry.
INTERACTION, NO_INTERACTION = "discrete", "discrete_no_interaction"
IMPROVED_GW, ORIGINAL_GW = "improved_gw", "gw"
#: How each finding is decided (Markdown, printed in the report).
RULES = f"""Per-point decisions use the verdict rule of the report (95 % Student-t interval over
realizations, the two models paired realization by realization, no reference band).
{RANGE_RULE}
(a) The relative area difference of the discrete model with and without interaction, at equal
load, within ±{100 * UNCHANGED_TOLERANCE:g} % supports "nearly unchanged", wholly outside contradicts it.
(b) Over the heavier half of the load path (the range tested), the same pair differing by more
than the scene's smallest tolerance (separation in σ, conductance relative) downwards supports
a shift (the interaction lowers both at a given load); within the tolerance, or upwards,
contradicts it; the separation and the conductance combined.
(c) The coefficient of variation over realizations of the exact (BEM) area and conductance at
equal load, lightest against heaviest load point: reproduced where the 95 % F-distribution
interval of their ratio lies above 1, contradicted where below 1 (the two points are treated
as independent samples, so the interval is approximate).
(d) Improved GW against the discrete model with interaction within the scene's largest
tolerance supports the claim, outside it contradicts it; area, separation and conductance
combined (original GW beside it for contrast).
(c) is decided on the two ends of the path, not over a range; (f) and (g), below, by majority.
(e) Not tested in the paper: the asperity model with the most points that hold against the BEM
at the largest tolerance (ties: smaller median |mean error|), and the loads where none holds,
which include those where none could be decided (the verdict tables say which).
Frames: (a), (b) and (d) compare the paper's models with each other; (c), (f) and (g) read the
exact solution of the finite window, the paper's problem; (e) and (h) judge each model against
the reference of its own frame (the interface, or the finite contact)."""


@dataclass(frozen=True)
class Finding:
    """One finding on one surface family: the claim, the deciding numbers, the verdict, and
    for a claim decided over the load path (:mod:`validation.judge.claims`) its range."""

    key: str          # "a" ... "h"
    claim: str
    evidence: str
    verdict: str
    range: ClaimRange | None = None

    @property
    def verdict_text(self) -> str:
        """The verdict as the report prints it ("reproduced from 2 % to 30 % contact")."""
        return self.range.verdict_text if self.range is not None else self.verdict

    def range_cells(self) -> list:
        """The range columns of ``findings.csv``: tested and reproduced area fractions, and the
        points that support, contradict and decide neither ("" where not decided over a
        range)."""
        if self.range is None:
            return [""] * 7
        r = self.range
        return [*(v if math.isfinite(v) else "" for v in (r.tested_from, r.tested_to,
                                                           r.reproduced_from, r.reproduced_to)),
                r.reproduced, r.contradicted, r.undecided]


def ranged_finding(key: str, claim: str, evidence: str, fraction: np.ndarray,
                   support: np.ndarray, against: np.ndarray) -> Finding:
    """A finding decided over the contact-area range of its points (:data:`RANGE_RULE`), the
    range in words after the evidence."""
    decided = decide_over_range(fraction, support, against)
    return Finding(key, claim, f"{evidence}; {decided.describe(np.asarray(fraction), against)}",
                   decided.verdict, decided)


def path_fraction(results) -> np.ndarray:
    """The reference's contact-area fraction at each load point, mean over realizations (the
    finite window's reference where the results hold it; NaN where there is none)."""
    curves = results[0].curves
    name = models.reference_among(curves)
    if name is None:
        return np.full(np.size(next(iter(curves.values())).load), np.nan)
    return np.mean([np.asarray(r.curves[name].area_fraction, float) for r in results], axis=0)


def majority(support: np.ndarray, against: np.ndarray) -> str:
    """Verdict of a claim over points: boolean arrays of points that support / contradict it."""
    support, against = np.asarray(support, bool), np.asarray(against, bool)
    points = support.size
    if points and not against.any() and 2 * support.sum() >= points:
        return REPRODUCED
    if points and 2 * against.sum() >= points:
        return CONTRADICTED
    return UNDECIDED


def _combine(verdicts: list[str]) -> str:
    if verdicts and all(v == REPRODUCED for v in verdicts):
        return REPRODUCED
    return CONTRADICTED if CONTRADICTED in verdicts else UNDECIDED


def _missing(key: str, claim: str, what: str) -> Finding:
    return Finding(key, claim, f"not tested: {what}", UNDECIDED)


def _range_text(values: np.ndarray, unit: str = "") -> str:
    values = values[np.isfinite(values)]
    if values.size == 0:
        return "no finite value"
    scale, suffix = (100.0, " %") if unit == "%" else (1.0, f" {unit}" if unit else "")
    return f"{scale * values.min():+.3g}{suffix} to {scale * values.max():+.3g}{suffix}"


def _interval(errors: np.ndarray) -> ErrorInterval:
    """The mean difference of two models over realizations with its confidence interval; on one
    surface the difference itself, exact (two models of the same surface: no sampling, and no
    reference band between them)."""
    if errors.shape[0] != 1:
        return confidence_interval(errors)
    mean = np.asarray(errors[0], dtype=float)
    known = np.isfinite(mean)
    return ErrorInterval(mean, np.where(known, 0.0, np.inf), np.full(mean.shape, np.nan),
                         known.astype(int))


def area_load_unchanged(results, area_fraction: np.ndarray | None = None) -> Finding:
    """Finding (a): discrete model with against without interaction, relative area at equal
    load, decided over the contact-area range (``area_fraction``: the reference's at each load
    point, default :func:`path_fraction`)."""
    claim = "interaction leaves the area–load relation nearly unchanged"
    if not results or not {INTERACTION, NO_INTERACTION} <= set(results[0].curves):
        return _missing("a", claim, "the scene lacks the discrete model with and without interaction")
    errors = pairwise_errors(results, INTERACTION, NO_INTERACTION, ("area",))["area"]
    interval = _interval(errors)
    verdicts = classify(interval, 0.0, UNCHANGED_TOLERANCE)
    counts = verdict_counts(verdicts)
    evidence = (f"area with / without interaction − 1: mean {_range_text(interval.mean, '%')} "
                f"over the load path; within ±{100 * UNCHANGED_TOLERANCE:g} % "
                f"({'on this surface' if errors.shape[0] == 1 else '95 % interval'}) at "
                f"{counts[HOLDS]} of {verdicts.size} points, outside at {counts[FAILS]} "
                f"[{verdict_strip(verdicts)}]")
    fraction = path_fraction(results) if area_fraction is None else area_fraction
    return ranged_finding("a", claim, evidence, fraction, verdicts == HOLDS, verdicts == FAILS)


def interaction_shift(results, threshold: float, area_fraction: np.ndarray | None = None
                      ) -> Finding:
    """Finding (b): separation and conductance shifted downwards by interaction, over the
    heavier half of the path (``area_fraction``: as in :func:`area_load_unchanged`)."""
    claim = "interaction shifts the separation and the conductance (stiffness) at a given load"
    if not results or not {INTERACTION, NO_INTERACTION} <= set(results[0].curves):
        return _missing("b", claim, "the scene lacks the discrete model with and without interaction")
    errors = pairwise_errors(results, INTERACTION, NO_INTERACTION, ("separation", "conductance"))
    fraction = path_fraction(results) if area_fraction is None else area_fraction
    heavy_fraction = np.asarray(fraction)[np.shape(fraction)[0] // 2:]
    parts, supports, againsts = [], [], []
    for quantity, stack in errors.items():
        heavy = stack[:, stack.shape[1] // 2:]
        interval = _interval(heavy)
        point = classify(interval, 0.0, threshold)
        down, up = (point == FAILS) & (interval.mean < 0), (point == FAILS) & (interval.mean > 0)
        supports.append(down)
        againsts.append((point == HOLDS) | up)
        unit = "σ" if quantity == "separation" else "%"
        parts.append(f"{quantity}: with − without {_range_text(interval.mean, unit)}, shifted "
                     f"down beyond {threshold:g}{' σ' if unit == 'σ' else ''} at "
                     f"{int(down.sum())} of {down.size} heavier points, no shift at "
                     f"{int(np.sum(point == HOLDS))}, up at {int(up.sum())} "
                     f"[{decide_over_range(heavy_fraction, down, againsts[-1]).verdict_text}]")
    support, against = combine_points(supports, againsts)
    return ranged_finding("b", claim, "; ".join(parts), heavy_fraction, support, against)


def _cv_ratio(values: np.ndarray) -> tuple[float, float, float, np.ndarray]:
    """Coefficient of variation per point, and the lightest/heaviest ratio with its interval."""
    summary = confidence_interval(values)
    with np.errstate(invalid="ignore", divide="ignore"):
        cv = summary.std / np.abs(summary.mean)
    count = summary.count
    light, heavy = cv[0], cv[-1]
    if count[0] < 2 or count[-1] < 2 or not (np.isfinite(light) and heavy > 0):
        return float("nan"), float("nan"), float("nan"), cv
    ratio = light / heavy
    upper_f = stats.f.ppf(0.975, count[0] - 1, count[-1] - 1)
    lower_f = stats.f.ppf(0.025, count[0] - 1, count[-1] - 1)
    return float(ratio), float(ratio / np.sqrt(upper_f)), float(ratio / np.sqrt(lower_f)), cv


def scatter_shrinks(results, reference_model: str | None = None) -> Finding:
    """Finding (c): scatter over realizations of the exact area and conductance at equal load
    (``reference_model``: default the registered reference among the curves)."""
    claim = "the scatter between realizations is large at low load and shrinks with load"
    if results and reference_model is None:
        reference_model = models.reference_among(results[0].curves)
    if not results or reference_model not in results[0].curves or len(results) < 2:
        return _missing("c", claim, "needs the BEM and at least two realizations")
    parts, verdicts = [], []
    for quantity in ("area", "conductance"):
        curves = [r.curves[reference_model] for r in results]
        if getattr(curves[0], quantity) is None:
            continue
        values = np.vstack([np.where(converged_points(c), getattr(c, quantity), np.nan)
                            for c in curves]).astype(float)
        ratio, low, high, cv = _cv_ratio(values)
        if not np.isfinite(ratio):
            parts.append(f"{quantity}: fewer than two converged BEM realizations at an end point")
            verdicts.append(UNDECIDED)
            continue
        verdicts.append(REPRODUCED if low > 1 else CONTRADICTED if high < 1 else UNDECIDED)
        parts.append(f"{quantity}: coefficient of variation {100 * cv[0]:.3g} % at the lightest "
                     f"load, {100 * cv[len(cv) // 2]:.3g} % mid-path, {100 * cv[-1]:.3g} % at the "
                     f"heaviest; ratio {ratio:.3g} (95 % interval {low:.3g}–{high:.3g})")
    return Finding("c", claim, "; ".join(parts) or "no BEM area", _combine(verdicts))


def improved_follows_discrete(results, tolerance: float,
                              area_fraction: np.ndarray | None = None) -> Finding:
    """Finding (d): improved GW against the discrete model with interaction (original GW
    beside), every quantity combined per point (``area_fraction``: as in
    :func:`area_load_unchanged`)."""
    claim = "improved GW follows the discrete model with interaction"
    if not results or not {IMPROVED_GW, INTERACTION} <= set(results[0].curves):
        return _missing("d", claim, "the scene lacks improved GW or the discrete model")
    quantities = tuple(q for q in ("area", "separation", "conductance")
                       if q in results[0].task.quantities)
    improved = pairwise_errors(results, IMPROVED_GW, INTERACTION, quantities)
    original = (pairwise_errors(results, ORIGINAL_GW, INTERACTION, quantities)
                if ORIGINAL_GW in results[0].curves else {})
    fraction = path_fraction(results) if area_fraction is None else area_fraction
    parts, supports, againsts = [], [], []
    for quantity, stack in improved.items():
        point = classify(confidence_interval(stack), 0.0, tolerance)
        supports.append(point == HOLDS)
        againsts.append(point == FAILS)
        text = (f"{quantity} {verdict_strip(point)} "
                f"[{decide_over_range(fraction, supports[-1], againsts[-1]).verdict_text}]")
        if quantity in original:
            text += f" (original GW {verdict_strip(classify(confidence_interval(original[quantity]), 0.0, tolerance))})"
        parts.append(text)
    support, against = combine_points(supports, againsts)
    return ranged_finding("d", claim, f"within ±{tolerance:g} of the discrete model, low → high "
                          "load: " + "; ".join(parts), fraction, support, against)


def _runs_text(load: np.ndarray, mask: np.ndarray) -> str:
    """The loads where ``mask`` is true, as runs ("1e-05–0.0001, 0.01"; "" where nowhere)."""
    return ", ".join(f"{load[a]:.2g}" if a == b else f"{load[a]:.2g}–{load[b]:.2g}"
                     for a, b in true_runs(mask))


def closest_models(comparison: Comparison) -> Finding:
    """Finding (e): the asperity model closest to the BEM per quantity, and where none holds."""
    claim = ("which model (asperity models, Persson) is closest to the exact BEM, and where "
             "none holds")
    parts = []
    quantities = list(dict.fromkeys(q for (_, q) in comparison.models))
    for quantity in quantities:
        entries = [e for (m, q), e in comparison.models.items() if q == quantity and e.verdicts]
        if not entries:
            continue
        index = int(np.argmax(entries[0].tolerances))
        tolerance = entries[0].tolerances[index]

        def score(entry, index=index):
            mean = np.abs(entry.summary.mean)
            median = np.nanmedian(mean) if np.any(np.isfinite(mean)) else np.inf
            return (-entry.counts(index)[HOLDS], median)

        best = min(entries, key=score)
        none = np.all([e.verdicts[index] != HOLDS for e in entries], axis=0)
        held = best.counts(index)[HOLDS]
        what = "" if best.reference_field in ("", quantity) else f", {best.reference_field}"
        closest = (f"{model_label(best.model)} ({held} of {none.size} points{what} hold within "
                   f"{tolerance:g})" if held else f"no model holds within {tolerance:g} anywhere")
        where = (f"none holds at Load {_runs_text(comparison.load, none)}" if none.any()
                 else "at every load at least one holds")
        parts.append(f"{quantity}: {closest}; {where}")
    return Finding("e", claim, "; ".join(parts) or "no comparison", NEW)


def check_findings(results, comparison: Comparison, tolerances: tuple[float, ...]) -> list[Finding]:
    """All findings (a)-(e) for the realizations of one surface family and their comparison."""
    fraction = comparison.area_fraction
    return [area_load_unchanged(results, fraction),
            interaction_shift(results, min(tolerances), fraction),
            scatter_shrinks(results),
            improved_follows_discrete(results, max(tolerances), fraction),
            closest_models(comparison)]
