"""Errors of a model against the reference at equal load, with verdicts and validity ranges.

Error measures (at equal total load W, realization by realization): relative for area and
conductance, in units of sigma for separation, the logarithm of the ratio for the leakage, with
the disagreements about sealing counted apart (:mod:`validation.judge.errors`, where the
measures are defined point by point).

A model may be compared with a different field of the reference than its own quantity's name:
its registry entry says which (``validation.common.models.entry(name).reference_fields``; Persson's
separation is a mean gap, compared with the reference's ``extras["mean_gap"]``).

At each load point the errors over realizations give a mean, a Student-t confidence interval
(95 %, or the level of a look of the sequential plan) and, with the reference's own error band,
a verdict (holds / fails / undecided; :mod:`validation.judge.verdicts`). The validity range at a
tolerance is the longest run of "holds". Beside it, a verdict on single surfaces from a normal
tolerance interval of the same errors (:mod:`validation.judge.tolerance`): holds per surface
where at least 90 % of surfaces are within the tolerance, with the same confidence.

The two readings have two reference bands (:mod:`validation.judge.bands`, docs/theory.md T50):
the verdict on the mean carries the mirror method's bias (``band``), the one per surface its
whole bound (``surface_band``, the band one surface carries); they are equal where the
reference has no method error of its own (the finite window's, a periodic surface's).

A scene of one realization (one measured scan) is one surface, not a sample of a population:
its verdicts come from its error and the band one surface carries alone
(:func:`validation.judge.verdicts.one_surface_verdicts`), and it has no per-surface reading.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from bem.common import checks
from bem.common.curve import ContactCurve
from validation.judge.errors import (ABSOLUTE_QUANTITIES, LOG_QUANTITIES,
                                     RELATIVE_QUANTITIES, converged_points, curve_errors,
                                     pairwise_errors, reached_points,
                                     sealing_disagreements)
from validation.common import models
from validation.judge.bands import NOT_ESTIMATED, _band
from validation.judge.frames import judged_frame, references_of, source_key
from validation.judge.tolerance import (SurfaceInterval, classify_per_surface, surface_interval,
                                        surface_reasons)
from validation.judge.verdicts import (CONFIDENCE, FAILS, HOLDS, REFERENCE_BAND, UNDECIDED,
                                       ErrorInterval, ValidityRange, classify,
                                       confidence_interval, one_surface_reasons,
                                       one_surface_verdicts, undecided_reasons, validity_range,
                                       verdict_counts, verdict_range)

__all__ = [
    "ABSOLUTE_QUANTITIES",
    "COMPARED_QUANTITIES",
    "LOG_QUANTITIES",
    "NOT_ESTIMATED",
    "RELATIVE_QUANTITIES",
    "Comparison",
    "ErrorSummary",
    "ModelComparison",
    "ValidityRange",
    "compare_realizations",
    "converged_points",
    "curve_errors",
    "reached_points",
    "pairwise_errors",
    "sealing_disagreements",
    "summarise_errors",
    "validity_range",
]

#: Quantities that get verdicts (the load path itself is not compared). Contact counts are not
#: among them: the BEM counts connected contact patches, the asperity models asperities.
COMPARED_QUANTITIES = ("area", "separation", "conductance", "stiffness", "leakage")


@dataclass(frozen=True)
class ErrorSummary:
    """Mean and scatter over realizations of one model's error in one quantity."""

    quantity: str
    mean: np.ndarray      # shape (points,)
    std: np.ndarray       # sample standard deviation over realizations (0 for one)
    count: int            # realizations


def summarise_errors(quantity: str, per_realization: list[np.ndarray]) -> ErrorSummary:
    """Mean and sample standard deviation over realizations (ignoring NaN entries)."""
    interval = confidence_interval(np.vstack(per_realization))
    return ErrorSummary(quantity, interval.mean, np.nan_to_num(interval.std, nan=0.0),
                        len(per_realization))


@dataclass(frozen=True)
class ModelComparison:
    """One model, one quantity: errors with their interval, verdicts and ranges per tolerance."""

    model: str
    quantity: str
    summary: ErrorSummary
    ranges: tuple[ValidityRange, ...]
    # (realization, load) points where the model or the BEM did not converge, or the model did
    # not reach the reference's load (``unreachable`` of them)
    unconverged: int = 0
    interval: ErrorInterval | None = None
    # reference band per point of the verdicts: on a population the mean's (the mirror method's
    # bias in it), on one surface the band one surface carries (its bound in it; eq. T50)
    band: np.ndarray | None = None
    verdicts: tuple[np.ndarray, ...] = ()             # per tolerance, one verdict per point
    tolerances: tuple[float, ...] = ()
    reference_field: str = ""                         # the reference field compared with
    complete: np.ndarray | None = None                # where every realization converged
    unreachable: int = 0                              # points the model did not reach
    surface: SurfaceInterval | None = None            # tolerance interval of single surfaces
    surface_verdicts: tuple[np.ndarray, ...] = ()     # per tolerance: holds per surface or not
    surface_ranges: tuple[ValidityRange, ...] = ()    # per tolerance: longest run per surface
    # leakage only, per point: realizations where exactly one of model and reference is sealed
    # (all of them, and those the reference's error estimate resolves); None for other fields
    sealing: np.ndarray | None = None
    sealing_resolved: np.ndarray | None = None
    # the errors themselves, shape (realizations, points), NaN where not compared
    errors: np.ndarray | None = None
    # the frame the model is judged in, the reference of that frame, and that reference's
    # mean contact-area fraction per point (docs/theory.md 8.10)
    frame: str = "finite"
    reference_model: str = ""
    area_fraction: np.ndarray | None = None
    # reference band per point one surface carries (the method's bound in it): the band of the
    # per-surface verdicts and of one surface's; None: the same as ``band``
    surface_band: np.ndarray | None = None

    @property
    def one_surface(self) -> bool:
        """Whether the comparison is of one surface (one realization), judged by the reference
        band alone (:func:`validation.judge.verdicts.one_surface_verdicts`)."""
        return self.errors is not None and np.shape(self.errors)[0] == 1

    def counts(self, index: int) -> dict[str, int]:
        """Points that hold, fail and are undecided at tolerance ``tolerances[index]``."""
        return verdict_counts(self.verdicts[index])

    def surface_counts(self, index: int) -> dict[str, int]:
        """Points that hold, fail and are undecided per surface at ``tolerances[index]``."""
        return verdict_counts(self.surface_verdicts[index])

    def surface_reasons(self, index: int) -> np.ndarray:
        """Why each point is undecided per surface at ``tolerances[index]`` ("" where decided;
        :func:`validation.judge.tolerance.surface_reasons`)."""
        if self.surface is None or self.interval is None:
            return np.full(np.shape(self.verdicts[index]), "")
        band = self.band if self.surface_band is None else self.surface_band
        band = np.full(self.interval.mean.shape, np.nan) if band is None else band
        return self._sealing_reasons(
            surface_reasons(self.surface, band, self.tolerances[index],
                            count=self.interval.count, complete=self.complete),
            self.surface_verdicts[index])

    def reasons(self, index: int) -> np.ndarray:
        """Why each point is undecided at ``tolerances[index]`` ("" where decided;
        :func:`validation.judge.verdicts.undecided_reasons`)."""
        if self.interval is None:
            return np.full(np.shape(self.verdicts[index]), "")
        band = np.full(self.interval.mean.shape, np.nan) if self.band is None else self.band
        if self.one_surface:
            return self._sealing_reasons(
                one_surface_reasons(self.errors[0], band, self.tolerances[index]),
                self.verdicts[index])
        return self._sealing_reasons(
            undecided_reasons(self.interval, band, self.tolerances[index],
                              complete=self.complete),
            self.verdicts[index])

    def _sealing_reasons(self, reasons: np.ndarray, verdicts: np.ndarray) -> np.ndarray:
        """Reasons that agree with the verdicts where the leakage's sealing rule decided them:
        none where a resolved disagreement fails the point, the reference band where the
        reference's own estimate cannot tell whether it seals (a finer grid decides)."""
        if self.sealing is None:
            return reasons
        reasons = np.where(np.asarray(verdicts) == UNDECIDED, reasons, "")
        return np.where((np.asarray(verdicts) == UNDECIDED) & (self.sealing > 0),
                        REFERENCE_BAND, reasons)


@dataclass(frozen=True)
class Comparison:
    """All models against the reference for one surface family of a scene: one ``value`` of
    its swept ``parameter`` (D of a WM surface, H of a self-affine one; "" and 0 for a measured
    map).

    ``load`` is the paper's dimensionless Load = W/(E* L^2) of the path; ``area_fraction`` the
    reference's mean area fraction at each load; ``band_source`` says per compared field where
    the reference band came from (the per-point estimates, or "not estimated").
    """

    value: float
    load: np.ndarray
    area_fraction: np.ndarray
    models: dict[tuple[str, str], ModelComparison]
    band_source: dict[str, str] = field(default_factory=dict)
    parameter: str = "D"
    confidence: float = CONFIDENCE  # of every interval and verdict (validation.run.sequential)
    # each realization's path, shape (realizations, points): the reference's area fraction and
    # Load (the headline interpolates along them, validation.judge.headline)
    realization_area_fraction: np.ndarray | None = None
    realization_load: np.ndarray | None = None
    # per frame: each realization's area fraction along the path of that frame's reference,
    # and the reference's name (``area_fraction`` above is the finite frame's where both are)
    frame_paths: dict[str, np.ndarray] = field(default_factory=dict)
    references: dict[str, str] = field(default_factory=dict)

    def band_source_of(self, entry: "ModelComparison") -> str:
        """Where the band of the reference field ``entry`` is compared with came from."""
        return self.band_source.get(entry.reference_field, "") if (
            not self.frame_paths or self.references.get("finite") is None
            or entry.frame == "finite") else \
            self.band_source.get(f"{entry.reference_field} ({entry.frame})", "")

    def paths_of(self, frame: str) -> np.ndarray:
        """Each realization's area fraction along the reference path of ``frame``."""
        if frame in self.frame_paths:
            return self.frame_paths[frame]
        paths = self.realization_area_fraction
        return np.atleast_2d(self.area_fraction if paths is None else paths)

    @property
    def D(self) -> float:
        """The sweep value (the fractal dimension D of a WM family; kept for old callers)."""
        return self.value


def _sealing_counts(results, model: str, reference_model: str, field_name: str
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Per point, realizations that disagree about sealing, and those the reference resolves."""
    pairs = [sealing_disagreements(r.curves[model], r.curves[reference_model], field_name)
             for r in results]
    return (np.sum([p[0] for p in pairs], axis=0), np.sum([p[1] for p in pairs], axis=0))


def _model_comparison(results, model, quantity, errors, bands, reference_model, load,
                      area_fraction, tolerances, field_name, confidence) -> ModelComparison:
    """``bands``: the reference band of the mean and the one one surface carries."""
    interval = confidence_interval(errors, confidence)
    band, surface_band = bands
    reached = np.vstack([reached_points(r.curves[model], r.curves[reference_model])
                         for r in results])
    complete = np.all(np.vstack([converged_points(r.curves[model])
                                 & converged_points(r.curves[reference_model])
                                 for r in results]) & reached, axis=0)
    single = errors.shape[0] == 1   # one surface: judged by the reference band alone
    if single:
        band = surface_band         # one surface carries the method's whole bound (eq. T50)
    verdicts = tuple(one_surface_verdicts(errors[0], band, tol) if single
                     else classify(interval, band, tol, complete=complete) for tol in tolerances)
    sealing = resolved = None
    if quantity in LOG_QUANTITIES:
        # a resolved disagreement about sealing is an infinite error: the point fails; an
        # unresolved one leaves it undecided (docs/theory.md, eq. L7 and below)
        sealing, resolved = _sealing_counts(results, model, reference_model, field_name)
        verdicts = tuple(np.where(resolved > 0, FAILS, np.where(sealing > 0, UNDECIDED, v))
                         for v in verdicts)
    surface, surface_verdicts = None, ()
    if not single:
        surface = surface_interval(interval.mean, interval.std, interval.count,
                                   confidence=confidence,
                                   floor=-1.0 if quantity in RELATIVE_QUANTITIES else -np.inf)
        surface_verdicts = tuple(classify_per_surface(surface, surface_band, tol,
                                                      complete=complete)
                                 for tol in tolerances)
    if sealing is not None:
        # an infinite error of some surface: per surface, nothing holds where sealing disagrees
        surface_verdicts = tuple(np.where((sealing > 0) & (v == HOLDS), UNDECIDED, v)
                                 for v in surface_verdicts)
    ranges = tuple(verdict_range(load, v == HOLDS, tol, area_fraction)
                   for v, tol in zip(verdicts, tolerances))
    surface_ranges = tuple(verdict_range(load, v == HOLDS, tol, area_fraction)
                           for v, tol in zip(surface_verdicts, tolerances))
    summary = summarise_errors(quantity, list(errors))
    return ModelComparison(model, quantity, summary, ranges,
                           _unconverged(results, model, reference_model), interval, band,
                           verdicts, tuple(tolerances), field_name, complete,
                           int(np.count_nonzero(~reached)), surface, surface_verdicts,
                           surface_ranges, sealing, resolved, errors, surface_band=surface_band)


def _unconverged(results, model: str, reference_model: str) -> int:
    return sum(int(np.count_nonzero(~(converged_points(r.curves[model])
                                      & converged_points(r.curves[reference_model])
                                      & reached_points(r.curves[model],
                                                       r.curves[reference_model]))))
               for r in results)


def _registered_fields(names) -> dict[str, dict[str, str]]:
    """model -> {quantity: reference field} from the registry (models it does not know: {})."""
    known = models.reference_fields()
    return {name: dict(known[name]) for name in names if name in known}


def _is_realization(item) -> bool:
    """Whether ``item`` looks like a :class:`validation.run.realization.RealizationResult`."""
    curves = getattr(item, "curves", None)
    return (hasattr(item, "task") and isinstance(curves, dict)
            and all(isinstance(curve, ContactCurve) for curve in curves.values()))


def compare_realizations(results, *, tolerances=(0.05, 0.2), reference_model: str | None = None,
                         reference_fields: dict[str, dict[str, str]] | None = None,
                         confidence: float = CONFIDENCE) -> Comparison:
    """Compare every model with the reference over the realizations of one sweep value (D, H).

    Parameters
    ----------
    results : list of validation.run.realization.RealizationResult
        Realizations of one surface family; each holds a curve per model.
    tolerances : tuple of float
        Error levels for the verdicts and validity ranges.
    reference_model : str, optional
        The model every other one is compared against; default: each model against the
        registered reference of its own frame among the curves (docs/theory.md 8.10).
    reference_fields : dict, optional
        model -> {quantity: reference field}; default: the registry's entries
        (:func:`validation.common.models.reference_fields`).
    confidence : float
        Confidence of the intervals and verdicts, on the mean and per surface, in [0.5, 1)
        (the sequential plan's, :mod:`validation.run.sequential`; default 95 %): below one
        half an interval states nothing, and near 0 its per-surface bounds are infinite.

    Notes
    -----
    On a separation path the loads of point k differ between realizations and ``load`` is that
    of the first realization: read such a comparison as one per separation point.
    """
    results = checks.instances("results", results, _is_realization, described=(
        "realization results (validation.run.realization.RealizationResult: .task and .curves)"))
    tolerances = tuple(float(t) for t in checks.real_array(
        "tolerances", tolerances, ndim=1, min_size=1, minimum=0.0, exclusive=True))
    if reference_model is not None and not isinstance(reference_model, str):
        raise checks.InputTypeError(f"reference_model must be a model name or None, got "
                                    f"{type(reference_model).__name__} {reference_model!r}")
    if reference_fields is not None and not isinstance(reference_fields, dict):
        raise checks.InputTypeError(f"reference_fields must be a dict (model -> {{quantity: "
                                    f"field}}) or None, got {type(reference_fields).__name__}")
    confidence = checks.real_number("confidence", confidence, minimum=0.5, maximum=1.0,
                                    exclusive_maximum=True)
    if not results:
        raise ValueError("results holds no realizations to compare")
    first = results[0]
    references = references_of(first.curves, reference_model)
    mapping = _registered_fields(first.curves) if reference_fields is None else reference_fields
    primary = references.get("finite") or next(iter(references.values()))
    primary_frame = next(f for f, name in references.items() if name == primary)
    load = _dimensionless_load(first, primary)
    paths = {frame: np.vstack([r.curves[name].area_fraction for r in results])
             for frame, name in references.items()}
    quantities = tuple(q for q in COMPARED_QUANTITIES if q in first.task.quantities)
    entries: dict[tuple[str, str], ModelComparison] = {}
    sources: dict[str, str] = {}
    for frame, reference in references.items():
        judged = [m for m in first.curves if m not in references.values()
                  and judged_frame(m, references, primary_frame) == frame]
        fields = tuple(dict.fromkeys(mapping.get(m, {}).get(q, q) for m in judged
                                     for q in quantities))
        bands = {name: _band(results, name, reference) for name in fields}
        means = {name: _band(results, name, reference, part="mean")[0] for name in fields}
        sources.update({source_key(k, frame, primary_frame): v[1] for k, v in bands.items()})
        area_fraction = paths[frame].mean(axis=0)
        for model in judged:
            own = mapping.get(model, {})
            errors = pairwise_errors(results, model, reference, quantities, own)
            for name, stack in errors.items():
                field_name = own.get(name, name)
                entries[(model, name)] = replace(_model_comparison(
                    results, model, name, stack, (means[field_name], bands[field_name][0]),
                    reference, load,
                    area_fraction, tolerances, field_name, confidence),
                    frame=frame, reference_model=reference, area_fraction=area_fraction)
    loads = np.vstack([_dimensionless_load(r, primary) for r in results])
    return Comparison(value=first.task.sweep_value, parameter=first.task.surface.sweep_name,
                      load=load, area_fraction=paths[primary_frame].mean(axis=0),
                      models=entries, band_source=sources, confidence=confidence,
                      realization_area_fraction=paths[primary_frame], realization_load=loads,
                      frame_paths=paths, references=dict(references))


def _dimensionless_load(result, reference: str) -> np.ndarray:
    """The paper's Load = W / (E* L^2) of one realization's reference path."""
    curve = result.curves[reference]
    return curve.load / (curve.e_star * result.task.surface.L**2)
