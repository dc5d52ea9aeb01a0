"""One surface's answer in the user's units: nominal pressure, real contact-area fraction,
separation and mean gap, interfacial stiffness per unit area and the leakage's effective
hydraulic aperture, for every model beside the boundary-element reference and its band.

The scene runs in units of E* (``Load = W / (E* A0) = p / E*``) and of the scan's length unit
(heights, separations, h_eff); the conversions are

* nominal pressure ``p = Load E*`` [Pa] (only when E* is given);
* real contact-area fraction ``A / A0`` (dimensionless);
* separation ``d``, mean gap ``ū`` and leakage ``h_eff`` in the scan's length unit;
* normal interfacial stiffness per unit nominal area ``K = -dp/dd = S / A0``, with
  ``S = conductance E* / 2`` (Barber's analogy, ``conductance = 2 S / E*``) [Pa/m = N/m³].

Every model's value is the one it predicts for the field it is compared with (Persson's theory
predicts the mean gap, not the separation); the reference's band is its error estimate in the
error measure of the comparison (relative for area and stiffness, in units of σ for separation
and mean gap, the logarithm of the ratio for h_eff) turned into the quantity's unit.
"""

from __future__ import annotations

import csv
import pathlib
from dataclasses import dataclass

import numpy as np

from validation.check.units import format_pressure
from validation.surfaces.units import readable
from validation.judge.verdicts import FAILS, HOLDS
from validation.common.labels import model_label, model_order
from validation.common import models
from validation.surfaces.topography import LENGTH_UNITS

__all__ = ["FIELDS", "PhysicalTable", "physical_tables", "table_lines", "write_csv"]

#: Reference fields shown, in order: (field, heading, unit kind) with kind "fraction",
#: "length" or "stiffness".
FIELDS = (("area", "Real contact-area fraction A/A0", "fraction"),
          ("separation", "Separation d", "length"),
          ("mean_gap", "Mean gap ū", "length"),
          ("stiffness", "Interfacial stiffness per unit area K = S/A0", "stiffness"),
          # a check scene written before the check spoke of stiffness compares the conductance
          ("conductance", "Interfacial stiffness per unit area K = S/A0", "stiffness"),
          ("leakage", "Effective hydraulic aperture h_eff (leak rate ∝ h_eff³)", "length"))
_SYMBOLS = {HOLDS: "✔", FAILS: "✘"}
#: The verdict of a field the reference cannot judge at the scan's resolution (physical.csv).
NOT_JUDGED = "not judged"


@dataclass(frozen=True)
class PhysicalTable:
    """One reference field at every pressure: the reference's value and band and each model's
    value and verdict (at the loosest tolerance), in physical units."""

    field: str
    heading: str
    unit: str                       # of every value ("" for a fraction)
    load: np.ndarray                # p / E*
    pressure: np.ndarray | None     # Pa (None without E*)
    reference: np.ndarray
    band: np.ndarray                # half-width of the reference's band, same unit
    models: dict[str, np.ndarray]   # model -> value
    verdicts: dict[str, np.ndarray] # model -> verdict at ``tolerance``
    tolerance: float
    tolerance_text: str = ""        # the tolerance in the field's measure, for the heading
    frame: str = "interface"        # of the reference and of the models judged against it
    judged: bool = True             # False: not judged at the scan's resolution (no marks)

    def rows(self) -> list[dict]:
        """The table as rows of ``physical.csv`` (the reference as ``bem`` with its band)."""
        out = []
        for k in range(self.load.size):
            common = dict(field=self.field, frame=self.frame, unit=self.unit or "1", point=k,
                          load_p_over_e_star=float(self.load[k]),
                          pressure_Pa=None if self.pressure is None else float(self.pressure[k]))
            out.append(common | dict(model="bem", value=float(self.reference[k]),
                                     reference_band=float(self.band[k]), verdict=None,
                                     tolerance=None))
            out += [common | dict(model=model, value=float(values[k]), reference_band=None,
                                  verdict=str(self.verdicts[model][k]) if self.judged
                                  else NOT_JUDGED, tolerance=self.tolerance)
                    for model, values in self.models.items()]
        return out

    def markdown(self) -> str:
        """The table in Markdown (:func:`table_lines`)."""
        return "\n".join(table_lines(self))

    def _repr_markdown_(self) -> str:
        return self.markdown()

    def __str__(self) -> str:
        return self.markdown()

    def to_frame(self):
        """A pandas DataFrame, a row per pressure: ``p_over_e_star``, ``pressure_Pa`` (with
        E*), ``reference``, ``band``, then each model's value and ``<model> verdict``. Needs
        pandas (not a dependency of this package)."""
        try:
            import pandas
        except ImportError:
            raise ImportError("PhysicalTable.to_frame needs pandas: pip install pandas") from None
        columns = {"p_over_e_star": self.load}
        if self.pressure is not None:
            columns["pressure_Pa"] = self.pressure
        columns |= {"reference": self.reference, "band": self.band}
        for model, values in self.models.items():
            columns[model] = values
            columns[f"{model} verdict"] = np.asarray(self.verdicts[model]).astype(str)
        return pandas.DataFrame(columns)


def _scale(field: str, kind: str, curve, e_star: float | None, unit: str) -> tuple[float, str]:
    """Factor from the curve's field to the physical value, and the unit written."""
    area = curve.nominal_area
    if kind == "fraction":
        return 1.0 / area, ""
    if kind == "length":
        return 1.0, unit
    # stiffness per unit area K = S / A0 [E*_scene / length], from S or from the conductance
    # 2 S / E*: K = conductance E*_scene / (2 A0)
    factor = 1.0 / area if field == "stiffness" else curve.e_star / (2.0 * area)
    factor /= curve.e_star                  # in units of the scene's E* ...
    if e_star is None:
        return factor, f"E*/{unit}"
    return factor * e_star / LENGTH_UNITS[unit], "N/m³"   # ... times E* [Pa], per metre


def _value(curve, name: str) -> np.ndarray | None:
    value = getattr(curve, name, None) if name != "mean_gap" else curve.extras.get("mean_gap")
    return None if value is None else np.asarray(value, dtype=float)


def _band(field: str, reference: np.ndarray, band: np.ndarray,
          sigma: float) -> np.ndarray:
    if field in ("separation", "mean_gap"):
        return band * sigma
    if field == "leakage":
        return reference * np.expm1(band)
    return band * np.abs(reference)


def physical_tables(realization, comparison, *, e_star: float | None, unit: str
                    ) -> list[PhysicalTable]:
    """The tables of one surface (a :class:`validation.run.runner.RealizationResult` and its
    :class:`validation.judge.compare.Comparison`), one per reference field the scene compares.
    ``e_star`` [Pa] or None (pressures and stiffness in units of E*); ``unit`` the scan's."""
    tables = []
    frames = list(dict.fromkeys(entry.frame for entry in comparison.models.values()))
    for frame in frames:
        for field, heading, kind in FIELDS:
            entries = {model: entry for (model, _), entry in comparison.models.items()
                       if entry.reference_field == field and entry.frame == frame}
            if entries:
                table = _table(realization, comparison, entries, field, heading, kind, e_star,
                               unit, frame if len(frames) > 1 else "")
                if table is not None:
                    tables.append(table)
    return tables


def _table(realization, comparison, entries, field, heading, kind, e_star, unit,
           frame: str) -> PhysicalTable | None:
    """The table of one reference field, of the models judged in one frame."""
    curves = realization.curves
    first = next(iter(entries.values()))
    reference_curve = curves[first.reference_model or models.reference_among(curves)]
    reference = _value(reference_curve, field)
    if reference is None:
        return None
    scale, written = _scale(field, kind, reference_curve, e_star, unit)
    band = _band(field, reference, np.asarray(first.band, dtype=float),
                 realization.sigma) * scale
    index = len(first.tolerances) - 1
    values, verdicts = {}, {}
    for model in model_order(entries):
        value = _value(curves[model], entries[model].quantity)
        if value is not None:
            values[model] = value * scale
            verdicts[model] = np.asarray(entries[model].verdicts[index])
    pressure = None if e_star is None else comparison.load * e_star
    tolerance = first.tolerances[index]
    if frame:
        heading = f"{heading}, {models.FRAME_LABELS[frame]}"
    return PhysicalTable(field, heading, written, np.asarray(comparison.load), pressure,
                         reference * scale, band, values, verdicts, tolerance,
                         _tolerance_text(field, tolerance, realization.sigma, unit),
                         first.frame)


def _tolerance_text(field: str, tolerance: float, sigma: float, unit: str) -> str:
    """A tolerance in the measure its field is judged in: relative (per cent), in units of σ
    (and the scan's length unit), or as the logarithm of the ratio (and the factor)."""
    if field in ("separation", "mean_gap"):
        return f"{tolerance:g} σ = {readable(tolerance * sigma)} {unit}"
    if field == "leakage":
        return f"{tolerance:g} in ln h_eff, a factor {np.exp(tolerance):.3g}"
    return f"{100 * tolerance:g} %"


def _number(value: float) -> str:
    return "–" if not np.isfinite(value) else readable(value)


def table_lines(table: PhysicalTable) -> list[str]:
    """A Markdown table: one row per pressure, the reference with its band, then each model
    with ✔ (holds), ✘ (fails) or ? (undecided) at the table's tolerance; a table not
    ``judged`` (a field the reference cannot judge at the scan's resolution) has the values
    alone, no mark."""
    judged = table.judged
    percent = table.unit == ""
    shown = (lambda v: _number(100 * v) + " %") if percent else _number
    unit = f" [{table.unit}]" if table.unit else ""
    header = (["p"] if table.pressure is not None else []) + ["p/E*", f"BEM{unit}"] \
        + [model_label(m) for m in table.models]
    marks = (f"(✔ holds, ✘ fails, ? undecided within "
             f"{table.tolerance_text or f'{table.tolerance:g}'})" if judged else
             "(not judged at this resolution: the values without verdicts; see the glance)")
    lines = [f"**{table.heading}**{unit} {marks}:\n",
             "| " + " | ".join(header) + " |",
             "|" + "---|" * len(header)]
    for k in range(table.load.size):
        row = ([format_pressure(table.pressure[k])] if table.pressure is not None else []) + \
            [f"{table.load[k]:.3g}", f"{shown(table.reference[k])} ± {shown(table.band[k])}"]
        row += [shown(values[k]) + (f" {_SYMBOLS.get(str(table.verdicts[m][k]), '?')}"
                                    if judged else "")
                for m, values in table.models.items()]
        lines.append("| " + " | ".join(row) + " |")
    return lines + [""] + _notes(table)


def _notes(table: PhysicalTable) -> list[str]:
    """What a reader would stop at in a table, said under it: a negative separation, a
    leakage of zero, a band wider than its value."""
    values = [table.reference] + list(table.models.values())
    notes = []
    if table.field in ("separation", "mean_gap") and any(np.any(v < 0) for v in values):
        notes.append("A negative separation: the rigid plane lies below the surface's mean "
                     "plane, as it does at heavy contact (and, in a finite frame, once the "
                     "nominal contact's bulk sink exceeds the interface's mean gap).")
    if table.field == "leakage" and any(np.any(v == 0) for v in values):
        notes.append("h_eff = 0: no fluid path joins inlet and outlet, the interface seals "
                     "(a model at 0 predicts sealing there).")
    wide = np.isfinite(table.band) & (table.band > np.abs(table.reference))
    if np.any(wide):
        notes.append(f"At {int(np.count_nonzero(wide))} pressure(s) the reference's band is "
                     "wider than its value: the reference cannot tell it from zero there (a "
                     "contact of a few pixels), and no verdict there is more than the band "
                     "allows.")
    return [" ".join(notes) + "\n"] if notes else []


def write_csv(tables: list[PhysicalTable], path: str | pathlib.Path) -> pathlib.Path:
    """``physical.csv``: one row per field, pressure and model (the reference as ``bem`` with
    its band), values in the unit of the ``unit`` column (:meth:`PhysicalTable.rows`)."""
    path = pathlib.Path(path)
    names = ["field", "frame", "unit", "point", "load_p_over_e_star", "pressure_Pa", "model",
             "value", "reference_band", "verdict", "tolerance"]

    def text(value) -> str:
        if value is None:
            return ""
        return f"{value:.10g}" if isinstance(value, float) else str(value)

    with path.open("w", newline="", encoding="utf-8") as handle:
        out = csv.writer(handle)
        out.writerow(names)
        for t in tables:
            for row in t.rows():
                row["tolerance"] = None if row["tolerance"] is None else f"{row['tolerance']:g}"
                out.writerow([text(row[name]) for name in names])
    return path
