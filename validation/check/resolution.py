"""Is the reference converged on the scan as sampled? One sentence per quantity, and what to
do when the contact area is not.

The reference band of a measured map comes first from the same scan on every second pixel
(eq. T32): it says how much the answer changes when the scan's finest wavelengths (two to four
pixels) are taken away, so it measures the *resolution* of the scan as much as the solver's
error. On a rough surface the real contact area is set by the shortest wavelengths in contact
(the rms slope grows as finer roughness is added, and the area at a given load falls with it:
docs/theory.md, "11.5 One surface"), so a large half-grid band
of the area says that the area depends on the pixel size: it is an answer about the scan as
sampled, not about the surface. The remedy is a short-wavelength cutoff: low-pass the scan at
a length of several pixels (``--short-cutoff``) so that every model and the reference see the
same band-limited surface, whose area the grid resolves.

Where the band alone keeps a verdict open, the reference is solved again on the scan
interpolated to twice its grid (:func:`validation.run.finer_sample.interpolated_scan`), which adds no
roughness: that band measures the solver's error on the surface as sampled, and it is the one
the verdicts use.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from validation.surfaces.units import length_in, readable

__all__ = ["CONVERGED", "Resolution", "cutoff_text", "resolution", "resolution_lines",
           "SUGGESTED_CUTOFF", "suggested_cutoff", "unjudged"]

#: Largest median half-grid band (in the error measure of the quantity) for which the
#: quantity is called converged at the scan's resolution: the smallest default tolerance.
CONVERGED = 0.05
#: Cutoff suggested when the area is not converged, in pixels of the scan (measured on a 1 nm
#: AFM scan: the area band fell from a median 55 % to 5 % at 8 pixels).
SUGGESTED_CUTOFF = 8
_MEASURE = {"area": "relative", "stiffness": "relative", "conductance": "relative",
            "separation": "in units of σ",
            "mean_gap": "in units of σ", "leakage": "log of the ratio"}
_NAMES = {"area": "contact area", "stiffness": "stiffness K", "conductance": "stiffness K",
          "separation": "separation", "mean_gap": "mean gap", "leakage": "leakage h_eff"}


@dataclass(frozen=True)
class Resolution:
    """The reference band of one quantity: on the scan as sampled (half grid) and as the
    verdicts use it (after the 2N interpolation where that was solved)."""

    field: str
    half_grid_median: float
    half_grid_max: float
    final_median: float
    refined_points: int

    @property
    def converged(self) -> bool:
        """Whether the median half-grid band is within :data:`CONVERGED`."""
        return bool(self.half_grid_median <= CONVERGED)


def _bands(comparison) -> dict[str, np.ndarray]:
    out = {}
    for entry in comparison.models.values():
        if entry.band is not None and entry.reference_field not in out:
            out[entry.reference_field] = np.asarray(entry.band, dtype=float)
    return out


def resolution(sampled, final, refined: np.ndarray | None = None,
               method: dict[str, np.ndarray] | None = None) -> list[Resolution]:
    """Per compared reference field: the half-grid band of ``sampled`` (the comparison before
    any finer solve) and the band of ``final`` (after it); ``refined`` (optional) marks the
    load points solved again on the interpolated scan. ``method`` (optional, per field) is
    the part of the bands that is the reference method's own error (the interface's mirror
    bound, eq. T50), which no grid narrows: it is taken out of both, so that what is left
    measures the resolution."""
    before, after = _bands(sampled), _bands(final)
    for field, part in (method or {}).items():
        for bands in (before, after):
            if field in bands:
                bands[field] = np.maximum(bands[field] - part, 0.0)
    count = 0 if refined is None else int(np.count_nonzero(refined))
    out = []
    for field in _MEASURE:
        if field in before:
            b, a = before[field], after.get(field, before[field])
            finite = np.isfinite(b)
            out.append(Resolution(field, float(np.median(b[finite])) if finite.any() else np.nan,
                                  float(np.max(b[finite])) if finite.any() else np.nan,
                                  float(np.nanmedian(a)) if np.isfinite(a).any() else np.nan,
                                  count))
    return out


def resolution_lines(rows: list[Resolution], *, spacing: float, unit: str,
                     short_cutoff: str | None) -> list[str]:
    """The report's section: a table of the bands, and in words whether the contact area is
    converged at the scan's resolution, with the remedy when it is not."""
    lines = ["## Is the reference converged on this scan?\n",
             "The reference's band comes from the scan solved on every second pixel (how much "
             "the answer moves when the finest wavelengths are taken away) and, where that band "
             "alone kept a verdict open, from the scan interpolated to twice its grid (which "
             "adds no roughness: the solver's own error on the surface as sampled). The "
             "interface reference's own method error (its mirror bound, which no grid narrows "
             "and which the verdicts' band includes) is left out of this table: what is left "
             "measures the resolution.\n",
             "| quantity | error measure | half-grid band, median (max) | band of the verdicts, "
             "median | converged at this resolution |", "|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {_NAMES[r.field]} | {_MEASURE[r.field]} | {r.half_grid_median:.3g} "
                     f"({r.half_grid_max:.3g}) | {r.final_median:.3g} | "
                     f"{'yes' if r.converged else 'no'} |")
    lines.append("")
    area = next((r for r in rows if r.field == "area"), None)
    applied = (None if short_cutoff is None
               else length_in("short_cutoff", short_cutoff, unit) / spacing)   # in pixels
    suggested = suggested_cutoff(spacing, unit, short_cutoff)
    if area is not None and not area.converged:
        lines.append(
            f"**The contact area is not converged at this resolution.** Solved on every second "
            f"pixel, the reference's area changes by a median {100 * area.half_grid_median:.0f} % "
            f"(up to {100 * area.half_grid_max:.0f} %): the area is set by roughness at the "
            + (f"scale of the cutoff ({readable(applied * spacing)} {unit})" if applied else
               f"scale of the pixel ({readable(spacing)} {unit})")
            + ", so the areas in the tables above are those of the scan as sampled, and a "
              "finer scan of the same surface would give a smaller one. "
            + (f"The scan was low-pass filtered at {cutoff_text(short_cutoff, spacing, unit)}; a "
               f"longer cutoff converges the area further, e.g. `--short-cutoff "
               f"{suggested:.3g}px` (= {readable(suggested * spacing)} {unit}). " if applied else
               f"To compare the theories on a surface whose area the scan resolves, apply a "
               f"short-wavelength cutoff of several pixels, e.g. `--short-cutoff "
               f"{suggested:.3g}px` (= {readable(suggested * spacing)} {unit}). ")
            + "Every model and the reference then see the same surface without the wavelengths "
              "below the cutoff, and the answer holds for that cutoff, which the report names.\n")
    elif area is not None:
        lines.append(
            f"The contact area is converged at this resolution (median half-grid band "
            f"{100 * area.half_grid_median:.1f} %)"
            + (f", with the scan low-pass filtered at {cutoff_text(short_cutoff, spacing, unit)}"
               if short_cutoff else "")
            + ".\n")
    return lines


def suggested_cutoff(spacing: float, unit: str, short_cutoff: str | None) -> float:
    """The cutoff [pixels] to suggest where the area is not converged: :data:`SUGGESTED_CUTOFF`
    pixels, or twice the cutoff already applied."""
    if short_cutoff is None:
        return float(SUGGESTED_CUTOFF)
    return 2.0 * length_in("short_cutoff", short_cutoff, unit) / spacing


def unjudged(rows: list[Resolution], *, spacing: float, unit: str,
             short_cutoff: str | None) -> dict[str, str]:
    """The fields the reference cannot judge at this resolution (the area, when its half-grid
    band is not converged), each with what to do: for the answer at a glance."""
    area = next((r for r in rows if r.field == "area"), None)
    if area is None or area.converged:
        return {}
    pixels = suggested_cutoff(spacing, unit, short_cutoff)
    option = (f"short-wavelength cutoff of {pixels:.3g} px = {readable(pixels * spacing)} {unit} "
              f"(`--short-cutoff {pixels:.3g}px`, `short_cutoff=\"{pixels:.3g}px\"`)")
    return {"area": f"not judged at this resolution: on every second pixel the reference's area "
                    f"changes by a median {100 * area.half_grid_median:.0f} % (below); apply a "
                    + ("longer " if short_cutoff else "") + f"{option} and check again"}


def cutoff_text(short_cutoff: str, spacing: float, unit: str) -> str:
    """A short-wavelength cutoff as the scene key writes it (``"7.8125e-09 m"``) in the scan's
    length ``unit`` and in pixels of ``spacing`` [unit]: ``7.81 nm (8 px)``."""
    length = length_in("short_cutoff", short_cutoff, unit)
    return f"{readable(length)} {unit} ({length / spacing:.3g} px)"
