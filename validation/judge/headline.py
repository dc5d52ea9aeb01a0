"""The headline: each model's error at fixed contact-area fractions of the reference.

Estimates first, verdicts second: what a reader cites is "GW under-predicts the contact area by
27 % (21–33 %) at 1 % contact", and "holds within 0.2" is a reading of it. A headline cell is
one model, one quantity and one fraction ``a*`` of the nominal area in contact in the reference
(:data:`HEADLINE_FRACTIONS`: 0.1 %, 1 %, 10 % and 30 %, where the load path reaches them).

Each realization r has a load path with the reference's area fraction ``a_r[k]`` and the
model's error ``e_r[k]`` at its points k (:mod:`validation.judge.compare`). The error at
``a*`` is interpolated along that path, linearly in ``ln a``::

    e_r(a*) = (1 - w) e_r[j-1] + w e_r[j],   w = ln(a*/a_r[j-1]) / ln(a_r[j]/a_r[j-1])

with j the first point where ``a_r[j] >= a*`` (the error at j itself where ``a_r[j] = a*``);
the reference band and the Load are interpolated with the same weights (the Load linearly in
``ln Load``). A fraction is in the headline of a surface family when every realization's path
crosses it between two points in contact (a fraction reached by some realizations only would
bias the mean towards them).

Over the realizations the interpolated errors give, exactly as at a load point
(:mod:`validation.judge.verdicts`, :mod:`validation.judge.tolerance`):

* the mean error and its 95 % Student-t interval (the confidence of the comparison);
* the per-surface 90 % interval: the normal tolerance interval ``m ± k2 s`` holding at least
  90 % of single surfaces with that confidence;
* the verdicts at each tolerance, on the mean and per surface, the band as at a load point.
  A realization whose error is undefined next to ``a*`` (unconverged, unreachable, or sealed on
  one side only) is left out, and the cell can then fail but not hold.

One surface (a scene of one realization) has no interval over realizations: its cell is the
error with ± the reference band, judged by
:func:`validation.judge.verdicts.one_surface_verdicts`, and has no per-surface interval.

:data:`REGIMES` names the regime of each fraction (``headline.csv``'s ``regime``): light contact
0.1–1 %, intermediate 10 %, heavy 30 %; the summary's tables take one fraction of each
(:data:`validation.report.summary.COLUMNS`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from validation.judge.compare import COMPARED_QUANTITIES, Comparison
from validation.judge.errors import RELATIVE_QUANTITIES
from validation.judge.tolerance import classify_per_surface, surface_interval
from validation.judge.verdicts import (
    CONFIDENCE,
    classify,
    confidence_interval,
    one_surface_reasons,
    one_surface_verdicts,
    undecided_reasons,
)

__all__ = [
    "HEADLINE_FRACTIONS",
    "REGIMES",
    "HeadlineCell",
    "along_path",
    "crossing",
    "headline",
    "headline_numbers",
    "reached_fractions",
    "regime_of",
]

#: Contact-area fractions of the reference at which the headline gives every model's error.
HEADLINE_FRACTIONS = (0.001, 0.01, 0.1, 0.3)
#: The contact regimes, by the headline fractions they hold.
REGIMES = (("light", (0.001, 0.01)), ("intermediate", (0.1,)), ("heavy", (0.3,)))


def regime_of(fraction: float) -> str:
    """The regime (:data:`REGIMES`) a headline fraction belongs to ("" for none)."""
    return next((name for name, held in REGIMES
                 if any(np.isclose(fraction, f, rtol=1e-9) for f in held)), "")


def crossing(area_fraction: np.ndarray, target: float
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Where each realization's path crosses the area fraction ``target``.

    Parameters
    ----------
    area_fraction : array, shape (realizations, points)
        The reference's contact-area fraction along each path, in path order.
    target : float
        The fraction sought, in (0, 1].

    Returns
    -------
    before, after : int arrays, shape (realizations,)
        The points on either side of the crossing (equal where a point lies on ``target``).
    weight : float array, shape (realizations,)
        ``w`` of the module docstring: the value at the crossing is
        ``(1 - w) v[before] + w v[after]``.
    reached : bool array, shape (realizations,)
        Whether the path crosses ``target`` between two points in contact (or at a point);
        elsewhere ``before``, ``after`` and ``weight`` are meaningless.
    """
    if not 0.0 < target <= 1.0:
        raise ValueError(f"target must be an area fraction in (0, 1], got {target!r}")
    area = np.atleast_2d(np.asarray(area_fraction, dtype=float))
    with np.errstate(invalid="ignore"):
        above = area >= target
    after = np.argmax(above, axis=1)
    rows = np.arange(area.shape[0])
    found = above[rows, after]
    exact = found & (area[rows, after] == target)
    before = np.where(exact, after, np.maximum(after - 1, 0))
    low, high = area[rows, before], area[rows, after]
    with np.errstate(invalid="ignore"):
        reached = found & (exact | ((after > 0) & (low > 0)))
    with np.errstate(divide="ignore", invalid="ignore"):
        weight = np.where(exact | ~reached, 0.0,
                          np.log(target / np.where(reached, low, 1.0))
                          / np.log(np.where(reached, high / np.where(reached, low, 1.0), 2.0)))
    return before, after, weight, reached


def along_path(values: np.ndarray, before: np.ndarray, after: np.ndarray,
               weight: np.ndarray) -> np.ndarray:
    """Values at the crossings of :func:`crossing`, per realization: ``values`` of shape
    (realizations, points) or (points,) (the same for every realization)."""
    values = np.asarray(values, dtype=float)
    rows = np.arange(before.size)
    if values.ndim == 1:
        low, high = values[before], values[after]
    else:
        low, high = values[rows, before], values[rows, after]
    return np.where(weight == 0.0, low, (1.0 - weight) * low + weight * high)


def reached_fractions(comparison: Comparison, fractions=HEADLINE_FRACTIONS,
                      frame: str | None = None) -> tuple[float, ...]:
    """The fractions every realization's reference path of ``comparison`` crosses (of
    ``frame``'s reference; default the comparison's own ``area_fraction``, the finite frame's
    where both are)."""
    paths = comparison.paths_of(frame) if frame is not None else np.atleast_2d(
        comparison.area_fraction if comparison.realization_area_fraction is None
        else comparison.realization_area_fraction)
    return tuple(f for f in fractions if crossing(paths, f)[3].all())


@dataclass(frozen=True)
class HeadlineCell:
    """One model's error in one quantity at one contact-area fraction of the reference.

    ``low`` and ``high`` bound the mean error's 95 % interval over realizations, or, for one
    surface (``one_surface``), the error ± the reference band; ``surface_low`` and
    ``surface_high`` the per-surface 90 % interval (NaN for one surface or fewer than three
    realizations). ``verdicts``, ``surface_verdicts`` and ``reasons`` hold one entry per
    tolerance of ``tolerances`` (per surface: "" for one surface).
    """

    model: str
    quantity: str
    reference_field: str
    fraction: float
    load: float               # mean Load = W/(E* L^2) at the fraction over the realizations
    realizations: int         # realizations whose error at the fraction is known
    mean: float
    low: float
    high: float
    surface_low: float
    surface_high: float
    band: float               # reference band at the fraction (NaN: not estimated)
    tolerances: tuple[float, ...]
    verdicts: tuple[str, ...]
    surface_verdicts: tuple[str, ...]
    reasons: tuple[str, ...]
    one_surface: bool = False
    confidence: float = CONFIDENCE
    frame: str = "finite"     # the frame of the model and of the reference it is judged against

    @property
    def half_width(self) -> float:
        """Half the width of the interval ``[low, high]``: the headline's precision."""
        return 0.5 * (self.high - self.low)


def headline_numbers(errors: np.ndarray, band: np.ndarray, tolerances, *,
                     one_surface: bool = False, confidence: float = CONFIDENCE,
                     floor: float | np.ndarray = -np.inf,
                     surface_band: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The numbers and verdicts of headline cells from the errors at their fraction.

    Parameters
    ----------
    errors : array, shape (realizations, cells)
        Each realization's error at the fraction, one column per cell (NaN where unknown).
    band : array, shape (cells,)
        The reference band of each cell (NaN: not estimated): on a population the mean's, on
        one surface the one it carries (docs/theory.md, eq. T50).
    tolerances : sequence of float
        The tolerances to judge at.
    one_surface : bool
        Judge one surface by its band alone (``errors`` then holds one row).
    confidence : float
        Confidence of the intervals and verdicts.
    floor : float or array, shape (cells,)
        The least error of any surface per cell (-1 for relative errors), the lower end of the
        per-surface interval at least (:func:`validation.judge.tolerance.surface_interval`).
    surface_band : array, shape (cells,), optional
        The band one surface carries, of the per-surface verdicts (default: ``band``).

    Returns
    -------
    dict of str to ndarray
        The fields of :class:`HeadlineCell` from ``realizations`` to ``reasons``, one entry
        per cell (``verdicts``, ``surface_verdicts`` and ``reasons``: shape (tolerances,
        cells)).
    """
    errors = np.atleast_2d(np.asarray(errors, dtype=float))
    band = np.broadcast_to(np.asarray(band, dtype=float), errors.shape[1:])
    tolerances = tuple(float(t) for t in tolerances)
    known = np.count_nonzero(np.isfinite(errors), axis=0)
    if one_surface:
        if errors.shape[0] != 1:
            raise ValueError(f"one surface has one error per cell, got {errors.shape[0]}")
        error = errors[0]
        nothing = np.full((len(tolerances),) + error.shape, "")
        return dict(realizations=known, mean=error, low=error - band, high=error + band,
                    surface_low=np.full(error.shape, np.nan),
                    surface_high=np.full(error.shape, np.nan), band=band,
                    verdicts=np.array([one_surface_verdicts(error, band, t) for t in tolerances]),
                    surface_verdicts=nothing,
                    reasons=np.array([one_surface_reasons(error, band, t) for t in tolerances]))
    interval = confidence_interval(errors, confidence)
    complete = known == errors.shape[0]
    surface_band = band if surface_band is None else np.broadcast_to(
        np.asarray(surface_band, dtype=float), band.shape)
    surface = surface_interval(interval.mean, interval.std, interval.count,
                               confidence=confidence, floor=floor)
    return dict(realizations=known, mean=interval.mean, low=interval.low, high=interval.high,
                surface_low=surface.low, surface_high=surface.high, band=band,
                verdicts=np.array([classify(interval, band, t, complete=complete)
                                   for t in tolerances]),
                surface_verdicts=np.array([classify_per_surface(surface, surface_band, t,
                                                                complete=complete)
                                           for t in tolerances]),
                reasons=np.array([undecided_reasons(interval, band, t, complete=complete)
                                  for t in tolerances]))


def headline(comparison: Comparison, fractions=HEADLINE_FRACTIONS) -> list[HeadlineCell]:
    """Every compared model and quantity of ``comparison`` at each fraction that every
    realization's path crosses (module docstring), ordered by the comparison's models and
    quantities, then by fraction. Each model's fractions are those of the reference of its own
    frame (docs/theory.md 8.10): the interface's contact area at a load is not the window's."""
    entries = [e for (_, quantity), e in comparison.models.items()
               if quantity in COMPARED_QUANTITIES and e.errors is not None]
    cells = []
    for frame in dict.fromkeys(e.frame for e in entries):
        cells += _frame_cells(comparison, [e for e in entries if e.frame == frame], frame,
                              fractions)
    position = {(e.model, e.quantity): i for i, e in enumerate(entries)}
    return sorted(cells, key=lambda c: (position[(c.model, c.quantity)], c.fraction))


def _frame_cells(comparison: Comparison, entries, frame: str, fractions) -> list[HeadlineCell]:
    """The headline cells of the entries of one frame, along that frame's reference paths."""
    paths = comparison.paths_of(frame)
    loads = comparison.realization_load
    loads = np.atleast_2d(comparison.load if loads is None else loads)
    cells = []
    for fraction in (f for f in fractions if crossing(paths, f)[3].all()):
        before, after, weight, _ = crossing(paths, fraction)
        with np.errstate(divide="ignore", invalid="ignore"):
            load = float(np.mean(np.exp(along_path(np.log(loads), before, after, weight))))
        errors = np.column_stack([along_path(e.errors, before, after, weight) for e in entries])
        band = np.array([np.nan if e.band is None
                         else np.mean(along_path(e.band, before, after, weight))
                         for e in entries])
        surface_band = np.array([
            np.nan if (e.band if e.surface_band is None else e.surface_band) is None
            else np.mean(along_path(e.band if e.surface_band is None else e.surface_band,
                                    before, after, weight)) for e in entries])
        # the entries of one comparison share its realizations and tolerances
        numbers = headline_numbers(errors, band, entries[0].tolerances,
                                   surface_band=surface_band,
                                   one_surface=entries[0].one_surface,
                                   confidence=comparison.confidence,
                                   floor=np.array([-1.0 if e.quantity in RELATIVE_QUANTITIES
                                                   else -np.inf for e in entries]))
        for i, e in enumerate(entries):
            cells.append(HeadlineCell(
                e.model, e.quantity, e.reference_field or e.quantity, fraction, load,
                int(numbers["realizations"][i]),
                *(float(numbers[name][i]) for name in ("mean", "low", "high", "surface_low",
                                                       "surface_high", "band")),
                tolerances=e.tolerances,
                verdicts=tuple(str(v) for v in numbers["verdicts"][:, i]),
                surface_verdicts=tuple(str(v) for v in numbers["surface_verdicts"][:, i]),
                reasons=tuple(str(v) for v in numbers["reasons"][:, i]),
                one_surface=e.one_surface, confidence=comparison.confidence, frame=frame))
    return cells
