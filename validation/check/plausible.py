"""Is the scan in the units the user meant? A plausibility check before any solve.

A check in physical units trusts three numbers the user writes: the heights' unit, the scan's
size and E*. Each wrong by a factor of a thousand (heights in nm read as metres, ``115MPa``
for ``115GPa``) still gives a report, confident and wrong. So, once the scan is read and before
any contact problem is solved, :func:`plausibility` looks at what the numbers imply:

* the rms slope ``h'_rms`` of the map as read (after the short-wavelength cutoff): measured
  rough surfaces have 0.001 to about 1 at their finest scale; every model and the reference
  share the half-space theory's small slopes. Above :data:`STEEP` the map is refused (heights
  in nm read as metres give 1e9 times the true slope), above 1 a warning says that the
  small-slope theory is stretched and how to cut the slopes (``--short-cutoff``);
* the rms height Sq and the scan's size, in metres: an Sq above :data:`TALL` (1 mm) or a scan
  wider than :data:`WIDE` (1 m) is not a roughness measurement, a pixel below :data:`FINE`
  (0.01 nm) is finer than an atom: refused, naming the unit to check;
* the nominal pressures against E* and the slope, through Persson's estimate of the real
  contact-area fraction, ``A/A0 = erf(sqrt(2) p / (E* h'_rms))`` (docs/theory.md eq. P3): a
  lowest pressure already in full contact (``A/A0`` ≥ :data:`FULL`) or a highest pressure
  touching less than one pixel of the scan is refused, naming the likely mistake
  ("full contact at 1 MPa: is E* in GPa?"); a range that reaches full contact part of the
  way is warned about (the report says at which pressures the reference is closed).

Persson's estimate is within a factor of about 1.3 of the exact area at light contact
(kappa = sqrt(8/pi) ≈ 1.6 against about 2); the thresholds are far enough from any plausible
case that this does not matter.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy import special

from validation.check.units import format_length, format_pressure
from validation.surfaces.units import LENGTH_UNITS

__all__ = ["FINE", "FULL", "STEEP", "TALL", "WIDE", "PlausibilityWarning", "contact_estimate",
           "plausibility"]

#: rms slope above which a map is refused: no measured rough surface is this steep on average
#: (84 degrees), while a unit mismatch of heights and size gives a factor 1e3 to 1e9.
STEEP = 10.0
#: rms height [m] above which a map is refused (a roughness of millimetres is a shape).
TALL = 1e-3
#: A scan's side [m] above which it is refused.
WIDE = 1.0
#: A pixel [m] below which it is refused (a hundredth of a nanometre: finer than an atom).
FINE = 1e-11
#: Persson's area fraction taken as full contact.
FULL = 0.99


class PlausibilityWarning(UserWarning):
    """A check's input is possible but unlikely (a steep map, a range that reaches full
    contact): the answer is given, and the warning says what to look at."""


def contact_estimate(load: np.ndarray | float, rms_slope: float) -> np.ndarray:
    """Persson's real contact-area fraction at nominal pressures ``load = p / E*``:
    ``erf(sqrt(2) p / (E* h'_rms))`` (eq. P3 with ``G = E*^2 h'_rms^2 / 8``)."""
    return special.erf(math.sqrt(2.0) * np.asarray(load, dtype=float) / rms_slope)


def _unit_hint(slope: float) -> str:
    """Which heights' unit, read as metres, would give a plausible slope."""
    for unit in ("mm", "um", "nm", "A", "pm"):
        if 1e-3 <= slope * LENGTH_UNITS[unit] <= 1.0:
            return (f"heights in {unit} read as metres give this: with heights in {unit} the "
                    f"rms slope is {slope * LENGTH_UNITS[unit]:.3g}")
    return "the heights' unit and the scan's size do not belong together"


def _scan_refusals(slope: float, rms_height: float, spacing: float,
                   size: tuple[float, float]) -> list[str]:
    """What makes a scan implausible in its units, one sentence each."""
    problems = []
    if slope > STEEP:
        problems.append(f"its rms slope is {slope:.3g}: far steeper than any measured rough "
                        f"surface (0.001 to about 1); {_unit_hint(slope)}. Check the heights' "
                        f"unit (file_unit, or the file's own) and the scan's size "
                        f"(physical_size, or an array's spacing)")
    if rms_height > TALL:
        problems.append(f"its rms height Sq is {format_length(rms_height)}: a roughness of "
                        f"more than {format_length(TALL)} is a shape, not a roughness; are "
                        f"the heights in nm or um, read as metres (file_unit)?")
    if max(size) > WIDE:
        problems.append(f"it is {format_length(size[0])} x {format_length(size[1])} wide: a "
                        f"roughness scan is micrometres to centimetres across; is its size "
                        f"in um or mm, read as metres (physical_size, or an array's spacing)?")
    if spacing < FINE:
        problems.append(f"its pixel is {spacing:.3g} m, finer than an atom; is the size or "
                        f"the spacing in nm or um, read as metres (physical_size, or an array's "
                        f"spacing)?")
    return problems


def _pressure(load: float, e_star: float | None) -> str:
    return f"{load:.3g} E*" if e_star is None else format_pressure(load * e_star)


def _load_refusals(low: float, high: float, e_star: float | None, slope: float,
                   pixels: int) -> list[str]:
    """Pressures that all lie in full contact, or all on less than one pixel."""
    at_low, at_high = (float(contact_estimate(p, slope)) for p in (low, high))
    given = "" if e_star is None else f"E* = {format_pressure(e_star)}, "
    if at_low >= FULL:
        fix = ("are the pressures in units of E* meant as they are?" if e_star is None else
               f"is E* in the next unit up ({format_pressure(1e3 * e_star)}), or the pressures "
               f"in the next unit down ({_pressure(low / 1e3, e_star)} to "
               f"{_pressure(high / 1e3, e_star)})?")
        return [f"full contact at {_pressure(low, e_star)}, the lowest pressure (Persson's "
                f"estimate A/A0 = {at_low:.3f} with {given}rms slope {slope:.3g}): nothing rough "
                f"is left to check; {fix}"]
    if at_high * pixels < 1.0:
        fix = ("are the pressures in units of E* meant as they are?" if e_star is None else
               f"is E* in the next unit down ({format_pressure(e_star / 1e3)}), or the "
               f"pressures in the next unit up ({_pressure(1e3 * low, e_star)} to "
               f"{_pressure(1e3 * high, e_star)})?")
        return [f"no contact at {_pressure(high, e_star)}, the highest pressure: Persson's "
                f"estimate A/A0 = {at_high:.2g} ({given}rms slope {slope:.3g}) is less than "
                f"one of the scan's {pixels} pixels; {fix}"]
    return []


def _e_star_hint(loads: tuple[float, float], e_star: float | None, slope: float) -> str:
    """Where E* in the next unit up would put the same pressures."""
    if e_star is None or 1e3 * e_star > 1.2e12:     # none stiffer than diamond's 1.2 TPa
        return ""
    low, high = (float(contact_estimate(p / 1e3, slope)) for p in loads)
    return (f"; is E* ({format_pressure(e_star)}) in the unit you meant? With E* = "
            f"{format_pressure(1e3 * e_star)} the same pressures give A/A0 ≈ {low:.2g} to "
            f"{high:.2g}")


def plausibility(name: str, heights: np.ndarray, spacing: float, size: tuple[float, float],
                 slope: float, loads: tuple[float, float] | None,
                 e_star: float | None) -> None:
    """Refuse a scan or pressures that are implausible in their units, warn about unlikely
    ones (module docstring).

    Parameters
    ----------
    name : str
        The scan, as messages name it (its file, or "the height array").
    heights : numpy.ndarray
        The map as the check reads it [m].
    spacing : float
        Its pixel [m].
    size : (float, float)
        Its width and height [m].
    slope : float
        Its rms slope.
    loads : (float, float) or None
        The lowest and highest nominal pressure as p / E*; None: the check's default range
        (chosen from the slope, always plausible).
    e_star : float or None
        E* [Pa], or None (pressures in units of E*).

    Raises
    ------
    ValueError
        Naming what is implausible and the likely mistake.

    Warns
    -----
    PlausibilityWarning
        A map steeper than 1 on average, or a pressure range that reaches full contact.
    """
    problems = _scan_refusals(slope, float(np.std(heights)), spacing, size)
    if not problems and loads is not None:
        problems = _load_refusals(*loads, e_star, slope, heights.size)
    if problems:
        text = "; and ".join(problems)
        raise ValueError(f"{name}: {text}" + ("" if text.endswith("?") else "."))
    if slope > 1.0:
        warnings.warn(f"{name}: its rms slope is {slope:.3g}, above 1: every model and the "
                      f"reference assume small slopes; if the heights' unit is right, a "
                      f"short-wavelength cutoff (short_cutoff='8px', on the command line "
                      f"--short-cutoff 8px) removes the steepest, least resolved wavelengths",
                      PlausibilityWarning, stacklevel=3)
    if loads is not None and float(contact_estimate(loads[1], slope)) >= FULL:
        full = loads[1]
        # the lowest pressure of full contact by Persson: erf(x) = FULL
        start = special.erfinv(FULL) * slope / math.sqrt(2.0)
        warnings.warn(f"{name}: from about {_pressure(start, e_star)} up to "
                      f"{_pressure(full, e_star)} the contact is closed (Persson's estimate "
                      f"A/A0 ≥ {FULL:g}): the verdicts there are about a flat, closed "
                      f"interface, not rough contact" + _e_star_hint(loads, e_star, slope),
                      PlausibilityWarning, stacklevel=3)
