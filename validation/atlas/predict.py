"""Each theory's error on a scan predicted from its descriptors, without a boundary-element solve:
:func:`predict_errors` and ``python -m validation predict SCAN``.

The scan and the pressures are read exactly as :func:`validation.check_scan` reads them
(:func:`validation.check.library.make_request`; the load points are those of the check's
scene), the scan's descriptors computed (:func:`validation.surface_descriptors`, a few FFTs),
and the stored error model (:mod:`validation.atlas.model`) evaluated at every load point: the predicted error of
each theory, its 90 % prediction interval and the verdict that interval gives at the check's
tolerance. Where a descriptor or the load lies outside the atlas, no verdict is given and the
result says which. :func:`against_check` sets a prediction against the check of the same scan:
how often the solved error lies inside the predicted interval, and how often the verdicts
agree where both decide.
"""

from __future__ import annotations

import csv
import math
import pathlib
import time
from dataclasses import dataclass

import numpy as np

from validation.atlas.model import interval_of, load_error_model, verdict_of
from validation.check.library import make_request
from validation.check.request import CheckRequest
from validation.common.labels import model_label
from validation.common.verdicts import FAILS, HOLDS
from validation.scenes.scene import LoadPath
from validation.surfaces.descriptors import SurfaceDescriptors, surface_descriptors
from validation.surfaces.units import parse_length

__all__ = ["COLUMNS", "Prediction", "PredictionCheck", "PredictedError", "against_check",
           "outside_atlas", "predict_errors", "predict_request"]

#: Columns of ``predicted.csv``.
COLUMNS = ("model", "frame", "quantity", "point", "Load", "pressure_Pa", "error", "low", "high",
           "tolerance", "verdict")
#: Verdict of a point outside the atlas.
OUTSIDE = "outside atlas"


@dataclass(frozen=True)
class PredictedError:
    """One theory's predicted error at one load point (a row of ``predicted.csv``)."""

    model: str
    frame: str
    quantity: str
    point: int
    load: float            # p / E*
    pressure: float        # p [Pa], NaN without E*
    error: float           # predicted relative error
    low: float             # 90 % prediction interval
    high: float
    tolerance: float
    verdict: str           # holds / fails / undecided / outside atlas


def outside_atlas(descriptors: SurfaceDescriptors, ranges: dict) -> list[str]:
    """The descriptors of a scan outside the atlas' range, each as a sentence."""
    out = []
    for name, label in (("hurst", "Hurst exponent H"), ("nayak", "Nayak's alpha"),
                        ("skewness", "skewness"), ("magnification", "magnification")):
        value = getattr(descriptors, name)
        low, high = ranges[name]
        if not (low <= value <= high):
            out.append(f"{label} = {value:.3g} is outside the atlas' {low:.3g} to {high:.3g}"
                       + (_cutoff_hint(descriptors, high) if name == "magnification"
                          and value > high else ""))
    return out


def _cutoff_hint(descriptors: SurfaceDescriptors, largest: float) -> str:
    """How long a short cutoff brings the magnification to 90 % of the atlas' largest."""
    wavelength = descriptors.short_wavelength * descriptors.magnification / (0.9 * largest)
    pixels = math.ceil(wavelength / descriptors.spacing)
    reached = descriptors.magnification * descriptors.short_wavelength / (pixels
                                                                         * descriptors.spacing)
    return (f" (a short cutoff of {pixels} pixels, --short-cutoff {pixels}px, brings it to "
            f"{reached:.3g})")


@dataclass(frozen=True)
class Prediction:
    """A scan's predicted errors (:func:`predict_errors`).

    Attributes
    ----------
    request : CheckRequest
        The scan and pressures, as the check reads them.
    descriptors : SurfaceDescriptors
        The scan's descriptors.
    rows : tuple of PredictedError
        Per model, frame, quantity and load point.
    outside : tuple of str
        The descriptors outside the atlas (then every verdict is "outside atlas").
    model : dict
        What the error model says of itself (atlas commit, grid, range, validation).
    seconds : float
        Time of the prediction [s].
    """

    request: CheckRequest
    descriptors: SurfaceDescriptors
    rows: tuple[PredictedError, ...]
    outside: tuple[str, ...]
    model: dict
    seconds: float

    def markdown(self) -> str:
        """The short report: the descriptors, where the scan sits in the atlas, and per theory
        a strip of predicted verdicts."""
        from validation.atlas.report import prediction_lines

        return "\n".join(prediction_lines(self))

    def write(self, folder: str | pathlib.Path, report: str = "report.md",
              extra: tuple[str, ...] = ()) -> pathlib.Path:
        """Write ``predicted.csv`` and the report (``report``, with the lines ``extra`` at its
        end) into ``folder``; returns the report's path."""
        folder = pathlib.Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        with open(folder / "predicted.csv", "w", newline="", encoding="utf-8") as stream:
            writer = csv.writer(stream)
            writer.writerow(COLUMNS)
            for r in self.rows:
                writer.writerow([r.model, r.frame, r.quantity, r.point, f"{r.load:.10g}",
                                 "" if math.isnan(r.pressure) else f"{r.pressure:.6g}",
                                 *("" if math.isnan(v) else f"{v:.4g}"
                                   for v in (r.error, r.low, r.high)),
                                 r.tolerance, r.verdict])
        path = folder / report
        path.write_text("\n".join([self.markdown(), *extra]) + "\n", encoding="utf-8")
        return path


def predict_errors(scan, *, e_star=None, pressures=None, short_cutoff=None, fill=None,
                   resample=None, physical_size=None, file_unit=None, spacing=None,
                   models=None, cache=None, model_file=None) -> Prediction:
    """Each theory's error on ``scan`` predicted by the atlas' error model, no solve.

    Parameters
    ----------
    scan, e_star, pressures, short_cutoff, fill, resample, physical_size, file_unit, spacing
        As for :func:`validation.check_scan`: the load points are the check's.
    models : sequence of str, optional
        The theories to predict (default: every one the error model has).
    cache : path, True/None or False
        Where a height array is written to be read as the check reads it (as for
        :func:`validation.check_scan`).
    model_file : path, optional
        Another error model file (default the package's).

    Returns
    -------
    Prediction

    Raises
    ------
    ValueError, TypeError
        Naming the argument, as :func:`validation.check_scan` does.
    """
    from validation.run.cache import default_cache_dir

    start = time.perf_counter()
    cache_dir = None if cache is False else str(default_cache_dir() if cache in (None, True)
                                                else cache)
    request = make_request(scan, e_star=e_star, pressures=pressures, short_cutoff=short_cutoff,
                           fill=fill, resample=resample, physical_size=physical_size,
                           file_unit=file_unit, spacing=spacing, cache_dir=cache_dir)
    return predict_request(request, models=models, model_file=model_file, start=start)


def predict_request(request: CheckRequest, *, models=None, model_file=None,
                    start: float | None = None) -> Prediction:
    """The prediction of a check's request (:func:`validation.check.library.make_request`):
    what :func:`predict_errors` returns, for a scan already read; ``start`` the
    :func:`time.perf_counter` the prediction's time counts from (default now)."""
    start = time.perf_counter() if start is None else start
    model = load_error_model(model_file)
    heights = request.read("m")
    low, high, count = request.loads(heights)   # p / E*: the check scene's load path
    loads = np.array([low] if count == 1 else
                     LoadPath(min=low, max=high, count=count, spacing="log").values())
    cutoff = None if request.short_cutoff is None else parse_length(
        "short_cutoff", request.short_cutoff)[0]            # "7.8e-09 m", metres
    descriptors = surface_descriptors(heights.heights, heights.spacing, short_cutoff=cutoff)
    ratio = loads / descriptors.rms_slope
    outside = outside_atlas(descriptors, model["range"])
    low_load, high_load = model["range"]["load_ratio"]
    inside_load = (ratio >= low_load * (1 - 1e-9)) & (ratio <= high_load * (1 + 1e-9))
    covariates = np.column_stack([np.full(loads.shape, descriptors.hurst),
                                  np.full(loads.shape, math.log10(descriptors.nayak)),
                                  np.full(loads.shape, descriptors.skewness), np.log10(ratio)])
    tolerance = float(model["tolerance"])
    known = {key.split("/")[0] for key in model["entries"]}
    if models is not None:
        models = (models,) if isinstance(models, str) else tuple(models)
        unknown = [m for m in models if m not in known]
        if unknown or not models:
            raise ValueError(f"models must name models of the error model ({', '.join(sorted(known))}), "
                             f"got {list(models)!r}")
    rows = []
    for key in model["entries"]:
        name, frame, quantity = key.split("/")
        if models is not None and name not in models:
            continue
        mean, low, high = interval_of(model, key, covariates)
        verdicts = verdict_of(low, high, tolerance)
        for k in range(loads.size):
            away = bool(outside) or not inside_load[k]
            verdict = OUTSIDE if away else str(verdicts[k])
            pressure = loads[k] * request.e_star if request.e_star is not None else math.nan
            # outside the atlas the model is not extrapolated: no number, no verdict
            numbers = (math.nan,) * 3 if away else (float(mean[k]), float(low[k]),
                                                    float(high[k]))
            rows.append(PredictedError(name, frame, quantity, k, float(loads[k]), pressure,
                                       *numbers, tolerance, verdict))
    rows.sort(key=lambda r: (model_label(r.model), r.quantity, r.point))
    return Prediction(request, descriptors, tuple(rows), tuple(outside),
                      {k: v for k, v in model.items() if k != "entries"},
                      time.perf_counter() - start)




@dataclass(frozen=True)
class PredictionCheck:
    """The prediction of a scan against its check, cell by cell (theory, quantity, pressure of
    the interface frame, inside the atlas).

    Attributes
    ----------
    cells : int
        Predicted cells the check solved and judged.
    inside : int
        Of those, the cells whose solved error lies inside the predicted 90 % interval.
    decided : int
        Cells where both the prediction and the check decide (holds or fails).
    agree : int
        Of those, the cells with the same verdict.
    """

    cells: int
    inside: int
    decided: int
    agree: int

    @property
    def coverage(self) -> float:
        """Share of the cells whose solved error lies inside the interval (NaN without any)."""
        return self.inside / self.cells if self.cells else math.nan

    @property
    def agreement(self) -> float:
        """Share of the cells both decide with the same verdict (NaN without any)."""
        return self.agree / self.decided if self.decided else math.nan

    def sentence(self) -> str:
        """One sentence for the command line and the report."""
        if not self.cells:
            return ("Prediction against the solve: no cell both the atlas predicted and the "
                    "check judged (the scan or its loads outside the atlas, or no field judged "
                    "at the scan's resolution).")
        agreement = ("" if not self.decided else
                     f"; the verdicts agree at {self.agree} of the {self.decided} cells both "
                     f"decide ({100 * self.agreement:.0f} %)")
        return (f"Prediction against the solve: the solved error lies inside the predicted "
                f"90 % interval at {self.inside} of {self.cells} cells "
                f"({100 * self.coverage:.0f} %){agreement}.")


def _solved(run, tables) -> tuple[np.ndarray, dict]:
    """The check's load points, and per (model, quantity) of the interface frame the solved
    error of the scan at each of them, the check's verdict there and the tolerance of its table
    (a table's field is the reference field the comparison compared with: Persson's mean gap
    for its separation, an older scene's conductance for its stiffness)."""
    from validation.judge.analysis import analyse

    comparison = analyse(run).comparisons[0]
    out = {}
    for table in tables:
        if table.frame != "interface" or not table.judged:
            continue
        for (model, quantity), found in comparison.models.items():
            if model in table.verdicts and found.errors is not None \
                    and found.frame == "interface" and found.reference_field == table.field:
                out[(model, "stiffness" if quantity == "conductance" else quantity)] = (
                    np.asarray(found.errors)[0], np.asarray(table.verdicts[model]),
                    table.tolerance)
    return np.asarray(comparison.load, dtype=float), out


def against_check(prediction: Prediction, result) -> PredictionCheck:
    """Compare ``prediction`` with ``result``, a :class:`validation.check.result.CheckResult` of
    the same scan and pressures (its whole scan, interface frame, at the tolerance of both).

    Raises
    ------
    ValueError
        Where the two have different load points.
    """
    loads, solved = _solved(result.runs[0], result.tables)
    predicted = np.array(sorted({(r.point, r.load) for r in prediction.rows}))
    if predicted.size and (predicted[:, 0].max() >= loads.size or not np.allclose(
            loads[predicted[:, 0].astype(int)], predicted[:, 1], rtol=1e-6)):
        raise ValueError("the prediction and the check have different load points")
    cells = inside = decided = agree = 0
    for row in prediction.rows:
        if row.verdict == OUTSIDE or (row.model, row.quantity) not in solved:
            continue
        errors, verdicts, tolerance = solved[(row.model, row.quantity)]
        error, verdict = float(errors[row.point]), str(verdicts[row.point])
        if not math.isfinite(error):
            continue
        cells += 1
        inside += row.low <= error <= row.high
        if row.verdict in (HOLDS, FAILS) and verdict in (HOLDS, FAILS) \
                and math.isclose(tolerance, row.tolerance):
            decided += 1
            agree += row.verdict == verdict
    return PredictionCheck(cells, inside, decided, agree)
