"""What a check returns: one scan's answer as a small frozen object.

:class:`CheckResult` holds the physical-unit tables of the reference and every model
(:class:`validation.check.physical.PhysicalTable`), the lines that head the check's report (the
answer at a glance, the tables, the frames and whether the reference is converged on the scan),
and the runs behind them, so that a notebook reads the answer without writing anything
(:meth:`~CheckResult.table`, :meth:`~CheckResult.glance`, :meth:`~CheckResult.plot`,
:meth:`~CheckResult.to_frame`) and :meth:`~CheckResult.write_report` writes the same report
folder as ``python -m validation check``. It pickles (numpy arrays and plain values).
"""

from __future__ import annotations

import pathlib
import re
import shutil
from dataclasses import dataclass, replace
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from validation.check.frames import frame_lines
from validation.check.glance import glance_lines
from validation.check.physical import PhysicalTable, physical_tables, table_lines, write_csv
from validation.check.request import CheckRequest
from validation.check.resolution import cutoff_text, resolution, resolution_lines, unjudged
from validation.check.units import format_pressure
from validation.surfaces.units import readable

if TYPE_CHECKING:  # the runner's results, imported where they are made
    from matplotlib.figure import Figure

    from validation.run.runner import SceneResult

__all__ = ["CheckResult", "Markdown", "check_sections"]

#: Other names a table is found by (:meth:`CheckResult.table`): the ensemble reports' word.
FIELD_ALIASES = {"conductance": "stiffness", "stiffness": "conductance"}
#: Share of filled points above which the report says so in bold.
MANY_FILLED = 0.05


class Markdown(str):
    """Markdown text that a notebook shows rendered (``_repr_markdown_``) and ``print`` shows
    as it is."""

    def _repr_markdown_(self) -> str:
        return str(self)


def _filled_text(request: CheckRequest) -> str:
    """How many points of the scan were missing and filled (``fill``), if any."""
    if request.fill is None:
        return ""
    scan = request.read("m")
    if not scan.filled:
        return ""
    share = scan.filled / scan.heights.size
    text = (f"{scan.filled} of {scan.heights.size} points ({100 * share:.3g} %) missing in the "
            f"file and filled (fill = {request.fill})")
    if share > MANY_FILLED:
        return (f"; **{text}: the filled points are not measured topography, yet every model "
                f"and the reference see them**")
    return f"; {text}"


def _quoted(text: str) -> str:
    """A TOML basic string."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def check_sections(request: CheckRequest, result: SceneResult, sampled: SceneResult
                   ) -> tuple[list[PhysicalTable], list[str], list[str]]:
    """The tables of a check in physical units, the lines that head its report (the surface,
    the answer at a glance, every model in physical units, the frames, and whether the
    reference is converged on the scan; ``sampled``: the same scene before any finer reference
    solve), and the answer at a glance alone."""
    from validation.common import models
    from validation.judge.analysis import analyse
    from validation.judge.bands import method_band

    scene = result.scene
    comparison = analyse(result).comparisons[0]
    half_grid = analyse(sampled).comparisons[0]
    realization = result.realizations[0.0][0]
    s = scene.surface
    unit = s.unit
    tables = physical_tables(realization, comparison, e_star=request.e_star, unit=unit)
    # the interface's reference: the check's answer, and the one its finer grid refines
    reference_name = (models.reference_among(realization.curves, "interface")
                      or models.reference_among(realization.curves))
    reference = realization.curves[reference_name]
    refined = np.asarray(reference.extras.get("grid", np.full(reference.load.shape, s.n))) > s.n
    rows, columns = s.grid
    e_star = ("E* not given: pressures and stiffness are in units of E*" if request.e_star is None
              else f"E* = {format_pressure(request.e_star)}")
    lines = [f"## Your surface: {request.name}\n",
             f"The whole scan as one surface: {rows} x {columns} pixels of "
             f"{readable(s.spacing, 4)} {unit}, plane removed, Sq (rms height) = "
             f"{readable(float(np.std(request.read(unit).heights)), 4)} {unit}, σ (rms of the "
             f"summit heights) = {readable(realization.sigma, 4)} {unit}, {e_star}"
             + (f", low-pass filtered at {cutoff_text(request.short_cutoff, s.spacing, unit)}"
                if request.short_cutoff else ", no short-wavelength cutoff")
             + _filled_text(request)
             + ". One surface is not a population: the reference solves this very surface, so "
               "a theory **holds** where |error| + band ≤ tolerance, **fails** where |error| − "
               "band > tolerance, and stays undecided only where the reference's band straddles "
               "the tolerance.\n"]
    realizations = result.realizations[0.0]
    method = {field: method_band(realizations, field, reference_name)
              for field in ("area", "separation", "mean_gap", "stiffness", "conductance",
                            "leakage")}
    rows_ = resolution(half_grid, comparison, refined, method)
    not_judged = unjudged(rows_, spacing=s.spacing, unit=unit, short_cutoff=request.short_cutoff)
    tables = [replace(t, judged=False) if t.field in not_judged else t for t in tables]
    glance = glance_lines(tables, not_judged)
    lines += glance
    lines += ["Every model's value at each pressure, beside the reference with its band "
              "(`physical.csv` has them all):\n",
              "![Each theory against the reference in physical units](check-physical.png)\n"]
    for table in tables:
        lines += table_lines(table)
    lines += frame_lines(tables, sigma=realization.sigma, unit=unit, e_star=request.e_star,
                         nominal_size=scene.nominal_size)
    lines += resolution_lines(rows_, spacing=s.spacing, unit=unit,
                              short_cutoff=request.short_cutoff)
    return tables, lines, glance


@dataclass(frozen=True)
class CheckResult:
    """One scan checked: the answer in physical units and the runs behind it.

    Attributes
    ----------
    request : CheckRequest
        What was asked (the scan, E*, the pressures, the cutoff, ...).
    tables : tuple of PhysicalTable
        Per reference field (and frame): the pressures, the reference with its band and every
        model's value and verdict at the scene's largest tolerance.
    sections : tuple of str
        The Markdown lines that head the check's report.
    answer : tuple of str
        The answer at a glance (Markdown lines, among ``sections``).
    scene_text : str
        The scene that answers the request (``check.toml``).
    seconds : float
        Computing time [s].
    runs : tuple of SceneResult
        The whole scan (first) and, when tiles were asked for, its tiles.
    sampled : SceneResult
        The whole scan before any finer reference solve (its half-grid band).
    """

    request: CheckRequest
    tables: tuple[PhysicalTable, ...]
    sections: tuple[str, ...]
    answer: tuple[str, ...]
    scene_text: str
    seconds: float
    runs: tuple
    sampled: object

    @classmethod
    def of(cls, request: CheckRequest, runs, sampled, *, scene_text: str,
           seconds: float) -> CheckResult:
        """The result of the runs of a check (``runs[0]`` the whole scan)."""
        tables, sections, answer = check_sections(request, runs[0], sampled)
        return cls(request, tuple(tables), tuple(sections), tuple(answer), scene_text,
                   float(seconds), tuple(runs), sampled)

    @property
    def fields(self) -> tuple[str, ...]:
        """The reference fields the check compares (``"area"``, ``"separation"``, ...)."""
        return tuple(dict.fromkeys(t.field for t in self.tables))

    def table(self, field: str = "area", frame: str | None = None) -> PhysicalTable:
        """The table of one reference field (shown as Markdown in a notebook): pressures, the
        reference with its band, every model's value and verdict. ``frame`` ("interface" or
        "finite") where the check answers in both; the first frame by default. The stiffness
        is also found as ``"conductance"``, the ensemble reports' word for it.

        Raises
        ------
        ValueError
            For a field or frame the check did not compare, naming the ones it did.
        """
        matches = [t for t in self.tables if t.field in (field, FIELD_ALIASES.get(field))
                   and frame in (None, t.frame)]
        if not matches:
            known = ", ".join(repr(f) for f in self.fields)
            frames = ", ".join(repr(f) for f in dict.fromkeys(t.frame for t in self.tables))
            raise ValueError(f"field must be one the check compared ({known}; frames "
                             f"{frames}), got field={field!r}, frame={frame!r}")
        return matches[0]

    def glance(self) -> Markdown:
        """Each theory's verdicts across the pressures and one sentence per field."""
        return Markdown("\n".join(self.answer))

    def markdown(self) -> Markdown:
        """The check's sections as they head its report."""
        return Markdown("\n".join(self.sections))

    def _repr_markdown_(self) -> str:
        return self.markdown()

    def plot(self) -> Figure:
        """Every theory against the reference with its band, one panel per table, in physical
        units (a matplotlib Figure, not attached to pyplot)."""
        from validation.check.figure import physical_figure

        return physical_figure(list(self.tables))

    def to_frame(self):
        """The tables as one pandas DataFrame, a row per field, frame, pressure and model (the
        reference as ``bem``, with its band): the rows of ``physical.csv``.

        Raises
        ------
        ImportError
            Without pandas (not a dependency of this package).
        """
        try:
            import pandas
        except ImportError:
            raise ImportError("CheckResult.to_frame needs pandas: pip install pandas") from None
        return pandas.DataFrame([row for t in self.tables for row in t.rows()])

    def write_report(self, folder: str | pathlib.Path, *, command: str | None = None,
                     executor=None, cache_dir: str | pathlib.Path | None = None) -> pathlib.Path:
        """Write the check's report folder (``report.md`` headed by the check's sections,
        ``physical.csv``, ``check.toml`` and every table and figure of a report); returns the
        path of ``report.md``. A scan given as an array is written beside it (``scan.npy``) and
        ``check.toml`` reads it from there. ``executor`` and ``cache_dir``: where the figures
        are drawn and kept, as in :func:`validation.report.write.write_report`, the check's own
        (``check-physical.png``) with the report's."""
        from validation.check.figure import physical_figure
        from validation.report.write import write_report

        folder = pathlib.Path(folder)
        scan = self.request.path.resolve()
        tables = list(self.tables)
        path = write_report(list(self.runs), folder, seconds=self.seconds, mode="one surface",
                            command=command, executor=executor, cache_dir=cache_dir,
                            lead=list(self.sections),
                            figure_jobs=[("check-physical.png", partial(physical_figure, tables),
                                          len(tables))])
        if self.request.scratch:   # the array's copy, read by check.toml from this folder
            if scan != (folder / "scan.npy").resolve():
                shutil.copyfile(scan, folder / "scan.npy")
            scan = pathlib.Path("scan.npy")
        write_csv(tables, folder / "physical.csv")
        # the scan's path as check.toml in this folder reads it (relative paths are the folder's)
        text = re.sub(r'(?m)^path = .*$', "path = " + _quoted(str(scan)), self.scene_text,
                      count=1)
        (folder / "check.toml").write_text(text, encoding="utf-8")
        return path
